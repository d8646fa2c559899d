"""Can the data tell which configuration each measured value of a mode belongs to?

The ordering laws (:mod:`eigenupdate.identify.plausibility`) catch a mode exchanged with
the bare structure, and the chi-square test (:mod:`eigenupdate.identify.consistency`)
catches an exchange that the model cannot fit. What is left is an exchange between two
perturbed configurations that the model fits within noise: on the paper's Fig. 2 system
(12 equations, 10 parameters), mode 1 or 2 of '0.35 kg at 1' and '0.35 kg at 4'
exchanged converges, passes the chi-square test, and gives masses 16-154 % wrong.

The test: for each mode and each pair of configurations whose measured values differ by
more than :data:`N_STD` combined std (values equal within noise make an exchange
change nothing), fit the model again with the two values exchanged, and compare the two
fits' chi-square statistics (:mod:`eigenupdate.identify.consistency`),
Delta = chi2_exchanged - chi2_first.

The rule is maximum likelihood: the update is refused when Delta <= 0 (the exchanged
labelling fits at least as well) and the exchanged fit's estimate lies outside the first
fit's confidence ellipsoid at :data:`eigenupdate.identify.consistency.ALPHA_DISTINCT`
(:func:`eigenupdate.identify.consistency.distance`): an exchange whose answer agrees with
the first within its stated uncertainty changes nothing a user reads, and is counted as
harmless instead. The error probabilities are stated with the rule. Linearised at the
first fit, the two labellings are d std apart: d is the norm of the exchange's change
of the data (in std) orthogonal to what the parameters (and the Bayesian prior
rows) can absorb, :func:`separation`. With Gaussian noise, Delta ~ N(d^2, (2d)^2) when
the first labelling is right and N(-d^2, (2d)^2) when the exchanged one is, so correct
data are refused, and exchanged data pass, each with probability Phi(-d/2); the message
gives d and that probability. Why not a rule with a fixed significance ALPHA for the
exchanged data (refuse unless Delta >= 2 d z_ALPHA - d^2): Fig. 2's plan (12 equations,
10 parameters) absorbs most of an exchange, d = 1.4-2.2 std for four candidates at
0.01 Hz, and at ALPHA = 0.01 it refused 18 of 20 correct noisy data sets; error-free
data (Delta = d^2) would be refused whenever d < z_ALPHA = 2.33. Such a plan cannot
separate the labellings; the chance that its tests end refused is counted in the
predicted chance of a gross error (:func:`eigenupdate.design.montecarlo.predict_gross`).

The refit starts from the study's initial model with the study's estimator and
optimiser, not from the first fit: the first fit is the attractor of its own labelling,
and the other labelling's fit is far away (on Fig. 2, ten Gauss-Newton steps from the
first fit did not reach it in one of the cases; from the initial model each converged
in 4 iterations, as the first fit did). It also keeps the Bayesian prior anchored at the
initial estimates. A refit counts once it fits as well, converged or stopped by the
iteration limit (its model is then a witness).

Cost: one update per candidate exchange, closest pairs (in std) first, each with the
study's iteration limit; at most :data:`MAX_REFITS` of them, together at most
on sparse models :data:`COST_SPARSE` times the first fit's eigen-solutions (the rest are
counted in the message); exchanges that break an ordering
law are refused before any solve; the test stops at the first ambiguous exchange.
Measured (the fit alone / with the checks, best of 3): Fig. 2 0.016 / 1.04 s (every
candidate), the paper's beam 0.036 / 0.88 s (24 of 73).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np
import scipy.stats

from eigenupdate.errors import InputError, NumericalError
from eigenupdate.identify.consistency import (
    DEFAULT_RELATIVE_STD,
    distance,
    residual_consistency,
    stated_covariance,
)
from eigenupdate.identify.updating import UpdateResult, update
from eigenupdate.identify.weights import prior_weights
from eigenupdate.measure.measurement import Measurement
from eigenupdate.model.configurations import Configuration
from eigenupdate.model.parametric import ParametricModel
from eigenupdate.solve.eigen import DENSE_LIMIT

N_STD = 3.0
"""Exchanges of values closer than this many combined std are not tested."""

MAX_REFITS = 24
"""At most this many exchanges are refitted (each one full update)."""
COST_SPARSE = 3
"""On models solved by the sparse path (over DENSE_LIMIT coordinates), where one fit
takes seconds to minutes, the refits together may take at most COST_SPARSE times the
first fit's eigen-solutions; the exchanges not reached are counted in the message. Small
(dense) models refit every candidate up to MAX_REFITS: a budget in eigen-solutions there
made which exchange was reached depend on the iteration counts, which differ between
BLAS kernels (on Fig. 2 the Prescott kernel spent 121 of 120 before the exchange that
the others reached)."""


@dataclass(frozen=True)
class Exchange:
    """Two labellings that both fit: mode ``mode`` of configurations ``a`` and ``b``
    exchanged fits at least as well as the first labelling (``chi2``: first, exchanged)."""

    a: str
    b: str
    mode: int
    chi2: tuple[float, float]
    dof: int
    parameter: str
    difference: float
    """Largest relative difference of an updated parameter between the two fits."""
    exchanged: dict[str, float]
    """Updated parameters of the exchanged labelling's fit, by name."""
    separation: float = float("inf")
    """d: the two labellings' separation in std, linearised at the first fit."""

    def message(self) -> str:
        p = float(scipy.stats.norm.cdf(-self.separation / 2))
        return (f"mode {self.mode} of {self.a!r} and {self.b!r} may be exchanged: both "
                f"labellings fit the data, the exchanged one at least as well (chi-square "
                f"{self.chi2[1]:.3g} against {self.chi2[0]:.3g} for {self.dof} degrees of "
                f"freedom; the labellings are {self.separation:.2g} std apart, so the "
                f"more likely one is the wrong one with probability {p:.2g}); {self.parameter} "
                f"differs by {100 * self.difference:.0f} % between the two fits")


