"""Cost of the dense path on small models (issue 22's checked virtual tests): one
linearisation (every configuration's eigen-solve and sensitivities) and one checked
trial of the designed plan, on the 6-mass network and the paper's Fig. 2 system at a
25 % prior.

    PYTHONPATH=src .venv/bin/python benchmarks/bench_dense.py [TRIALS]

Uses only what main had before the dense path, so the same file times both trees: run
it with PYTHONPATH pointing to each, back to back (OPENBLAS_NUM_THREADS=1 keeps BLAS
threads out of the comparison on a shared machine). Prints the median CPU time per
call (process time: a shared machine's load inflates wall time) and a digest of the
trials' outcomes and estimates, which must be the same on both.
"""

from __future__ import annotations

import hashlib
import sys
import time

import numpy as np
from mc_prior_analysis import case_model

from eigenupdate.design.montecarlo import TrialSetup, noise_std, run_trial
from eigenupdate.design.plan import design_plan
from eigenupdate.model.configurations import BASE, Configuration
from eigenupdate.solve.jacobian import linearise


def _median_time(f, seconds: float = 2.0) -> float:
    times = []
    end = time.process_time() + seconds
    while time.process_time() < end or len(times) < 5:
        t0 = time.process_time()
        f()
        times.append(time.process_time() - t0)
    return float(np.median(times))


def main() -> None:
    trials = int(sys.argv[1]) if len(sys.argv) > 1 else 6
    for case in ("network", "fig2"):
        model, spec, iters, tol, opt = case_model(case, 0.25)
        res = design_plan(model, spec, "bayesian")
        configs = (Configuration(BASE), *res.configurations)
        modes = tuple(res.modes)
        std = noise_std(model, configs, modes, None, spec, "design")
        setup = TrialSetup(model, configs, modes, std, "bayesian", iters, tol, optimizer=opt)
        s = model.values * 1.01
        lin = _median_time(lambda m=model, c=configs, k=modes, v=s: linearise(m, c, k, v))
        t0 = time.process_time()
        out = [run_trial(seed, setup) for seed in np.random.SeedSequence(7).spawn(trials)]
        per = (time.process_time() - t0) / trials
        digest = hashlib.sha256()
        for t in out:
            digest.update(t["outcome"].encode())
            digest.update(np.asarray(t["estimate"]).tobytes())
        print(f"{case:8s} n={model.n} p={len(model.parameters)} configurations "
              f"{len(configs)}: linearise {lin * 1e3:.3f} ms; checked trial {per:.3f} s "
              f"(mean of {trials}); outcomes+estimates sha256 {digest.hexdigest()[:12]}",
              flush=True)


if __name__ == "__main__":
    main()
