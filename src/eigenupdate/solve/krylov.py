"""Krylov subspaces of the bare structure's factorisation for perturbed configurations.

A configuration differs from the bare structure by a diagonal low-rank term at a few
rows R: K_c = K + U diag(dk) U^T, M_c = M + U diag(dm) U^T, U the unit vectors at R.
Its modes satisfy (K - lambda M) x = -U (dk - lambda dm) x_R, so they lie in the span of
the bare structure's modes and of (K - lambda M)^-1 U, which the block Krylov space of
A^-1 M started from A^-1 U (A = K - sigma M, the factorisation already made) approximates
quickly once the bare modes are deflated. Per set of rows one subspace is built:

    V = [Phi | Q_1 ... Q_L | Q_{L+1}],  V^T M V = I,

Phi the bare structure's computed eigenpairs (rigid-body, wanted and the next ones),
Q_1 from A^-1 U, Q_{j+1} from A^-1 M Q_j, each deflated against what precedes it. The
Rayleigh-Ritz step (:mod:`eigenupdate.solve.perturbed`) uses Phi and Q_1..Q_L; the extra
block Q_{L+1} makes A_c^-1 M_c x exactly representable for every Ritz vector x, which
gives the residual of the shift-inverted problem in the A_c norm from small projected
matrices only:


* ``V^T A V``: A Q_j is known from the right-hand side of the solve that produced Q_j
  (A Q_j = (rhs_j - A V C_j) R_j^-1), which avoids forming K x: K x cancels on stiff
  models (on the 103k frame explicit products moved the Ritz values by 4e-11, the
  recurrence by 2.5e-13). But the recurrence amplifies the solve's rounding by the
  Gram-Schmidt cancellation rho_j = |W_j|_M / sigma_min(R_j); where that exceeds RHO_MAX
  (the bare modes nearly span A^-1 U, or the Krylov space is nearly exhausted) the level
  is formed by explicit products A Q_j = K Q_j - sigma M Q_j instead (on a 90-coordinate
  network level 0 had rho = 1e7 and the recurrence moved the Ritz values by 3e-11,
  beyond the certified 1e-11; explicit: 3e-13);
* ``A^-1 M V`` and ``A^-1 U`` are known in V from the orthogonalisation coefficients;
  the configuration's A_c^-1 follows by Woodbury in those coordinates.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.linalg import blas

from eigenupdate.solve import parallel
from eigenupdate.solve.eigen import ShiftInvert

LEVELS = 6
"""Krylov levels in the Rayleigh-Ritz basis; a configuration that fails the certificate
is tried once more with EXTRA_LEVELS more."""

EXTRA_LEVELS = 3

RHO_MAX = 1e3
"""Largest Gram-Schmidt cancellation |W_j|_M / sigma_min(R_j) of a Krylov level whose
projected stiffness comes from the recurrence (which amplifies the solve's rounding by it,
so by at most 1e3 x 1e-16 here); a level beyond it is formed by explicit products."""


@dataclass(frozen=True)
class Base:
    """The bare structure's shift-invert operator and every eigenpair it gave.

    Attributes
    ----------
    op : factorisation of A = K - sigma M.
    M : mass matrix (CSR).
    rigid_scale : max_i K_ii / M_ii of the bare structure: the scale of the rigid-body test
        (see :func:`eigenupdate.solve.eigen.rigid_mask`; a few added terms hardly move it).
    lam : (kb,) eigenvalues computed for the bare structure, ascending, rigid-body
        modes included.
    phi : (n, kb) their mass-normalised modes.
    Mphi : M phi.
    K : stiffness matrix (CSR), for the levels formed by explicit products.
    """

    op: ShiftInvert
    M: sp.csr_array
    rigid_scale: float
    lam: np.ndarray
    phi: np.ndarray
    Mphi: np.ndarray
    K: sp.csr_array

    @property
    def theta(self) -> np.ndarray:
        return self.lam - self.op.sigma


@dataclass(frozen=True)
class Subspace:
    """Krylov part of the basis for the configurations that perturb the rows ``rows``.

    The basis is V = [phi | Q] (``phi`` from :class:`Base`), V^T M V = I; its first ``m``
    columns are the Rayleigh-Ritz basis, the last block serves the certificate.

    Attributes
    ----------
    rows : (k,) perturbed rows, ascending.
    Q : (n, (levels + 1) k) Krylov blocks, M-orthogonal to phi.
    G : (me, me) V^T A V.
    H : (me, m) coordinates of A^-1 M V[:, :m] in V.
    F : (me, k) coordinates of A^-1 U in V.
    Z : (k, k) U^T A^-1 U.
    m : size of the Rayleigh-Ritz basis.
    levels : Krylov levels in the Rayleigh-Ritz basis.
    """

    rows: np.ndarray
    Q: np.ndarray
    G: np.ndarray
    H: np.ndarray
    F: np.ndarray
    Z: np.ndarray
    m: int
    levels: int

    def rows_of_basis(self, phi: np.ndarray) -> np.ndarray:
        """V[rows, :]."""
        return np.hstack([phi[self.rows], self.Q[self.rows]])


def make_base(K, M, op: ShiftInvert, lam: np.ndarray, phi: np.ndarray) -> Base:
    """Collect the bare structure's operator and eigenpairs (see :class:`Base`)."""
    M = sp.csr_array(M)
    phi = np.asfortranarray(phi, dtype=float)
    k, m = np.asarray(K.diagonal(), float), np.asarray(M.diagonal(), float)
    ok = m > 0
    scale = float(np.max(k[ok] / m[ok])) if ok.any() else 1.0
    return Base(op, M, scale, np.asarray(lam, float), phi, np.asfortranarray(M @ phi),
                sp.csr_array(K))


