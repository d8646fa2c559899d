"""The two optimisers of :func:`eigenupdate.identify.updating.update`, on the paired
equations it builds (:mod:`eigenupdate.identify.pairing`).

* :func:`trust_region`: ``scipy.optimize.least_squares`` with the exact Jacobian, method
  ``dogbox`` (see :mod:`eigenupdate.identify.updating` for why not ``trf``); the
  convergence tests and the iteration limit run in its callback at every accepted point;
* :func:`gauss_newton`: the paper's iteration, bounded and halved steps.

Both work on :class:`Point` (a linearisation, its pairing, residuals f and df/dz) given
by the :class:`~eigenupdate.identify.fit.Fit` they are handed, which also holds the
history, the pairing, the bounds and the stopping settings.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace
from enum import Enum
from typing import TYPE_CHECKING

import numpy as np
from scipy.optimize import least_squares, lsq_linear

from eigenupdate.errors import InputError, NumericalError
from eigenupdate.solve.eigen import LANCZOS_RTOL
from eigenupdate.solve.jacobian import Linearisation
from eigenupdate.solve.reduced import MAX_ENTRIES, ReducedModel

if TYPE_CHECKING:
    from eigenupdate.identify.fit import Fit

MAX_HALVINGS = 30
TR_METHOD = "dogbox"


class Step(Enum):
    """How an iterate was reached; the value is the note the history prints."""

    INITIAL = "initial"
    FULL = "full step"
    BOUNDED = "step bounded: a parameter would become non-physical"
    HALVED = "step halved: objective rose"
    FAILED = "line search failed"
    TRUST = "trust-region step"
    SHRUNK = "trust-region step after the region shrank"
    FINAL = "last Gauss-Newton step, taken without a further solve"
    REDUCED = "step to the optimum of a reduced model that follows the mode shapes"


INITIAL_REGION = 0.5
"""The trust region's first half-width, in each parameter's scale: a step may change a
parameter by at most half its initial value until the model has earned more. SciPy's
dogbox starts at |z0|_inf = 1, all of a parameter; on a 2,160-coordinate frame of the
benchmark's family (2 x 2 bays, 5 storeys, seed 3) its first step changed a parameter by
100 % (to the floor of the bounds) along a direction the data hardly see, and the fit
crept back for 27 iterations; from 0.5 it converges in 9. Over 20 clamped frames of that
family (benchmarks/README.md) 16 converge against 15; the 103k frame's first step
(47 %) fits inside it."""


SOLVER_RTOL = LANCZOS_RTOL
"""Relative error the sparse eigen-solver may leave in an eigenvalue: Lanczos' residual
tolerance (the certified Rayleigh-Ritz path is tighter, 1e-11). An objective that errors of
this size alone can give is converged where no step lowers it (:meth:`Fit.solver_floor`)."""


RATE_MAX = 0.5
""":func:`finish_step` needs the Gauss-Newton steps to shrink at least this fast."""


def finish_step(p: Point, dz: np.ndarray, previous: float | None, xtol: float,
                before: float | None = None) -> tuple[Point, float] | None:
    """The point p + dz, taken without an eigen-solution, if the step after it is
    predicted below ``xtol``; else None.

    ``previous`` is the largest change of the full step that reached p (None if the step
    was cut), ``before`` that of the full step before it (None if unknown or cut). With
    the observed contraction rho = max|dz| / previous, the steps after p + dz add up to
    at most rho' / (1 - rho') max|dz| if the iteration keeps contracting at a rate
    rho' <= rho. Linear convergence gives rho' = rho. Where the contraction itself
    improved, from rho0 = previous / before to rho < rho0, rho' = rho^2 / rho0 (the
    improvement continues at the observed pace): that holds for every iteration of
    order p >= 1 (e_k+1 = C e_k^p, so rho' / rho = rho^(p-1) <= rho / rho0), the
    quadratic convergence of error-free data included, and it gives rho again for linear
    convergence. On the 103k benchmark frame the reduced model's steps were 5.2e-2,
    7.0e-3, then 2.3e-5: linear rates predict 7e-8 after the last, above the
    convergence test's xtol 1e-8, the improving rate 1.7e-9 (the step then made was
    1.2e-8, at the eigen-solver's noise in the parameters): that saves the final
    linearisation, one of four. The eigenvalues and residuals at p + dz are the
    linearisation's, in error by O(|dz|^2) (the same order as the predicted step): far
    below the data's precision when the test passes. Returns the point and the predicted
    step.
    """
    largest = float(np.max(np.abs(dz)))
    if previous is None or not previous > 0 or not largest < RATE_MAX * previous:
        return None
    rate = largest / previous
    if before is not None and before > 0 and previous < RATE_MAX * before:
        rate = min(rate, rate * rate / (previous / before))
    after = rate / (1 - rate) * largest
    if not after < xtol:
        return None
    lin = replace(p.lin, eigenvalues=p.lin.eigenvalues + p.lin.normalised @ dz)
    f = p.f + p.A @ dz  # the prior rows are linear in z: exact there
    return Point(p.z + dz, lin, p.perm, [], f, p.A, float(f @ f), True), after


@dataclass
class Point:
    """One evaluated parameter vector: its linearisation, pairing and equations."""

    z: np.ndarray
    lin: Linearisation
    perm: np.ndarray
    pending: list
    f: np.ndarray  # weighted residuals (model - measured), then the prior rows
    A: np.ndarray  # df/dz
    obj: float
    predicted: bool = False  # z is a last step taken without a solve (see finish_step)


def gauss_newton(fit: Fit, point: Point, max_iterations: int, offset: int = 0
                 ) -> tuple[int, str, Point]:
    """The paper's iteration from ``point``: Gauss-Newton steps, bounded and halved when
    needed, at most ``max_iterations``; the history numbers them from ``offset`` + 1.
    Returns (status, message, final point)."""
    status, message = 0, f"iteration limit ({offset + max_iterations}) reached"
    for it in range(1, max_iterations + 1):
        t = time.perf_counter()
        stop = fit.stop_test(point)
        if stop is not None:
            status, message, _ = stop
            break
        dz, kind = gn_step(point.A, -point.f, point.z, fit.lower)
        alpha, refused = 1.0, None
        trial = fit.attempt(point.z + alpha * dz, point.obj)
        refused = fit.refusal or refused
        while (trial is None or not trial.obj < point.obj) and alpha > 0.5**MAX_HALVINGS:
            alpha *= 0.5  # NaN is not lower
            kind = Step.HALVED
            trial = fit.attempt(point.z + alpha * dz, point.obj)
            refused = fit.refusal or refused
        if trial is None or not trial.obj < point.obj:
            floor = fit.solver_floor(point)
            if point.obj <= floor:
                status, message = 2, (
                    f"converged at the eigen-solver's precision: no step lowers the "
                    f"objective {point.obj:.2e}, below the {floor:.2e} that eigenvalue "
                    f"errors of {SOLVER_RTOL:g} alone give")
                break
            status = 3
            message = (
                f"iteration {offset + it}: no step along the Gauss-Newton direction lowers "
                f"the objective"
                + (f" (a trial step was refused: {refused})" if refused else "")
            )
            fit.record(offset + it, point.z, point.obj, 0.0, Step.FAILED)
            break
        point = trial
        fit.pairing.accept(point.perm, point.pending, point.lin.shapes, it)
        fit.record(offset + it, point.z, point.obj, alpha, kind)
        fit.say(f"[{offset + it}/{offset + max_iterations}] iteration {offset + it}: "
                f"objective {point.obj:.6g}, "
                f"step {alpha:g} x Gauss-Newton "
                f"({kind.value}), largest change {np.max(np.abs(alpha * dz)):.2e}, "
                f"{time.perf_counter() - t:.1f} s (total {fit.elapsed():.1f} s)")
    else:
        message += fit.remaining(point)
    return status, message, point


def trust_region(fit: Fit, point: Point) -> tuple[int, str, Point, bool]:
    """scipy.optimize.least_squares (dogbox) on the paired equations from ``point``; our
    convergence tests and the iteration limit (counted over the whole history) run in its
    callback at every accepted point. Where the Gauss-Newton steps contract fast enough,
    the last one is taken without a further solve (:func:`finish_step`, with the fit's
    ``xtol``; 0 never). Returns (SciPy's status, message, final point, success)."""
    max_iterations, xtol, lower, say = fit.max_iterations, fit.xtol, fit.lower, fit.say
    state = {"point": point, "why": None, "t": time.perf_counter(), "rejected": 0,
             "gn": None, "refused_since": 0, "previous": None, "before": None,
             "finish": None}
    def worse(cur):
        # a refused or turned-down point: finite residuals far above the current ones,
        # so that the step is rejected as one that raises the objective (SciPy 1.17's
        # dogbox fails on a callback after non-finite residuals only)
        return np.full(cur.f.size, np.sqrt(1e6 * (cur.obj + 1.0) / cur.f.size))

    def fun(z):
        cur = state["point"]
        if np.array_equal(z, cur.z):
            # the region shrank to round-off: after refused points that is no convergence
            return worse(cur) if state["refused_since"] else cur.f
        p = fit.attempt(z, cur.obj)
        if fit.refusal is not None:  # a point the eigen-solver refuses: the region shrinks
            state["refused"] = fit.refusal
            state["refused_since"] += 1
        if p is None:
            state["rejected"] += 1
            return worse(cur)
        if not p.obj < cur.obj:
            state["rejected"] += 1
        return p.f

    def jac(z):
        p = fit.evaluate(z)
        cur = state["point"]
        if not np.array_equal(z, cur.z):  # an accepted step
            it = len(fit.history)
            fit.pairing.accept(p.perm, p.pending, p.lin.shapes, it)
            gn = state["gn"]
            frac = float(np.linalg.norm(z - cur.z) / np.linalg.norm(gn)) if gn is not None \
                and np.linalg.norm(gn) > 0 else 1.0
            kind = Step.SHRUNK if state["rejected"] else Step.TRUST
            full = gn is not None and np.linalg.norm(z - cur.z - gn) <= 1e-6 * np.linalg.norm(gn)
            fit.record(it, z, p.obj, frac, kind)
            say(f"[{it}/{max_iterations}] iteration {it}: objective {p.obj:.6g}, "
                f"step {frac:.3g} x Gauss-Newton "
                f"({kind.value}), largest change {np.max(np.abs(z - cur.z)):.2e}, "
                f"{time.perf_counter() - state['t']:.1f} s (total "
                f"{fit.elapsed():.1f} s)")
            state.update(point=p, rejected=0, t=time.perf_counter(), gn=None, refused_since=0,
                         previous=float(np.max(np.abs(z - cur.z))) if full else None,
                         before=state["previous"] if full else None)
        return p.A

    def callback(intermediate_result):  # SciPy passes the result under this name
        p = state["point"]
        stop = fit.stop_test(p)
        if stop is not None:
            state["why"] = stop[1]
            raise StopIteration
        state["gn"], kind = gn_step(p.A, -p.f, p.z, lower)
        last = fit.iterations >= max_iterations
        done = None if kind is not Step.FULL or not xtol > 0 else \
            finish_step(p, state["gn"], state["previous"], xtol, state["before"])
        if done is not None and not last:
            state["why"] = _record_final(fit, done[0], state["gn"], state["previous"], done[1])
            state["finish"] = done[0]
            raise StopIteration
        if last:
            state["why"] = f"iteration limit ({max_iterations}) reached{fit.remaining(p)}"
            raise StopIteration

    stop = fit.stop_test(point)
    if stop is not None:
        return -2, f"{stop[1]} (at the initial point)", point, True
    if fit.iterations == 0 and point.lin.certificate is not None:
        point, why = _reduced_steps(fit, point)
        state["point"] = point
        if why is not None:
            return -2, why, point, True
        if fit.iterations >= max_iterations:
            return 0, f"iteration limit ({max_iterations}) reached{fit.remaining(point)}", \
                point, False
    if np.any(point.z <= lower):  # trf starts strictly inside its bounds (as SciPy would)
        point = fit.evaluate(np.where(point.z <= lower, lower + 1e-10 * np.maximum(1, lower),
                                      point.z))
        fit.pairing.accept(point.perm, point.pending, point.lin.shapes, 0)
        state["point"] = point
    state["gn"] = gn_step(point.A, -point.f, point.z, lower)[0]
    # SciPy's variable is the change from the start, so that its first trust region (the
    # box |dz| <= x_scale when x0 = 0) is INITIAL_REGION, not |z0|_inf (all of a parameter)
    origin = point.z.copy()
    res = least_squares(lambda dz: fun(origin + dz), np.zeros_like(origin),
                        jac=lambda dz: jac(origin + dz), bounds=(lower - origin, np.inf),
                        method=TR_METHOD, x_scale=INITIAL_REGION,
                        max_nfev=4 * max_iterations + 10, callback=callback)
    res.x = origin + res.x
    final = state["finish"]
    if final is None:
        final = fit.evaluate(res.x) if not np.array_equal(res.x, state["point"].z) \
            else state["point"]
    # our own stop (status -2): its reason, not SciPy's "callback raised StopIteration"
    message = res.message if state["why"] is None else state["why"]
    success = res.status in (1, 2, 3, 4) or message.startswith("converged")
    if state["refused_since"] and res.status in (2, 3, 4):
        success = False  # the region shrank on refused points only: no convergence
        message += "; but every trial point since the last iterate was refused"
    if state["refused_since"] or (res.status == 0 and state.get("refused")):
        message += f" (a trial point was refused: {state['refused']})"
    return int(res.status), message, final, success


def _reduced_steps(fit: Fit, point: Point) -> tuple[Point, str | None]:
    """Steps of a large model (the sparse path) to the optimum of a reduced model of its
    configurations (:mod:`eigenupdate.solve.reduced`), built at ``point`` and anchored
    at each point reached, while each lowers the objective a hundredfold; then the
    trust region continues. Gauss-Newton's steps miss how the mode shapes change: on
    the 6,228-coordinate benchmark frame its first step leaves the parameters 23 % off
    from a start 4.8 % off, the reduced model's 1.6e-3 (benchmarks/README.md).
    Returns the last point and, if the fit converged there, why."""
    rom, say, step = None, fit.say, None
    size = fit.model.n * ReducedModel.columns(fit.model, fit.configurations, fit.modes)
    if size > MAX_ENTRIES:
        say(f"[0/{fit.max_iterations}] no reduced model: its basis would hold {size:.2g} "
            f"numbers (at most {MAX_ENTRIES:.0e}); trust-region steps follow")
        return point, None
    while fit.iterations < fit.max_iterations:
        t = time.perf_counter()
        try:
            rom = fit.reduced_model(point, rom)
            trial = fit.reduced_step(point, rom)
            why = "did not lower the objective"
        except (InputError, NumericalError, np.linalg.LinAlgError) as exc:
            trial, why = None, f"failed ({exc})"
        if trial is None:
            say(f"[{fit.iterations}/{fit.max_iterations}] the reduced model's step {why} "
                f"({time.perf_counter() - t:.1f} s): trust-region steps follow")
            return point, None
        it = len(fit.history)
        fit.pairing.accept(trial.perm, trial.pending, trial.lin.shapes, it)
        gn = gn_step(point.A, -point.f, point.z, fit.lower)[0]
        frac = float(np.linalg.norm(trial.z - point.z) / np.linalg.norm(gn)) \
            if np.linalg.norm(gn) > 0 else 1.0
        before, step = step, float(np.max(np.abs(trial.z - point.z)))
        fit.record(it, trial.z, trial.obj, frac, Step.REDUCED)
        say(f"[{it}/{fit.max_iterations}] iteration {it}: objective {trial.obj:.6g}, "
            f"step {frac:.3g} x Gauss-Newton ({Step.REDUCED.value}), largest change "
            f"{step:.2e}, {time.perf_counter() - t:.1f} s (total {fit.elapsed():.1f} s)")
        gained = trial.obj <= REDUCED_GAIN * point.obj
        point = trial
        stop = fit.stop_test(point)
        if stop is not None:
            return point, stop[1]
        gn, kind = gn_step(point.A, -point.f, point.z, fit.lower)
        done = finish_step(point, gn, step, fit.xtol, before) if kind is Step.FULL \
            and fit.xtol > 0 and fit.iterations < fit.max_iterations else None
        if done is not None:
            return done[0], _record_final(fit, done[0], gn, step, done[1])
        if not gained:
            return point, None
    return point, None


REDUCED_GAIN = 1e-2
"""A reduced-model step is followed by another only if it lowered the objective at least
this much (then the model's curvature still pays for its cost)."""


def _record_final(fit: Fit, final: Point, gn: np.ndarray, previous: float, after: float
                  ) -> str:
    """Record the last step taken without a solve (:func:`finish_step`); its message."""
    it = len(fit.history)
    fit.record(it, final.z, final.obj, 1.0, Step.FINAL)
    fit.say(f"[{it}/{fit.max_iterations}] iteration {it}: objective {final.obj:.6g} "
            f"(predicted), {Step.FINAL.value}, largest change "
            f"{np.max(np.abs(gn)):.2e}; the step after it predicted "
            f"{after:.1e} (total {fit.elapsed():.1f} s)")
    return (f"converged: largest normalised step {after:.1e} predicted after the last one "
            f"({np.max(np.abs(gn)):.1e}, taken without a further solve; contraction "
            f"{np.max(np.abs(gn)) / previous:.1e})")


def resolution(A: np.ndarray) -> np.ndarray | None:
    """Posterior std of each normalised parameter from the weighted (by 1 / sigma) A;
    None where undefined. Not for plain least squares: its variance would come from the
    residual, which with error-free data is the very misfit the next step removes."""
    s, vt = np.linalg.svd(A, full_matrices=False)[1:]
    if s.size == 0 or s[-1] <= s[0] * 1e-12:
        return None
    return np.sqrt(np.sum((vt / s[:, None]) ** 2, axis=0))


def gn_step(A, b, z, lower) -> tuple[np.ndarray, Step]:
    """Gauss-Newton step; if it would make a parameter non-physical, the bounded
    least-squares step instead (z + dz >= lower), so the direction stays a descent one."""
    dz = np.linalg.lstsq(A, b, rcond=None)[0]
    if np.all(z + dz >= lower):
        return dz, Step.FULL
    dz = lsq_linear(A, b, bounds=(lower - z, np.inf), method="bvls").x
    return dz, Step.BOUNDED
