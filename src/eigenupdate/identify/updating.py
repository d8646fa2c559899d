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

A step that would make a parameter non-physical is replaced by the bounded
least-squares step (parameters stay above 1e-3 of their initial value, or >= 0 when
that is 0); a step that raises the objective is halved until it lowers it. The history
records both; a full step that lowers the objective is taken unchanged, so plain
Gauss-Newton iterates (Table 4) are reproduced exactly.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import lsq_linear

from eigenupdate.errors import InputError
from eigenupdate.identify.plausibility import check_measured_frequencies
from eigenupdate.io.measurements import Measurement, eigenvalue_std, select, to_eigenvalue
from eigenupdate.model.configurations import Configuration
from eigenupdate.model.parametric import ParametricModel
from eigenupdate.solve.jacobian import Linearisation, linearise

METHODS = ("least-squares", "weighted-least-squares", "bayesian")
MAX_HALVINGS = 30
FLOOR = 1e-3
"""A parameter with a positive initial value may not fall below FLOOR times it."""


@dataclass
class UpdateResult:
    """Outcome of :func:`update`, read like SciPy's ``OptimizeResult``.

    Attributes
    ----------
    method, converged, message, nit : as their names say; ``nit`` counts iterations.
    parameters : final value of every parameter (updated and fixed), by name.
    std : posterior standard deviation of each updated parameter, None where undefined
        (rank-deficient J without a prior; no residual degrees of freedom).
    history : one entry per iterate; ``history[0]`` is the initial model and
        ``history[i]`` the model after iteration i. Each holds ``parameters``,
        ``objective``, ``step`` (fraction of the Gauss-Newton step taken) and ``note``.
    rows : (configuration, mode) of each equation.
    measured_hz, initial_hz, updated_hz : frequencies of each row.
    model : the updated model.
    """

    method: str
    converged: bool
    message: str
    nit: int
    parameters: dict[str, float]
    std: dict[str, float | None]
    history: list[dict] = field(repr=False)
    rows: list[tuple[str, int]] = field(repr=False)
    measured_hz: np.ndarray = field(repr=False)
    initial_hz: np.ndarray = field(repr=False)
    updated_hz: np.ndarray = field(repr=False)
    model: ParametricModel = field(repr=False)

    @property
    def success(self) -> bool:
        return self.converged


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
    method : one of ``METHODS``.
    max_iterations : iteration limit.
    xtol : converged when the largest change of a normalised parameter s_j / s_j0 that
        the next step would make is below ``xtol``,
    ftol : or when the objective decrease the next step predicts is below ``ftol`` times
        the objective (with noisy data the iteration stalls at round-off otherwise).
    source : file name for error messages.
    """
    if method not in METHODS:
        raise InputError(
            f"unknown method {method!r}; expected one of {', '.join(METHODS)}",
            field="updating.method",
        )
    if max_iterations < 1:
        raise InputError("max_iterations must be >= 1", field="updating.max_iterations")
    weighted = method != "least-squares"
    upd = model.updated
    if upd.size == 0:
        raise InputError("no parameter is updated (every parameter has update = false)",
                         field="model")
    names = [model.names[j] for j in upd]
    rows = [(c.name, k) for c in configurations for k in sorted(set(modes))]
    f_meas, f_std = select(measurements, rows, weighted, source)
    check_measured_frequencies(configurations, measurements, source=source)
    lam_meas = to_eigenvalue(f_meas)
    w = 1.0 / eigenvalue_std(f_meas, f_std) if weighted else np.ones_like(lam_meas)

    scale = np.array([model.parameters[j].scale for j in upd])
    z0 = model.values[upd] / scale
    prior = np.zeros_like(z0)  # sqrt of W_s in normalised parameters
    if method == "bayesian":
        stds = [model.parameters[j].std for j in upd]
        prior = np.array([0.0 if s is None else sc / s for s, sc in zip(stds, scale, strict=True)])
        if not prior.any():
            raise InputError(
                "the bayesian method needs a std for at least one updated parameter", field="model"
            )

    def full(z: np.ndarray) -> np.ndarray:
        s = model.values.copy()
        s[upd] = z * scale
        return s

    def evaluate(z: np.ndarray) -> tuple[Linearisation, float]:
        lin = linearise(model, configurations, modes, full(z))
        r = w * (lam_meas - lin.eigenvalues)
        a = prior * (z - z0)
        return lin, float(r @ r + a @ a)

    def snapshot(z, obj, step, note) -> dict:
        return {
            "parameters": dict(zip(model.names, full(z).tolist(), strict=True)),
            "objective": obj,
            "step": step,
            "note": note,
        }

    lower = FLOOR * z0  # 0 for parameters whose initial value is 0
    z = z0.copy()
    lin, obj = evaluate(z)
    lin0 = lin
    rank = np.linalg.matrix_rank(np.vstack([w[:, None] * lin.normalised, np.diag(prior)]))
    if rank < z.size:
        # the minimum-norm step would leave the undetermined combinations at their initial
        # values and call that converged: a silently wrong answer
        raise InputError(
            f"the test plan does not determine the parameters: rank {rank} of J for "
            f"{z.size} updated parameters (see 'eigenupdate check'); add perturbations or "
            f"modes, hold parameters fixed, or give priors and use the bayesian method",
            field="perturbation / measurement.modes",
        )
    history = [snapshot(z, obj, 0.0, "initial")]
    converged, message = False, f"iteration limit ({max_iterations}) reached"
    for it in range(1, max_iterations + 1):
        A = np.vstack([w[:, None] * lin.normalised, np.diag(prior)])
        b = np.concatenate([w * (lam_meas - lin.eigenvalues), prior * (z0 - z)])
        dz, note = _step(A, b, z, lower)
        predicted = obj - float(np.sum((A @ dz - b) ** 2))  # decrease the linear model expects
        if np.max(np.abs(dz)) < xtol or predicted <= ftol * obj:
            converged = True
            message = (
                f"converged: largest normalised step {np.max(np.abs(dz)):.1e}, "
                f"predicted objective decrease {predicted / obj if obj else 0:.1e} relative"
            )
            break
        alpha = 1.0
        while True:
            try:
                trial, trial_obj = evaluate(z + alpha * dz)
            except InputError:  # e.g. the trial model has lost a mode
                trial, trial_obj = None, np.inf
            if trial_obj < obj:
                break
            alpha *= 0.5
            note = "step halved: objective rose"
            if alpha < 0.5**MAX_HALVINGS:
                trial = None
                break
        if trial is None:
            message = (
                f"iteration {it}: no step along the Gauss-Newton direction lowers the objective"
            )
            history.append(snapshot(z, obj, 0.0, "line search failed"))
            break
        z, lin, obj = z + alpha * dz, trial, trial_obj
        history.append(snapshot(z, obj, alpha, note))
    nit = len(history) - 1

    lin_final = lin  # always the linearisation at the current z
    std = _posterior_std(lin_final, w, prior, lam_meas, method) * scale
    updated = model.with_values(full(z))
    return UpdateResult(
        method=method,
        converged=converged,
        message=message,
        nit=nit,
        parameters=dict(zip(model.names, full(z).tolist(), strict=True)),
        std={
            n: (None if not np.isfinite(s) else float(s)) for n, s in zip(names, std, strict=True)
        },
        history=history,
        rows=rows,
        measured_hz=f_meas,
        initial_hz=np.sqrt(lin0.eigenvalues) / (2 * np.pi),
        updated_hz=np.sqrt(np.maximum(lin_final.eigenvalues, 0)) / (2 * np.pi),
        model=updated,
    )


def _step(A, b, z, lower) -> tuple[np.ndarray, str]:
    """Gauss-Newton step; if it would make a parameter non-physical, the bounded
    least-squares step instead (z + dz >= lower), so the direction stays a descent one."""
    dz = np.linalg.lstsq(A, b, rcond=None)[0]
    if np.all(z + dz >= lower):
        return dz, "full step"
    dz = lsq_linear(A, b, bounds=(lower - z, np.inf), method="bvls").x
    return dz, "step bounded: a parameter would become non-physical"


def _posterior_std(lin, w, prior, lam_meas, method) -> np.ndarray:
    """Posterior std of the normalised parameters (NaN where undefined)."""
    A = w[:, None] * lin.normalised
    H = A.T @ A + np.diag(prior**2)
    p = H.shape[0]
    if np.linalg.matrix_rank(H) < p:
        return np.full(p, np.nan)
    cov = np.linalg.inv(H)
    if method == "least-squares":
        dof = A.shape[0] - p
        if dof <= 0:
            return np.full(p, np.nan)
        r = lam_meas - lin.eigenvalues
        cov = cov * float(r @ r) / dof
    return np.sqrt(np.maximum(np.diag(cov), 0.0))
