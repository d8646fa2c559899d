"""One checked update: the update that ``eigenupdate update`` and every Monte Carlo trial
run, with the checks that decide whether its answer may be reported.

In order:

1. the ordering laws of the measured frequencies (:mod:`eigenupdate.identify.plausibility`,
   with the bare structure's rigid-body count): data that break them are refused
   (InputError) before any fit;
2. the update (:func:`eigenupdate.identify.updating.update`);
3. the chi-square test of its residuals (:mod:`eigenupdate.identify.consistency`): a fit
   the data reject is not converged - unless its tracked modes changed order on the way
   (a "re-paired" note): the start's order pairing of those modes was then wrong for the
   structure, so the fit is run again from its own estimate with the modes paired by
   order there, and taken if the data accept it (one more update; a stiffened plate whose
   near-edge modes 1-2 cross between start and truth: rejected, then the truth,
   tests/identify/test_refit_crossed_modes.py);
4. uniqueness by multi-start (:func:`second_solution`): fits from a few draws of the
   prior; one that passes the same test and lies outside the first fit's confidence
   region at :data:`ALPHA_SECOND` is a second solution the frequencies cannot separate;
5. the exchange test (:mod:`eigenupdate.identify.exchange`): another labelling of the
   measured modes that fits as well.

Each failed check is an :attr:`CheckedUpdate.outcome` of its own, so a Monte Carlo counts
it instead of taking its estimate as a test's result.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np

from eigenupdate.errors import InputError, NumericalError
from eigenupdate.identify.consistency import (
    ALPHA_DISTINCT,
    Consistency,
    distance,
    residual_consistency,
    stated_covariance,
)
from eigenupdate.identify.exchange import MAX_REFITS, ExchangeTest, exchange_test
from eigenupdate.identify.plausibility import check_measured_frequencies
from eigenupdate.identify.updating import UpdateResult, update
from eigenupdate.measure.measurement import Measurement
from eigenupdate.model.configurations import Configuration
from eigenupdate.model.parametric import ParametricModel
from eigenupdate.solve.eigen import DENSE_LIMIT
from eigenupdate.solve.jacobian import solve_configurations

CONVERGED = "converged"
NOT_CONVERGED = "not converged"
REJECTED = "rejected"
SECOND_SOLUTION = "second solution"
EXCHANGE = "exchange"
OUTCOMES = (CONVERGED, NOT_CONVERGED, REJECTED, SECOND_SOLUTION, EXCHANGE)
"""What a checked update can end in; the last three are gross errors of a test that the
checks caught (a refused input raises InputError instead)."""

STARTS = 8
"""Fits from draws of the prior that test a converged fit's uniqueness (dense models with
a prior std on every updated parameter). A basin reached from a fraction q of the prior
is missed with probability (1 - q)^STARTS. On a random 6-mass network with 10 % priors
(tests/identify/test_checked.py) the 6 converged trials of 200 farthest from the truth (4.2-16
reported std) were caught as second solutions by 16 starts, 5 of them by 8, none by 4."""

ALPHA_SECOND = ALPHA_DISTINCT
"""A second fit counts as another solution when it lies outside the first fit's
(1 - ALPHA_SECOND) confidence ellipsoid: (x2 - x1)^T C^-1 (x2 - x1) above the chi-square
quantile with p degrees of freedom (C the first fit's posterior covariance;
:func:`eigenupdate.identify.consistency.distance`)."""


def draw_values(model: ParametricModel, rng: np.random.Generator) -> np.ndarray:
    """All parameter values with the updated ones drawn from their priors N(s_0, sigma_s),
    truncated at 0 (physical values only); fixed parameters keep their values.

    >>> from eigenupdate.model.parameters import Parameter
    >>> from eigenupdate.model.spring_mass import Mass, Spring, spring_mass_model
    >>> m = spring_mass_model([Mass(Parameter("m", 2.0, 0.1), 1)],
    ...                       [Spring(Parameter("k", 800.0, 40.0, update=False), (0, 1))])
    >>> v = draw_values(m, np.random.default_rng(0)); round(float(v[0]), 4), float(v[1])
    (2.0126, 800.0)
    """
    values = model.values.copy()
    for j in model.updated:
        p = model.parameters[j]
        if p.std is None:
            raise InputError(f"parameter {p.name!r} has no std to draw its true value from; "
                             f"give one, or a truth file (--truth)", field="model")
        v = -1.0
        while v < 0:
            v = p.value + p.std * rng.normal()
        values[j] = v
    return values


def has_prior(model: ParametricModel) -> bool:
    """Every updated parameter has a prior std to draw from."""
    return all(model.parameters[j].std is not None for j in model.updated)


@dataclass(frozen=True)
class SecondSolution:
    """A fit from another start that the data accept as well, far from the first.

    ``distance2``: (x2 - x1)^T C^-1 (x2 - x1) with the first fit's covariance, against
    ``limit`` (chi-square quantile at ALPHA_SECOND; C from the stated std,
    :func:`eigenupdate.identify.consistency.stated_covariance`); ``chi2``: first and second fit's
    statistics; ``parameter``/``difference``: the largest relative difference."""

    values: dict[str, float]
    distance2: float
    limit: float
    chi2: tuple[float, float]
    parameter: str
    difference: float

    def message(self) -> str:
        return (f"a second solution fits the data: a fit from a draw of the prior passes "
                f"the chi-square test (chi-square {self.chi2[1]:.3g} against the first fit's "
                f"{self.chi2[0]:.3g}) and lies {np.sqrt(self.distance2):.1f} std (ellipsoid "
                f"radius; limit {np.sqrt(self.limit):.1f} at {ALPHA_SECOND:g}) from it; "
                f"{self.parameter} differs by {100 * self.difference:.0f} %; the frequencies "
                f"cannot tell the two apart: add perturbations or modes, or tighter priors")


@dataclass(frozen=True)
class CheckedUpdate:
    """Outcome of :func:`checked_update`.

    Attributes
    ----------
    result : the update; ``success`` is False and ``message`` says why unless
        ``outcome`` is "converged".
    outcome : one of :data:`OUTCOMES`.
    consistency : the chi-square test of the fit (None: not run, or no degrees of freedom).
    second : the second solution found, if any; ``starts``: fits tried for it.
    exchange : the exchange test (None: not run).
    """

    result: UpdateResult
    outcome: str
    consistency: Consistency | None = None
    second: SecondSolution | None = None
    starts: int = 0
    exchange: ExchangeTest | None = None

    @property
    def gross(self) -> bool:
        """The checks caught a wrong answer (rejected, second solution, exchange)."""
        return self.outcome in (REJECTED, SECOND_SOLUTION, EXCHANGE)


def _crossed(res: UpdateResult) -> str:
    """Where the fit's tracked modes changed order ("configuration modes a, b; ..."), ""
    if nowhere."""
    notes = (res.pairing or {}).get("notes", [])
    return "; ".join(f"{n['configuration']} modes {', '.join(map(str, n['modes']))}"
                     for n in notes if n["kind"] == "re-paired")


def _joined(first: UpdateResult, again: UpdateResult, crossed: str) -> UpdateResult:
    """The refit ``again`` (started at ``first``'s estimate) as one update from the
    study's model: ``first``'s initial frequencies, both histories, iterations, solves
    and pairing notes."""
    later = tuple(replace(h, iteration=h.iteration + first.nit) for h in again.history[1:])
    pairing = dict(again.pairing or {}, notes=[*(first.pairing or {}).get("notes", []),
                                                *(again.pairing or {}).get("notes", [])])
    return replace(again, history=first.history + later, nit=first.nit + again.nit,
                   nfev=first.nfev + again.nfev, initial_hz=first.initial_hz,
                   pairing=pairing, message=(
                       f"{again.message}; refitted from a first fit the data rejected, "
                       f"whose tracked modes had crossed ({crossed}), with the modes "
                       f"paired by order at it"))


def _consistency(res: UpdateResult, meas, model, method) -> Consistency | None:
    return residual_consistency(res.rows, res.measured_hz, res.updated_hz, meas,
                                res.identifiability.rank,
                                model=model if method == "bayesian" else None,
                                updated=res.parameters)


def second_solution(model: ParametricModel, configurations: Sequence[Configuration],
                    modes: Sequence[int], measurements: Mapping[tuple[str, int], Measurement],
                    fit: UpdateResult, chi2: float, *, starts: int,
                    rng: np.random.Generator, **kw) -> tuple[SecondSolution | None, int]:
    """Fit again from ``starts`` draws of the prior (``kw``: the first fit's settings);
    the first fit that passes the chi-square test outside the first fit's confidence
    ellipsoid (see :data:`ALPHA_SECOND`), and the number of fits tried."""
    if not has_prior(model) or starts < 1:
        return None, 0
    method = kw["method"]
    cov = stated_covariance(model, configurations, modes, fit, measurements, method)[1]
    for i in range(starts):
        try:
            res = update(model, configurations, modes, measurements,
                         start=draw_values(model, rng), **kw)
        except (InputError, NumericalError):
            continue  # a start the solver refuses: not a solution
        test = _consistency(res, measurements, model, method)
        if not res.success or test is None or test.rejected:
            continue
        d2, limit = distance(fit.x, cov, res.x)
        if d2 > limit:
            rel = np.abs(res.x - fit.x) / np.maximum(np.abs(fit.x), np.finfo(float).tiny)
            j = int(np.argmax(rel))
            return SecondSolution(dict(zip(res.names, res.x.tolist(), strict=True)), d2,
                                  limit, (chi2, test.chi2), fit.names[j], float(rel[j])), i + 1
    return None, starts


def checked_update(
    model: ParametricModel,
    configurations: Sequence[Configuration],
    modes: Sequence[int],
    measurements: Mapping[tuple[str, int], Measurement],
    *,
    method: str,
    optimizer: str = "trust-region",
    max_iterations: int = 20,
    xtol: float = 1e-8,
    source: str | None = None,
    progress: Callable[[str], None] | None = None,
    max_refits: int = MAX_REFITS,
    starts: int | None = None,
    seed: int | np.random.SeedSequence | None = 0,
) -> CheckedUpdate:
    """The update with its checks (see the module). InputError for data that break the
    ordering laws or that the update refuses.

    Parameters
    ----------
    model, configurations, modes, measurements, method, optimizer, max_iterations, xtol,
    source, progress : as :func:`eigenupdate.identify.updating.update`.
    max_refits : exchanges refitted at most (:func:`eigenupdate.identify.exchange.exchange_test`).
    starts : fits from draws of the prior for :func:`second_solution` (default
        :data:`STARTS` on dense models, 0 on sparse ones, where one fit takes minutes).
    seed : of the draws of the starts (the same data give the same verdict).
    """
    n_rigid = solve_configurations(model, configurations[:1], 1)[0].n_rigid
    check_measured_frequencies(configurations, measurements, source=source, n_rigid=n_rigid)
    kw = dict(method=method, optimizer=optimizer, max_iterations=max_iterations, xtol=xtol)
    res = update(model, configurations, modes, measurements, source=source,
                 progress=progress, **kw)
    if not res.success:
        return CheckedUpdate(res, NOT_CONVERGED)
    fit = _consistency(res, measurements, model, method)
    if fit is None:
        return CheckedUpdate(res, CONVERGED)
    crossed = _crossed(res)
    if fit.rejected and crossed:
        # the start's order pairing was wrong for modes that crossed on the way: the fit
        # followed it; pair again by order at the rejected fit, nearer the structure
        if progress is not None:
            progress(f"refit: the data reject the fit and its tracked modes crossed "
                     f"({crossed}); fitting again from it, its modes paired by order there")
        again = update(model, configurations, modes, measurements, source=source,
                       progress=progress, start=res.x, **kw)
        refit = _consistency(again, measurements, model, method) if again.success else None
        if refit is not None and not refit.rejected:
            res, fit = _joined(res, again, crossed), refit
    if fit.rejected:
        return CheckedUpdate(replace(res, success=False,
                                     message=f"{res.message}; but {fit.message()}"),
                             REJECTED, fit)
    if starts is None:
        starts = STARTS if model.n <= DENSE_LIMIT else 0
    second, tried = second_solution(model, configurations, modes, measurements, res,
                                    fit.chi2, starts=starts,
                                    rng=np.random.default_rng(seed), **kw)
    if second is not None:
        return CheckedUpdate(replace(res, success=False,
                                     message=f"{res.message}; but {second.message()}"),
                             SECOND_SOLUTION, fit, second, tried)
    swap = exchange_test(model, configurations, modes, measurements, res, fit.chi2,
                         max_refits=max_refits, **kw)
    if swap.ambiguous is not None:
        return CheckedUpdate(replace(res, success=False, message=f"{res.message}; but "
                                     f"{swap.ambiguous.message()}"),
                             EXCHANGE, fit, None, tried, swap)
    if swap.skipped or swap.harmless:
        same = (f", fitting as well with the same answer within its std: {swap.harmless}"
                if swap.harmless else "")
        res = replace(res, message=f"{res.message}; mode exchanges between configurations "
                      f"tested: {swap.refitted}, not tested (limit): {swap.skipped}{same}")
    return CheckedUpdate(res, CONVERGED, fit, None, tried, swap)
