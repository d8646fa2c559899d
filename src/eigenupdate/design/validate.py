"""``design --validate N``: a Monte Carlo of the designed plan beside its prediction."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from eigenupdate.design.montecarlo import (
    GROSS_DRAWS,
    MonteCarloResult,
    TrialSetup,
    montecarlo,
    noise_std,
    std_with_error,
)
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
    predicted_std, predicted_error : the prediction over the prior and its standard
        error: the spread of checked virtual tests at draws of the prior where at least
        MIN_CONVERGED of them converged, else the design's linearised std averaged over
        the prior (``prior_std``).
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
    prior_std : the design's linearised std averaged over the prior.
    empirical_error : standard error of ``empirical_std`` (kurtosis-aware).
    virtual_tests : checked virtual tests behind ``predicted_std`` (0: it is
        ``prior_std``).
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
    prior_std: np.ndarray | None = None
    empirical_error: np.ndarray | None = None
    virtual_tests: int = 0

    def ratio_interval(self, z: float = 1.96) -> np.ndarray | None:
        """(p, 3) empirical / predicted std with its lower and upper bound at ``z``
        standard errors (delta method, the two independent)."""
        if self.empirical_std is None:
            return None
        r = self.empirical_std / self.predicted_std
        se = r * np.hypot(self.empirical_error / self.empirical_std,
                          self.predicted_error / self.predicted_std)
        return np.column_stack([r, r - z * se, r + z * se])


def validate_design(model: ParametricModel, spec: DesignSpec, result: DesignResult,
                    method: str, trials: int, max_iterations: int, tolerance: float,
                    seed: int | None = 0, executor=None, progress=None,
                    optimizer: str = "trust-region", virtual_tests: int | None = None
                    ) -> Validation:
    """Run ``trials`` virtual tests of the designed plan (truth drawn from the prior, noise
    as the [design] table states, updated as the study updates) and set their spread
    beside the design's prediction: the spread of ``virtual_tests`` checked virtual tests
    at draws of the prior (another seed stream; default as many as ``trials``, at least
    :data:`eigenupdate.design.montecarlo.GROSS_DRAWS`), else the linearised std averaged
    over the prior."""
    configs = (Configuration(BASE), *result.configurations)
    modes = tuple(result.modes)
    std = noise_std(model, configs, modes, None, spec, "design")
    setup = TrialSetup(model, configs, modes, std, method, max_iterations, tolerance,
                       optimizer=optimizer)
    n_virtual = max(trials, GROSS_DRAWS) if virtual_tests is None else virtual_tests
    mc = montecarlo(setup, trials, seed=seed, executor=executor, progress=progress,
                    virtual_tests=n_virtual)
    plan = result.plans[0]
    names = result.names
    ok = [t for t in mc.trials if t["converged"]]
    emp = emp_se = cover = None
    if len(ok) >= 2:
        err = np.array([t["estimate"] - t["truth"] for t in ok])
        rep = np.array([t["std"] for t in ok])
        emp, emp_se = std_with_error(err)
        cover = np.mean(np.abs(err) <= 2 * rep, axis=0)
    prior_std = np.array([plan.std[n] for n in names])
    prior_se = np.array([plan.std_error[n] for n in names])
    checked = mc.gross is not None and mc.gross.std is not None
    return Validation(names, mc.gross.std if checked else prior_std,
                      mc.gross.std_of_std if checked else prior_se,
                      np.array([plan.linear_std[n] for n in names]), emp, cover,
                      plan.gross_risk if mc.gross is None else mc.gross.fraction, mc,
                      1.0 - len(ok) / len(mc.trials), prior_std, emp_se,
                      mc.gross.draws if checked else 0)
