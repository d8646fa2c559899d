"""Iterative updating of the parameters from measured eigenvalues.

Each iteration linearises the model (Eq. 1, J delta s = delta lambda) and takes a step,
in parameters normalised by their initial values (which scales them by their sizes). Two
optimisers:

* ``trust-region`` (default): ``scipy.optimize.least_squares`` with the exact Fox-Kapoor
  Jacobian as ``jac`` and the bounds below; SciPy's implementation rather than our own,
  so that its step control and its stopping reasons (status codes and words, reported as
  they are) are the library's. Method ``dogbox`` (a rectangular trust-region dogleg), not
  ``trf``: trf's reflective scaling damps every step by the size of the gradient while
  far from the optimum even with the bounds inactive (the weighted Fig. 2 fit from the
  paper's start: 15 iterations with trf, 3 with dogbox, whose steps there are Gauss-
  Newton's). Every residual is an eigen-solution of all configurations: the
  linearisation gives the residual and J together, so ``fun`` and ``jac`` at the same
  point cost one solve (:mod:`eigenupdate.identify.optimizers`).
  On a large model (the sparse path) its first steps go to the optimum of a reduced
  model that follows the mode shapes (:mod:`eigenupdate.solve.reduced`, built once at
  the start and anchored at each point reached, exact there in value and J), solved in
  full; while each lowers the objective a hundredfold. Gauss-Newton's linear model misses
  how the shapes change: on the 103k benchmark frame its first step put densities 49 %
  off from a start 4.8 % off, and the update took 7 linearisations; with the reduced
  model 4 (history note "step to the optimum of a reduced model ...").
* ``gauss-newton``: the paper's plain iteration with the safeguards below; it reproduces
  Table 4's iterates exactly.

Estimators:

* ``least-squares``: minimise ||delta lambda - J delta s||^2 (paper Section 5);
* ``weighted-least-squares``: weights W_lambda = diag(1 / sigma_lambda^2), with
  sigma_lambda = 8 pi^2 f sigma_f from the frequency standard deviations;
* ``bayesian``: Eq. (6), the minimum-change estimator anchored at the initial
  estimates s_i, W_s = diag(1 / sigma_s^2) from the prior standard deviations
  (a parameter without a prior std gets no anchoring weight). It is Gauss-Newton on
  delta lambda^T W_lambda delta lambda + (s - s_i)^T W_s (s - s_i), solved here as a
  stacked least-squares problem rather than through the normal equations, which would
  square the condition number (paper Section 3).

The weights come from :mod:`eigenupdate.identify.weights`; the rank check before the
first step and the posterior covariance after the last come from the same SVD as
``eigenupdate check`` (:func:`eigenupdate.identify.identifiability.identifiability`).

Parameters stay above 1e-3 of their initial value (>= 0 when that is 0): bounds of the
trust-region method; in Gauss-Newton a step that would cross them is replaced by the
bounded least-squares step, and a step that raises the objective is halved until it
lowers it. The history records both; a full step that lowers the objective is taken
unchanged, so plain Gauss-Newton iterates (Table 4) are reproduced exactly.

Which model mode each measured frequency is fitted to, and through which equation (one
per mode, or the sum over a cluster of modes the data cannot order), is
:mod:`eigenupdate.identify.pairing`'s.

Both optimisers stop when the Gauss-Newton step at an accepted point is below ``xtol``,
when it would change no parameter by more than ``PRECISION`` of its posterior standard
deviation (the data cannot resolve it), or when the decrease it predicts is below
``ftol``, or, with noisy data, when the optimum of its Gauss-Newton model lies within
``JOINT`` (0.1) posterior std of the current point, all parameters together (the decrease
it predicts is below 0.01 of one datum's variance; weighted and Bayesian methods, where
the objective passes the chi-square test; the message says "converged at the data's
precision"). A fit of noisy data on weakly determined parameters creeps (its steps cut to
a fraction of Gauss-Newton's) for many iterations after the test on each parameter alone
would stop it. All are checked before the step's point is solved, so a converged fit
costs no extra eigen-solution. At the iteration limit the message gives the same
distance. The trust region also stops where the Gauss-Newton steps contract so fast that
the step after the next one is predicted below ``xtol``: it takes that last step without
solving its point (:func:`eigenupdate.identify.optimizers.finish_step`; the history marks
it, the message gives the prediction). Where no step lowers the objective and it lies
below what eigenvalue errors of the eigen-solver's tolerance alone give
(:meth:`eigenupdate.identify.fit.Fit.solver_floor`), the fit has converged "at the
eigen-solver's precision"; above that floor it is a failure (status 3).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence

import numpy as np

from eigenupdate.errors import InputError
from eigenupdate.identify.fit import FLOOR, JOINT, PRECISION, Fit
from eigenupdate.identify.identifiability import IdentifiabilityReport
from eigenupdate.identify.optimizers import Point, Step, gauss_newton, trust_region
from eigenupdate.identify.pairing import Pairing, PairingNote
from eigenupdate.identify.plausibility import check_frequency_scale, check_measured_frequencies
from eigenupdate.identify.result import UpdateResult
from eigenupdate.identify.weights import OPTIMIZERS, estimator_weights
from eigenupdate.measure.measurement import Measurement, select, to_eigenvalue
from eigenupdate.model.configurations import Configuration
from eigenupdate.model.parametric import ParametricModel
from eigenupdate.solve.jacobian import Linearisation, linearise

__all__ = ["FLOOR", "JOINT", "PRECISION", "STATUS_MESSAGES", "Step", "UpdateResult", "update"]

STATUS_MESSAGES = {
    0: "iteration limit reached",
    1: "converged: the largest normalised step is below xtol",
    2: "converged: the predicted relative objective decrease is below ftol",
    3: "stopped: no step along the Gauss-Newton direction lowers the objective",
    4: "converged: the next step is below what the data resolve",
}
"""Meaning of :attr:`UpdateResult.status` of the ``gauss-newton`` optimiser (``success``
for 1, 2 and 4). The ``trust-region`` optimiser reports SciPy's ``least_squares`` status
and message (-2: stopped by our convergence test or iteration limit, named in the
message; 0: evaluation limit; 1-4: SciPy's own convergence tests)."""
CONVERGED = (1, 2, 4)


def update(
    model: ParametricModel,
    configurations: Sequence[Configuration],
    modes: Sequence[int],
    measurements: Mapping[tuple[str, int], Measurement],
    *,
    method: str = "least-squares",
    optimizer: str = "trust-region",
    max_iterations: int = 20,
    xtol: float = 1e-8,
    ftol: float = 1e-10,
    source: str | None = None,
    progress: Callable[[str], None] | None = None,
    start: np.ndarray | None = None,
) -> UpdateResult:
    """Update the model's updated parameters from measured natural frequencies.

    Parameters
    ----------
    model : initial model (its parameter values are the initial estimates s_i).
    configurations : the bare structure and the perturbed ones.
    modes : elastic mode numbers used in every configuration.
    measurements : {(configuration name, mode): Measurement}; frequencies in Hz.
    method : one of :data:`eigenupdate.identify.weights.ESTIMATORS`.
    optimizer : one of :data:`OPTIMIZERS`.
    max_iterations : iteration limit (accepted steps).
    xtol : converged when the largest change of a normalised parameter s_j / s_j0 that
        the next step would make is below ``xtol``,
    ftol : or when the objective decrease the next step predicts is below ``ftol`` times
        the objective (with noisy data the iteration stalls at round-off otherwise),
        or when the next step is below PRECISION of every posterior std, or the
        optimum of its Gauss-Newton model within JOINT posterior std (jointly).
    source : file name for error messages.
    progress : called with one line per iteration, "[i/max_iterations] iteration i: ..."
        (objective, step, largest change, seconds).
    start : all parameter values to start the iteration from (default: the model's);
        the Bayesian prior stays centred on the model's values.
    """
    # the inputs
    if max_iterations < 1:
        raise InputError("max_iterations must be >= 1", field="updating.max_iterations")
    if optimizer not in OPTIMIZERS:
        raise InputError(f"unknown optimizer {optimizer!r}; expected one of {list(OPTIMIZERS)}",
                         field="updating.optimizer")
    upd = model.updated
    if upd.size == 0:
        raise InputError("no parameter is updated (every parameter has update = false)",
                         field="model")
    rows = [(c.name, k) for c in configurations for k in sorted(set(modes))]
    weights = estimator_weights(model, method, rows, measurements, source)
    f_meas, _ = select(measurements, rows, False, source)
    check_measured_frequencies(configurations, measurements, source=source)
    std_hz = np.array([measurements[r].std_hz or 0.0 for r in rows])
    std_rel = 2 * std_hz / f_meas  # of lambda = (2 pi f)^2
    say = progress or (lambda line: None)
    fit = Fit(model, configurations, modes, rows, to_eigenvalue(f_meas), weights, std_rel,
              max_iterations=max_iterations, xtol=xtol, ftol=ftol, say=say,
              solve=linearise)  # this module's name: tests and benchmarks wrap it

    # the start, and the modes the data cannot order fitted through their sums
    z = fit.z0.copy() if start is None else np.asarray(start, dtype=float)[upd] / fit.scale
    point = fit.cluster(fit.evaluate(z))
    lin0 = point.lin
    if start is None:  # the data against the initial model: units
        check_frequency_scale(rows, f_meas, np.sqrt(np.maximum(lin0.eigenvalues, 0.0))
                              / (2 * np.pi), source=source)
    plan = fit.report(point)
    if not plan.identifiable:
        # the minimum-norm step would leave the undetermined combinations at their initial
        # values and call that converged: a silently wrong answer
        raise _not_determined(plan, fit.pairing, z.size)
    fit.record(0, z, point.obj, 0.0, Step.INITIAL)
    clusters = fit.pairing.to_dict()["clusters"]
    say(f"[0/{max_iterations}] iteration 0: objective {point.obj:.6g}, "
        f"{len(fit.pairing.groups)} equations"
        + (f", fitted through their sum: {clusters}" if clusters else "")
        + f", {fit.elapsed():.1f} s")

    # the iteration; again with each mode whose cluster the fit has settled
    point, status, message, success = _optimise(fit, point, optimizer)
    if success and fit.pairing.clustered:
        released = _resolved_clusters(fit, point)
        if released:
            point = fit.restart(point)  # solved afresh if the last step had no solve
            say(f"[{fit.iterations}/{max_iterations}] clusters resolved at the fit: "
                f"{released}; refitting with {len(fit.pairing.groups)} equations")
            point, status, message, success = _optimise(fit, point, optimizer)
    return _result(fit, point, lin0, status, message, success, method, optimizer, f_meas)


def _optimise(fit: Fit, point: Point, optimizer: str) -> tuple[Point, int, str, bool]:
    """Run ``optimizer`` from ``point``: (final point, status, message, success)."""
    if optimizer == "gauss-newton":
        # a refit after released clusters numbers on and shares the iteration limit
        done = fit.iterations
        if done >= fit.max_iterations:
            return point, 0, f"iteration limit ({fit.max_iterations}) reached", False
        status, message, point = gauss_newton(fit, point, fit.max_iterations - done,
                                              offset=done)
        return point, status, message, status in CONVERGED
    status, message, point, success = trust_region(fit, point)
    return _finish_by_gauss_newton(fit, point, status, message, success)


def _not_determined(plan: IdentifiabilityReport, pairing: Pairing, n: int) -> InputError:
    clusters = (f" ({len(pairing.groups)} equations: modes the data cannot order are "
                f"fitted through their sum)" if pairing.clustered else "")
    return InputError(
        f"the test plan does not determine the parameters: rank {plan.rank} of J for "
        f"{n} updated parameters{clusters} (see 'eigenupdate check'); add "
        f"perturbations or modes, hold parameters fixed, or give priors and use the "
        f"bayesian method",
        field="perturbation / measurement.modes",
    )


def _result(fit: Fit, point: Point, lin0: Linearisation, status: int, message: str,
            success: bool, method: str, optimizer: str, f_meas: np.ndarray) -> UpdateResult:
    """The :class:`UpdateResult` at the final point, with its posterior covariance."""
    pairing, upd, scale, lin = fit.pairing, fit.upd, fit.scale, point.lin
    final = fit.report(point)
    cov = _posterior_cov(final, point.f[:len(pairing.groups)], method)
    cov = None if cov is None else cov * np.outer(scale, scale)
    std = np.full(upd.size, np.nan) if cov is None else np.sqrt(np.maximum(np.diag(cov), 0.0))
    names = [fit.model.names[j] for j in upd]
    values = fit.full(point.z)
    lam_paired, J_paired = pairing.paired(lin.eigenvalues, lin.J, point.perm)
    return UpdateResult(
        x=values[upd],
        names=names,
        success=bool(success),
        status=status,
        message=message,
        nit=fit.iterations,
        nfev=fit.nfev,
        cost=0.5 * point.obj,
        fun=point.f.copy(),
        jac=J_paired.copy(),
        cov=cov,
        std={n: (None if not np.isfinite(s) else float(s)) for n, s in zip(names, std,
                                                                            strict=True)},
        method=method,
        parameters=dict(zip(fit.model.names, values.tolist(), strict=True)),
        history=tuple(fit.history),
        rows=fit.rows,
        measured_hz=f_meas,
        initial_hz=np.sqrt(lin0.eigenvalues) / (2 * np.pi),
        updated_hz=np.sqrt(np.maximum(pairing.by_row(lam_paired), 0)) / (2 * np.pi),
        identifiability=final,
        model=fit.model.with_values(values),
        solver={**fit.solver.as_dict(), "linearisations": fit.n_lin} if fit.n_lin else None,
        optimizer=optimizer,
        pairing=pairing.to_dict(),
        units=fit.model.units,
        perturbations={c.name: c.listed() for c in fit.configurations},
    )


def _finish_by_gauss_newton(fit: Fit, point: Point, status: int, message: str,
                            success: bool) -> tuple[Point, int, str, bool]:
    """SciPy's own tests (ftol, xtol) can stop the trust region where the fit is not done:
    a region shrunk on turned-down trial points (on the paper's beam with 10 % priors, 4 of
    200 draws stopped after one iteration up to 11 posterior std from the truth, "both ftol
    and xtol satisfied"). Success needs our convergence test at the final point; where
    SciPy claims it and the test does not, Gauss-Newton with its line search continues."""
    if not success or fit.stop_test(point) is not None:
        return point, status, message, success
    left = fit.max_iterations - fit.iterations
    if left < 1:
        return point, status, message, False
    fit.say(f"[{fit.iterations}/{fit.max_iterations}] the trust region stopped short of the "
            f"fit ({message}): continuing by Gauss-Newton")
    # Gauss-Newton counts its own iterations, numbered on in the history
    status, gn_message, point = gauss_newton(fit, point, left, offset=fit.iterations)
    return (point, status, f"{gn_message} (Gauss-Newton after the trust region: {message})",
            status in CONVERGED)


def _resolved_clusters(fit: Fit, point: Point) -> list:
    """Release the clusters that the fit has settled, and say which.

    Clusters are chosen at the start, where the start model's error can make modes that
    are well apart look exchangeable (on the Fig. 2 system with 25 % priors, modes 84 and
    94 Hz apart were fitted through their sum, the fit lost three equations and converged
    to a wrong point in some draws). At the fit the test is asked again; a pair is released
    when its swapped pairing is no longer plausible and the tracked modes are in frequency
    order (no crossing happened on the way, so the order the test numbers them in holds).
    """
    pairing, rows, iteration = fit.pairing, fit.rows, len(fit.history)
    lam_fit = pairing.paired(point.lin.eigenvalues, point.lin.normalised, point.perm)[0]
    still = {(a, b) for _, a, b in Pairing(rows, fit.lam_meas, lam_fit, fit.std_rel, fit.w,
                                            None).candidates}
    keep, released = [], []
    for g in pairing.groups:
        for a, b in zip(g[:-1], g[1:], strict=True):
            if (a, b) in still or not point.perm[a] < point.perm[b]:
                keep.append((a, b))
            else:
                released.append((rows[a][0], [rows[a][1], rows[b][1]]))
    if released:
        pairing.cluster(keep)
        for c, modes in released:
            pairing.notes.append(PairingNote(
                "cluster resolved", c, tuple(modes), iteration,
                "at the fit the swapped pairing is no longer plausible and the modes kept "
                "their order: refitted with each mode"))
    return released


def _posterior_cov(report: IdentifiabilityReport, r: np.ndarray, method: str
                   ) -> np.ndarray | None:
    """Posterior covariance of the normalised parameters from the report's SVD; for plain
    least squares scaled by the variance of the residuals ``r`` of the equations (None
    where undefined)."""
    if report.cov is None:
        return None
    if method != "least-squares":
        return report.cov
    dof = r.size - report.cov.shape[0]
    if dof <= 0:
        return None
    return report.cov * float(r @ r) / dof
