"""Predicted against empirical accuracy and chance of a gross error of designed plans, over
priors of a given size (issue 22): the paper's beam, the Fig. 2 system and a random
6-mass network (tests/models.py, seed 0), every updated parameter with a prior std of
PRIOR x its value, the Bayesian method, the plan ``eigenupdate design`` chooses, then
``design --validate TRIALS``.

    .venv/bin/python benchmarks/mc_prior_cases.py TRIALS {beam,fig2,network} PRIOR

Prints the plan, the outcome counts, the gross-error fraction against its prediction,
and per parameter empirical / predicted std over the trials without a gross error.
"""

from __future__ import annotations

import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from eigenupdate.design.plan import design_plan
from eigenupdate.design.spec import DesignSpec
from eigenupdate.design.validate import validate_design
from eigenupdate.io.study import load_study

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))
from models import random_network  # noqa: E402


def with_prior(model, prior: float):
    ps = [replace(p, std=prior * abs(p.value)) if p.update and p.value != 0 else p
          for p in model.parameters]
    return replace(model, parameters=tuple(ps))


def main() -> None:
    trials, case, prior = int(sys.argv[1]), sys.argv[2], float(sys.argv[3])
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
    model = with_prior(model, prior)
    t0 = time.perf_counter()
    res = design_plan(model, spec, "bayesian")
    plan = res.plans[0]
    v = validate_design(model, spec, res, "bayesian", trials, iters, tol, 0, optimizer=opt)
    s = v.montecarlo.summary()
    print(f"== {case} prior {prior}: plan {plan.configurations}; "
          f"{time.perf_counter() - t0:.0f} s")
    print(f"   trials {s['trials']}: converged {s['converged']}, not converged "
          f"{s['not_converged']}, refused {s['refused']}, caught {s['caught']}")
    print(f"   gross fraction {s['gross_error_fraction']:.3f}; predicted "
          f"{s['predicted_gross_error_fraction']:.3f} +- "
          f"{s['predicted_gross_error_fraction_error']:.3f} "
          f"{s['predicted_gross_by_outcome']}; crowding risk {plan.gross_risk}")
    r = v.empirical_std / v.predicted_std
    print(f"   emp/pred over trials without gross error: {r.min():.2f}-{r.max():.2f}; "
          + " ".join(f"{n}:{x:.2f}" for n, x in zip(v.names, r, strict=True)))


if __name__ == "__main__":
    main()
