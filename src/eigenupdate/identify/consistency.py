"""Do the measured frequencies accept the fitted model? A chi-square test of the final
residuals against the stated frequency std.

A converged iteration only says the parameters stopped moving. If two configurations'
values of one mode are exchanged (a labelling slip, or modes paired by shape across a
crossing), each value still obeys the ordering laws of
:mod:`eigenupdate.identify.plausibility`, and the iteration converges, to a wrong model
(on the paper's Fig. 2 data, mode 2 of '0.35 kg at 1' and '0.35 kg at 2' exchanged gives
a mass 371 % wrong), but the residuals stay far above the measurement noise. Under a
correct model with Gaussian frequency errors of the stated std, the sum of squared
normalised residuals (plus the prior rows of the Bayesian estimator) follows a
chi-square law with m + p_prior - rank degrees of freedom; each normalised residual is
at most a standard normal (leverage only shrinks it). The fit is rejected if the sum
exceeds the chi-square quantile at :data:`ALPHA`, or one residual exceeds the normal
quantile at ``ALPHA / (2 m)`` (Bonferroni): a correct fit is rejected with probability
at most 2 ALPHA.

A frequency without std is judged against :data:`DEFAULT_RELATIVE_STD` of itself.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import scipy.stats

from eigenupdate.measure.measurement import Measurement
from eigenupdate.model.parametric import ParametricModel

ALPHA = 1e-4
"""Probability that each test rejects a correct fit. Real data carry some model error
beyond their stated std: the paper's free beam (Table 7, std 0.5 and 1.0 Hz) fits with
chi-square 45.4 for 20 degrees of freedom, p = 1e-3; the limit at 1e-4 is 52.4."""

DEFAULT_RELATIVE_STD = 1e-4
"""std of a frequency given without one, as a fraction of it: 0.01 Hz at 100 Hz, the
resolution to which the paper tabulates its frequencies (Tables 5 and 7)."""


@dataclass(frozen=True)
class Misfit:
    """One equation: measured and fitted frequency, residual in std."""

    configuration: str
    mode: int
    measured_hz: float
    updated_hz: float
    z: float


@dataclass(frozen=True)
class Consistency:
    """Outcome of :func:`residual_consistency`.

    Attributes
    ----------
    chi2, dof, chi2_limit : the statistic, its degrees of freedom and the quantile at ALPHA.
    z_limit : the Bonferroni limit of one normalised residual.
    misfits : every frequency equation, largest |z| first.
    assumed : number of frequencies judged against DEFAULT_RELATIVE_STD (no std given).
    """

    chi2: float
    dof: int
    chi2_limit: float
    z_limit: float
    misfits: list[Misfit]
    assumed: int

    @property
    def rejected(self) -> bool:
        return bool(self.chi2 > self.chi2_limit or abs(self.misfits[0].z) > self.z_limit)

    def message(self) -> str:
        """One line: which configurations and modes do not fit, and why that matters."""
        bad = [m for m in self.misfits if abs(m.z) > self.z_limit] or self.misfits[:1]
        worst = "; ".join(f"configuration {m.configuration!r} mode {m.mode}: measured "
                          f"{m.measured_hz:.6g} Hz, fitted {m.updated_hz:.6g} Hz "
                          f"({m.z:+.1f} std)" for m in bad[:3])
        more = f" and {len(bad) - 3} more" if len(bad) > 3 else ""
        assumed = (f"; {self.assumed} frequencies have no std_hz and are judged against "
                   f"{DEFAULT_RELATIVE_STD:g} of themselves" if self.assumed else "")
        return (f"the data reject the fit: chi-square {self.chi2:.4g} for {self.dof} degrees "
                f"of freedom (limit {self.chi2_limit:.4g} at {ALPHA:g}); {worst}{more}; modes "
                f"may be exchanged between configurations or mis-numbered, or the model "
                f"cannot represent the structure{assumed}")


def residual_consistency(
    rows: list[tuple[str, int]],
    measured_hz: np.ndarray,
    updated_hz: np.ndarray,
    measurements: Mapping[tuple[str, int], Measurement],
    rank: int,
    *,
    model: ParametricModel | None = None,
    updated: Mapping[str, float] | None = None,
) -> Consistency | None:
    """The chi-square test of a fit (see the module); None without degrees of freedom.

    Parameters
    ----------
    rows : (configuration, mode) of each frequency equation.
    measured_hz, updated_hz : measured and fitted frequency of each row.
    measurements : the measurements, for their std.
    rank : rank of the fit's (weighted, stacked) Jacobian: parameters it determined.
    model, updated : the initial model and the fitted values by name: the Bayesian
        estimator's prior rows (s - s0) / sigma_s of parameters with a prior std.

    Examples
    --------
    Three frequencies, one parameter fitted, the third 5 std away:

    >>> m = {("a", k): Measurement("a", k, f, 0.1) for k, f in [(1, 10.0), (2, 20.0),
    ...                                                         (3, 30.5)]}
    >>> c = residual_consistency([("a", 1), ("a", 2), ("a", 3)], np.array([10.0, 20.0,
    ...                          30.5]), np.array([10.0, 20.0, 30.0]), m, rank=1)
    >>> c.dof, round(c.chi2, 6), c.rejected, c.misfits[0].mode
    (2, 25.0, True, 3)
    """
    measured_hz = np.asarray(measured_hz, dtype=float)
    updated_hz = np.asarray(updated_hz, dtype=float)
    std = np.array([measurements[r].std_hz or DEFAULT_RELATIVE_STD * abs(f)
                    for r, f in zip(rows, measured_hz, strict=True)])
    assumed = sum(not measurements[r].std_hz for r in rows)
    z = (measured_hz - updated_hz) / std
    prior = np.zeros(0)
    if model is not None and updated is not None:
        prior = np.array([(updated[p.name] - p.value) / p.std for p in
                          (model.parameters[j] for j in model.updated)
                          if p.std and p.name in updated])
    dof = len(rows) + prior.size - rank
    if dof <= 0 or not np.all(np.isfinite(z)) or not np.all(np.isfinite(prior)):
        return None
    chi2 = float(np.sum(z ** 2) + np.sum(prior ** 2))
    misfits = sorted((Misfit(c, k, float(f), float(u), float(zz))
                      for (c, k), f, u, zz in zip(rows, measured_hz, updated_hz, z, strict=True)),
                     key=lambda m: -abs(m.z))
    return Consistency(chi2, dof, float(scipy.stats.chi2.isf(ALPHA, dof)),
                       float(scipy.stats.norm.isf(ALPHA / (2 * len(rows)))), misfits, assumed)


def stated_covariance(model: ParametricModel, configurations, modes, fit,
                      measurements: Mapping[tuple[str, int], Measurement], method: str
                      ) -> tuple[np.ndarray, np.ndarray]:
    """(J, cov) at the fit ``fit`` (an UpdateResult): the Jacobian of its rows in
    normalised parameters, and the covariance of its estimate (physical units) from the
    stated frequency std (DEFAULT_RELATIVE_STD where none) and, for the Bayesian method,
    the prior: (J^T W J + W_s)^-1. Not the fit's own ``cov``, which an unweighted
    estimator scales by its residuals, so that a wrong fit's large residuals would make
    its confidence region large enough to hold any rival."""
    from eigenupdate.identify.weights import prior_weights
    from eigenupdate.solve.jacobian import linearise

    lin = linearise(model, configurations, modes, fit.model.values)
    jn = lin.normalised[[lin.rows.index(r) for r in fit.rows]]
    f = np.asarray(fit.measured_hz, dtype=float)
    s_lam = 8 * np.pi ** 2 * f * np.array([measurements[r].std_hz or DEFAULT_RELATIVE_STD * abs(x)
                                           for r, x in zip(fit.rows, f, strict=True)])
    prior = prior_weights(model) if method == "bayesian" else np.zeros(jn.shape[1])
    A = np.vstack([jn / s_lam[:, None], np.diag(prior)])
    cov = np.linalg.pinv(A.T @ A) * np.outer(lin.scale, lin.scale)
    return jn, cov


ALPHA_DISTINCT = 1e-4
"""Two fits are distinct answers when the second lies outside the first's
(1 - ALPHA_DISTINCT) confidence ellipsoid (see :func:`distance`)."""


def distance(x: np.ndarray, cov: np.ndarray, other: np.ndarray) -> tuple[float, float]:
    """(d2, limit): d2 = (other - x)^T cov^+ (other - x), the squared distance of
    ``other`` from the estimate ``x`` in its posterior covariance, and the chi-square
    quantile at :data:`ALPHA_DISTINCT` with len(x) degrees of freedom it is compared with.

    >>> d2, limit = distance(np.zeros(2), np.diag([1.0, 4.0]), np.array([3.0, 2.0]))
    >>> d2, round(limit, 3)       # 9 + 1; -2 ln 1e-4
    (10.0, 18.421)
    """
    dx = np.asarray(other, dtype=float) - np.asarray(x, dtype=float)
    return (float(dx @ np.linalg.pinv(cov) @ dx),
            float(scipy.stats.chi2.isf(ALPHA_DISTINCT, dx.size)))