@dataclass(frozen=True)
class ExchangeTest:
    """Outcome of :func:`exchange_test`: the first ambiguous exchange found (or None),
    the exchanges refitted, and those not refitted beyond :data:`MAX_REFITS`."""

    ambiguous: Exchange | None
    refitted: int
    skipped: int
    harmless: int = 0
    """Exchanges that fit as well but whose estimate lies inside the first fit's
    confidence ellipsoid: the labelling does not change the answer."""


def _std(m: Measurement) -> float:
    return m.std_hz or DEFAULT_RELATIVE_STD * abs(m.frequency_hz)


def separation(J: np.ndarray, measured_hz: np.ndarray, std_hz: np.ndarray,
               prior: np.ndarray, i: int, j: int) -> float:
    """d of exchanging the values of rows ``i`` and ``j`` (see the module): the exchange's
    change of the eigenvalue data in std, orthogonal to the columns of the weighted
    Jacobian ``J`` (normalised parameters) stacked on the prior rows ``diag(prior)``.

    Rows 0 and 1 exchanged, the parameter moving row 2 only: nothing absorbs the change,
    d = |delta lambda| sqrt(1 / s_0^2 + 1 / s_1^2), s_i = 8 pi^2 f_i sigma_f:

    >>> f, s = np.array([10.0, 11.0, 12.0]), np.full(3, 0.01)
    >>> d = separation(np.array([[0.0], [0.0], [1.0]]), f, s, np.zeros(1), 0, 1)
    >>> dl = (2 * np.pi) ** 2 * (11.0 ** 2 - 10.0 ** 2)
    >>> bool(np.isclose(d, dl * np.hypot(1 / (8 * np.pi**2 * 0.1), 1 / (8 * np.pi**2 * 0.11))))
    True
    """
    lam = (2 * np.pi * measured_hz) ** 2
    s_lam = 8 * np.pi ** 2 * measured_hz * std_hz
    delta = np.zeros(lam.size + prior.size)
    delta[i] = (lam[j] - lam[i]) / s_lam[i]
    delta[j] = (lam[i] - lam[j]) / s_lam[j]
    A = np.vstack([J / s_lam[:, None], np.diag(prior)])
    coef = np.linalg.lstsq(A, delta, rcond=None)[0]
    return float(np.linalg.norm(delta - A @ coef))


