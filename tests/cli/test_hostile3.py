"""Hostile inputs of round 3 (tools/hostile_round3.py): the leftovers of round 2. Each
refusal is one line on standard error, exit 2, no traceback, nothing written."""

import json
import shutil

from conftest import ROOT
from refusals import one_line as _one_line

FRF_EXAMPLE = ROOT / "examples" / "paper_beam_frf"




def test_saved_extraction_refused_over_swapped_frf_files(tmp_path, run_cli):
    """Two FRF files swapped in [measurement.frf] after `extract --save`: both hold two
    FRFs at the same points, so the saved extraction (which recorded only how many) drew
    '0.2 kg at 1''s fits over the FRFs of '0.2 kg at 3'. It now records each FRF's values
    (SHA-256, hashlib) and the report refuses the swap; unswapped, it is accepted."""
    from eigenupdate.io.study import load_study
    from eigenupdate.measure.survey import TestExtraction
    from eigenupdate.workflow import _study_frfs

    d = tmp_path / "frf"
    shutil.copytree(FRF_EXAMPLE, d)
    code, _, err = run_cli("extract", d / "study.toml", "-o", d / "x.csv", "--save",
                           d / "x.json")
    assert code == 0, err
    saved = TestExtraction.from_dict(json.loads((d / "x.json").read_text()), "x.json")
    assert [x["file"] for x in saved.frfs["0.2 kg at 1"]] == ["0.2_kg_at_1.uff"] * 2
    saved.require_frfs(_study_frfs(load_study(d / "study.toml")), "x.json")  # as saved
    text = (d / "study.toml").read_text()
    a, b = '"frf/0.2_kg_at_1.uff"', '"frf/0.2_kg_at_3.uff"'
    (d / "study.toml").write_text(text.replace(a, "@").replace(b, a).replace("@", b))
    code, _, err = run_cli("report", d / "study.toml", "--saved-only", "--extraction",
                           d / "x.json", "-o", d / "r.html")
    _one_line(code, err, "x.json", "'0.2 kg at 1' was fitted to FRFs 0.2_kg_at_1.uff",
              "0.2_kg_at_3.uff", "extract again")
    assert not (d / "r.html").exists()
    # the same bytes under the old names (files swapped on disk): refused as well
    (d / "study.toml").write_text(text)
    f1, f3 = d / "frf" / "0.2_kg_at_1.uff", d / "frf" / "0.2_kg_at_3.uff"
    one = f1.read_bytes()
    f1.write_bytes(f3.read_bytes())
    f3.write_bytes(one)
    code, _, err = run_cli("report", d / "study.toml", "--saved-only", "--extraction",
                           d / "x.json", "-o", d / "r.html")
    _one_line(code, err, "'0.2 kg at 1' was fitted to FRFs")
    assert not (d / "r.html").exists()


def test_a_unit_the_value_does_not_have_is_refused(tmp_path, run_cli):
    """unit = "g" on the 9.7 kg mass of paper Fig. 2 printed 9.7 g: a unit is a label, so
    on the package's SI models it must be the quantity's SI unit (kg; kg m^2 on a beam's
    rotational coordinate) or the study is refused; the SI unit itself is accepted."""
    src = ROOT / "examples" / "paper_fig2"
    for f in src.iterdir():
        if f.is_file():
            shutil.copy(f, tmp_path / f.name)
    text = (src / "study.toml").read_text()
    for unit, ok in [("g", False), ("t", False), ("kg m^2", False), ("kg", True)]:
        (tmp_path / "study.toml").write_text(
            text.replace("value = 9.7  # kg", f'value = 9.7\nunit = "{unit}"', 1))
        code, out, err = run_cli("frequencies", tmp_path / "study.toml")
        if ok:
            assert code == 0, err
        else:
            _one_line(code, err, "model.mass[1].unit", f"'{unit}' is not the unit",
                      "SI, kg here")
    beam = (ROOT / "examples" / "paper_beam" / "study.toml").read_text()
    for coordinate, unit, ok in [(11, "kg m^2", False), (12, "kg m^2", True), (12, "kg", False),
                                 (11, "kg", True)]:
        (tmp_path / "beam.toml").write_text(beam.replace(
            "coordinate = 11\nvalue = 0.0", f'coordinate = {coordinate}\nunit = "{unit}"\n'
                                            "value = 0.0", 1).replace(
            'frequencies = "', f'frequencies = "{ROOT}/examples/paper_beam/', 1))
        code, out, err = run_cli("frequencies", tmp_path / "beam.toml")
        if ok:
            assert code == 0, err
        else:
            _one_line(code, err, "model.point_mass[1].unit")


