"""Weights of the three estimators, shared by the update and the identifiability check.

* ``least-squares``: unit weights, no prior (paper Section 5);
* ``weighted-least-squares``: W_lambda = diag(1 / sigma_lambda^2), with
  sigma_lambda = 8 pi^2 f sigma_f from the frequency standard deviations;
* ``bayesian``: W_lambda as above and W_s = diag(1 / sigma_s^2) from the prior standard
  deviations of the parameters (Eq. 6; a parameter without a prior std gets none).

Both are returned as square roots, in parameters normalised by their initial values.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from eigenupdate.choices import ESTIMATORS, OPTIMIZERS
from eigenupdate.errors import InputError
from eigenupdate.measure.measurement import Measurement, eigenvalue_std, select
from eigenupdate.model.parametric import ParametricModel

__all__ = ["ESTIMATORS", "OPTIMIZERS", "EstimatorWeights", "check_estimator", "estimator_weights",
           "prior_weights"]


@dataclass(frozen=True)
class EstimatorWeights:
    """Square roots of the weights: ``rows`` (1 / sigma_lambda per equation, or None for
    unit weights) and ``prior`` (sigma_s0 / sigma_s per updated parameter, or None)."""

    rows: np.ndarray | None
    prior: np.ndarray | None


def check_estimator(method: str) -> str:
    """``method`` if it is one of :data:`ESTIMATORS`, else an InputError."""
    if method not in ESTIMATORS:
        raise InputError(f"unknown method {method!r}; expected one of {', '.join(ESTIMATORS)}",
                         field="updating.method")
    return method


def estimator_weights(
    model: ParametricModel,
    method: str,
    rows: Sequence[tuple[str, int]] | None = None,
    measurements: Mapping[tuple[str, int], Measurement] | None = None,
    source: str | None = None,
) -> EstimatorWeights:
    """Weights of ``method`` for the equations ``rows`` ((configuration, mode) pairs).

    Without ``measurements`` the equations get unit weights (a plan checked before the
    test); the prior of the Bayesian method needs only the model.

    Examples
    --------
    >>> from eigenupdate.model.parameters import Parameter
    >>> from eigenupdate.model.spring_mass import Mass, Spring, spring_mass_model
    >>> model = spring_mass_model([Mass(Parameter("m", 2.0, std=0.5), 1)],
    ...                           [Spring(Parameter("k", 800.0), (0, 1))])
    >>> estimator_weights(model, "bayesian").prior.tolist()   # 2 kg / 0.5 kg; k: none
    [4.0, 0.0]
    """
    check_estimator(method)
    w = None
    if method != "least-squares" and measurements is not None:
        f, s = select(measurements, rows or [], True, source)
        w = 1.0 / eigenvalue_std(f, s)
    prior = None
    if method == "bayesian":
        prior = prior_weights(model)
        if not prior.any():
            raise InputError("the bayesian method needs a std for at least one updated parameter",
                             field="model")
    return EstimatorWeights(w, prior)


def prior_weights(model: ParametricModel) -> np.ndarray:
    """W_s^(1/2) of Eq. 6 in normalised parameters: s_0 / sigma_s of each updated
    parameter, 0 where it has no prior std.

    >>> from eigenupdate.model.parameters import Parameter
    >>> from eigenupdate.model.spring_mass import Mass, Spring, spring_mass_model
    >>> model = spring_mass_model([Mass(Parameter("m", 2.0, std=0.5), 1)],
    ...                           [Spring(Parameter("k", 800.0), (0, 1))])
    >>> prior_weights(model).tolist()
    [4.0, 0.0]
    """
    return np.array([0.0 if model.parameters[j].std is None
                     else model.parameters[j].scale / model.parameters[j].std
                     for j in model.updated])
