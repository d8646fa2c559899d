"""Hostile inputs of issue 23 that once gave a traceback: prior stds at the ends of the
accepted range (1e-100, 1e100) on a model with a zero parameter matrix, for every
command that computes with them. Each must end with exit 0, 1 or 2 and one line."""

import re
import sys
from pathlib import Path

import pytest
from conftest import ROOT

sys.path.insert(0, str(ROOT / "tools"))
import fuzz  # noqa: E402


@pytest.fixture(scope="module")
def mixed(tmp_path_factory):
    d = tmp_path_factory.mktemp("mtx")
    fuzz._mtx(d)
    (d / "k1.mtx").write_text("%%MatrixMarket matrix coordinate real symmetric\n4 4 0\n")
    text = (d / "study.toml").read_text()
    count = iter(range(100))
    text = re.sub(r'(name = "\w+"\nvalue = [^\n]+\n)',
                  lambda m: m.group(1) + f"std = {'1e-100' if next(count) % 2 else '1e100'}\n",
                  text)
    (d / "study.toml").write_text(text.replace('method = "least-squares"',
                                               'method = "bayesian"'))
    return d


@pytest.mark.parametrize("args", [["check"], ["update"], ["frequencies"],
                                  ["sweep", "--coordinate", "1", "--max-mass", "1", "-o",
                                   "sweep.png"]])
def test_extreme_prior_stds(mixed, run_cli, args):
    argv = [args[0], mixed / "study.toml", *[str(mixed / a) if a.endswith(".png") else a
                                             for a in args[1:]]]
    code, out, err = run_cli(*argv)
    assert code in (0, 1, 2), err
    assert "Traceback" not in err and "nan" not in out.lower()
    if code == 2:
        assert len(err.strip().splitlines()) == 1, err
    assert Path(mixed / "study.toml").exists()


def test_table_without_rows():
    """A Monte Carlo whose every trial is refused has no parameter rows (fuzz seed 1,
    case 1109: TypeError in the table before)."""
    from eigenupdate.report.text import table

    assert table(["parameter", "bias"], []).splitlines() == ["parameter  bias",
                                                              "---------  ----"]
