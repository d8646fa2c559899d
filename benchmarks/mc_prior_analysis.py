"""Why predicted and empirical std differ (issue 22): the Monte Carlo of
``mc_prior_cases.py`` with, per converged trial, the linearised posterior variance at its
own truth, so the comparison separates sampling error, selection by the checks and the
estimator's nonlinearity.

    .venv/bin/python benchmarks/mc_prior_analysis.py TRIALS {beam,fig2,network} PRIOR [SEED]

Prints per parameter: the empirical std with a bootstrap 90 % interval, the design's
prediction with its standard error, sqrt(mean C(s)) over the converged trials' truths
(what linearisation at each truth predicts for exactly those trials), the same over all
trials, and the robust spread (1.4826 MAD) and kurtosis of the errors.
"""

from __future__ import annotations

import sys
import time

import numpy as np
from mc_prior_cases import ROOT, random_network, with_prior  # noqa: F401

from eigenupdate.design.plan import design_plan
from eigenupdate.design.validate import validate_design
from eigenupdate.design.prior import linear_variances
from eigenupdate.design.spec import DesignSpec
from eigenupdate.io.study import load_study


def case_model(case: str, prior: float):
    if case == "network":
        model = random_network(np.random.default_rng(0), 6)
        spec = DesignSpec(coordinates=(1, 2, 3, 4, 5, 6), masses=(1.0, 2.0, 5.0),
                          configurations=3, modes=(1, 2, 3, 4),
                          frequency_std_hz=(0.01,) * 4, prior_draws=64)
        iters, tol, opt = 20, 1e-8, "trust-region"
    else:
        st = load_study(ROOT / "examples" / ("paper_beam" if case == "beam" else "paper_fig2")
                        / "study.toml")
        model, spec = st.model, st.design
        iters, tol, opt = st.max_iterations, st.tolerance, st.optimizer
    return with_prior(model, prior), spec, iters, tol, opt


def main() -> None:
    trials, case, prior = int(sys.argv[1]), sys.argv[2], float(sys.argv[3])
    seed = int(sys.argv[4]) if len(sys.argv) > 4 else 0
    model, spec, iters, tol, opt = case_model(case, prior)
    res = design_plan(model, spec, "bayesian")
    t0 = time.perf_counter()
    v = validate_design(model, spec, res, "bayesian", trials, iters, tol, seed, optimizer=opt)
    dt = time.perf_counter() - t0
    mc = v.montecarlo
    ok = [t for t in mc.trials if t["converged"]]
    print(f"== {case} prior {prior} seed {seed}: plan {res.plans[0].configurations}; "
          f"{len(mc.trials)} trials + {mc.gross.draws} in {dt:.0f} s; converged {len(ok)}")
    from eigenupdate.design.montecarlo import noise_std
    from eigenupdate.model.configurations import BASE, Configuration
    configs = (Configuration(BASE), *res.configurations)
    std = noise_std(model, configs, tuple(res.modes), None, spec, "design")
    upd = model.updated
    full = []
    for t in mc.trials:
        vals = model.values.copy()
        vals[upd] = t["truth"]
        full.append(vals)
    var = linear_variances(model, configs, tuple(res.modes), std, "bayesian", full)
    conv = np.array([t["converged"] for t in mc.trials])
    err = np.array([t["estimate"] - t["truth"] for t in ok])
    rng = np.random.default_rng(1)
    boot = np.array([err[rng.integers(0, len(ok), len(ok))].std(axis=0, ddof=1)
                     for _ in range(2000)])
    lo, hi = np.quantile(boot, [0.05, 0.95], axis=0)
    emp = err.std(axis=0, ddof=1)
    c_ok = np.sqrt(var[conv].mean(axis=0))
    c_all = np.sqrt(var.mean(axis=0))
    mad = 1.4826 * np.median(np.abs(err - np.median(err, axis=0)), axis=0)
    z = err / np.sqrt(var[conv])
    kurt = (((err - err.mean(0)) / emp) ** 4).mean(axis=0)
    print("   name  emp [90% boot]  pred+-se  lin@truths(conv) lin@truths(all) "
          "robust  kurt  z_std  z_robust")
    for i, n in enumerate(v.names):
        zi = z[:, i]
        print(f"   {n:4s} emp/pred {emp[i] / v.predicted_std[i]:.2f} "
              f"[{lo[i] / v.predicted_std[i]:.2f},{hi[i] / v.predicted_std[i]:.2f}] "
              f"pred se {v.predicted_error[i] / v.predicted_std[i]:.2f}  "
              f"conv/pred {c_ok[i] / v.predicted_std[i]:.2f} all/pred "
              f"{c_all[i] / v.predicted_std[i]:.2f} robust/pred {mad[i] / v.predicted_std[i]:.2f}"
              f" kurt {kurt[i]:.1f} z_std {zi.std(ddof=1):.2f} "
              f"z_rob {1.4826 * np.median(np.abs(zi - np.median(zi))):.2f}")


if __name__ == "__main__":
    main()
