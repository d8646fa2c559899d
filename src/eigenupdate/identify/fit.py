"""The least-squares problem that :func:`eigenupdate.identify.updating.update` solves.

A :class:`Fit` holds what stays fixed during an update (the equations' rows, weights,
measured eigenvalues, the parameters' scales and prior, the stopping settings) and what
the iteration builds up (the pairing of model modes to measured ones, a small cache of
evaluated points, the history, the solver's certificates). Its methods are the steps
both optimisers (:mod:`eigenupdate.identify.optimizers`) take:

* :meth:`Fit.evaluate`: the linearisation at a point, paired, with residuals and df/dz;
* :meth:`Fit.attempt`: a trial point, None if its objective is not below the current one
  or the eigen-solver refuses it (a step too long);
* :meth:`Fit.stop_test`: the convergence test at an accepted point;
* :meth:`Fit.record`: an accepted point into the history.

Parameters are normalised by their scales: z = s / scale.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence

import numpy as np
from scipy.optimize import least_squares
from scipy.stats import chi2

from eigenupdate.errors import InputError, NumericalError
from eigenupdate.identify.identifiability import IdentifiabilityReport, identifiability
from eigenupdate.identify.optimizers import SOLVER_RTOL, Point, Step, gn_step, resolution
from eigenupdate.identify.pairing import Pairing
from eigenupdate.identify.result import Iterate
from eigenupdate.identify.weights import EstimatorWeights
from eigenupdate.model.configurations import Configuration
from eigenupdate.model.parametric import ParametricModel
from eigenupdate.solve.eigen import WarmStart
from eigenupdate.solve.jacobian import Linearisation, linearise
from eigenupdate.solve.perturbed import CertificateReport
from eigenupdate.solve.reduced import ReducedModel

FLOOR = 1e-3
"""A parameter with a positive initial value may not fall below FLOOR times it."""
PRECISION = 0.01
"""A next step below this fraction of every parameter's posterior std is converged."""
JOINT = 0.1
"""Converged at the data's precision: the optimum of the Gauss-Newton model lies within
JOINT posterior std of the current point, all parameters together (its objective
decrease is below JOINT^2 in units of one datum's variance)."""
CHI2_LEVEL = 0.999
"""JOINT applies where the objective lies below this quantile of its chi-square."""
REDUCED_XTOL = 1e-8
"""The reduced model's optimum is solved to this relative step (its own accuracy is
lower: the point it gives is solved in full)."""
REDUCED_NFEV = 40
CACHE_SIZE = 3
"""Points kept: ``fun`` and ``jac`` at the same point cost one solve; few (memory)."""


