"""Iterative updating of the parameters from measured eigenvalues.

Each iteration linearises the model (Eq. 1, J delta s = delta lambda) and takes a
Gauss-Newton step, in parameters normalised by their initial values:

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

A step that would make a parameter non-physical is replaced by the bounded
least-squares step (parameters stay above 1e-3 of their initial value, or >= 0 when
that is 0); a step that raises the objective is halved until it lowers it. The history
records both; a full step that lowers the objective is taken unchanged, so plain
Gauss-Newton iterates (Table 4) are reproduced exactly.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from enum import Enum

import numpy as np
from scipy.optimize import lsq_linear

from eigenupdate.errors import InputError, NumericalError
from eigenupdate.identify.identifiability import IdentifiabilityReport, identifiability
from eigenupdate.identify.plausibility import check_measured_frequencies
from eigenupdate.identify.weights import estimator_weights
from eigenupdate.io.measurements import Measurement, select, to_eigenvalue
from eigenupdate.model.configurations import Configuration
from eigenupdate.model.parametric import ParametricModel
from eigenupdate.solve.eigen import WarmStart
from eigenupdate.solve.jacobian import Linearisation, Rejected, linearise
from eigenupdate.solve.perturbed import CertificateReport

MAX_HALVINGS = 30
FLOOR = 1e-3
"""A parameter with a positive initial value may not fall below FLOOR times it."""

STATUS_MESSAGES = {
    0: "iteration limit reached",
    1: "converged: the largest normalised step is below xtol",
    2: "converged: the predicted relative objective decrease is below ftol",
    3: "stopped: no step along the Gauss-Newton direction lowers the objective",
}
"""Meaning of :attr:`UpdateResult.status` (``success`` for 1 and 2)."""


class Step(Enum):
    """How an iterate was reached; the value is the note the history prints."""

    INITIAL = "initial"
    FULL = "full step"
    BOUNDED = "step bounded: a parameter would become non-physical"
    HALVED = "step halved: objective rose"
    FAILED = "line search failed"


@dataclass(frozen=True)
class Iterate:
    """One entry of the history: the model after ``iteration`` iterations.

    ``parameters`` holds every parameter (updated and fixed) by name; ``objective`` is
    the weighted sum of squares (plus the prior term); ``step`` the fraction of the
    Gauss-Newton step taken; ``kind`` how it was taken.
    """

    iteration: int
    parameters: dict[str, float]
    objective: float
    step: float
    kind: Step

    def to_dict(self) -> dict:
        return {"iteration": self.iteration, "parameters": self.parameters,
                "objective": self.objective, "step": self.step, "note": self.kind.value}


@dataclass(frozen=True)
class UpdateResult:
    """Outcome of :func:`update`, in the shape of SciPy's ``OptimizeResult``.

    Attributes
    ----------
    x : final physical values of the updated parameters, in the order of ``names``.
    names : names of the updated parameters.
    success : True if the iteration converged; ``converged`` is the same.
    status : integer code, see :data:`STATUS_MESSAGES`.
    message : what happened, with the numbers of the convergence test.
    nit : iterations taken; ``nfev``: model linearisations (eigen-solutions + J).
    cost : half the final objective, as ``scipy.optimize.least_squares``.
    jac : d lambda / d s at the solution, physical units (equations x updated parameters).
    cov : posterior covariance of ``x`` (physical units), None where undefined.
    std : posterior standard deviation of each updated parameter by name, None where
        undefined (rank-deficient A; no residual degrees of freedom).
    method : the estimator.
    parameters : final value of every parameter (updated and fixed), by name.
    history : one :class:`Iterate` per iterate; ``history[0]`` is the initial model.
    rows : (configuration, mode) of each equation.
    measured_hz, initial_hz, updated_hz : frequencies of each row.
    identifiability : the SVD report at the solution (what ``check`` computes there).
    model : the updated model.
    solver : sparse models: what the perturbed-configuration fast path did over all
        linearisations (:meth:`eigenupdate.solve.perturbed.CertificateReport.as_dict`
        plus ``linearisations``); None on the dense path.
    """

    x: np.ndarray
    names: list[str]
    success: bool
    status: int
    message: str
    nit: int
    nfev: int
    cost: float
    jac: np.ndarray = field(repr=False)
    cov: np.ndarray | None = field(repr=False)
    std: dict[str, float | None]
    method: str
    parameters: dict[str, float]
    history: tuple[Iterate, ...] = field(repr=False)
    rows: list[tuple[str, int]] = field(repr=False)
    measured_hz: np.ndarray = field(repr=False)
    initial_hz: np.ndarray = field(repr=False)
    updated_hz: np.ndarray = field(repr=False)
    identifiability: IdentifiabilityReport = field(repr=False)
    model: ParametricModel = field(repr=False)
    solver: dict | None = field(default=None, repr=False)

    @property
    def converged(self) -> bool:
        return self.success

    def to_dict(self) -> dict:
        """JSON-ready dictionary (``eigenupdate update --json`` and ``--save``)."""
        return {
            "method": self.method,
            "converged": self.success,
            "success": self.success,
            "status": self.status,
            "message": self.message,
            "iterations": self.nit,
            "nit": self.nit,
            "nfev": self.nfev,
            "cost": self.cost,
            "names": self.names,
            "x": self.x.tolist(),
            "parameters": self.parameters,
            "std": self.std,
            "cov": None if self.cov is None else self.cov.tolist(),
            "rank": self.identifiability.rank,
            "condition_J": self.identifiability.condition_J,
            "history": [h.parameters for h in self.history],
            "steps": [{k: v for k, v in h.to_dict().items() if k in ("objective", "step", "note")}
                      for h in self.history],
            "frequencies": [
                {"configuration": c, "mode": k, "measured_hz": float(m), "initial_hz": float(i),
                 "updated_hz": float(u)}
                for (c, k), m, i, u in zip(self.rows, self.measured_hz, self.initial_hz,
                                           self.updated_hz, strict=True)
            ],
            **({"solver": self.solver} if self.solver is not None else {}),
        }


def update(
    model: ParametricModel,
    configurations: Sequence[Configuration],
    modes: Sequence[int],
    measurements: Mapping[tuple[str, int], Measurement],
    *,
    method: str = "least-squares",
    max_iterations: int = 20,
    xtol: float = 1e-8,
    ftol: float = 1e-10,
    source: str | None = None,
) -> UpdateResult:
    """Update the model's updated parameters from measured natural frequencies.

    Parameters
    ----------
    model : initial model (its parameter values are the initial estimates s_i).
    configurations : the bare structure and the perturbed ones.
    modes : elastic mode numbers used in every configuration.
    measurements : {(configuration name, mode): Measurement}; frequencies in Hz.
    method : one of :data:`eigenupdate.identify.weights.ESTIMATORS`.
    max_iterations : iteration limit.
    xtol : converged when the largest change of a normalised parameter s_j / s_j0 that
        the next step would make is below ``xtol``,
    ftol : or when the objective decrease the next step predicts is below ``ftol`` times
        the objective (with noisy data the iteration stalls at round-off otherwise).
    source : file name for error messages.
    """
    if max_iterations < 1:
        raise InputError("max_iterations must be >= 1", field="updating.max_iterations")
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

    def evaluate(z: np.ndarray, above: float | None = None) -> tuple[Linearisation, float]:
        """The linearisation at z and its objective; with ``above``, (None, inf) as soon
        as the rows already solved give an objective of at least ``above``."""
        nonlocal nfev
        nfev += 1
        a = prior * (z - z0)

        def reject(known: dict[str, np.ndarray]) -> bool:
            part = float(a @ a)
            for (name, k), i in index.items():
                if name in known:
                    part += float(w[i] * (lam_meas[i] - known[name][k - 1])) ** 2
            return part >= above

        try:
            lin = linearise(model, configurations, modes, full(z), warm=warm,
                            reject=None if above is None else reject)
        except Rejected:
            return None, np.inf
        if lin.certificate is not None:
            solver.merge(lin.certificate)
            n_lin[0] += 1
        r = w * (lam_meas - lin.eigenvalues)
        return lin, float(r @ r + a @ a)

    def attempt(z: np.ndarray, obj: float, refused: list[str]):
        """A trial point of the line search: evaluate(z), turned down as soon as its
        objective reaches ``obj``. A point the eigen-solver refuses (a density driven
        towards its floor leaves near-massless coordinates) is a step too long, not the
        end of the run: (None, inf), the reason appended to ``refused``."""
        try:
            return evaluate(z, above=obj)
        except (InputError, NumericalError) as exc:
            refused.append(str(exc))
            return None, np.inf

    def iterate(i, z, obj, step, kind) -> Iterate:
        return Iterate(i, dict(zip(model.names, full(z).tolist(), strict=True)), obj, step, kind)

    def report(lin: Linearisation) -> IdentifiabilityReport:
        return identifiability(lin.normalised, lin.names, weights.rows, weights.prior)

    lower = FLOOR * z0  # 0 for parameters whose initial value is 0
    z = z0.copy()
    lin, obj = evaluate(z)
    lin0 = lin
    plan = report(lin)
    if not plan.identifiable:
        # the minimum-norm step would leave the undetermined combinations at their initial
        # values and call that converged: a silently wrong answer
        raise InputError(
            f"the test plan does not determine the parameters: rank {plan.rank} of J for "
            f"{z.size} updated parameters (see 'eigenupdate check'); add perturbations or "
            f"modes, hold parameters fixed, or give priors and use the bayesian method",
            field="perturbation / measurement.modes",
        )
    history = [iterate(0, z, obj, 0.0, Step.INITIAL)]
    status, message = 0, f"iteration limit ({max_iterations}) reached"
    for it in range(1, max_iterations + 1):
        A = np.vstack([w[:, None] * lin.normalised, np.diag(prior)])
        b = np.concatenate([w * (lam_meas - lin.eigenvalues), prior * (z0 - z)])
        dz, kind = _step(A, b, z, lower)
        predicted = obj - float(np.sum((A @ dz - b) ** 2))  # decrease the linear model expects
        largest = float(np.max(np.abs(dz)))
        if largest < xtol or predicted <= ftol * obj:
            status = 1 if largest < xtol else 2
            message = (
                f"converged: largest normalised step {largest:.1e}, "
                f"predicted objective decrease {predicted / obj if obj else 0:.1e} relative"
            )
            break
        alpha, refused = 1.0, []
        trial, trial_obj = attempt(z + alpha * dz, obj, refused)
        while not trial_obj < obj and alpha > 0.5**MAX_HALVINGS:  # NaN is not lower
            alpha *= 0.5
            kind = Step.HALVED
            trial, trial_obj = attempt(z + alpha * dz, obj, refused)
        if not trial_obj < obj:
            status = 3
            message = (
                f"iteration {it}: no step along the Gauss-Newton direction lowers the objective"
                + (f" (a trial step was refused: {refused[-1]})" if refused else "")
            )
            history.append(iterate(it, z, obj, 0.0, Step.FAILED))
            break
        z, lin, obj = z + alpha * dz, trial, trial_obj
        history.append(iterate(it, z, obj, alpha, kind))
    nit = len(history) - 1

    final = report(lin)  # lin is always the linearisation at the current z
    cov = _posterior_cov(final, lin, w, lam_meas, method)
    cov = None if cov is None else cov * np.outer(scale, scale)
    std = np.full(upd.size, np.nan) if cov is None else np.sqrt(np.maximum(np.diag(cov), 0.0))
    names = [model.names[j] for j in upd]
    return UpdateResult(
        x=full(z)[upd],
        names=names,
        success=status in (1, 2),
        status=status,
        message=message,
        nit=nit,
        nfev=nfev,
        cost=0.5 * obj,
        jac=lin.J.copy(),
        cov=cov,
        std={n: (None if not np.isfinite(s) else float(s)) for n, s in zip(names, std,
                                                                            strict=True)},
        method=method,
        parameters=dict(zip(model.names, full(z).tolist(), strict=True)),
        history=tuple(history),
        rows=rows,
        measured_hz=f_meas,
        initial_hz=np.sqrt(lin0.eigenvalues) / (2 * np.pi),
        updated_hz=np.sqrt(np.maximum(lin.eigenvalues, 0)) / (2 * np.pi),
        identifiability=final,
        model=model.with_values(full(z)),
        solver={**solver.as_dict(), "linearisations": n_lin[0]} if n_lin[0] else None,
    )


def _step(A, b, z, lower) -> tuple[np.ndarray, Step]:
    """Gauss-Newton step; if it would make a parameter non-physical, the bounded
    least-squares step instead (z + dz >= lower), so the direction stays a descent one."""
    dz = np.linalg.lstsq(A, b, rcond=None)[0]
    if np.all(z + dz >= lower):
        return dz, Step.FULL
    dz = lsq_linear(A, b, bounds=(lower - z, np.inf), method="bvls").x
    return dz, Step.BOUNDED


def _posterior_cov(report: IdentifiabilityReport, lin: Linearisation, w: np.ndarray,
                   lam_meas: np.ndarray, method: str) -> np.ndarray | None:
    """Posterior covariance of the normalised parameters from the report's SVD; for plain
    least squares scaled by the residual variance (None where undefined)."""
    if report.cov is None:
        return None
    if method != "least-squares":
        return report.cov
    dof = lin.J.shape[0] - lin.J.shape[1]
    if dof <= 0:
        return None
    r = lam_meas - lin.eigenvalues
    return report.cov * float(r @ r) / dof
