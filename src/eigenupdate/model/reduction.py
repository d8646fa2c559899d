"""Static (Guyan) reduction of K and M to a set of kept coordinates.

NASTRAN reduces a model with ASET/OMIT cards this way before the eigenvalue analysis, so
its printed frequencies are those of the reduced model: with a the kept and o the omitted
coordinates, u_o = -K_oo^-1 K_oa u_a, T = [I; -K_oo^-1 K_oa],
K_r = T^T K T = K_aa - K_ao K_oo^-1 K_oa and M_r = T^T M T (Guyan, AIAA J. 3, 1965).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from eigenupdate.errors import InputError


def guyan(k: sp.spmatrix, m: sp.spmatrix, keep: np.ndarray) -> tuple[sp.csr_array,
                                                                      sp.csr_array]:
    """K and M reduced to the rows ``keep`` (indices into K's rows).

    Examples
    --------
    Two unit springs in series to ground with unit masses, the middle one omitted:
    the kept end sees a spring of 1/2 and a mass 1 + 1/4.

    >>> k = sp.csr_array([[2.0, -1.0], [-1.0, 1.0]])
    >>> kr, mr = guyan(k, sp.eye_array(2, format="csr"), np.array([1]))
    >>> float(kr[0, 0]), float(mr[0, 0])
    (0.5, 1.25)
    """
    n = k.shape[0]
    keep = np.asarray(keep, int)
    omit = np.setdiff1d(np.arange(n), keep)
    k, m = sp.csc_array(k), sp.csr_array(m)
    if omit.size == 0:
        return sp.csr_array(k), m
    koo = sp.csc_array(k[omit][:, omit])
    koa = k[omit][:, keep].toarray()
    try:
        lu = spla.splu(koo)
        g = -lu.solve(koa)
    except RuntimeError:
        raise InputError(f"the omitted coordinates' stiffness K_oo is singular: the "
                         f"{omit.size} omitted coordinates must be restrained through the "
                         f"kept ones (ASET/OMIT)") from None
    if not np.all(np.isfinite(g)):
        raise InputError("the omitted coordinates' stiffness K_oo is singular (ASET/OMIT)")
    t = np.zeros((n, keep.size))
    t[keep, np.arange(keep.size)] = 1.0
    t[omit] = g
    kr = t.T @ (k @ t)
    mr = t.T @ (m @ t)
    return sp.csr_array((kr + kr.T) / 2), sp.csr_array((mr + mr.T) / 2)
