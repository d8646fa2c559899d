"""A reduced model of every configuration around one parameter point, for an update's
step far from the optimum.

Gauss-Newton's model of the eigenvalues is linear in the parameters: it misses how the
mode shapes change with them. Where the data see some parameters only through small
frequency shifts (densities through the added masses), that second-order error is
amplified: on the 6,228-coordinate benchmark frame, from a start 4.8 % off, the first
Gauss-Newton step leaves the parameters 23 % off and the fit needs 7 eigen-solutions of
every configuration. Rayleigh-Ritz on a basis V that holds

* the bare structure's modes computed at the point,
* the static responses A^-1 e_r at the coordinates r of the additions and one Krylov
  level A^-1 M A^-1 e_r (with the bare modes they span the configurations' modes: adding
  those modes themselves changed no step on that frame),
* A^-1 K_j phi_i for every stiffness parameter j and every bare mode phi_i used (the
  right-hand sides of the modes' derivatives, Nelson's method, with A = K - sigma M for
  K - lambda_i M),

follows the shape changes a step makes: solved to its optimum, the same start ends
1.6e-3 off (the densities' own derivative directions A^-1 M_j phi_i double the basis for
a factor of two there; alone, without the stiffnesses', they leave 0.25). The reduced
eigenvalues are corrected to the full model's values and sensitivities at the point
(first-order consistent, as a trust region's model must be), so a basis truncated to TOL
loses only curvature.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import scipy.linalg
from scipy.optimize import linear_sum_assignment

from eigenupdate.model.configurations import Configuration
from eigenupdate.model.parametric import ParametricModel
from eigenupdate.solve import parallel
from eigenupdate.solve.eigen import ShiftInvert
from eigenupdate.solve.jacobian import Linearisation
from eigenupdate.solve.restricted import projected

TOL = 1e-12
"""Basis directions whose M-norm, after the columns are M-normalised, falls below
sqrt(TOL) of the largest are dropped (a shape error of 1e-4 moves an eigenvalue by
~1e-8 relative; the first-order correction absorbs the rest at the point)."""

MAX_ENTRIES = 10**8
"""Largest basis (coordinates x columns) built: the basis and its mass products take about
three times this many doubles (2.4 GB here; the 103k benchmark frame's 200 columns: 0.5
GB). A larger model or more parameters x modes are left to the trust region alone."""

EXTRA = 6
"""Reduced eigenpairs beyond the highest mode used among which the tracked ones are
chosen (modes that swap within a step)."""


class ReducedModel:
    """Reduced eigenvalues of every configuration near the point of ``lin``.

    Parameters
    ----------
    model, configurations, modes : as for :func:`eigenupdate.solve.jacobian.linearise`.
    lin : the linearisation at ``values`` (sparse path: it holds the modes' shapes).
    values : all parameter values at the point.

    Examples
    --------
    A chain of six masses on springs, its base and a mass added at the last one: the
    basis spans all six coordinates here, so the reduced model is exact at a point 20 %
    away, where the linearisation is not.

    >>> import numpy as np
    >>> from eigenupdate.model.parameters import Parameter
    >>> from eigenupdate.model.spring_mass import Mass, Spring, spring_mass_model
    >>> from eigenupdate.model.configurations import Configuration, mass_at
    >>> from eigenupdate.solve.jacobian import linearise
    >>> model = spring_mass_model(
    ...     [Mass(Parameter(f"m{i}", 1.0, update=False), i) for i in range(1, 7)],
    ...     [Spring(Parameter(f"k{i}", 100.0, update=i < 3), (i - 1, i)) for i in range(1, 7)])
    >>> configs = [Configuration("base"), mass_at(6, 0.5)]
    >>> lin = linearise(model, configs, [1, 2], dense=False)
    >>> rom = ReducedModel(model, configs, [1, 2], lin, model.values)
    >>> s = np.array([120.0, 80.0])
    >>> lam, J = rom.evaluate(s)
    >>> values = model.values.copy(); values[model.updated] = s
    >>> full = linearise(model, configs, [1, 2], values, dense=False)
    >>> float(np.max(np.abs(lam / full.eigenvalues - 1))) < 1e-9
    True
    >>> linear = lin.eigenvalues + lin.J @ (s - 100.0)
    >>> float(np.max(np.abs(linear / full.eigenvalues - 1))) > 1e-3
    True
    """

    @staticmethod
    def columns(model: ParametricModel, configurations: Sequence[Configuration],
                modes: Sequence[int]) -> int:
        """Columns of the basis before truncation (its bare modes, two per added
        coordinate, one per stiffness parameter and mode): with ``model.n``, what
        :data:`MAX_ENTRIES` bounds."""
        nm = len(set(int(k) for k in modes))
        sites = {int(r) for c in configurations for r in c.rows(model)}
        stiff = sum(model.k_terms[j] is not None for j in model.updated)
        return nm * (1 + stiff) + 2 * len(sites)

    def __init__(self, model: ParametricModel, configurations: Sequence[Configuration],
                 modes: Sequence[int], lin: Linearisation, values: np.ndarray,
                 operator: ShiftInvert | None = None):
        values = np.asarray(values, dtype=float)
        model = model.at(values)  # a nonlinear model's K_j, M_j at the point
        upd = model.updated
        self.modes = sorted(set(int(k) for k in modes))
        self.configurations = list(configurations)
        K, M = model.stiffness(values), model.mass(values)
        op = operator if _factorises(operator, K, M) else None
        if op is None:
            positive = lin.eigenvalues[lin.eigenvalues > 0]
            op = ShiftInvert(K, M, -0.1 * float(np.min(positive)) if positive.size else -1.0)
        rows = [c.rows(model) for c in configurations]
        sites = np.unique(np.concatenate(rows)) if rows else np.zeros(0, int)
        bare = next((i for i, c in enumerate(configurations) if not c.additions), 0)
        phi = np.asarray(lin.shapes[bare], dtype=float)
        kt = [model.k_terms[j] for j in upd]
        mt = [model.m_terms[j] for j in upd]
        E = np.zeros((model.n, sites.size))
        E[sites, np.arange(sites.size)] = 1.0
        static = _solve(op, E)
        X = np.hstack([phi, static, _solve(op, np.hstack(
            [np.asarray(M @ static)] + [np.asarray(k @ phi) for k in kt if k is not None]))])
        del E, static
        MX = M @ X
        norm = np.sqrt(np.maximum(np.einsum("ij,ij->j", X, MX), 1e-300))
        X /= norm
        MX /= norm
        G = _inner(X, MX)
        w, V = np.linalg.eigh(_sym(G))
        keep = w > TOL * w[-1]
        # the basis W = X T (M-orthonormal) is never formed: every projection goes
        # through X and then T, which saves two products of X's size
        T = V[:, keep] / np.sqrt(w[keep])
        # single precision for the shapes' projections in anchor(): they only choose
        # which reduced mode follows which (MAC), and halve its cost
        self._T, self._MX = T, MX.astype(np.float32)
        del MX
        self.dim = T.shape[1]
        self.K0 = _sym(T.T @ _inner(X, K @ X) @ T)
        self.M0 = _sym(T.T @ G @ T)
        # the projections of the parameter matrices, shared among threads
        terms = parallel.map_shares(
            lambda share: [None if t is None else T.T @ projected(t, X) @ T for t in share],
            kt + mt, model.n)
        self.Kj, self.Mj = terms[:len(kt)], terms[len(kt):]
        self.adds = []
        for c, r in zip(configurations, rows, strict=True):
            U = X[r] @ T
            dk = np.array([a.stiffness for a in c.additions])
            dm = np.array([a.mass for a in c.additions])
            self.adds.append((U.T @ (dk[:, None] * U), U.T @ (dm[:, None] * U)))
        self._upd = upd
        self.s0 = values[upd].copy()
        self.anchor(lin, values)

    def anchor(self, lin: Linearisation, values: np.ndarray) -> None:
        """Make the model exact in value and sensitivities at the point of ``lin``
        (all parameter values ``values``), whose modes it then follows."""
        values = np.asarray(values, dtype=float)
        nm = len(self.modes)
        R = self._T.T @ _inner(self._MX, np.concatenate(
            lin.shapes, axis=1, dtype=np.float32, casting="same_kind"))
        self.ref = [R[:, i * nm:(i + 1) * nm] for i in range(len(self.configurations))]
        self.at = values[self._upd].copy()
        self.offset = np.zeros_like(lin.eigenvalues)
        self.slope = np.zeros_like(lin.J)
        lam, J = self.evaluate(self.at)
        self.offset = lin.eigenvalues - lam
        self.slope = lin.J - J

    def evaluate(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Eigenvalues of the point's modes (in the order of its linearisation's rows,
        each followed by its shape) and d lambda / d s at updated parameter values
        ``s`` (physical units)."""
        s = np.asarray(s, dtype=float)
        dp = s - self.s0
        Kr, Mr = self.K0.copy(), self.M0.copy()
        for d, k, m in zip(dp, self.Kj, self.Mj, strict=True):
            if d:
                if k is not None:
                    Kr += d * k
                if m is not None:
                    Mr += d * m
        nm = len(self.modes)
        top = min(self.dim, self.modes[-1] + EXTRA)
        lam = np.empty(nm * len(self.configurations))
        Y = np.empty((self.dim, lam.size))
        for i, ((dK, dM), ref) in enumerate(zip(self.adds, self.ref, strict=True)):
            Mc = Mr + dM
            w, v = scipy.linalg.eigh(Kr + dK, Mc, subset_by_index=[0, top - 1])
            mac = np.abs(v.T @ (Mc @ ref))
            rows, cols = linear_sum_assignment(-mac)
            pick = rows[np.argsort(cols)]
            lam[i * nm:(i + 1) * nm] = w[pick]
            Y[:, i * nm:(i + 1) * nm] = v[:, pick]
        J = np.zeros((lam.size, len(self.Kj)))
        for j, (k, m) in enumerate(zip(self.Kj, self.Mj, strict=True)):
            if k is not None:
                J[:, j] += np.einsum("ij,ij->j", Y, k @ Y)
            if m is not None:
                J[:, j] -= lam * np.einsum("ij,ij->j", Y, m @ Y)
        return lam + self.offset + self.slope @ (s - self.at), J + self.slope


def _factorises(op: ShiftInvert | None, K, M) -> bool:
    """Whether ``op`` (the linearisation's, reused: its factorisation is 0.2-0.3 s at 103k)
    is of K - sigma M for these K, M with sigma < 0 (positive definite, as the basis
    needs); any other is refactorised."""
    if op is None or not op.sigma < 0 or op.matrix.shape != K.shape:
        return False
    diff = op.matrix - (K - op.sigma * M)
    return diff.nnz == 0 or not np.any(diff.data)


def _blocks(count: int, rows: int) -> list[tuple[int, int]]:
    """``count`` items (rows or columns of vectors of ``rows`` coordinates) cut into one
    contiguous block per thread."""
    k = max(1, min(parallel.shares(rows), count))
    cut = np.linspace(0, count, k + 1).astype(int)
    return list(zip(cut[:-1], cut[1:], strict=True))


def _solve(op: ShiftInvert, B: np.ndarray) -> np.ndarray:
    """op.solve on the columns of B, one block of columns per thread (the triangular
    solves release the GIL)."""
    n, c = B.shape
    return np.hstack(parallel.map_shares(
        lambda share: [op.solve(B[:, a:b]) for a, b in share], _blocks(c, n), n))


def _inner(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """A^T B summed over blocks of rows, one per thread (BLAS runs single-threaded)."""
    n = A.shape[0]
    return sum(parallel.map_shares(lambda share: [A[a:b].T @ B[a:b] for a, b in share],
                                   _blocks(n, n), n))


def _sym(A: np.ndarray) -> np.ndarray:
    return (A + A.T) / 2
