"""Perturbed configurations from the bare structure's factorisation: a Krylov subspace,
Rayleigh-Ritz and a residual certificate per eigenvalue.

A configuration differs from the bare structure by a diagonal low-rank term at a few
rows R: K_c = K + U diag(dk) U^T, M_c = M + U diag(dm) U^T, U the unit vectors at R.
Its modes satisfy (K - lambda M) x = -U (dk - lambda dm) x_R, so they lie in the span of
the bare structure's modes and of (K - lambda M)^-1 U, which the block Krylov space of
A^-1 M started from A^-1 U (A = K - sigma M, the factorisation already made) approximates
quickly once the bare modes are deflated. Per set of rows one subspace is built:

    V = [Phi | Q_1 ... Q_L | Q_{L+1}],  V^T M V = I,

Phi the bare structure's computed eigenpairs (rigid-body, wanted and the next ones),
Q_1 from A^-1 U, Q_{j+1} from A^-1 M Q_j, each deflated against what precedes it. The
Rayleigh-Ritz step uses Phi and Q_1..Q_L; the extra block Q_{L+1} makes
A_c^-1 M_c x exactly representable for every Ritz vector x, which gives the residual of
the shift-inverted problem in the A_c norm from small projected matrices only:

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

For the Ritz value mu = 1/theta of the operator A_c^-1 M_c (self-adjoint in the A_c inner
product) with residual norm rho, an eigenvalue lies within rho; with the gap delta to
the neighbouring Ritz values the eigenvalue error is at most rho^2/delta and the angle
of the mode at most rho/delta (Kato-Temple, Davis-Kahan). The bare modes are trusted to
the eigen-solver's tolerance (residual 1e-10, second order in the eigenvalues). The
Ritz values are also checked against interlacing: a positive semi-definite rank-k mass
addition can only lower eigenvalue i, and not below bare eigenvalue i - k (a grounded
spring: raise it, not above i + k). A configuration that fails gets EXTRA_LEVELS more
Krylov levels; if it still fails, the caller solves it by shift-invert Lanczos.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg
import scipy.sparse as sp
from scipy.linalg import blas

from eigenupdate.model.configurations import Configuration
from eigenupdate.model.parametric import ParametricModel
from eigenupdate.solve import parallel
from eigenupdate.solve.eigen import RIGID_RTOL, EigenSolution, ShiftInvert

LEVELS = 6
"""Krylov levels in the Rayleigh-Ritz basis; a configuration that fails the certificate
is tried once more with EXTRA_LEVELS more."""

EXTRA_LEVELS = 3

MAX_ROWS = 6
"""Configurations perturbing more rows use shift-invert Lanczos: each Krylov level costs
one solve per row, and a Lanczos run about 50."""

RHO_MAX = 1e3
"""Largest Gram-Schmidt cancellation |W_j|_M / sigma_min(R_j) of a Krylov level whose
projected stiffness comes from the recurrence (which amplifies the solve's rounding by it,
so by at most 1e3 x 1e-16 here); a level beyond it is formed by explicit products."""

EIG_RTOL = 1e-11
"""Certified bound on the relative error of every wanted eigenvalue."""

VEC_TOL = 1e-5
"""Bound on the angle (A norm) of every wanted mode of the certified Rayleigh-Ritz step.
A mode off by angle e gives Fox-Kapoor sensitivities off by at most about 2 e relative
to lambda. That only slows Gauss-Newton down, never moves its solution (the
eigenvalues are certified to EIG_RTOL); and the bound (rho / gap) overestimates the
angle some 100x on the benchmark frame, while the modes returned come from a basis one
Krylov level larger (measured against full re-solves: tests, benchmarks)."""

NEXT_RTOL = 1e-8
"""Bound on the next eigenvalue's relative error (it only serves the repeated-eigenvalue
test, at 1e-6)."""


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


@dataclass(frozen=True)
class RitzResult:
    """Rayleigh-Ritz solution of one configuration and its certificate.

    Attributes
    ----------
    solution : the elastic eigen-solution (modes are the Ritz vectors).
    eig_bound : (n_modes,) bound on the relative error of each wanted eigenvalue.
    vec_bound : (n_modes,) bound on the angle of each wanted mode.
    passed : whether the certificate holds (bounds below EIG_RTOL / VEC_TOL, next
        eigenvalue below NEXT_RTOL, interlacing consistent).
    coefficients : (me, n_modes) the modes' coordinates in the basis [phi | Q].
    """

    solution: EigenSolution
    eig_bound: np.ndarray
    vec_bound: np.ndarray
    passed: bool
    coefficients: np.ndarray


@dataclass
class CertificateReport:
    """What the fast path did for one set of configurations.

    Attributes
    ----------
    configurations : perturbed configurations solved (the bare structure not counted).
    passed : certified with the first Krylov subspace.
    passed_extended : certified after EXTRA_LEVELS more Krylov levels.
    fallback : solved by shift-invert Lanczos instead (certificate failed twice, or
        more than MAX_ROWS rows, or a model too small for the subspace).
    max_eig_bound, max_vec_bound : largest certified bounds among those that passed.
    levels : Krylov levels of the first subspace.
    fallback_names : the configurations solved by Lanczos.
    """

    configurations: int = 0
    passed: int = 0
    passed_extended: int = 0
    fallback: int = 0
    max_eig_bound: float = 0.0
    max_vec_bound: float = 0.0
    levels: int = LEVELS
    fallback_names: list[str] = field(default_factory=list)
    bounds: dict[str, float] = field(default_factory=dict, repr=False)
    """Largest relative eigenvalue bound of each certified configuration, by name."""

    def add(self, r: RitzResult | None, extended: bool, name: str) -> None:
        self.configurations += 1
        if r is None or not r.passed:
            self.fallback += 1
            self.fallback_names.append(name)
            return
        self.bounds[name] = float(np.max(r.eig_bound, initial=0.0))
        if extended:
            self.passed_extended += 1
        else:
            self.passed += 1
        self.max_eig_bound = max(self.max_eig_bound, float(np.max(r.eig_bound, initial=0.0)))
        self.max_vec_bound = max(self.max_vec_bound, float(np.max(r.vec_bound, initial=0.0)))

    def merge(self, other: CertificateReport) -> None:
        """Add another report's counts (e.g. over the iterations of an update)."""
        self.configurations += other.configurations
        self.passed += other.passed
        self.passed_extended += other.passed_extended
        self.fallback += other.fallback
        self.max_eig_bound = max(self.max_eig_bound, other.max_eig_bound)
        self.max_vec_bound = max(self.max_vec_bound, other.max_vec_bound)
        self.fallback_names += [n for n in other.fallback_names if n not in self.fallback_names]
        self.bounds.update(other.bounds)

    def as_dict(self) -> dict:
        return {
            "path": "krylov-rayleigh-ritz",
            "configurations": self.configurations,
            "certified": self.passed + self.passed_extended,
            "certified_with_extra_level": self.passed_extended,
            "fallback_lanczos": self.fallback,
            "fallback_configurations": list(self.fallback_names),
            "max_eigenvalue_bound": self.max_eig_bound,
            "max_mode_angle_bound": self.max_vec_bound,
            "krylov_levels": self.levels,
        }


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
        # classical Gram-Schmidt in the M inner product, twice. Against the bare modes
        # a second time only if the first pass removed a noticeable part: after level 0
        # Q_{j-1} is M-orthogonal to them, so A^-1 M Q_{j-1} holds only their residual's
        # share. The updates are BLAS products into W (beta = 1): no temporary of W's
        # size (W and its column blocks are Fortran-contiguous, so dgemm writes in place).
        size = np.sqrt(np.einsum("ij,ij->j", W, M @ W))
        again = True
        for p in range(2):
            if p == 0 or again:
                cp = Mphi.T @ W
                again = bool(np.any(np.linalg.norm(cp, axis=0) > 1e-3 * size))
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
        with np.errstate(divide="ignore"):
            rho = size.reshape(ns, k).max(axis=1) / np.sqrt(np.maximum(ev[:, 0], 0.0))
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


