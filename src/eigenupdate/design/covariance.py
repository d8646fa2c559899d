"""Linearised posterior covariance of the normalised parameters for a test plan.

One function, from the normalised sensitivity matrix, the eigenvalue weights and the prior,
for the three estimators of :mod:`eigenupdate.identify.updating`:

* ``least-squares``: the unweighted estimate with the stated measurement noise,
  C = J^+ Sigma J^+T (the sandwich; equal to the weighted one when every row has the same std);
* ``weighted-least-squares``: C = (J^T W J)^-1, W = diag(1 / sigma_lambda^2);
* ``bayesian`` (Eq. 6): C = (J^T W J + W_s)^-1, W_s = diag(1 / sigma_s^2).

Computed through the SVD of the stacked (weighted) system, never through J^T J.
"""

from __future__ import annotations

import numpy as np

INFO_RTOL = 1e-13
"""A plan whose information matrix has an eigenvalue below this fraction of its largest (a
singular value of the weighted J below about 3e-7 of the largest) does not determine the
parameters: its variances are reported as ``inf``. The threshold is on the information
matrix because the search scores plans through it, whose round-off is about 1e-16."""


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
    if method == "least-squares":
        A = J
    elif method == "bayesian":
        A = np.vstack([w[:, None] * J, np.diag(prior)])
    else:
        A = w[:, None] * J
    if A.shape[0] < p:
        return np.full((p, p), np.inf)
    u, s, vt = np.linalg.svd(A, full_matrices=False)
    if s[-1] ** 2 <= INFO_RTOL * s[0] ** 2:
        return np.full((p, p), np.inf)
    if method == "least-squares":
        pinv = (vt.T / s) @ u.T  # (p, rows)
        return (pinv / w**2) @ pinv.T
    return (vt.T / s**2) @ vt
