"""Linearised posterior covariance of the normalised parameters for a test plan.

One function, from the normalised sensitivity matrix, the eigenvalue weights and the prior,
for the three estimators of :mod:`eigenupdate.identify.updating`:

* ``least-squares``: the unweighted estimate with the stated measurement noise,
  C = J^+ Sigma J^+T (the sandwich; equal to the weighted one when every row has the same std);
* ``weighted-least-squares``: C = (J^T W J)^-1, W = diag(1 / sigma_lambda^2);
* ``bayesian`` (Eq. 6): C = (J^T W J + W_s)^-1, W_s = diag(1 / sigma_s^2).

Computed through the SVD of the stacked (weighted) system, never through J^T J, and
judged determined by the rank rule of :func:`eigenupdate.identify.identifiability.identifiability`,
so that a plan the planner reports is one ``eigenupdate check`` accepts, and back.
"""

from __future__ import annotations

import numpy as np

from eigenupdate.identify.identifiability import identifiability


def posterior_covariance(
    J: np.ndarray, w: np.ndarray, prior: np.ndarray, method: str
) -> np.ndarray:
    """Posterior covariance of the normalised parameters; all ``inf`` if undetermined.

    Parameters
    ----------
    J : (rows, p) sensitivity matrix with respect to the normalised parameters.
    w : (rows,) 1 / sigma_lambda of each row.
    prior : (p,) s_j0 / sigma_s of each parameter, 0 where it has no prior (used only by
        ``bayesian``).
    method : ``least-squares``, ``weighted-least-squares`` or ``bayesian``.

    Examples
    --------
    Two equations, one parameter: lambda = 100 s measured twice with std 1; the weighted
    variance is 1 / (2 * 100^2); a prior of std 0.01 (weight 100) halves it.

    >>> import numpy as np
    >>> J, w = np.array([[100.0], [100.0]]), np.ones(2)
    >>> float(posterior_covariance(J, w, np.zeros(1), "weighted-least-squares")[0, 0])
    5e-05
    >>> float(posterior_covariance(J, w, np.array([100.0]), "bayesian")[0, 0])
    3.3333333333333335e-05
    """
    p = J.shape[1]
    names = [str(j) for j in range(p)]
    if method == "least-squares":  # the estimate ignores w; the noise does not
        if J.shape[0] < p or not identifiability(J, names).identifiable:
            return np.full((p, p), np.inf)
        u, s, vt = np.linalg.svd(J, full_matrices=False)
        pinv = (vt.T / s) @ u.T  # (p, rows)
        return (pinv / w**2) @ pinv.T
    rep = identifiability(J, names, w, prior if method == "bayesian" else None)
    return rep.cov if rep.identifiable else np.full((p, p), np.inf)
