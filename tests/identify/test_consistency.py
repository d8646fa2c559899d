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
from eigenupdate.measure.measurement import Measurement

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
    assert doc["success"] is False
    assert json.loads((fig2 / "r.json").read_text())["success"] is False


@pytest.mark.parametrize("std", [None, "0.01"])
def test_correct_data_still_converge(fig2, run_cli, std):
    _write(fig2, _rows(), std)
    code, _, err = run_cli("update", fig2 / "study.toml")
    assert code == 0, err


def test_noisy_data_at_their_stated_std_are_accepted(fig2, run_cli):
    """Data simulated with 0.01 Hz noise and std 0.01 Hz: the chi-square test rejects a
    correct model with probability <= 2 ALPHA = 2e-4 per seed. The exchange test refuses
    it where an exchanged labelling fits at least as well, which at this std happens
    (Fig. 2's mode 1 of '0.35 kg at 1' and '0.35 kg at 4' are only 2.1 std apart as
    labellings: 5 of seeds 0-19 are refused). Seeds 0-4 are kept, each with the best
    exchanged labelling's chi-square at least 1.3 above the fit's (not a round-off
    margin)."""
    (fig2 / "truth.toml").write_text((FIG2 / "truth.toml").read_text())
    text = (fig2 / "study.toml").read_text().replace('method = "least-squares"',
                                                      'method = "weighted-least-squares"')
    (fig2 / "study.toml").write_text(text)
    for seed in range(5):
        assert run_cli("simulate", fig2 / "truth.toml", "-o", fig2 / "measured.csv",
                       "--noise-hz", "0.01", "--seed", seed, "--force")[0] == 0
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
    rows = list(csv.DictReader(ln for ln in open(fig2 / "sim.csv", newline="")
                               if not ln.startswith("#")))
    base = {r["mode"]: float(r["frequency_hz"]) for r in rows if r["configuration"] == "base"}
    for r in rows:
        if r["configuration"] == "spring at 2" and r["mode"] == "2":
            r["frequency_hz"] = repr(base["2"] - 0.5)  # 0.5 Hz below the bare structure
    _write(fig2, rows, None)
    code, _, err = run_cli("update", fig2 / "study.toml")
    assert code == 2
    assert "added stiffness cannot lower an eigenvalue" in err and "'spring at 2'" in err


PERTURBED = ("0.35 kg at 1", "0.35 kg at 2", "0.35 kg at 4")
SWAPS = [(k, a, b) for k in ("1", "2", "3") for i, a in enumerate(PERTURBED)
         for b in PERTURBED[i + 1:]]


@pytest.mark.parametrize("std", [None, "0.01"])
@pytest.mark.parametrize("swap", SWAPS, ids=["-".join(s) for s in SWAPS])
def test_no_exchange_between_perturbed_configurations_converges(fig2, run_cli, std, swap):
    """All 9 single-mode exchanges between the perturbed configurations of Fig. 2
    (error-free data): each is refused by the chi-square test, the exchange test or the
    iteration limit (exit 1). Before the exchange test, mode 1 and mode 2 of
    '0.35 kg at 1' / '0.35 kg at 4' (and, with std, mode 1 of '0.35 kg at 2' /
    '0.35 kg at 4') converged, passed the chi-square test, exit 0."""
    k, a, b = swap
    _write(fig2, _exchange(_rows(), k, a, b), std)
    code, out, err = run_cli("update", fig2 / "study.toml", "--json")
    assert code == 1, err
    assert json.loads(out)["success"] is False


@pytest.mark.parametrize("std", [None, 0.01])
@pytest.mark.parametrize("mode", [1, 2])
def test_exchange_test_finds_the_true_labelling(std, mode):
    """The exchanged data's wrong fit passes the chi-square test; the exchange test
    finds the exchange, and its refit is the truth (truth.toml: the data are
    error-free, so the true labelling fits to the update's xtol 1e-8; 1e-6 allows the
    conditioning of J, cond < 1e2 here)."""
    from dataclasses import replace as dc_replace

    from eigenupdate.identify.exchange import exchange_test
    from eigenupdate.identify.updating import update
    from eigenupdate.io.study import load_study

    study = load_study(FIG2 / "study.toml")
    truth = load_study(FIG2 / "truth.toml").model
    a, b = "0.35 kg at 1", "0.35 kg at 4"
    meas = {key: dc_replace(m, std_hz=std) for key, m in study.measurements().items()}
    meas[(a, mode)], meas[(b, mode)] = (dc_replace(meas[(a, mode)],
                                                   frequency_hz=meas[(b, mode)].frequency_hz),
                                        dc_replace(meas[(b, mode)],
                                                   frequency_hz=meas[(a, mode)].frequency_hz))
    kw = dict(method=study.method, optimizer=study.optimizer,
              max_iterations=study.max_iterations, xtol=study.tolerance)
    fit = update(study.model, study.configurations, study.modes, meas, **kw)
    c = residual_consistency(fit.rows, fit.measured_hz, fit.updated_hz, meas,
                             fit.identifiability.rank)
    assert fit.success and not c.rejected  # what the exchange test is for
    wrong = max(abs(fit.parameters[n] / truth.values[truth.names.index(n)] - 1)
                for n in fit.names)
    assert wrong > 0.1
    found = exchange_test(study.model, study.configurations, study.modes, meas, fit, c.chi2,
                          **kw).ambiguous
    assert found is not None and {found.a, found.b} == {a, b} and found.mode == mode
    assert found.chi2[1] <= found.chi2[0]
    # the largest difference between the two fits is the wrong fit's error (relative to it)
    assert found.difference == pytest.approx(max(
        abs(truth.values[truth.names.index(n)] / fit.parameters[n] - 1) for n in fit.names),
        rel=1e-5)
    for n, v in found.exchanged.items():
        assert v == pytest.approx(truth.values[truth.names.index(n)], rel=1e-6), n


def test_exchange_test_cost_is_bounded():
    """Correct Fig. 2 data: no exchange fits as well; with max_refits = 2 only the two
    closest candidates are refitted and the rest counted as not tested."""
    from eigenupdate.identify.exchange import candidates, exchange_test
    from eigenupdate.identify.updating import update
    from eigenupdate.io.study import load_study

    study = load_study(FIG2 / "study.toml")
    meas = study.measurements()
    kw = dict(method=study.method, optimizer=study.optimizer,
              max_iterations=study.max_iterations, xtol=study.tolerance)
    fit = update(study.model, study.configurations, study.modes, meas, **kw)
    chi2 = residual_consistency(fit.rows, fit.measured_hz, fit.updated_hz, meas,
                                fit.identifiability.rank).chi2
    n = len(candidates(study.configurations, study.modes, meas))
    assert n > 2
    t = exchange_test(study.model, study.configurations, study.modes, meas, fit, chi2,
                      max_refits=2, **kw)
    assert (t.ambiguous, t.refitted, t.skipped) == (None, 2, n - 2)
    assert exchange_test(study.model, study.configurations, study.modes, meas, fit, chi2,
                         **kw).ambiguous is None
