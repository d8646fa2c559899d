"""Multipoint constraints (rigid elements, MPC equations) eliminated as NASTRAN does.

Each constraint makes one dependent coordinate a linear combination of others,
u_m = sum_n G_mn u_n, where an n may itself be dependent (chains of rigid elements). With
d the dependent and i the independent coordinates, u_d = (I - G_dd)^-1 G_di u_i, so
u = T u_i and the model keeps K_r = T^T K T, M_r = T^T M T: linear in K and M, so a
parameter's K_j and M_j reduce the same way.

Rigid bodies: :func:`rigid_equations` gives the equations of a rigid body whose motion is
fixed by exactly six independent components (RBE2, RBAR, NASTRAN-95's CRIGD1/2/3), at
grids whose displacement axes (CD) may differ from basic.
"""

from __future__ import annotations

import warnings

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from eigenupdate.errors import InputError
from eigenupdate.model.frame3d import skew


def rigid_map(offset: np.ndarray) -> np.ndarray:
    """6 x 6 map from a point's displacements (u, theta; basic) to those of a point
    rigidly attached at ``offset`` from it: u' = u + theta x offset, theta' = theta.

    >>> (rigid_map(np.array([1.0, 0.0, 0.0]))[1] + 0.0).tolist()  # v' = v + rz * 1
    [0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
    """
    t = np.eye(6)
    t[:3, 3:] = -skew(np.asarray(offset, float)[None])[0]
    return t


def rigid_equations(xyz: np.ndarray, frames: np.ndarray,
                    independent: list[tuple[int, int]], dependent: list[tuple[int, int]],
                    label: str) -> list[tuple[tuple[int, int], list[tuple[tuple[int, int],
                                                                              float]]]]:
    """Equations of a rigid body: each dependent (grid index, component 1-6) as a
    combination of the six independent ones.

    ``xyz`` (n, 3) positions in basic, ``frames`` (n, 3, 3) displacement axes (rows) in
    basic. The body's motion q is its displacement at the first independent grid (basic);
    a component of grid g is row c of blockdiag(F_g, F_g) rigid_map(x_g - x_0) q.
    """
    if len(independent) != 6 or len(set(independent)) != 6:
        raise InputError(f"{label}: the independent components must fix the rigid body: "
                         f"six of them, got {len(set(independent))}")
    origin = xyz[independent[0][0]]

    def row(g, c):
        f = np.zeros((6, 6))
        f[:3, :3] = f[3:, 3:] = frames[g]
        return (f @ rigid_map(xyz[g] - origin))[c - 1]

    s_ind = np.array([row(g, c) for g, c in independent])
    if np.linalg.matrix_rank(s_ind) < 6:
        raise InputError(f"{label}: the independent components do not fix the rigid body "
                         f"(a rotation or translation is left free)")
    inv = np.linalg.inv(s_ind)
    out = []
    for g, c in dependent:
        coef = row(g, c) @ inv
        terms = [(independent[k], float(v)) for k, v in enumerate(coef)
                 if abs(v) > 1e-14 * max(np.abs(coef).max(), 1.0)]
        out.append(((g, c), terms))
    return out


