"""Eigenvalue sensitivities by Fox & Kapoor (1968).

For a mass-normalised mode phi_i with simple eigenvalue lambda_i,

    d lambda_i / d s_j = phi_i^T (K_j - lambda_i M_j) phi_i,

with K_j = dK/ds_j and M_j = dM/ds_j. Added masses and springs are known constants,
so the same K_j, M_j serve every configuration. For a repeated eigenvalue the modes
are not unique and the eigenvalues are not differentiable in the ordinary sense; a
Jacobian built from arbitrary modes of the eigenspace would be silently wrong, so
:func:`eigenvalue_derivatives` refuses it (:class:`RepeatedEigenvalueError`).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from eigenupdate.errors import RepeatedEigenvalueError
from eigenupdate.solve.eigen import EigenSolution

__all__ = ["REPEATED_RTOL", "RepeatedEigenvalueError", "check_distinct", "eigenvalue_derivatives",
           "stacked_derivatives"]

REPEATED_RTOL = 1e-6
"""Eigenvalues closer than this (relative) count as repeated."""


def check_distinct(solution: EigenSolution, modes: Sequence[int], where: str = "") -> None:
    """Raise RepeatedEigenvalueError if a used mode (1-based) has a repeated eigenvalue."""
    lam = solution.eigenvalues
    if solution.next_eigenvalue is not None:
        lam = np.append(lam, solution.next_eigenvalue)
    for k in modes:
        i = k - 1
        for j in (i - 1, i + 1):
            if 0 <= j < lam.size:
                gap = abs(lam[j] - lam[i]) / max(abs(lam[i]), abs(lam[j]))
                if gap < REPEATED_RTOL:
                    a, b = sorted((i + 1, j + 1))
                    f = np.sqrt(max(lam[i], 0)) / (2 * np.pi)
                    raise RepeatedEigenvalueError(
                        f"modes {a} and {b} have a repeated eigenvalue ({f:.6g} Hz, relative gap "
                        f"{gap:.1e}); its derivative is not defined: break the symmetry, or "
                        f"use modes that are not repeated",
                        field=where or None,
                    )


def eigenvalue_derivatives(
    solution: EigenSolution,
    modes: Sequence[int],
    k_terms: Sequence,
    m_terms: Sequence,
    where: str = "",
) -> np.ndarray:
    """Matrix of d lambda / d s_j, one row per mode (1-based, elastic), one column per term.

    Examples
    --------
    One mass m on one spring k: lambda = k/m, so d lambda/dk = 1/m and d lambda/dm = -k/m^2.

    >>> import numpy as np
    >>> from eigenupdate.solve.eigen import solve_elastic
    >>> k, m = 800.0, 2.0
    >>> sol = solve_elastic(np.array([[k]]), np.array([[m]]), 1)
    >>> eigenvalue_derivatives(sol, [1], [np.ones((1, 1)), None], [None, np.ones((1, 1))])
    array([[   0.5, -200. ]])
    """
    check_distinct(solution, modes, where)
    idx = np.asarray(modes, dtype=int) - 1
    phi = solution.modes[:, idx]
    lam = solution.eigenvalues[idx]
    out = np.zeros((idx.size, len(k_terms)))
    for j, (kj, mj) in enumerate(zip(k_terms, m_terms, strict=True)):
        if kj is not None:
            out[:, j] += np.einsum("ij,ij->j", phi, kj @ phi)
        if mj is not None:
            out[:, j] -= lam * np.einsum("ij,ij->j", phi, mj @ phi)
    return out


def stacked_derivatives(solution: EigenSolution, modes: Sequence[int], k_stack: np.ndarray,
                        m_stack: np.ndarray, where: str = "") -> np.ndarray:
    """:func:`eigenvalue_derivatives` with dense (terms, n, n) stacks of K_j and M_j
    (zero where a parameter does not enter): one product for every parameter, for small
    models where the per-term loop costs more than the arithmetic.

    Examples
    --------
    >>> import numpy as np
    >>> from eigenupdate.solve.eigen import solve_elastic
    >>> sol = solve_elastic(np.array([[800.0]]), np.array([[2.0]]), 1)
    >>> stacked_derivatives(sol, [1], np.array([[[1.0]], [[0.0]]]),
    ...                     np.array([[[0.0]], [[1.0]]]))
    array([[   0.5, -200. ]])
    """
    check_distinct(solution, modes, where)
    idx = np.asarray(modes, dtype=int) - 1
    phi = solution.modes[:, idx]
    lam = solution.eigenvalues[idx]
    dk = np.einsum("ik,pik->kp", phi, k_stack @ phi)
    dm = np.einsum("ik,pik->kp", phi, m_stack @ phi)
    return dk - lam[:, None] * dm