class Fit:
    """The weighted, paired least-squares problem of one update, and its iteration state.

    Parameters
    ----------
    model : initial model; its updated parameters' values are z0 (normalised: 1 unless a
        parameter's scale differs from its value).
    configurations, modes : as :func:`eigenupdate.identify.updating.update`.
    rows : the (configuration, mode) of each equation.
    lam_meas : measured eigenvalues of ``rows``.
    weights : the estimator's square-root weights (rows, prior).
    std_rel : relative std of each measured eigenvalue (0 where unknown), for the pairing.
    max_iterations, xtol, ftol : the stopping settings of ``update``.
    say : receives the progress lines.
    solve : the linearisation (:func:`eigenupdate.solve.jacobian.linearise`; tests and
        benchmarks wrap the one :mod:`eigenupdate.identify.updating` passes).
    """

    def __init__(self, model: ParametricModel, configurations: Sequence[Configuration],
                 modes: Sequence[int], rows: list[tuple[str, int]], lam_meas: np.ndarray,
                 weights: EstimatorWeights, std_rel: np.ndarray, *, max_iterations: int,
                 xtol: float, ftol: float, say: Callable[[str], None],
                 solve: Callable[..., Linearisation | None] = linearise):
        self.model, self.configurations, self.modes = model, configurations, modes
        self.rows, self.lam_meas, self.std_rel = rows, lam_meas, std_rel
        self.weights = weights
        self.w = np.ones_like(lam_meas) if weights.rows is None else weights.rows
        self.upd = model.updated
        self.scale = np.array([model.parameters[j].scale for j in self.upd])
        self.z0 = model.values[self.upd] / self.scale
        self.prior = np.zeros_like(self.z0) if weights.prior is None else weights.prior
        self.lower = FLOOR * self.z0  # 0 for parameters whose initial value is 0
        self.max_iterations, self.xtol, self.ftol, self.say = max_iterations, xtol, ftol, say
        self.solve = solve
        self.index = {row: i for i, row in enumerate(rows)}
        self.pairing: Pairing | None = None  # made at the first point
        self.history: list[Iterate] = []
        self.nfev = 0
        self.solver, self.n_lin = CertificateReport(), 0
        self.warm = WarmStart()  # each linearisation starts the next one's eigen-solve
        self.refusal: str | None = None  # why the eigen-solver refused the last attempt
        self._cache: dict[bytes, Point] = {}
        self._mass_diagonal: np.ndarray | None = None
        self.t0 = time.perf_counter()

    def full(self, z: np.ndarray) -> np.ndarray:
        """All parameter values, with the updated ones at normalised z."""
        s = self.model.values.copy()
        s[self.upd] = z * self.scale
        return s

    def evaluate(self, z: np.ndarray, above: float | None = None) -> Point | None:
        """The linearisation at z, paired, and its objective; with ``above``, None as
        soon as the rows already solved give an objective of at least ``above``
        (under the current pairing; an estimate that only shortens steps). The first
        point evaluated makes the pairing."""
        key = z.tobytes()
        if key in self._cache:
            return self._cache[key]
        self.nfev += 1
        early = None if above is None or self.pairing is None else self._reject(z, above)
        lin = self.solve(self.model, self.configurations, self.modes, self.full(z),
                         warm=self.warm, reject=early)
        if lin is None:
            return None
        if lin.certificate is not None:
            self.solver.merge(lin.certificate)
            self.n_lin += 1
        if self.pairing is None:  # the start: which modes the data can order, which not
            if self._mass_diagonal is None:
                self._mass_diagonal = np.asarray(self.model.mass().diagonal(), dtype=float)
            self.pairing = Pairing(self.rows, self.lam_meas, lin.eigenvalues, self.std_rel,
                                   self.w, None if lin.shapes is None else self._mass_diagonal,
                                   lin.next_eigenvalues)
        p = self.paired(z, lin)
        if len(self._cache) >= CACHE_SIZE:
            self._cache.pop(next(iter(self._cache)))
        self._cache[key] = p
        return p

    def _reject(self, z: np.ndarray, above: float) -> Callable[[dict], bool]:
        """The early test of :meth:`evaluate`: the objective of the rows whose
        eigenvalues are known (single-mode equations only) reaches ``above``."""
        a = self.prior * (z - self.z0)
        pairing, w, lam_meas, rows = self.pairing, self.w, self.lam_meas, self.rows

        def reject(known: dict[str, np.ndarray]) -> bool:
            part = float(a @ a)
            for (name, _k), i in self.index.items():
                j = pairing.perm[i]  # position of this row's tracked mode
                if name in known and len(pairing.groups[pairing.group_of[i]]) == 1:
                    part += float(w[i] * (lam_meas[i] - known[name][rows[j][1] - 1])) ** 2
            return part >= above

        return reject

    def attempt(self, z: np.ndarray, obj: float) -> Point | None:
        """A trial point: :meth:`evaluate` turned down as soon as its objective reaches
        ``obj``. A point the eigen-solver refuses (a density driven towards its floor
        leaves near-massless coordinates) is a step too long, not the end of the run:
        None, with the reason in :attr:`refusal` (None otherwise)."""
        self.refusal = None
        try:
            return self.evaluate(z, above=obj)
        except (InputError, NumericalError) as exc:
            self.refusal = str(exc)
            return None

    def reduced_model(self, point: Point, rom: ReducedModel | None = None) -> ReducedModel:
        """The reduced model of the configurations (:mod:`eigenupdate.solve.reduced`)
        exact at ``point``: ``rom`` anchored there, or a new one."""
        if rom is None:
            return ReducedModel(self.model, self.configurations, self.modes, point.lin,
                                self.full(point.z), self.warm.operator)
        rom.anchor(point.lin, self.full(point.z))
        return rom

    def reduced_step(self, point: Point, rom: ReducedModel) -> Point | None:
        """The optimum of ``rom`` (exact at ``point``) under the current pairing, solved
        in full: that point if its objective is below ``point``'s, else None."""
        pairing, prior, z0 = self.pairing, self.prior, self.z0
        cache: dict[bytes, tuple[np.ndarray, np.ndarray]] = {}
        far = np.full(point.f.size, np.sqrt(1e6 * (point.obj + 1.0) / point.f.size))

        def equations(z):
            key = z.tobytes()
            if key not in cache:
                try:
                    lam, J = rom.evaluate(z * self.scale)
                except np.linalg.LinAlgError:  # a trial far outside: a step too long
                    return far, point.A
                lam, Jn = pairing.paired(lam, J * self.scale, point.perm)
                r, Ar = pairing.equations(lam, Jn)
                cache.clear()
                cache[key] = (np.concatenate([r, prior * (z - z0)]),
                              np.vstack([Ar, np.diag(prior)]))
            return cache[key]

        # the model is exact at its point: the point's own equations, without an evaluation
        cache[point.z.tobytes()] = (point.f, point.A)
        # dogbox, as the trust region of the full problem (see its module for why)
        res = least_squares(lambda z: equations(z)[0], point.z, jac=lambda z: equations(z)[1],
                            bounds=(self.lower, np.inf), method="dogbox", xtol=REDUCED_XTOL,
                            max_nfev=REDUCED_NFEV)
        trial = self.attempt(res.x, point.obj)
        return trial if trial is not None and trial.obj < point.obj else None

    def paired(self, z: np.ndarray, lin: Linearisation) -> Point:
        """The point z with linearisation ``lin`` under the current pairing."""
        pairing = self.pairing
        perm, pending = pairing.match(lin.shapes)
        lam, Jn = pairing.paired(lin.eigenvalues, lin.normalised, perm)
        r, Ar = pairing.equations(lam, Jn)
        f = np.concatenate([r, self.prior * (z - self.z0)])
        A = np.vstack([Ar, np.diag(self.prior)])
        return Point(z.copy(), lin, perm, pending, f, A, float(f @ f))

    def restart(self, point: Point) -> Point:
        """``point`` re-paired after the pairing changed (solved afresh where it was a
        step taken without a solve); the cache holds it alone."""
        self._cache.clear()
        if point.predicted:
            point = self.evaluate(point.z)
        else:
            point = self.paired(point.z, point.lin)
        self._cache.clear()
        self._cache[point.z.tobytes()] = point
        return point

    def cluster(self, point: Point) -> Point:
        """Fit the most ambiguous pairs of the start through their sums, while J keeps
        enough rank (half of the redundancy); the start point under that pairing."""
        pairing, z, lin = self.pairing, point.z, point.lin
        if pairing.candidates:
            kept, refused = [], []
            fewest = z.size + (len(self.rows) - z.size + 1) // 2
            for cand in pairing.candidates:
                pairing.cluster([c[1:] for c in kept + [cand]])
                ok = len(pairing.groups) >= fewest and self.report(self.paired(z, lin)).identifiable
                (kept if ok else refused).append(cand)
            pairing.cluster([c[1:] for c in kept], refused)
            point = self.restart(point)
        pairing.accept(point.perm, point.pending, point.lin.shapes, 0)
        return point

    def report(self, p: Point) -> IdentifiabilityReport:
        """Identifiability (rank, posterior covariance) of the paired equations at p."""
        pairing, weights = self.pairing, self.weights
        Jn = pairing.paired(p.lin.eigenvalues, p.lin.normalised, p.perm)[1]
        if weights.rows is None:  # unit weights; a cluster's sum weighs 1 / sqrt(size)
            return identifiability(pairing.weights[:, None] * (pairing.S @ Jn), p.lin.names,
                                   None, weights.prior)
        return identifiability(pairing.S @ Jn, p.lin.names, pairing.weights, weights.prior)

    def stop_test(self, p: Point) -> tuple[int, str, np.ndarray] | None:
        """(status, message, step) if the Gauss-Newton step at p says converged."""
        dz, predicted = self._gauss_newton(p)
        largest = float(np.max(np.abs(dz)))
        std = None if self.weights.rows is None else resolution(p.A)
        resolved = float(np.max(np.abs(dz) / std)) if std is not None else np.inf
        if largest < self.xtol or predicted <= self.ftol * p.obj or resolved < PRECISION:
            status = 1 if largest < self.xtol else 2 if predicted <= self.ftol * p.obj else 4
            return status, (
                f"converged: largest normalised step {largest:.1e}, predicted objective "
                f"decrease {predicted / p.obj if p.obj else 0:.1e} relative"
                + (f", step {resolved:.1e} of the posterior std" if std is not None else "")
            ), dz
        joint = self._joint(p, predicted)
        if joint < JOINT**2:  # the test above on each parameter alone needs 0.01 std
            return 2, (
                f"converged at the data's precision: the Gauss-Newton step predicts an "
                f"objective decrease of {joint:.1e} data variances, so the optimum lies within "
                f"{np.sqrt(max(joint, 0.0)):.2f} posterior std (all parameters together; "
                f"largest normalised step {largest:.1e})"
            ), dz
        return None

    def solver_floor(self, p: Point) -> float:
        """The objective that eigenvalue errors of SOLVER_RTOL alone can give at p: below
        it the residuals are the eigen-solver's own, and a step the line search cannot
        make is no failure. (On a free-free frame with error-free data the fit stalled
        at 6.0e-13 against this floor's 7.9e-12, 8e-8 from the truth, and said 'not
        converged'.)"""
        lam = np.abs(self.pairing.paired(p.lin.eigenvalues, p.lin.normalised, p.perm)[0])
        e = self.pairing.weights * (self.pairing.S @ (SOLVER_RTOL * lam))
        return float(e @ e)

    def remaining(self, p: Point) -> str:
        """How far the optimum of the Gauss-Newton model at p still lies, for a message
        where the iteration stops short of convergence; empty if not defined."""
        joint = self._joint(p, self._gauss_newton(p)[1])
        if not np.isfinite(joint):
            return ""
        return (f"; the Gauss-Newton step predicts the optimum {np.sqrt(max(joint, 0.0)):.2g} "
                f"posterior std away (converged below {JOINT})")

    def _gauss_newton(self, p: Point) -> tuple[np.ndarray, float]:
        """The Gauss-Newton step at p and the objective decrease it predicts."""
        dz = gn_step(p.A, -p.f, p.z, self.lower)[0]
        return dz, p.obj - float(np.sum((p.A @ dz + p.f) ** 2))

    def _joint(self, p: Point, predicted: float) -> float:
        """The predicted decrease in data variances (the squared distance to the
        optimum in posterior std); inf where :meth:`variance` is not defined."""
        variance = self.variance(p)
        return predicted / variance if np.isfinite(variance) else np.inf

    def variance(self, p: Point) -> float:
        """One datum's variance in the objective's units where the data's precision is
        known and the fit matches it: 1 where the weights are 1 / std and the objective
        passes the chi-square test (below its 99.9 % quantile for the equations beyond
        the parameters); else inf, and JOINT never stops the fit. Plain least squares
        has no stated precision (its residual could be a wrong minimum's misfit), and
        an objective far above the chi-square is not noise."""
        if self.weights.rows is None or self.pairing is None:
            return np.inf
        dof = p.f.size - p.z.size
        return 1.0 if dof > 0 and p.obj <= chi2.ppf(CHI2_LEVEL, dof) else np.inf

    def record(self, i: int, z: np.ndarray, obj: float, step: float, kind: Step) -> None:
        """Append iteration i (all parameter values at z) to the history."""
        values = dict(zip(self.model.names, self.full(z).tolist(), strict=True))
        self.history.append(Iterate(i, values, obj, step, kind))

    @property
    def iterations(self) -> int:
        """Iterations recorded so far (the start is not one)."""
        return len(self.history) - 1

    def elapsed(self) -> float:
        return time.perf_counter() - self.t0