def build_subspaces(
    base: Base, row_sets: Sequence[np.ndarray], levels: int = LEVELS
) -> list[Subspace | None]:
    """Subspaces for several row sets at once (see the module docstring); None for a set
    whose Krylov space is exhausted (a model too small for the fast path).

    Sets of equal size are built together (:class:`Blocks`): each level is one
    multi-column solve, and the deflation against the bare modes and each set's own
    earlier blocks is batched over the sets. ``levels`` Krylov levels go into the
    Rayleigh-Ritz basis, one more into the certificate.
    """
    return [None if b is None else b.subspace(i) for b, i in _grown(base, row_sets, levels)]


def _grown(base: Base, row_sets, levels: int):
    """(Blocks, index in it) of each row set, ``levels + 1`` levels built."""
    sets = [np.unique(np.asarray(r, dtype=int)) for r in row_sets]
    out: list = [(None, 0)] * len(sets)
    work = []
    for k in sorted({r.size for r in sets}):
        idx = [i for i, r in enumerate(sets) if r.size == k]
        # one share of the sets per thread: the sets' subspaces are independent
        for share in np.array_split(idx, min(parallel.shares(base.phi.shape[0]), len(idx))):
            blocks = Blocks(base, np.array([sets[i] for i in share]), levels + 1)
            work.append(blocks)
            for g, i in enumerate(share):
                out[i] = (blocks, g)
    parallel.map_shares(lambda share: [b.grow(levels + 1) for b in share], work,
                        base.phi.shape[0])
    return out


