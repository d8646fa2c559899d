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
``ftol``: checked before the step's point is solved, so a converged fit costs no extra
eigen-solution. The trust region also stops where the Gauss-Newton steps contract so fast
that the step after the next one is predicted below ``xtol``: it takes that last step
without solving its point (:func:`eigenupdate.identify.optimizers.finish_step`; the
history marks it, the message gives the prediction).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping, Sequence

import numpy as np

from eigenupdate.errors import InputError, NumericalError
from eigenupdate.identify.identifiability import IdentifiabilityReport, identifiability
from eigenupdate.identify.optimizers import (
    Point,
    Step,
    gauss_newton,
    gn_step,
    resolution,
    trust_region,
)
from eigenupdate.identify.pairing import Pairing, PairingNote
from eigenupdate.identify.plausibility import check_measured_frequencies
from eigenupdate.identify.result import Iterate, UpdateResult
from eigenupdate.identify.weights import OPTIMIZERS, estimator_weights
from eigenupdate.measure.measurement import Measurement, select, to_eigenvalue
from eigenupdate.model.configurations import Configuration
from eigenupdate.model.parametric import ParametricModel
from eigenupdate.solve.eigen import WarmStart
from eigenupdate.solve.jacobian import Linearisation, Rejected, linearise
from eigenupdate.solve.perturbed import CertificateReport

