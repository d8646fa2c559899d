"""Can the data tell which configuration each measured value of a mode belongs to?

The ordering laws (:mod:`eigenupdate.identify.plausibility`) catch a mode exchanged with
the bare structure, and the chi-square test (:mod:`eigenupdate.identify.consistency`)
catches an exchange that the model cannot fit. What is left is an exchange between two
perturbed configurations that the model fits within noise: on the paper's Fig. 2 system
(12 equations, 10 parameters), mode 1 or 2 of '0.35 kg at 1' and '0.35 kg at 4'
exchanged converges, passes the chi-square test, and gives masses 16-154 % wrong.

The test: for each mode and each pair of configurations whose measured values differ by
more than :data:`N_STD` combined std (values equal within noise make an exchange
change nothing), fit the model again with the two values exchanged. If that labelling
also converges, passes the same chi-square test, and fits at least as well as the first
(chi-square no larger), the data do not prefer the first labelling, and it may not be
reported as the answer.

Why "at least as well" and not "also passes": the question is symmetric. Whenever an
exchanged data set's wrong fit passes the chi-square test, the correct data's
exchanged labelling passes it too, with the same statistic: on the shipped Fig. 2 data
the exchange of mode 1 of '0.35 kg at 1' and '0.35 kg at 4' fits with chi-square 18.4
(limit 18.42, no std) or 4.4 (std 0.01 Hz), so "also passes" would refuse the correct
data as well. Between two labellings with the same parameters, the Gaussian likelihoods
differ by exp(-delta chi-square / 2): the rule keeps the more likely labelling
(maximum likelihood), and it refuses every error-free exchange, whose exchanged-back
labelling fits exactly. With noise, two labellings separated by d std in the data are
confused with probability about Phi(-d / 2), either way; the message gives both
statistics.

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

from eigenupdate.errors import InputError, NumericalError
from eigenupdate.identify.consistency import DEFAULT_RELATIVE_STD, residual_consistency
from eigenupdate.identify.updating import UpdateResult, update
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

    def message(self) -> str:
        return (f"mode {self.mode} of {self.a!r} and {self.b!r} may be exchanged: both "
                f"labellings fit the data, the exchanged one at least as well (chi-square "
                f"{self.chi2[1]:.3g} against {self.chi2[0]:.3g} for {self.dof} degrees of "
                f"freedom); {self.parameter} "
                f"differs by {100 * self.difference:.0f} % between the two fits")


@dataclass(frozen=True)
class ExchangeTest:
    """Outcome of :func:`exchange_test`: the first ambiguous exchange found (or None),
    the exchanges refitted, and those not refitted beyond :data:`MAX_REFITS`."""

    ambiguous: Exchange | None
    refitted: int
    skipped: int


def _std(m: Measurement) -> float:
    return m.std_hz or DEFAULT_RELATIVE_STD * abs(m.frequency_hz)


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
    refitted, spent = 0, 0
    budget = np.inf if model.n <= DENSE_LIMIT else COST_SPARSE * fit.nfev
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
        first, other = fit.x, res.x
        rel = np.abs(other - first) / np.maximum(np.abs(first), np.finfo(float).tiny)
        j = int(np.argmax(rel))
        return ExchangeTest(
            Exchange(a, b, k, (chi2, np.nan if test is None else test.chi2),
                     0 if test is None else test.dof, fit.names[j], float(rel[j]),
                     dict(zip(res.names, res.x.tolist(), strict=True))),
            refitted, n_all - refitted)
    return ExchangeTest(None, refitted, n_all - refitted)