def candidates(configurations: Sequence[Configuration], modes: Sequence[int],
               measurements: Mapping[tuple[str, int], Measurement], n_std: float = N_STD
               ) -> list[tuple[float, int, str, str]]:
    """(separation in std, mode, a, b) of every exchange that changes the data by more
    than ``n_std`` combined std, closest first.

    Examples
    --------
    >>> from eigenupdate.model.configurations import Configuration
    >>> m = {(c, 1): Measurement(c, 1, f, 0.01) for c, f in [("a", 10.0), ("b", 10.02),
    ...                                                      ("c", 10.5)]}
    >>> [(k, a, b) for _, k, a, b in candidates([Configuration(n) for n in "abc"], [1], m)]
    [(1, 'b', 'c'), (1, 'a', 'c')]
    """
    out = []
    for k in sorted(set(modes)):
        for ca, cb in itertools.combinations(configurations, 2):
            ma, mb = measurements[(ca.name, k)], measurements[(cb.name, k)]
            sep = abs(ma.frequency_hz - mb.frequency_hz) / math.hypot(_std(ma), _std(mb))
            if sep > n_std:
                out.append((sep, k, ca.name, cb.name))
    return sorted(out)


def exchange_test(
    model: ParametricModel,
    configurations: Sequence[Configuration],
    modes: Sequence[int],
    measurements: Mapping[tuple[str, int], Measurement],
    fit: UpdateResult,
    chi2: float,
    *,
    method: str,
    optimizer: str,
    max_iterations: int,
    xtol: float,
    max_refits: int = MAX_REFITS,
) -> ExchangeTest:
    """Refit each candidate exchange (see the module) after a converged fit ``fit``
    whose chi-square statistic is ``chi2``; the arguments are those of the first fit."""
    todo = candidates(configurations, modes, measurements)
    n_all, todo = len(todo), todo[:max_refits]
    refitted, spent, harmless = 0, 0, 0
    budget = np.inf if model.n <= DENSE_LIMIT else COST_SPARSE * fit.nfev
    index = {r: i for i, r in enumerate(fit.rows)}
    std_hz = np.array([_std(measurements[r]) for r in fit.rows])
    if todo:
        jn, cov = stated_covariance(model, configurations, modes, fit, measurements, method)
        prior = prior_weights(model) if method == "bayesian" else np.zeros(jn.shape[1])
    for _, k, a, b in todo:
        if spent >= budget:
            break
        swapped = dict(measurements)
        ma, mb = measurements[(a, k)], measurements[(b, k)]
        swapped[(a, k)] = replace(ma, frequency_hz=mb.frequency_hz, std_hz=mb.std_hz)
        swapped[(b, k)] = replace(mb, frequency_hz=ma.frequency_hz, std_hz=ma.std_hz)
        refitted += 1
        try:
            res = update(model, configurations, modes, swapped, method=method,
                         optimizer=optimizer, max_iterations=max_iterations, xtol=xtol)
        except (InputError, NumericalError):
            continue  # the exchanged values break an ordering law, or cannot be fitted
        spent += res.nfev
        # a refit stopped by its iteration limit still counts if it already fits as well:
        # its model is a witness that the exchanged labelling fits the data
        test = residual_consistency(res.rows, res.measured_hz, res.updated_hz, swapped,
                                    res.identifiability.rank,
                                    model=model if method == "bayesian" else None,
                                    updated=res.parameters)
        if test is not None and (test.rejected or test.chi2 > chi2):
            continue
        if np.all(np.isfinite(res.x)):
            d2, limit = distance(fit.x, cov, res.x)
            if d2 <= limit:
                harmless += 1
                continue  # both labellings give one answer within its confidence region
        d = separation(jn, fit.measured_hz, std_hz, prior, index[(a, k)], index[(b, k)])
        first, other = fit.x, res.x
        rel = np.abs(other - first) / np.maximum(np.abs(first), np.finfo(float).tiny)
        j = int(np.argmax(rel))
        return ExchangeTest(
            Exchange(a, b, k, (chi2, np.nan if test is None else test.chi2),
                     0 if test is None else test.dof, fit.names[j], float(rel[j]),
                     dict(zip(res.names, res.x.tolist(), strict=True)), d),
            refitted, n_all - refitted, harmless)
    return ExchangeTest(None, refitted, n_all - refitted, harmless)