FLOOR = 1e-3
"""A parameter with a positive initial value may not fall below FLOOR times it."""
PRECISION = 0.01
"""A next step below this fraction of every parameter's posterior std is converged."""

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
        or when the next step is below PRECISION of every posterior std.
    source : file name for error messages.
    progress : called with one line per iteration, "[i/max_iterations] iteration i: ..."
        (objective, step, largest change, seconds).
    start : all parameter values to start the iteration from (default: the model's);
        the Bayesian prior stays centred on the model's values.
    """
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
    lam_meas = to_eigenvalue(f_meas)
    w = np.ones_like(lam_meas) if weights.rows is None else weights.rows
    std_hz = np.array([measurements[r].std_hz or 0.0 for r in rows])
    std_rel = 2 * std_hz / f_meas  # of lambda = (2 pi f)^2

    scale = np.array([model.parameters[j].scale for j in upd])
    z0 = model.values[upd] / scale
    prior = np.zeros_like(z0) if weights.prior is None else weights.prior  # sqrt W_s
    nfev = 0

    def full(z: np.ndarray) -> np.ndarray:
        s = model.values.copy()
        s[upd] = z * scale
        return s

    solver, n_lin = CertificateReport(), [0]
    warm = WarmStart()  # each linearisation starts the next one's eigen-solve
    index = {row: i for i, row in enumerate(rows)}
    pairing: Pairing | None = None
    cache: dict[bytes, Point] = {}

    def evaluate(z: np.ndarray, above: float | None = None) -> Point | None:
        """The linearisation at z, paired, and its objective; with ``above``, None as
        soon as the rows already solved give an objective of at least ``above``
        (under the current pairing; an estimate that only shortens steps)."""
        nonlocal nfev
        key = z.tobytes()
        if key in cache:
            return cache[key]
        nfev += 1
        a = prior * (z - z0)

        def reject(known: dict[str, np.ndarray]) -> bool:
            part = float(a @ a)
            for (name, _k), i in index.items():
                j = pairing.perm[i]  # position of this row's tracked mode
                if name in known and len(pairing.groups[pairing.group_of[i]]) == 1:
                    part += float(w[i] * (lam_meas[i] - known[name][rows[j][1] - 1])) ** 2
            return part >= above

        nonlocal pairing
        try:
            lin = linearise(model, configurations, modes, full(z), warm=warm,
                            reject=None if above is None or pairing is None else reject)
        except Rejected:
            return None
        if lin.certificate is not None:
            solver.merge(lin.certificate)
            n_lin[0] += 1
        if pairing is None:  # the start: which modes the data can order, which not
            pairing = Pairing(rows, lam_meas, lin.eigenvalues, std_rel, w,
                              None if lin.shapes is None else mass_diagonal)
        p = paired(z, lin)
        if len(cache) > 2:  # fun and jac at the same point: one solve; keep few (memory)
            cache.pop(next(iter(cache)))
        cache[key] = p
        return p

    def paired(z: np.ndarray, lin: Linearisation) -> Point:
        perm, pending = pairing.match(lin.shapes)
        lam, Jn = pairing.paired(lin.eigenvalues, lin.normalised, perm)
        r, Ar = pairing.equations(lam, Jn)
        f = np.concatenate([r, prior * (z - z0)])
        A = np.vstack([Ar, np.diag(prior)])
        return Point(z.copy(), lin, perm, pending, f, A, float(f @ f))

    def attempt(z: np.ndarray, obj: float, refused: list[str]) -> Point | None:
        """A trial point: evaluate(z), turned down as soon as its objective reaches
        ``obj``. A point the eigen-solver refuses (a density driven towards its floor
        leaves near-massless coordinates) is a step too long, not the end of the run:
        None, the reason appended to ``refused``."""
        try:
            return evaluate(z, above=obj)
        except (InputError, NumericalError) as exc:
            refused.append(str(exc))
            return None

    def iterate(i, z, obj, step, kind) -> Iterate:
        return Iterate(i, dict(zip(model.names, full(z).tolist(), strict=True)), obj, step, kind)

    def report(p: Point) -> IdentifiabilityReport:
        Jn = pairing.paired(p.lin.eigenvalues, p.lin.normalised, p.perm)[1]
        if weights.rows is None:  # unit weights; a cluster's sum weighs 1 / sqrt(size)
            return identifiability(pairing.weights[:, None] * (pairing.S @ Jn), p.lin.names,
                                   None, weights.prior)
        return identifiability(pairing.S @ Jn, p.lin.names, pairing.weights, weights.prior)

    lower = FLOOR * z0  # 0 for parameters whose initial value is 0
    z = z0.copy() if start is None else np.asarray(start, dtype=float)[upd] / scale
    t0 = time.perf_counter()
    mass_diagonal = np.asarray(model.mass().diagonal(), dtype=float)
    point = evaluate(z)
    lin0 = point.lin
    if pairing.candidates:  # cluster the most ambiguous pairs first, while J keeps its rank
        kept, refused = [], []
        fewest = z.size + (len(rows) - z.size + 1) // 2  # keep half of the redundancy
        for cand in pairing.candidates:
            pairing.cluster([c[1:] for c in kept + [cand]])
            ok = len(pairing.groups) >= fewest and report(paired(z, lin0)).identifiable
            (kept if ok else refused).append(cand)
        pairing.cluster([c[1:] for c in kept], refused)
        point = paired(z, lin0)
        cache.clear()
        cache[z.tobytes()] = point
    pairing.accept(point.perm, point.pending, point.lin.shapes, 0)
    plan = report(point)
    if not plan.identifiable:
        # the minimum-norm step would leave the undetermined combinations at their initial
        # values and call that converged: a silently wrong answer
        clusters = (f" ({len(pairing.groups)} equations: modes the data cannot order are "
                    f"fitted through their sum)" if pairing.clustered else "")
        raise InputError(
            f"the test plan does not determine the parameters: rank {plan.rank} of J for "
            f"{z.size} updated parameters{clusters} (see 'eigenupdate check'); add "
            f"perturbations or modes, hold parameters fixed, or give priors and use the "
            f"bayesian method",
            field="perturbation / measurement.modes",
        )
    history = [iterate(0, z, point.obj, 0.0, Step.INITIAL)]
    say = progress or (lambda line: None)
    clusters = pairing.to_dict()["clusters"]
    say(f"[0/{max_iterations}] iteration 0: objective {point.obj:.6g}, "
        f"{len(pairing.groups)} equations"
        + (f", fitted through their sum: {clusters}" if clusters else "")
        + f", {time.perf_counter() - t0:.1f} s")

    def stop_test(p: Point) -> tuple[int, str, np.ndarray] | None:
        """(status, message, step) if the Gauss-Newton step at p says converged."""
        dz = gn_step(p.A, -p.f, p.z, lower)[0]
        predicted = p.obj - float(np.sum((p.A @ dz + p.f) ** 2))
        largest = float(np.max(np.abs(dz)))
        std = None if weights.rows is None else resolution(p.A)
        resolved = float(np.max(np.abs(dz) / std)) if std is not None else np.inf
        if largest < xtol or predicted <= ftol * p.obj or resolved < PRECISION:
            status = 1 if largest < xtol else 2 if predicted <= ftol * p.obj else 4
            return status, (
                f"converged: largest normalised step {largest:.1e}, predicted objective "
                f"decrease {predicted / p.obj if p.obj else 0:.1e} relative"
                + (f", step {resolved:.1e} of the posterior std" if std is not None else "")
            ), dz
        return None

    if optimizer == "gauss-newton":
        status, message, point = gauss_newton(point, evaluate, attempt, stop_test, pairing,
                                               history, iterate, lower, max_iterations, say,
                                               t0)
        success = status in (1, 2, 4)
    else:
        status, message, point, success = trust_region(point, evaluate, stop_test, pairing,
                                                        history, iterate, lower,
                                                        max_iterations, say, t0, xtol)
        point, status, message, success = _finish_by_gauss_newton(
            point, status, message, success, stop_test, evaluate, attempt, pairing, history,
            iterate, lower, max_iterations, say, t0)
    if success and pairing.clustered:
        released = _resolved_clusters(pairing, rows, lam_meas, std_rel, w, point, len(history))
        if released:
            # refit with every mode whose pairing the fit has settled (solved afresh where
            # the last step was taken without a solve)
            cache.clear()
            point = evaluate(point.z) if point.predicted else paired(point.z, point.lin)
            cache[point.z.tobytes()] = point
            say(f"[{len(history) - 1}/{max_iterations}] clusters resolved at the fit: "
                f"{released}; refitting with {len(pairing.groups)} equations")
            if optimizer == "gauss-newton":
                status, message, point = gauss_newton(point, evaluate, attempt, stop_test,
                                                       pairing, history, iterate, lower,
                                                       max_iterations, say, t0)
                success = status in (1, 2, 4)
            else:
                status, message, point, success = trust_region(
                    point, evaluate, stop_test, pairing, history, iterate, lower,
                    max_iterations, say, t0, xtol)
                point, status, message, success = _finish_by_gauss_newton(
                    point, status, message, success, stop_test, evaluate, attempt, pairing,
                    history, iterate, lower, max_iterations, say, t0)
    nit = len(history) - 1
    z, lin = point.z, point.lin

    final = report(point)
    cov = _posterior_cov(final, point.f[:len(pairing.groups)], method)
    cov = None if cov is None else cov * np.outer(scale, scale)
    std = np.full(upd.size, np.nan) if cov is None else np.sqrt(np.maximum(np.diag(cov), 0.0))
    names = [model.names[j] for j in upd]
    lam_paired, J_paired = pairing.paired(lin.eigenvalues, lin.J, point.perm)
    return UpdateResult(
        x=full(z)[upd],
        names=names,
        success=bool(success),
        status=status,
        message=message,
        nit=nit,
        nfev=nfev,
        cost=0.5 * point.obj,
        fun=point.f.copy(),
        jac=J_paired.copy(),
        cov=cov,
        std={n: (None if not np.isfinite(s) else float(s)) for n, s in zip(names, std,
                                                                            strict=True)},
        method=method,
        parameters=dict(zip(model.names, full(z).tolist(), strict=True)),
        history=tuple(history),
        rows=rows,
        measured_hz=f_meas,
        initial_hz=np.sqrt(lin0.eigenvalues) / (2 * np.pi),
        updated_hz=np.sqrt(np.maximum(pairing.by_row(lam_paired), 0)) / (2 * np.pi),
        identifiability=final,
        model=model.with_values(full(z)),
        solver={**solver.as_dict(), "linearisations": n_lin[0]} if n_lin[0] else None,
        optimizer=optimizer,
        pairing=pairing.to_dict(),
    )


def _finish_by_gauss_newton(point, status, message, success, stop_test, evaluate, attempt,
                            pairing, history, iterate, lower, max_iterations, say, t0):
    """SciPy's own tests (ftol, xtol) can stop the trust region where the fit is not done:
    a region shrunk on turned-down trial points (on the paper's beam with 10 % priors, 4 of
    200 draws stopped after one iteration up to 11 posterior std from the truth, "both ftol
    and xtol satisfied"). Success needs our convergence test at the final point; where
    SciPy claims it and the test does not, Gauss-Newton with its line search continues."""
    if not success or stop_test(point) is not None:
        return point, status, message, success
    left = max_iterations - (len(history) - 1)
    if left < 1:
        return point, status, message, False
    say(f"[{len(history) - 1}/{max_iterations}] the trust region stopped short of the fit "
        f"({message}): continuing by Gauss-Newton")
    done = len(history) - 1

    def shifted(i, z, obj, step, kind):  # Gauss-Newton counts its own iterations
        return iterate(done + i, z, obj, step, kind)

    status, gn_message, point = gauss_newton(point, evaluate, attempt, stop_test, pairing,
                                             history, shifted, lower, left, say, t0)
    return (point, status, f"{gn_message} (Gauss-Newton after the trust region: {message})",
            status in (1, 2, 4))


def _resolved_clusters(pairing: Pairing, rows, lam_meas, std_rel, w, point, iteration: int
                       ) -> list:
    """Release the clusters that the fit has settled, and say which.

    Clusters are chosen at the start, where the start model's error can make modes that
    are well apart look exchangeable (on the Fig. 2 system with 25 % priors, modes 84 and
    94 Hz apart were fitted through their sum, the fit lost three equations and converged
    to a wrong point in some draws). At the fit the test is asked again; a pair is released
    when its swapped pairing is no longer plausible and the tracked modes are in frequency
    order (no crossing happened on the way, so the order the test numbers them in holds).
    """
    lam_fit = pairing.paired(point.lin.eigenvalues, point.lin.normalised, point.perm)[0]
    still = {(a, b) for _, a, b in Pairing(rows, lam_meas, lam_fit, std_rel, w,
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
