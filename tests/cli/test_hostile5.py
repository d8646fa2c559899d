"""Hostile inputs of round 5 (tools/hostile_round5.py) that need no pyNastran: input
files too large to read whole are refused before they are read, naming the file."""

import shutil

import pytest
from conftest import ROOT
from refusals import one_line

FIG2 = ROOT / "examples" / "paper_fig2"
FRF_EXAMPLE = ROOT / "examples" / "paper_beam_frf"


def _sparse(path, size):
    with open(path, "r+b" if path.exists() else "wb") as f:
        f.truncate(size)


@pytest.mark.parametrize(("name", "what"), [("study.toml", "study file"),
                                            ("measured.csv", "measurement file")])
def test_an_input_beyond_the_size_budget_is_refused_unread(tmp_path, run_cli, monkeypatch,
                                                           name, what):
    """A sparse 10 GB study file was read until memory ran out ('out of memory', naming
    no file). Here the budget is lowered to 1 MB and the file made 3 MB (sparse zeros,
    which no reader could parse: a refusal for their content would not say 'MB')."""
    d = tmp_path / "fig2"
    shutil.copytree(FIG2, d)
    _sparse(d / name, 3 * 2**20)
    monkeypatch.setenv("EIGENUPDATE_MAX_INPUT_MB", "1")
    code, _, err = run_cli("check", d / "study.toml")
    one_line(code, err, f"{name}: the {what} is 3 MB, read whole into memory; the limit "
                        f"is 1 (set EIGENUPDATE_MAX_INPUT_MB to raise it)")


def test_the_size_budget_must_be_a_number(tmp_path, run_cli, monkeypatch):
    """A bad setting of the new limit stops every command, as the others do."""
    monkeypatch.setenv("EIGENUPDATE_MAX_INPUT_MB", "lots")
    code, _, err = run_cli("check", FIG2 / "study.toml")
    one_line(code, err, "EIGENUPDATE_MAX_INPUT_MB: must be an integer >= 1, got 'lots'")


def test_an_frf_file_beyond_the_size_budget_is_refused_before_it_is_hashed(
        tmp_path, run_cli, monkeypatch):
    """extract hashes every FRF file (one file given for two tests) before reading it: a
    sparse 10 GB UFF file was read whole there ('out of memory', naming no file)."""
    d = tmp_path / "frf"
    shutil.copytree(FRF_EXAMPLE, d)
    _sparse(d / "frf" / "base.uff", 3 * 2**20)
    monkeypatch.setenv("EIGENUPDATE_MAX_INPUT_MB", "1")
    code, _, err = run_cli("extract", d / "study.toml", "-o", d / "x.csv")
    one_line(code, err, "base.uff: the FRF file is 3 MB, read whole into memory")
    assert not (d / "x.csv").exists()