class Blocks:
    """Krylov blocks of several row sets of equal size k, built level by level together.

    Level j of set g is Q_j (n x k), M-orthonormal and M-orthogonal to the bare modes and
    to the set's earlier levels; W_j = A^-1 rhs_j = V C_j + Q_j R_j records how it was
    obtained (rhs_0 = U, rhs_{j+1} = M Q_j), which :func:`_assemble` turns into the
    projected matrices (V^T A Q_j by explicit products where the recurrence would amplify
    rounding, see the module docstring). A set can be continued later with more levels
    (:meth:`take`), so
    a configuration that fails the certificate costs one more solve per level, not a
    new subspace.
    """

    def __init__(self, base: Base, rows: np.ndarray, capacity: int):
        n, kb = base.phi.shape
        ns, k = rows.shape
        self.base, self.rows, self.capacity, self.done = base, rows, capacity, 0
        # transposed blocks, set by set: QT[g] = [Q_0 ... Q_levels]^T of set g, rows
        # contiguous, so that a set's vectors are contiguous in memory
        self.QT = np.empty((ns, capacity * k, n))
        self.MQT = np.empty((ns, capacity * k, n))
        self.C: list[np.ndarray] = []  # C[j]: (ns, kb + j k, k)
        self.R: list[np.ndarray] = []  # R[j]: (ns, k, k)
        self.alive = np.ones(ns, bool)
        self.Z = np.zeros((ns, k, k))
        # explicit[j]: (ns,) which sets have level j by explicit products; GQ[j]: their
        # V^T A Q_j, (ns, kb + (j + 1) k, k) (NaN for the others)
        self.explicit: list[np.ndarray] = []
        self.GQ: list[np.ndarray] = []

    def grow(self, levels: int) -> None:
        """Build levels until ``levels`` are built (at most the capacity)."""
        while self.done < min(levels, self.capacity):
            self._level()

    def _level(self) -> None:
        base, rows = self.base, self.rows
        phi, Mphi, M = base.phi, base.Mphi, base.M
        n, kb = phi.shape
        ns, k = rows.shape
        j, jk = self.done, self.done * k
        if j == 0:
            rhs = np.zeros((n, ns * k), order="F")
            rhs[rows.ravel(), np.arange(ns * k)] = 1.0
        else:
            rhs = np.asfortranarray(self.MQT[:, jk - k:jk].reshape(ns * k, n).T)
        W = np.asfortranarray(base.op.solve(rhs).reshape(n, ns * k))
        del rhs
        if j == 0:
            self.Z = W[rows.ravel()].reshape(ns, k, ns, k)[np.arange(ns), :, np.arange(ns), :]
        WT = W.T.reshape(ns, k, n)  # a view of W
        MQT = self.MQT[:, :jk]
        C = np.zeros((ns, kb + jk, k))
        # classical Gram-Schmidt in the M inner product, twice ("twice is enough"). The
        # second pass against the bare modes costs two dense products with them, less
        # than the sparse product M W that deciding whether it is needed would take. The
        # updates are BLAS products into W (beta = 1): no temporary of W's size (W and its
        # column blocks are Fortran-contiguous, so dgemm writes in place).
        for _ in range(2):
            cp = Mphi.T @ W
            out = blas.dgemm(-1.0, phi, cp, 1.0, W, overwrite_c=True)
            assert np.shares_memory(out, W)
            C[:, :kb] += cp.T.reshape(ns, k, kb).transpose(0, 2, 1)
            if jk:
                c_own = MQT @ WT.transpose(0, 2, 1)  # (ns, j k, k)
                for g in range(ns):
                    blas.dgemm(-1.0, self.QT[g, :jk].T, c_own[g], 1.0,
                               W[:, g * k:(g + 1) * k], overwrite_c=True)
                C[:, kb:] += c_own
        MW = M @ W
        MWT = self.MQT[:, jk:jk + k]
        MWT[:] = MW.T.reshape(ns, k, n)
        del MW
        gram = WT @ MWT.transpose(0, 2, 1)
        ev, U = np.linalg.eigh((gram + gram.transpose(0, 2, 1)) / 2)
        # |W|_M before the orthogonalisation, by Pythagoras (V is M-orthonormal): the
        # removed coefficients C and what is left, diag(gram)
        size = np.sqrt(np.einsum("gik,gik->gk", C, C)
                       + np.maximum(np.einsum("gkk->gk", gram), 0.0))
        with np.errstate(divide="ignore"):
            rho = size.max(axis=1) / np.sqrt(np.maximum(ev[:, 0], 0.0))
        bad = ~(ev[:, 0] > 1e-24 * ev[:, -1])  # the Krylov space is exhausted
        self.alive &= ~bad
        ev[bad] = 1.0
        Tt = (U / np.sqrt(ev)[:, None, :]).transpose(0, 2, 1)
        QTj = self.QT[:, jk:jk + k]
        if k == 1:
            np.multiply(WT, Tt, out=QTj)
            MWT *= Tt
        else:
            np.matmul(Tt, WT, out=QTj)
            MWT[:] = Tt @ MWT
        explicit = self.alive & (rho > RHO_MAX)
        GQ = np.full((ns, kb + jk + k, k), np.nan)
        for g in np.flatnonzero(explicit):  # A Q_j = K Q_j - sigma M Q_j
            AQT = (base.K @ QTj[g].T).T - base.op.sigma * MWT[g]
            GQ[g, :kb] = (AQT @ phi).T
            GQ[g, kb:] = self.QT[g, :jk + k] @ AQT.T
        self.explicit.append(explicit)
        self.GQ.append(GQ)
        self.C.append(C)
        self.R.append(np.sqrt(ev)[:, :, None] * U.transpose(0, 2, 1))
        self.done += 1

    def take(self, sets: Sequence[int], capacity: int) -> Blocks:
        """The sets ``sets`` with what is built of them, room for ``capacity`` levels."""
        sel = np.asarray(sets, dtype=int)
        out = Blocks(self.base, self.rows[sel], capacity)
        k = self.rows.shape[1]
        jk = self.done * k
        out.QT[:, :jk] = self.QT[sel, :jk]
        out.MQT[:, :jk] = self.MQT[sel, :jk]
        out.C = [c[sel] for c in self.C]
        out.GQ = [g[sel] for g in self.GQ]
        out.explicit = [e[sel] for e in self.explicit]
        out.R = [r[sel] for r in self.R]
        out.alive, out.Z, out.done = self.alive[sel], self.Z[sel], self.done
        return out

    def subspace(self, g: int) -> Subspace | None:
        """Set g's subspace: every built level but the last in the Rayleigh-Ritz basis,
        the last for the certificate (None if its Krylov space is exhausted)."""
        if not self.alive[g]:
            return None
        k = self.rows.shape[1]
        return _assemble(self.base, self.rows[g], self.QT[g, :self.done * k].T,
                         [c[g] for c in self.C], [r[g] for r in self.R], self.Z[g],
                         [q[g] if e[g] else None for q, e in zip(self.GQ, self.explicit,
                                                                 strict=True)],
                         self.done - 1)