def ritz(
    base: Base, sub: Subspace, rows: np.ndarray, dk: Sequence[float], dm: Sequence[float],
    n_modes: int, vectors: bool = True,
) -> RitzResult:
    """Rayleigh-Ritz of one configuration in ``sub`` and its certificate.

    The configuration adds stiffness ``dk`` and mass ``dm`` at ``rows`` (repeats are
    summed); every row must be one of ``sub.rows``. Without ``vectors`` the modes are
    left as their coordinates in the basis (``RitzResult.coefficients``; the solution's
    ``modes`` is then empty).
    """
    sigma = base.op.sigma
    pos = np.searchsorted(sub.rows, rows)
    if np.any(pos >= sub.rows.size) or np.any(sub.rows[np.minimum(pos, sub.rows.size - 1)]
                                                != rows):
        raise ValueError("configuration rows outside the subspace's rows")
    k = sub.rows.size
    addk, addm = np.zeros(k), np.zeros(k)
    np.add.at(addk, pos, np.asarray(dk, float))
    np.add.at(addm, pos, np.asarray(dm, float))
    d = addk - sigma * addm
    m = sub.m
    VR = sub.rows_of_basis(base.phi)
    Gc = sub.G + VR.T @ (d[:, None] * VR)
    Mc = VR.T @ (addm[:, None] * VR)
    Mc[np.diag_indices_from(Mc)] += 1.0
    theta, Y = scipy.linalg.eigh(Gc[:m, :m], Mc[:m, :m])
    lam = theta + sigma

    rigid = np.abs(lam) < RIGID_RTOL * base.rigid_scale
    n_rigid = int(np.count_nonzero(rigid[: n_modes + 8]))
    want = np.arange(n_rigid, min(n_rigid + n_modes + 1, m))
    # residual of mu = 1/theta for A_c^-1 M_c in the A_c norm, from projected quantities
    Yw = Y[:, want]
    b = sub.H @ Yw + sub.F @ (addm[:, None] * (VR[:, :m] @ Yw))  # A^-1 M_c x
    t = VR @ b  # U^T A^-1 M_c x
    S = np.eye(k) + d[:, None] * sub.Z
    c = b - sub.F @ np.linalg.solve(S, d[:, None] * t)  # A_c^-1 M_c x (Woodbury)
    s = c
    s[:m] -= Yw / theta[want]
    rho2 = np.einsum("ij,ij->j", s, Gc @ s)
    rho = np.sqrt(np.maximum(rho2, 0.0) / theta[want])  # |x|_A^2 = theta
    mu = 1.0 / theta
    gap = np.full(want.size, np.inf)
    for a, i in enumerate(want):
        if i > 0:  # next lower eigenvalue (larger mu), certified or rigid
            lo_rho = rho[a - 1] if a > 0 else 0.0
            gap[a] = min(gap[a], mu[i - 1] - lo_rho - mu[i])
        if i + 1 < m:
            hi_rho = rho[a + 1] if a + 1 < want.size else 0.0
            gap[a] = min(gap[a], mu[i] - mu[i + 1] - hi_rho)
    gap = np.maximum(gap, 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        dmu = np.where(gap > rho, rho**2 / gap, rho)
        vec = np.where(gap > 0, rho / gap, np.inf)
    eig = dmu / mu[want] * theta[want] / np.abs(lam[want])  # relative error in lambda
    passed = bool(want.size == n_modes + 1 and np.all(eig[:-1] <= EIG_RTOL)
                  and np.all(vec[:-1] <= VEC_TOL) and eig[-1] <= NEXT_RTOL)
    if passed:
        passed = _interlaces(base.lam, lam, addk, addm, eig, want)
    # the solution returned: Rayleigh-Ritz in the whole basis, which contains the one
    # certified (its Ritz values are lower, so closer to the true ones, and the bounds
    # still hold for them)
    theta_e, Ye = scipy.linalg.eigh(Gc, Mc)
    lam_e = theta_e + sigma
    use = want[:n_modes]
    coef = Ye[:, use]
    modes = _vectors(base.phi, sub.Q, coef) if vectors else np.empty((0, use.size))
    sol = EigenSolution(lam_e[use].copy(), modes, n_rigid,
                        float(lam_e[want[-1]]) if want.size > n_modes else None)
    return RitzResult(sol, eig[:n_modes], vec[:n_modes], passed, coef)


def _vectors(phi: np.ndarray, Q: np.ndarray, coef: np.ndarray) -> np.ndarray:
    """[phi | Q] @ coef without forming [phi | Q]."""
    x = phi @ coef[:phi.shape[1]]
    x += Q @ coef[phi.shape[1]:]
    return x


def _interlaces(lam_base, lam, addk, addm, eig, want, rtol=1e-9) -> bool:
    """Ritz values consistent with interlacing under a PSD rank-k addition.

    Mass only lowers eigenvalue i but not below bare eigenvalue i - k; a grounded spring
    raises it but not above bare eigenvalue i + k. Ritz values are upper bounds, so the
    true value lies in [lambda (1 - eig), lambda].
    """
    km, kk = int(np.count_nonzero(addm)), int(np.count_nonzero(addk))
    nb = lam_base.size
    for a, i in enumerate(want):
        lo_i = i - km if km else i
        hi_i = i + kk if kk else i
        lower = lam_base[lo_i] if 0 <= lo_i < nb else -np.inf
        upper = lam_base[hi_i] if hi_i < nb else np.inf
        tol = rtol * abs(lam[i])
        if lam[i] < lower - tol or lam[i] * (1 - eig[a]) > upper + tol:
            return False
    return True


def solve_perturbed(
    model: ParametricModel,
    K,
    M,
    base_op: ShiftInvert,
    base_sol: EigenSolution,
    configurations: Sequence[Configuration],
    n_modes: int,
    report: CertificateReport | None = None,
) -> list[EigenSolution | None]:
    """Certified Ritz solutions of the perturbed configurations (None where the caller
    must solve: the bare structure, more than MAX_ROWS rows, or a failed certificate).

    ``base_sol`` must come from the sparse solver (its ``computed`` eigenpairs form the
    shared part of every subspace). Configurations perturbing the same rows share one
    subspace (several masses at one coordinate, paper Table 2).

    Examples
    --------
    A chain of 60 unit masses and springs, fixed at one end; 0.5 kg added at the free end.
    The Ritz eigenvalues against a dense solve of the perturbed matrices:

    >>> import numpy as np, scipy.sparse as sp
    >>> from eigenupdate.model.parameters import Parameter
    >>> from eigenupdate.model.spring_mass import Mass, Spring, spring_mass_model
    >>> from eigenupdate.model.configurations import mass_at
    >>> from eigenupdate.solve.eigen import base_operator, solve_elastic
    >>> n = 60
    >>> model = spring_mass_model([Mass(Parameter(f"m{i}", 1.0), i) for i in range(1, n + 1)],
    ...     [Spring(Parameter(f"k{i}", 1e4), (i - 1, i)) for i in range(1, n + 1)])
    >>> K, M = model.stiffness(), model.mass()
    >>> op, sol = base_operator(K, M, 3)
    >>> config = mass_at(n, 0.5)
    >>> report = CertificateReport()
    >>> ritz_sol = solve_perturbed(model, K, M, op, sol, [config], 3, report)[0]
    >>> dK, dM = config.delta(model)
    >>> exact = solve_elastic(K + dK, M + dM, 3, dense=True).eigenvalues
    >>> np.round(ritz_sol.eigenvalues, 6).tolist()
    [6.630686, 59.652379, 165.568802]
    >>> bool(np.allclose(ritz_sol.eigenvalues, exact, rtol=1e-11))
    True
    >>> report.passed, report.max_eig_bound < EIG_RTOL
    (1, True)
    """
    report = CertificateReport() if report is None else report
    report.levels = LEVELS
    out: list[EigenSolution | None] = [None] * len(configurations)
    if base_sol.computed is None:
        return out
    base = make_base(K, M, base_op, *base_sol.computed)
    groups: dict[tuple[int, ...], list[int]] = {}
    rows_of = {}
    for i, c in enumerate(configurations):
        if not c.additions:
            continue
        rows = c.rows(model)
        key = tuple(np.unique(rows).tolist())
        if len(key) > MAX_ROWS:
            report.add(None, False, c.name)
            continue
        rows_of[i] = rows
        groups.setdefault(key, []).append(i)
    fams = families(base, list(groups))
    order = [(key, i) for key, members in groups.items() for i in members]
    first = dict(zip([i for _, i in order], parallel.map_shares(
        lambda share: [fams[key].first_try(rows_of[i], *_additions(configurations[i]), n_modes)
                       for key, i in share], order, model.n), strict=True))
    retry = [i for _, i in order if first[i] is not None and not first[i].passed]
    widen(base, [fams[k] for k in groups if any(i in retry for i in groups[k])])
    for key, members in groups.items():
        for i in members:
            r, extended = first[i], False
            if i in retry and fams[key].wider is not None:
                r = ritz(base, fams[key].wider, rows_of[i], *_additions(configurations[i]),
                         n_modes)
                extended = True
            report.add(r, extended, configurations[i].name)
            if r is not None and r.passed:
                out[i] = r.solution
    return out


def _additions(c: Configuration) -> tuple[list[float], list[float]]:
    return [a.stiffness for a in c.additions], [a.mass for a in c.additions]


class Family:
    """The subspaces of one row set: the first (None if the model is too small for it)
    and, for configurations that fail the certificate, one EXTRA_LEVELS wider, which
    continues the first one's Krylov sequence."""

    def __init__(self, base: Base, blocks: Blocks | None, index: int):
        self.base = base
        self._blocks, self._index = blocks, index
        self.first = None if blocks is None else blocks.subspace(index)
        self.wider: Subspace | None = None
        self.widened = self.first is None

    def first_try(self, rows, dk, dm, n_modes: int, vectors: bool = True
                  ) -> RitzResult | None:
        """Rayleigh-Ritz in the first subspace (None if there is none)."""
        if self.first is None:
            return None
        return ritz(self.base, self.first, rows, dk, dm, n_modes, vectors)

    def solve(self, rows, dk, dm, n_modes: int, vectors: bool = True
              ) -> tuple[RitzResult | None, Subspace | None]:
        """Certified Ritz solution if there is one (else the last attempt, or None), and
        the subspace that gave it; the wider subspace is built when first needed."""
        r = self.first_try(rows, dk, dm, n_modes, vectors)
        if r is None or r.passed:
            return r, self.first
        widen(self.base, [self])
        if self.wider is None:
            return r, self.first
        return ritz(self.base, self.wider, rows, dk, dm, n_modes, vectors), self.wider


def widen(base: Base, fams: Sequence[Family]) -> None:
    """Build the wider subspaces of ``fams`` that are not built yet, together: the
    families' Krylov sequences continued by EXTRA_LEVELS levels."""
    todo: dict[int, list[Family]] = {}
    for f in fams:
        if not f.widened:
            todo.setdefault(id(f._blocks), []).append(f)
    for group in todo.values():
        blocks = group[0]._blocks
        wider = blocks.take([f._index for f in group], blocks.done + EXTRA_LEVELS)
        wider.grow(wider.capacity)
        for g, f in enumerate(group):
            f.wider, f.widened = wider.subspace(g), True


def families(base: Base, keys: Sequence[tuple[int, ...]]) -> dict[tuple[int, ...], Family]:
    """A :class:`Family` per row set (a tuple of ascending rows), first subspaces built
    together; row sets too large for the model get none (their configurations go to
    Lanczos)."""
    n, kb = base.phi.shape
    fit = [k for k in keys if 2 * (kb + (LEVELS + EXTRA_LEVELS + 1) * len(k)) <= n]
    built = dict(zip(fit, _grown(base, [np.array(k) for k in fit], LEVELS), strict=True))
    return {k: Family(base, *built.get(k, (None, 0))) for k in keys}
