"""Static (Guyan) and dynamic (Craig-Bampton) reduction of K and M to kept coordinates.

NASTRAN reduces a model with ASET/OMIT cards this way before the eigenvalue analysis, so
its printed frequencies are those of the reduced model: with a the kept and o the omitted
coordinates, u_o = -K_oo^-1 K_oa u_a, T = [I; -K_oo^-1 K_oa],
K_r = T^T K T = K_aa - K_ao K_oo^-1 K_oa and M_r = T^T M T (Guyan, AIAA J. 3, 1965).
With QSET cards NASTRAN adds fixed-interface modes of the omitted coordinates
(:func:`craig_bampton`).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sl
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
    g = _static_modes(k[omit][:, omit], k[omit][:, keep].toarray(), omit.size)
    t = np.zeros((n, keep.size))
    t[keep, np.arange(keep.size)] = 1.0
    t[omit] = g
    kr = t.T @ (k @ t)
    mr = t.T @ (m @ t)
    return sp.csr_array((kr + kr.T) / 2), sp.csr_array((mr + mr.T) / 2)


def craig_bampton(k: sp.spmatrix, m: sp.spmatrix, boundary: np.ndarray, n_modes: int
                  ) -> tuple[sp.csr_array, sp.csr_array, np.ndarray]:
    """K and M reduced to the rows ``boundary`` and ``n_modes`` fixed-interface modes.

    The omitted coordinates o (all rows not in ``boundary``) move with the boundary b
    statically and in the lowest ``n_modes`` modes of K_oo, M_oo (the boundary held),
    mass-normalised: u = T [u_b; q], T = [[I, 0], [-K_oo^-1 K_ob, Phi]] (Craig & Bampton,
    AIAA J. 6, 1968; NASTRAN's dynamic reduction with QSET). The reduced coordinates are
    ``[boundary; q]``: u_b stays the physical boundary displacement. With every omitted
    mode kept the eigenvalues are the full model's; with fewer they are upper bounds
    (Rayleigh-Ritz).

    Parameters
    ----------
    k, m : the full (n, n) stiffness and mass.
    boundary : indices of the boundary (kept physical) rows.
    n_modes : number of fixed-interface modes kept, 1 to the number of omitted rows.

    Returns
    -------
    kr, mr : the reduced matrices, size ``boundary.size + n_modes``.
    lam : the eigenvalues of the kept fixed-interface modes, ascending.

    Raises
    ------
    InputError
        ``n_modes`` outside 1 to the number of omitted rows, K_oo singular or not
        positive definite, or the mode
        ``n_modes`` repeated by the next (the kept subspace would be arbitrary).

    Examples
    --------
    Two unit masses on unit springs in series to ground, the first one the boundary: the
    one fixed-interface mode (the second mass on its spring) keeps both frequencies
    (eigenvalues (3 -+ sqrt 5) / 2).

    >>> k = sp.csr_array([[2.0, -1.0], [-1.0, 1.0]])
    >>> kr, mr, lam = craig_bampton(k, sp.eye_array(2, format="csr"), np.array([0]), 1)
    >>> import scipy.linalg as sl
    >>> [round(float(x), 6) for x in sl.eigh(kr.toarray(), mr.toarray(), eigvals_only=True)]
    [0.381966, 2.618034]
    >>> float(lam[0])
    1.0
    """
    n = k.shape[0]
    boundary = np.asarray(boundary, int)
    omit = np.setdiff1d(np.arange(n), boundary)
    if not 1 <= n_modes <= omit.size:
        raise InputError(f"{n_modes} fixed-interface modes asked of {omit.size} omitted "
                         f"coordinates: the q-set must have 1 to {omit.size} coordinates")
    k, m = sp.csr_array(k), sp.csr_array(m)
    koo, moo = k[omit][:, omit], m[omit][:, omit]
    g = _static_modes(koo, k[omit][:, boundary].toarray(), omit.size)
    lam, phi = _lowest_modes(koo, moo, min(n_modes + 1, omit.size))
    if not np.isfinite(lam[n_modes - 1]):
        raise InputError(f"the omitted coordinates have {int(np.isfinite(lam).sum())} "
                         f"fixed-interface mode(s) with mass, fewer than the {n_modes} "
                         f"q-set coordinates")
    gap = lam[n_modes] - lam[n_modes - 1] if lam.size > n_modes else np.inf
    if gap <= 1e-8 * lam[n_modes - 1]:  # a massless next mode (inf) leaves no doubt
        raise InputError(f"fixed-interface modes {n_modes} and {n_modes + 1} have one "
                         f"frequency: which of them the {n_modes} q-set coordinates keep is "
                         f"arbitrary; give one q-set coordinate more or fewer")
    t = np.zeros((n, boundary.size + n_modes))
    t[boundary, np.arange(boundary.size)] = 1.0
    t[np.ix_(omit, np.arange(boundary.size))] = g
    t[omit, boundary.size:] = phi[:, :n_modes]
    kr = t.T @ (k @ t)
    mr = t.T @ (m @ t)
    return (sp.csr_array((kr + kr.T) / 2), sp.csr_array((mr + mr.T) / 2), lam[:n_modes])


def _static_modes(koo: sp.csr_array, koa: np.ndarray, n_omit: int) -> np.ndarray:
    """-K_oo^-1 K_oa; InputError if K_oo is singular (an omitted part held by nothing)."""
    try:
        g = -spla.splu(sp.csc_array(koo)).solve(koa)
    except RuntimeError:
        raise InputError(f"the omitted coordinates' stiffness K_oo is singular: the "
                         f"{n_omit} omitted coordinates must be restrained through the "
                         f"kept ones (ASET/OMIT)") from None
    if not np.all(np.isfinite(g)):
        raise InputError("the omitted coordinates' stiffness K_oo is singular (ASET/OMIT)")
    return g


_INDEFINITE = ("the omitted coordinates' stiffness K_oo is not positive definite (a "
               "negative stiffness among them): their fixed-interface modes are not "
               "those of a structure held at the boundary (QSET)")


def _lowest_modes(koo: sp.csr_array, moo: sp.csr_array, n: int
                  ) -> tuple[np.ndarray, np.ndarray]:
    """The ``n`` lowest eigenpairs of K_oo phi = lam M_oo phi, phi^T M_oo phi = I (lam
    inf for a mode without mass)."""
    size = koo.shape[0]
    if size <= 2000 or n >= size // 2:  # dense is quicker than ARPACK at this size
        # M phi = mu K phi with K_oo definite: massless rows (rotations of a lumped mass
        # model) are mu = 0, infinite lam, instead of a singular M_oo that eigh refuses
        try:
            mu, phi = sl.eigh(moo.toarray(), koo.toarray(),
                              subset_by_index=[size - n, size - 1])
        except np.linalg.LinAlgError:  # K_oo not definite: eigh's Cholesky of it fails
            raise InputError(_INDEFINITE) from None
        mu, phi = mu[::-1], phi[:, ::-1]
        heavy = mu > 1e-12 * max(mu[0], 0.0)
        lam = np.where(heavy, 1.0 / np.where(heavy, mu, 1.0), np.inf)
    else:
        lam, phi = spla.eigsh(sp.csc_array(koo), k=n, M=sp.csc_array(moo), sigma=0.0,
                              which="LM")
        order = np.argsort(lam)
        lam, phi = lam[order], phi[:, order]
        if lam[0] <= 0:
            raise InputError(_INDEFINITE)
    norm = np.sqrt(np.einsum("ij,ij->j", phi, moo @ phi))
    return lam, phi / np.where(np.isfinite(lam), norm, 1.0)