def interpolation_equations(xyz: np.ndarray, frames: np.ndarray, ref: int, ref_comps: list[int],
                            independent: list[tuple[int, int, float]], label: str) -> list:
    """Equations of NASTRAN's RBE3: the reference grid's components ``ref_comps`` follow
    the weighted least-squares rigid motion q of the independent (grid, translational
    component, weight) triples: q = (sum w s s^T)^-1 sum w s u, s the row that maps q to a
    component (MSC's RBE3 with translational independent components, where its weights
    need no characteristic length)."""
    rows, weights, keys = [], [], []
    for g, c, w in independent:
        if c not in (1, 2, 3):
            raise InputError(f"{label}: rotational independent components are not supported "
                             f"(only 1, 2, 3)")
        if not w > 0:
            raise InputError(f"{label}: weight {w:g} must be > 0")
        f = np.zeros((6, 6))
        f[:3, :3] = f[3:, 3:] = frames[g]
        rows.append((f @ rigid_map(xyz[g] - xyz[ref]))[c - 1])
        weights.append(w)
        keys.append((g, c))
    s = np.array(rows)
    w = np.array(weights)
    normal = s.T @ (w[:, None] * s)
    lam, vec = np.linalg.eigh(normal)
    null = vec[:, lam <= 1e-10 * lam.max()]
    fr = np.zeros((6, 6))
    fr[:3, :3] = fr[3:, 3:] = frames[ref]
    out = []
    for c in ref_comps:
        e = fr[c - 1]
        if null.size and np.abs(e @ null).max() > 1e-8:
            raise InputError(f"{label}: the independent grids do not determine component {c} "
                             f"of the reference grid (collinear grids?)")
        coef = e @ np.linalg.pinv(normal) @ (s.T * w)
        out.append(((ref, c), [(k, float(v)) for k, v in zip(keys, coef, strict=True)
                               if v != 0.0]))
    return out


def constraint_transform(n: int, dependent: np.ndarray, rows: np.ndarray,
                         cols: np.ndarray, coefs: np.ndarray, labels: list[str]
                         ) -> tuple[sp.csr_array, np.ndarray]:
    """T (n x n_i) with u = T u_i, and the independent rows i.

    ``dependent[k]`` is the row each equation k defines; the equations' terms are
    ``coefs`` at (equation ``rows``, coordinate ``cols``). ``labels[k]`` names the card
    of equation k in errors (a coordinate made dependent twice, a loop of constraints).
    """
    dependent = np.asarray(dependent, int)
    uniq, first, count = np.unique(dependent, return_index=True, return_counts=True)
    if np.any(count > 1):
        k = int(np.flatnonzero(count > 1)[0])
        twice = [labels[i] for i in np.flatnonzero(dependent == uniq[k])]
        raise InputError(f"{twice[1]}: makes a coordinate dependent that {twice[0]} already "
                         f"makes dependent (row {int(uniq[k])})")
    is_dep = np.zeros(n, bool)
    is_dep[dependent] = True
    independent = np.flatnonzero(~is_dep)
    d_index = np.full(n, -1)
    d_index[dependent] = np.arange(dependent.size)
    i_index = np.full(n, -1)
    i_index[independent] = np.arange(independent.size)
    rows, cols, coefs = (np.asarray(a) for a in (rows, cols, coefs))
    on_dep = is_dep[cols]
    nd, ni = dependent.size, independent.size
    g_dd = sp.csc_array((coefs[on_dep], (rows[on_dep], d_index[cols[on_dep]])), shape=(nd, nd))
    g_di = sp.csc_array((coefs[~on_dep], (rows[~on_dep], i_index[cols[~on_dep]])),
                        shape=(nd, ni))
    a = sp.csc_array(sp.eye_array(nd, format="csc") - g_dd)
    if g_dd.nnz:  # chains: a dependent coordinate on the right of another's equation
        with warnings.catch_warnings():
            warnings.simplefilter("error", spla.MatrixRankWarning)
            try:
                sol = sp.csr_array(spla.spsolve(a, g_di)).reshape((nd, ni))
            except (RuntimeError, spla.MatrixRankWarning):
                raise InputError("the multipoint constraints form a loop (a coordinate "
                                 "depends on itself through rigid elements or MPCs)") from None
    else:
        sol = g_di
    t = sp.csr_array((np.ones(ni), (independent, np.arange(ni))), shape=(n, ni))
    dep_rows = sp.csr_array(sol)
    perm = sp.csr_array((np.ones(nd), (dependent, np.arange(nd))), shape=(n, nd))
    return sp.csr_array(t + perm @ dep_rows), independent