def _assemble(base: Base, rows, Qmat, C, R, Z, GQ, levels: int) -> Subspace:
    """One set's Subspace from its blocks and orthogonalisation coefficients."""
    phi, theta = base.phi, base.theta
    kb = phi.shape[1]
    k = rows.size
    nl = levels + 1
    me = kb + nl * k
    m = me - k
    # G = V^T A V from small matrices: A Q_j = (rhs_j - A V C_j) R_j^-1, where V^T rhs_j
    # is V[rows]^T for j = 0 and selects block j - 1 after (V^T M Q_{j-1}); a level with
    # explicit products (GQ[j] not None) takes those instead
    G = np.zeros((me, me))
    G[np.arange(kb), np.arange(kb)] = theta
    QR = Qmat[rows]
    for j in range(nl):
        c = kb + j * k
        if GQ[j] is not None:
            VtAQ, QtAQ = GQ[j][:c], GQ[j][c:]
        else:
            Vt_rhs = np.zeros((c, k))
            Qt_rhs = np.zeros((k, k))
            if j == 0:
                Vt_rhs[:kb] = phi[rows].T
                Qt_rhs = QR[:, :k].T
            else:
                Vt_rhs[c - k:c] = np.eye(k)
            Rinv = np.linalg.inv(R[j])
            VtAQ = (Vt_rhs - G[:c, :c] @ C[j]) @ Rinv
            QtAQ = (Qt_rhs - VtAQ.T @ C[j]) @ Rinv
        G[:c, c:c + k] = VtAQ
        G[c:c + k, :c] = VtAQ.T
        G[c:c + k, c:c + k] = (QtAQ + QtAQ.T) / 2
    H = np.zeros((me, m))
    H[np.arange(kb), np.arange(kb)] = 1.0 / theta
    for j in range(levels):  # A^-1 M Q_j = V_{<= j} C_{j+1} + Q_{j+1} R_{j+1}
        c0 = kb + j * k
        H[:c0 + k, c0:c0 + k] = C[j + 1]
        H[c0 + k:c0 + 2 * k, c0:c0 + k] = R[j + 1]
    F = np.zeros((me, k))
    F[:kb] = C[0]
    F[kb:kb + k] = R[0]
    return Subspace(np.asarray(rows), Qmat, G, H, F, (Z + Z.T) / 2, m, levels)
