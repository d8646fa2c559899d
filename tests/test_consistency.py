"""Physics checks of measured data around the update (issue 23): the ordering laws
(identify/plausibility.py, with the bare structure's rigid-body modes) before it, and the
chi-square test of the final residuals (identify/consistency.py) after it.

The exchanged-mode cases are the paper's Fig. 2 data (error-free, from truth.toml) with
the values of one mode exchanged between two perturbed configurations: each value alone
obeys every ordering law, and before this check the update converged to a model 371 %
(mode 2) or 910 % (mode 2, other pair) wrong with exit status 0."""

import csv
import json
import re

import numpy as np
import pytest
from conftest import EXAMPLES

from eigenupdate.identify.consistency import ALPHA, DEFAULT_RELATIVE_STD, residual_consistency
from eigenupdate.io.measurements import Measurement

FIG2 = EXAMPLES / "paper_fig2"


def _rows():
    with open(FIG2 / "measured.csv", newline="") as fh:
        return list(csv.DictReader(fh))


def _write(d, rows, std):
    with open(d / "measured.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["configuration", "mode", "frequency_hz", "std_hz"])
        for r in rows:
            w.writerow([r["configuration"], r["mode"], r["frequency_hz"],
                        "" if std is None else std])


def _exchange(rows, mode, a, b):
    rows = [dict(r) for r in rows]
    ia = next(i for i, r in enumerate(rows) if (r["configuration"], r["mode"]) == (a, mode))
    ib = next(i for i, r in enumerate(rows) if (r["configuration"], r["mode"]) == (b, mode))
    rows[ia]["frequency_hz"], rows[ib]["frequency_hz"] = (rows[ib]["frequency_hz"],
                                                          rows[ia]["frequency_hz"])
    return rows


@pytest.fixture
def fig2(tmp_path):
    (tmp_path / "study.toml").write_text((FIG2 / "study.toml").read_text())
    return tmp_path


@pytest.mark.parametrize("std", [None, "0.01"])
@pytest.mark.parametrize("pair", [("0.35 kg at 1", "0.35 kg at 2"),
                                  ("0.35 kg at 2", "0.35 kg at 4")])
def test_mode_2_exchanged_between_configurations(fig2, run_cli, std, pair):
    _write(fig2, _exchange(_rows(), "2", *pair), std)
    code, out, err = run_cli("update", fig2 / "study.toml", "--json", "--save",
                             fig2 / "r.json")
    assert code == 1, err
    line = err.strip().splitlines()[-1]
    assert line.startswith("eigenupdate: not converged:")
    assert "the data reject the fit" in line and "modes may be exchanged" in line
    # the rows that do not fit are named; the least-squares fit spreads the exchange
    # over all rows, so they need not be the exchanged ones
    assert re.search(r"configuration '[^']+' mode \d: measured [0-9.]+ Hz, fitted [0-9.]+ Hz "
                     r"\([+-][0-9.]+ std\)", line), line
    if std is None:
        assert "no std_hz" in line
    doc = json.loads(out)
    assert doc["converged"] is False
    assert json.loads((fig2 / "r.json").read_text())["converged"] is False


@pytest.mark.parametrize("std", [None, "0.01"])
def test_correct_data_still_converge(fig2, run_cli, std):
    _write(fig2, _rows(), std)
    code, _, err = run_cli("update", fig2 / "study.toml")
    assert code == 0, err


def test_noisy_data_at_their_stated_std_are_accepted(fig2, run_cli):
    """Data simulated with 0.01 Hz noise and std 0.01 Hz: a correct model is rejected
    with probability <= 2 ALPHA = 2e-4 per seed; 5 fixed seeds."""
    (fig2 / "truth.toml").write_text((FIG2 / "truth.toml").read_text())
    text = (fig2 / "study.toml").read_text().replace('method = "least-squares"',
                                                      'method = "weighted-least-squares"')
    (fig2 / "study.toml").write_text(text)
    for seed in range(5):
        assert run_cli("simulate", fig2 / "truth.toml", "-o", fig2 / "measured.csv",
                       "--noise-hz", "0.01", "--seed", seed)[0] == 0
        code, _, err = run_cli("update", fig2 / "study.toml")
        assert code == 0, (seed, err)


def test_chi_square_against_closed_form():
    """chi2 = sum z^2 by hand; limits are scipy's quantiles at ALPHA (independent: the
    chi-square with 2 dof has the closed-form quantile -2 ln ALPHA)."""
    m = {("a", k): Measurement("a", k, f, s) for k, f, s in [(1, 10.0, 0.1), (2, 20.0, None),
                                                              (3, 30.0, 0.2)]}
    upd = np.array([10.05, 20.0 * (1 + 3 * DEFAULT_RELATIVE_STD), 29.9])
    c = residual_consistency([("a", 1), ("a", 2), ("a", 3)], np.array([10.0, 20.0, 30.0]),
                             upd, m, rank=1)
    assert c.dof == 2 and c.assumed == 1
    assert c.chi2 == pytest.approx(0.5 ** 2 + 3 ** 2 + 0.5 ** 2, rel=1e-9)
    assert c.chi2_limit == pytest.approx(-2 * np.log(ALPHA), rel=1e-9)
    assert not c.rejected  # 9.5 < 18.4; |z| = 3 < 4.0
    assert residual_consistency([("a", 1)], np.array([1.0]), np.array([1.0]),
                                {("a", 1): Measurement("a", 1, 1.0, 0.1)}, rank=1) is None


SPRING = """
[[perturbation]]
name = "spring at 2"
coordinate = 2
stiffness = 2e5
"""


def test_added_stiffness_cannot_lower_a_grounded_structure(fig2, run_cli):
    """Fig. 2 is grounded (k1 to ground): no rigid-body mode, so a grounded spring can
    only raise each eigenvalue. A measured mode below the bare one was accepted before
    (the bound allowed for rigid-body modes the structure does not have)."""
    text = (fig2 / "study.toml").read_text().replace("[measurement]", SPRING + "[measurement]")
    (fig2 / "study.toml").write_text(text)
    (fig2 / "truth.toml").write_text((FIG2 / "truth.toml").read_text().replace(
        "[measurement]", SPRING + "[measurement]"))
    assert run_cli("simulate", fig2 / "truth.toml", "-o", fig2 / "sim.csv")[0] == 0
    rows = list(csv.DictReader(open(fig2 / "sim.csv", newline="")))
    base = {r["mode"]: float(r["frequency_hz"]) for r in rows if r["configuration"] == "base"}
    for r in rows:
        if r["configuration"] == "spring at 2" and r["mode"] == "2":
            r["frequency_hz"] = repr(base["2"] - 0.5)  # 0.5 Hz below the bare structure
    _write(fig2, rows, None)
    code, _, err = run_cli("update", fig2 / "study.toml")
    assert code == 2
    assert "added stiffness cannot lower an eigenvalue" in err and "'spring at 2'" in err
