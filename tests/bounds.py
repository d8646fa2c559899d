"""Error bounds that the tests' tolerances follow from, not the digits of one CPU.

A backward-stable method (LAPACK's eigh and LU, SuperLU, ARPACK's Lanczos on a
factorisation) returns the exact answer to a problem perturbed, in norm, by a small
multiple of the unit round-off; its forward error is at most that multiple times the
problem's condition number. LAPACK's own error bounds write the multiple as p(n) eps with
p(n) "a modestly growing function of n" (LAPACK Users' Guide, 3rd ed., section 4.7);
``BACKWARD`` = 10 is the multiple taken here. Two results that each carry such an error
agree within the sum of their bounds.

>>> import numpy as np
>>> K, M = np.diag([1.0, 1e8]), np.eye(2)
>>> float(eigenvalue_condition(K, M, np.array([1.0]), np.array([[1.0], [0.0]]))[0])
100000001.0
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

EPS = float(np.finfo(float).eps)
BACKWARD = 10.0


def _norm1(A) -> float:
    """||A||_1, an upper bound of ||A||_2 for a symmetric A."""
    A = sp.csr_array(A) if sp.issparse(A) else np.asarray(A)
    return float(abs(A).sum(axis=0).max())


def eigenvalue_condition(K, M, lam, X) -> np.ndarray:
    """Relative normwise condition number of each eigenvalue of K x = lam M x.

    kappa = (||K|| + |lam| ||M||) ||x||_2^2 / (|lam| |x^T M x|) (Higham & Higham,
    "Structured backward error and condition of generalized eigenvalue problems", SIAM
    J. Matrix Anal. Appl. 20 (1998)), with the 1-norm bounding the 2-norm.
    """
    lam = np.asarray(lam, float)
    X = np.asarray(X, float).reshape(-1, lam.size)
    xMx = np.abs(np.einsum("ij,ij->j", X, np.asarray(M @ X)))
    return (_norm1(K) + np.abs(lam) * _norm1(M)) * np.einsum("ij,ij->j", X, X) / (
        np.abs(lam) * xMx)


def eigenvalue_floor(K, M, lam, X) -> np.ndarray:
    """Relative error a backward-stable eigen-solver may make on each eigenvalue."""
    return BACKWARD * EPS * eigenvalue_condition(K, M, lam, X)


def solve_floor(D) -> float:
    """Normwise relative error a backward-stable solve of D x = b may make."""
    D = D.toarray() if sp.issparse(D) else np.asarray(D)
    return BACKWARD * EPS * float(np.linalg.cond(D))


def inverse_entry_error(D) -> float:
    """Bound on the error of any entry of D^-1 computed by a backward-stable solve.

    |delta x| <= BACKWARD eps cond(D) ||x|| and ||x|| <= ||D^-1|| for a unit right-hand
    side, so every entry is within BACKWARD eps sigma_max / sigma_min^2.
    """
    D = D.toarray() if sp.issparse(D) else np.asarray(D)
    s = np.linalg.svd(D, compute_uv=False)
    return BACKWARD * EPS * float(s[0] / s[-1] ** 2)


def assert_eigenvalues_agree(got, ref, K, M, certified: float = 0.0) -> None:
    """``got`` equals the eigenvalues of ``ref`` (an EigenSolution of K, M) within both
    solvers' rounding floors, plus ``certified`` (relative) where ``got`` carries a
    certified bound of its own."""
    lam = np.asarray(ref.eigenvalues, float)
    floor = eigenvalue_floor(K, M, lam, ref.modes)
    rel = np.abs(np.asarray(got, float) - lam) / np.abs(lam)
    assert np.all(rel <= 2 * floor + certified), (rel, floor)


def assert_matrix_derivatives(model, rtol: float = 1e-7) -> None:
    """dK/ds_j and dM/ds_j of ``model`` (its k_terms, m_terms) against central differences
    of K(s), M(s) with h = 1e-5 s_j, entry by entry relative to the largest.

    For K(s) smooth (polynomial or rational in s_j) the truncation is ~(h/s)^2 = 1e-10 and
    the round-off eps |K| / (h/s) ~ 2e-11 relative: ``rtol`` 1e-7 leaves a wide margin and
    still fails on a wrong power or a missing term (errors of order 1).
    """
    s = model.values
    for j in range(s.size):
        h = 1e-5 * s[j]
        up, dn = s.copy(), s.copy()
        up[j] += h
        dn[j] -= h
        for exact, fun in ((model.k_terms[j], model.stiffness), (model.m_terms[j], model.mass)):
            fd = (fun(up) - fun(dn)) / (2 * h)
            if exact is None:
                assert abs(fd).max() == 0
                continue
            assert abs(exact - fd).max() <= rtol * abs(exact).max()


def assert_thickness_derivatives(mats, T: np.ndarray) -> None:
    """The exact dK/dT, dM/dT of ``mats(T)`` (a dict with K, M, dK, dM) against central
    finite differences. Truncation error is estimated from steps h and 2h (|D_h - D_2h|
    is 3/4 of D_2h's error, four times D_h's), rounding by 4 eps ||K|| / h; the exact
    derivative must be within."""
    exact = mats(T)
    for name in ("K", "M"):
        def central(step, name=name):
            return (mats(T + step)[name] - mats(T - step)[name]) / (2 * step)
        step = 1e-4 * T.min()
        d1, d2 = central(step), central(2 * step)
        scale = np.abs(exact[name]).max()
        bound = np.abs(d1 - d2) + 4 * EPS * scale / step
        assert np.all(np.abs(d1 - exact["d" + name]) <= bound + 1e-300)
