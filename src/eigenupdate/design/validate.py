"""``design --validate N``: a Monte Carlo of the designed plan beside its prediction."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from eigenupdate.design.montecarlo import MonteCarloResult, TrialSetup, montecarlo, noise_std
from eigenupdate.design.plan import DesignResult
from eigenupdate.design.spec import DesignSpec
from eigenupdate.model.configurations import BASE, Configuration
from eigenupdate.model.parametric import ParametricModel


@dataclass(frozen=True)
class Validation:
    """Predicted against empirical accuracy of the designed plan.

    Attributes
    ----------
    names : updated parameters.
    predicted_std, predicted_error : the design's prediction over the prior and its Monte
        Carlo standard error.
    linear_std : linearised std at the prior mean.
    empirical_std : std of (estimate - truth) over the converged trials (None: too few).
    coverage_2std : fraction of converged trials within 2 reported std of the truth.
    predicted_gross_risk : the chance of a gross error predicted for the plan: by checked
        virtual tests at draws of the prior
        (:func:`eigenupdate.design.montecarlo.predict_gross`), else the design's
        crowding risk.
    montecarlo : the trials themselves.
    empirical_gross_risk : fraction of the trials that did not converge, were refused or
        were caught by the checks.
    """

    names: list[str]
    predicted_std: np.ndarray
    predicted_error: np.ndarray
    linear_std: np.ndarray
    empirical_std: np.ndarray | None
    coverage_2std: np.ndarray | None
    predicted_gross_risk: float | None
    montecarlo: MonteCarloResult
    empirical_gross_risk: float | None = None


def validate_design(model: ParametricModel, spec: DesignSpec, result: DesignResult,
                    method: str, trials: int, max_iterations: int, tolerance: float,
                    seed: int | None = 0, executor=None, progress=None,
                    optimizer: str = "trust-region") -> Validation:
    """Run ``trials`` virtual tests of the designed plan (truth drawn from the prior, noise
    as the [design] table states, updated as the study updates) and set their spread
    beside the design's prediction."""
    configs = (Configuration(BASE), *result.configurations)
    modes = tuple(result.modes)
    std = noise_std(model, configs, modes, None, spec, "design")
    setup = TrialSetup(model, configs, modes, std, method, max_iterations, tolerance,
                       optimizer=optimizer)
    mc = montecarlo(setup, trials, seed=seed, executor=executor, progress=progress)
    plan = result.plans[0]
    names = result.names
    ok = [t for t in mc.trials if t["converged"]]
    emp = cover = None
    if len(ok) >= 2:
        err = np.array([t["estimate"] - t["truth"] for t in ok])
        rep = np.array([t["std"] for t in ok])
        emp = err.std(axis=0, ddof=1)
        cover = np.mean(np.abs(err) <= 2 * rep, axis=0)
    return Validation(names, np.array([plan.std[n] for n in names]),
                      np.array([plan.std_error[n] for n in names]),
                      np.array([plan.linear_std[n] for n in names]), emp, cover,
                      plan.gross_risk if mc.gross is None else mc.gross.fraction, mc,
                      1.0 - len(ok) / len(mc.trials))
