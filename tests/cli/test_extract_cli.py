"""Issue 9: `eigenupdate extract` without a model, on files, with the kind option, and its
exit status (2 with the table printed when a used mode is not found)."""

import json

import numpy as np
import pyuff
from conftest import EXAMPLES

from eigenupdate.io.uff import read_frfs

FRF_DIR = EXAMPLES / "paper_beam_frf" / "frf"


def _study(tmp_path, body):
    s = tmp_path / "study.toml"
    s.write_text(body)
    return s


def test_study_with_only_a_measurement_table(run_cli, tmp_path):
    s = _study(tmp_path, f'[measurement]\nmodes = [1, 2]\n[measurement.frf]\n'
                         f'"0.2 kg at 1" = "{FRF_DIR}/0.2_kg_at_1.uff"\n'
                         f'base = "{FRF_DIR}/base.uff"\n')
    code, out, err = run_cli("extract", s, "-o", tmp_path / "m.csv", "--uff55", tmp_path / "m.uff")
    assert code == 0, err
    assert "numbered by order: no model" in out
    rows = (tmp_path / "m.csv").read_text().splitlines()
    assert rows[1].startswith("base,1,199.8")  # the bare structure first
    code, out, err = run_cli("check", s)
    assert code == 2 and "[model] is required (only 'extract' runs without a model)" in err


def test_frf_files_on_the_command_line(run_cli, tmp_path):
    code, out, err = run_cli("extract", FRF_DIR / "base.uff", FRF_DIR / "0.2_kg_at_1.uff",
                             "-o", tmp_path / "m.csv", "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert [c["name"] for c in doc["configurations"]] == ["base", "0.2_kg_at_1"]
    assert [m["mode"] for m in doc["configurations"][0]["modes"]] == [1, 2, 3]


def test_a_used_mode_not_found_exits_2_with_the_table(run_cli, tmp_path):
    study = (EXAMPLES / "paper_beam_frf" / "study.toml").read_text()
    study = study.replace('"frf/', f'"{FRF_DIR}/').replace("modes = [1, 2]", "modes = [1, 2, 4]")
    s = _study(tmp_path, study)
    code, out, err = run_cli("extract", s, "-o", tmp_path / "m.csv")
    assert code == 2
    assert "numbered against the initial model" in out  # the table is still printed
    last = err.strip().splitlines()[-1]
    assert "configuration 'base': elastic mode 4 was not found" in last, last
    assert "Traceback" not in err and not (tmp_path / "m.csv").exists()


def test_kind_option_for_an_unlabelled_accelerance(run_cli, tmp_path):
    (frf,) = read_frfs(FRF_DIR / "base.uff")[:1]
    f = frf.frequency_hz
    acc = -((2 * np.pi * f) ** 2) * frf.receptance
    path = tmp_path / "acc.uff"
    dset = pyuff.prepare_58(binary=0, data=acc, x=f, abscissa_spacing=1, func_type=4,
                            rsp_node=1, rsp_dir=3, ref_node=11, ref_dir=3,
                            abscissa_spec_data_type=18, ordinate_spec_data_type=1,
                            orddenom_spec_data_type=13)
    pyuff.UFF(str(path)).write_sets(dset, mode="add")
    body = f'[measurement.frf]\nbase = "{path}"\n'
    code, out, err = run_cli("extract", _study(tmp_path, body), "-o", tmp_path / "m.csv")
    assert code == 2 and '[measurement.frf_options] kind = "accelerance"' in err
    body += '[measurement.frf_options]\nkind = "accelerance"\n'
    code, out, err = run_cli("extract", _study(tmp_path, body), "-o", tmp_path / "m.csv")
    assert code == 0, err
    body = body.replace('kind = "accelerance"', f'kind = {{"{path.name}" = "accelerance"}}')
    code, out, err = run_cli("extract", _study(tmp_path, body), "-o", tmp_path / "m.csv")
    assert code == 0, err
    code, out, err = run_cli("extract", path, "--kind", "accelerance", "-o", tmp_path / "n.csv")
    assert code == 0, err
    assert (tmp_path / "n.csv").read_text().splitlines()[1].startswith("acc,1,199.")


def test_kind_is_refused_for_a_csv_frf(run_cli, tmp_path):
    """An FRF CSV holds receptance: an explicit other kind is refused, not ignored."""
    f = np.linspace(1.0, 100.0, 200)
    h = 1.0 / (1e4 - (2 * np.pi * f) ** 2 + 100j)
    path = tmp_path / "a.csv"
    path.write_text("frequency_hz,real,imag\n" + "".join(
        f"{x!r},{y.real!r},{y.imag!r}\n" for x, y in zip(f, h, strict=True)))
    code, _, err = run_cli("extract", path, "--kind", "accelerance", "-o", tmp_path / "m.csv")
    assert code == 2 and "a.csv" in err and "receptance" in err, err
    assert not (tmp_path / "m.csv").exists()
