"""Hostile inputs of round 4 (tools/hostile_round4.py): outputs over files the command
did not write, blank ids on NASTRAN cards, and the newest features. Each refusal is one
line on standard error, exit 2, no traceback, nothing written."""

import shutil

import pytest
from conftest import ROOT
from refusals import one_line as _one_line

FIG2 = ROOT / "examples" / "paper_fig2"
FRF_EXAMPLE = ROOT / "examples" / "paper_beam_frf"




def _copy(src, dst):
    shutil.copytree(src, dst)
    return dst


# (example, argv after the study, the output file, the flag named); {o} is the output
OUTPUTS = [
    (FIG2, "truth.toml", ["simulate", "-o", "{o}"], "m.csv", "-o"),
    (FIG2, "study.toml", ["update", "--save", "{o}"], "r.json", "--save"),
    (FIG2, "study.toml", ["sweep", "--coordinate", "1", "--max-mass", "1", "-o", "{o}"],
     "s.png", "-o"),
    (FIG2, "study.toml", ["frf", "--input", "1", "--output", "2", "--fmax", "200", "-o", "{o}"],
     "f.pdf", "-o"),
    (FIG2, "study.toml", ["report", "--saved-only", "-o", "{o}"], "r.html", "-o"),
    (FIG2, "study.toml", ["montecarlo", "--trials", "3", "--in-process", "--seed", "4",
                          "--truth", "{d}/../truth.toml", "-o", "{d}"], "mc/trials.csv",
     "-o trials.csv"),
    (FRF_EXAMPLE, "study.toml", ["extract", "-o", "{o}"], "x.csv", "-o"),
    (FRF_EXAMPLE, "study.toml", ["extract", "-o", "{d}/x.csv", "--save", "{o}"], "x.json",
     "--save"),
    (FRF_EXAMPLE, "study.toml", ["extract", "-o", "{d}/x.csv", "--uff55", "{o}"], "m.uff",
     "--uff55"),
]


@pytest.mark.parametrize(("example", "study", "argv", "name", "flag"), OUTPUTS,
                         ids=[f"{a[0]} {a[-1]}" for _, _, a, _, _ in OUTPUTS])
def test_an_output_over_a_file_the_command_did_not_write_needs_force(
        tmp_path, run_cli, example, study, argv, name, flag):
    """`simulate -o` and `extract -o` wrote over measured CSVs (a hand-made one looks the
    same), and every other output replaced whatever was there. Now one rule for all
    (io.outputs.check_outputs): an existing file is replaced only if it is this option's
    own earlier output (a signature line, a JSON schema, a figure's Creator) or with
    --force; the study's inputs never. A copy of the measured CSV stands for another
    test's data."""
    d = _copy(example, tmp_path / "ex")
    out = d / name
    out.parent.mkdir(exist_ok=True)
    data = (FIG2 / "measured.csv").read_bytes()
    out.write_bytes(data)
    args = [a.format(o=out, d=out.parent) for a in argv]
    cmd = [args[0], d / study, *args[1:]]
    code, stdout, err = run_cli(*cmd)
    _one_line(code, err, f"{name.split('/')[-1]}: {flag}: exists and is not an earlier "
                         f"output of {flag}", "--force")
    assert out.read_bytes() == data and stdout == ""
    ok = (0, 1) if argv[0] == "montecarlo" else (0,)  # 1: files written, no statistics
    code, _, err = run_cli(*cmd, "--force")
    assert code in ok, err
    assert out.read_bytes() != data
    code, _, err = run_cli(*cmd)  # its own earlier output: replaced without --force
    assert code in ok, err


def test_an_input_is_refused_even_with_force(tmp_path, run_cli):
    """--force replaces a file the command did not write, never one the run reads: the
    study (simulate), its measurement CSV (update --save) or an FRF file (extract)."""
    d = _copy(FIG2, tmp_path / "fig2")
    before = {p.name: p.read_bytes() for p in d.iterdir()}
    code, _, err = run_cli("simulate", d / "truth.toml", "-o", d / "truth.toml", "--force")
    _one_line(code, err, "truth.toml: -o: is an input of this run")
    code, _, err = run_cli("update", d / "study.toml", "--save", d / "measured.csv", "--force")
    _one_line(code, err, "measured.csv: --save: is an input of this run")
    assert {p.name: p.read_bytes() for p in d.iterdir()} == before
    f = _copy(FRF_EXAMPLE, tmp_path / "frf")
    uff = f / "frf" / "base.uff"
    data = uff.read_bytes()
    code, _, err = run_cli("extract", f / "study.toml", "-o", uff, "--force")
    _one_line(code, err, "base.uff: -o: is an input of this run")
    assert uff.read_bytes() == data


def test_simulated_csv_reads_back_with_its_signature(tmp_path, run_cli):
    """The signature line of `simulate -o` is a comment the measurement reader skips: the
    update from simulated truth data recovers the truth (paper Fig. 2, truth.toml's
    values to 1e-6, as test_paper_fig2's iteration)."""
    import json

    d = _copy(FIG2, tmp_path / "fig2")
    code, _, err = run_cli("simulate", d / "truth.toml", "-o", d / "measured.csv", "--force")
    assert code == 0, err
    assert (d / "measured.csv").read_text().startswith(
        "# eigenupdate simulate: frequencies of truth.toml\nconfiguration,mode,")
    code, out, err = run_cli("update", d / "study.toml", "--json")
    assert code == 0, err
    got = json.loads(out)["parameters"]
    assert got["m1"] == pytest.approx(10.0, rel=1e-6) and got["k1"] == pytest.approx(1e6, rel=1e-6)


def test_extract_plots_do_not_replace_foreign_figures(tmp_path, run_cli):
    """`extract --plots DIR` replaced any extract_*.png there; now only its own earlier
    plots (Creator 'eigenupdate figure') without --force. The bare beam's two FRFs only."""
    text = (FRF_EXAMPLE / "study.toml").read_text()
    i = text.index("[[perturbation]]")
    (tmp_path / "study.toml").write_text(
        text[:i] + '[measurement]\nmodes = [1, 2]\n[measurement.frf]\n'
                   f'"base" = "{FRF_EXAMPLE / "frf" / "base.uff"}"\n')
    plots = tmp_path / "plots"
    plots.mkdir()
    foreign = plots / "extract_base_1.png"
    foreign.write_bytes(b"\x89PNG\r\n\x1a\n a photograph of the test rig")
    cmd = ["extract", tmp_path / "study.toml", "-o", tmp_path / "x.csv", "--plots", plots]
    code, _, err = run_cli(*cmd)
    _one_line(code, err, "extract_base_1.png: --plots: exists and is not an earlier output",
              "--force")
    assert not (tmp_path / "x.csv").exists()
    assert run_cli(*cmd, "--force")[0] == 0
    assert b"eigenupdate figure" in foreign.read_bytes()
    assert run_cli(*cmd)[0] == 0  # x.csv and the plots: its own earlier outputs