def test_an_earlier_save_bdf_output_is_replaced_any_other_file_needs_force(tmp_path):
    """The rule of `--save-bdf` (README "NASTRAN models"): a file that starts with its
    comment block is its own earlier output and is replaced; any other existing file
    (another study's deck, an INCLUDEd mesh) only with --force; a new name always."""
    import pytest

    from eigenupdate.errors import InputError
    from eigenupdate.io.nastran_write import SIGNATURE
    from eigenupdate.io.outputs import check_replaceable

    ours, deck = tmp_path / "updated.bdf", tmp_path / "other.bdf"
    ours.write_text(f"$ {SIGNATURE} frame.bdf by study study.toml\nGRID,1\n")
    deck.write_text("$ another study's deck\nGRID,1\n")
    check_replaceable(ours, "--save-bdf", "$ " + SIGNATURE, force=False)
    check_replaceable(tmp_path / "new.bdf", "--save-bdf", "$ " + SIGNATURE, force=False)
    check_replaceable(deck, "--save-bdf", "$ " + SIGNATURE, force=True)
    with pytest.raises(InputError, match="exists and is not an earlier output of --save-bdf"):
        check_replaceable(deck, "--save-bdf", "$ " + SIGNATURE, force=False)


def test_design_does_not_replace_another_study_without_force(tmp_path, run_cli):
    """`design -o truth.toml` wrote the plan over the example's truth study (not an
    input of the run); now refused before the design, the file unchanged. Its own earlier
    plan (first line '# eigenupdate design: plan from ...') is replaced, as is any file
    with --force."""
    src = ROOT / "examples" / "paper_fig2"
    for f in src.iterdir():
        if f.is_file():
            shutil.copy(f, tmp_path / f.name)
    before = (tmp_path / "truth.toml").read_bytes()
    code, out, err = run_cli("design", tmp_path / "study.toml", "-o", tmp_path / "truth.toml")
    _one_line(code, err, "truth.toml: -o: exists and is not an earlier output of -o")
    assert out == "" and (tmp_path / "truth.toml").read_bytes() == before
    for extra in ([], []):  # a new name, then its own earlier output
        code, _, err = run_cli("design", tmp_path / "study.toml", "-o", tmp_path / "p.toml",
                               *extra)
        assert code == 0, err
    assert (tmp_path / "p.toml").read_text().startswith(
        "# eigenupdate design: plan from study.toml\n")
    code, _, err = run_cli("design", tmp_path / "study.toml", "-o", tmp_path / "truth.toml",
                           "--force")
    assert code == 0, err


def _chain(d, n, *, massless=(), empty=(), modes="[1, 2]"):
    """A chain of n unit masses and 1e6 N/m springs, free-free, as a matrices study
    (n > 400: the sparse, shift-invert path); ``massless`` coordinates get no mass,
    ``empty`` ones neither mass nor springs."""
    import numpy as np
    import scipy.io
    import scipy.sparse as sp

    k = np.array([0.0 if i in empty or i + 1 in empty else 1e6 for i in range(n - 1)])
    K = sp.diags([np.r_[k, 0] + np.r_[0, k], -k, -k], [0, 1, -1])
    M = sp.diags([[0.0 if i in massless or i in empty else 1.0 for i in range(n)]], [0])
    d.mkdir()
    scipy.io.mmwrite(d / "K0.mtx", sp.coo_matrix((n, n)))
    scipy.io.mmwrite(d / "M0.mtx", sp.coo_matrix(M))
    scipy.io.mmwrite(d / "K.mtx", sp.coo_matrix(K))
    (d / "study.toml").write_text(
        '[model]\ntype = "matrices"\nK0 = "K0.mtx"\nM0 = "M0.mtx"\n[[model.parameter]]\n'
        'name = "k"\nvalue = 1.0\nK = "K.mtx"\n[[perturbation]]\ncoordinate = 3\n'
        f"mass = 0.5\n[measurement]\nmodes = {modes}\n")
    return d / "study.toml"


def test_singular_and_massless_sparse_models_say_why_in_our_words(tmp_path, run_cli):
    """A 600-coordinate chain (sparse path): a coordinate with neither spring nor mass
    made SuperLU's "Factor is exactly singular" the message; mass at only 3 coordinates
    ended in a traceback, ARPACK error -9999 (a shift-inverted operator of rank 3 has no
    Krylov basis of 2k + 1 vectors). Each is now one line naming the cause; the same chain
    with every coordinate massive solves (source of the cause: K and M as built)."""
    study = _chain(tmp_path / "empty", 600, empty={299})
    code, _, err = run_cli("frequencies", study)
    _one_line(code, err, "K - sigma M is singular", "1 coordinate(s) with neither "
              "stiffness nor mass (row(s) 300 of K and M are empty)")
    assert "Factor" not in err
    study = _chain(tmp_path / "three", 600, massless=set(range(600)) - {100, 300, 500})
    code, _, err = run_cli("frequencies", study)
    _one_line(code, err, "the model has mass at only 3 of its 600 coordinates",
              "has stiffness and no mass")
    assert "ARPACK error" not in err
    study = _chain(tmp_path / "none", 600, massless=set(range(600)))
    code, _, err = run_cli("frequencies", study)
    _one_line(code, err, "a motion with neither strain energy nor mass")
    code, out, err = run_cli("frequencies", _chain(tmp_path / "fine", 600))
    assert code == 0, err
