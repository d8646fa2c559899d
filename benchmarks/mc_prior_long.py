"""A long Monte Carlo of a designed plan against its checked virtual tests (issue 22), for
as long as a wall-time budget allows, each record kept so that the tails can be studied.

    .venv/bin/python benchmarks/mc_prior_long.py {beam,fig2,network} PRIOR MINUTES OUT.pkl

Runs the trials of ``design --validate`` (seed stream 0) and the checked virtual tests
behind the prediction (the GROSS_SEED stream) alternately, one of each at a time, so both
sides hold the same number when the budget runs out; the first k of each are exactly
those ``validate_design(..., trials=k, virtual_tests=k)`` would run. Saves every record
(truth, estimate, reported std, outcome, message) to OUT.pkl every minute and at the end,
then prints the summary of ``mc_prior_report.py``.
"""

from __future__ import annotations

import pickle
import sys
import time

import numpy as np
from mc_prior_analysis import case_model

from eigenupdate.design.montecarlo import TrialSetup, gross_seeds, noise_std, run_trial
from eigenupdate.design.plan import design_plan
from eigenupdate.model.configurations import BASE, Configuration

MOST = 20000  # seeds spawned per stream; the budget stops the run long before


def main() -> None:
    case, prior, minutes, out = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), sys.argv[4]
    model, spec, iters, tol, opt = case_model(case, prior)
    res = design_plan(model, spec, "bayesian")
    configs = (Configuration(BASE), *res.configurations)
    modes = tuple(res.modes)
    std = noise_std(model, configs, modes, None, spec, "design")
    setup = TrialSetup(model, configs, modes, std, "bayesian", iters, tol, optimizer=opt)
    mc_seeds = np.random.SeedSequence(0).spawn(MOST)
    vt_seeds = gross_seeds(MOST)
    doc = {"case": case, "prior": prior, "plan": res.plans[0].configurations,
           "names": res.names, "trials": [], "virtual": [], "seconds": 0.0}
    t0 = last = time.perf_counter()
    for i in range(MOST):
        doc["trials"].append(run_trial(mc_seeds[i], setup))
        doc["virtual"].append(run_trial(vt_seeds[i], setup))
        now = time.perf_counter()
        doc["seconds"] = now - t0
        if now - last > 60 or now - t0 > 60 * minutes:
            with open(out, "wb") as f:
                pickle.dump(doc, f)
            last = now
            print(f"{i + 1} of each in {now - t0:.0f} s", flush=True)
        if now - t0 > 60 * minutes:
            break


if __name__ == "__main__":
    main()
