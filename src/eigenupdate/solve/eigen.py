"""Elastic eigen-solutions of K phi = lambda M phi, lambda = omega^2 in (rad/s)^2.

Modes are mass-normalised (phi^T M phi = 1). Rigid-body modes are detected and
excluded, so elastic mode 1 is always the first flexible mode, whatever the supports.

Two paths:

* dense (``scipy.linalg.eigh``) for small models;
* sparse shift-invert Lanczos (``scipy.sparse.linalg.eigsh``) about a small negative
  shift sigma, so K - sigma M is non-singular even for a free structure. The LU
  factorisation of K - sigma M is kept in a :class:`ShiftInvert`; a perturbed
  configuration only adds a few diagonal terms, so its operator reuses the base
  factorisation through the Woodbury identity instead of factorising again.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass, field, replace

import numpy as np
import scipy.linalg
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from eigenupdate.errors import InputError, NotConvergedError, SingularMatrixError
from eigenupdate.solve import parallel

DENSE_LIMIT = 400
"""Models with at most this many coordinates use the dense solver."""

LANCZOS_RTOL = 1e-10
"""ARPACK's relative residual tolerance in :func:`lowest_modes`."""

FREE_SHIFT_RATIO = 20.0
"""A structure with rigid-body modes is solved about a shift between -lambda_1 / 10 and
-lambda_1 / FREE_SHIFT_RATIO (see :func:`base_operator`)."""

RIGID_RTOL = 1e-13
"""A mode is rigid when |lambda| < RIGID_RTOL * max_i K_ii / M_ii (see :func:`rigid_mask`)."""


@dataclass(frozen=True)
class EigenSolution:
    """Lowest elastic eigenpairs of one configuration.

    Attributes
    ----------
    eigenvalues : (k,) elastic eigenvalues, ascending, (rad/s)^2.
    modes : (n, k) mass-normalised mode shapes.
    n_rigid : number of rigid-body modes found and excluded.
    next_eigenvalue : the (k+1)-th elastic eigenvalue if it was computed, to detect a
        repeated eigenvalue at the edge of the modes used.
    computed : sparse path: every eigenpair Lanczos returned (lambda ascending with
        the rigid-body ones, mass-normalised modes), reused as a subspace basis by
        :mod:`eigenupdate.solve.perturbed`.
    """

    eigenvalues: np.ndarray
    modes: np.ndarray
    n_rigid: int
    next_eigenvalue: float | None = None
    computed: tuple[np.ndarray, np.ndarray] | None = field(default=None, repr=False,
                                                            compare=False)

    @property
    def frequencies_hz(self) -> np.ndarray:
        return np.sqrt(np.maximum(self.eigenvalues, 0.0)) / (2 * np.pi)


def rigid_mask(K, M, lam: np.ndarray) -> np.ndarray:
    """True for rigid-body modes (ascending ``lam``).

    A rigid-body eigenvalue is zero up to round-off, which is about machine epsilon
    times the largest eigenvalue; max_i K_ii / M_ii estimates that one, in any units.
    Eigenvalues below RIGID_RTOL times it are rigid. A model whose lowest elastic
    eigenvalue is itself near round-off (an over-refined mesh, a near-massless
    coordinate) cannot be told apart from a rigid body: that is an error, not a guess.
    """
    k, m = np.asarray(K.diagonal()), np.asarray(M.diagonal())
    ok = m > 0
    with np.errstate(over="ignore"):  # a subnormal mass: the eigenvalues are checked below
        scale = float(np.max(k[ok] / m[ok])) if ok.any() else 1.0
    if not scale > 0:  # K = 0 (e.g. a spring-mass model without springs): all rigid
        return np.ones(np.shape(lam), dtype=bool)
    rigid = np.abs(lam) < RIGID_RTOL * scale
    if rigid.any() and (~rigid).any():
        worst, first = np.max(np.abs(lam[rigid])), np.min(lam[~rigid])
        if first > 0 and worst > 1e-3 * first:
            raise InputError(
                f"cannot separate rigid-body from elastic modes: eigenvalue {worst:.3g} is at "
                f"the round-off level of this model (max K_ii/M_ii = {scale:.3g}); the model "
                f"is too ill-conditioned (over-refined mesh or near-massless coordinates)"
            )
    return rigid


def massless_hint(K, M, coordinates: np.ndarray) -> str:
    """'; coordinate c has almost no mass ...' when one coordinate's K_ii / M_ii is beyond
    1e8 times the smallest (its mode leaves the others at round-off), else ''.

    >>> K, M = np.diag([1.0, 1.0, 1.0]), np.diag([1.0, 1e-30, 1.0])
    >>> massless_hint(K, M, np.array([1, 2, 3]))
    '; coordinate 2 has almost no mass (M_ii = 1e-30, K_ii/M_ii is 1e+30 times the smallest)'
    """
    k, m = np.asarray(K.diagonal(), dtype=float), np.asarray(M.diagonal(), dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(m > 0, k / m, np.where(k > 0, np.inf, 0.0))
    finite = ratio[np.isfinite(ratio) & (ratio > 0)]
    if finite.size == 0:
        return ""
    i = int(np.argmax(ratio))
    rel = ratio[i] / np.min(finite)
    if not rel > 1e8:
        return ""
    if not m[i] > 0:
        return f"; coordinate {int(coordinates[i])} has stiffness and no mass"
    return (f"; coordinate {int(coordinates[i])} has almost no mass (M_ii = {m[i]:.3g}, "
            f"K_ii/M_ii is {rel:.3g} times the smallest)")


def _singular_cause(K, M, sigma: float) -> str:
    """Why K - sigma M cannot be factorised, in the model's terms."""
    empty = np.flatnonzero((abs(K).sum(axis=1) == 0) & (abs(M).sum(axis=1) == 0))
    if empty.size:
        rows = ", ".join(str(i + 1) for i in empty[:5]) + (" ..." if empty.size > 5 else "")
        return (f"{empty.size} coordinate(s) with neither stiffness nor mass (row(s) {rows} "
                f"of K and M are empty); remove them or connect them")
    if sigma < 0:  # K - sigma M is then semi-definite: K and M share a null vector
        return ("a motion with neither strain energy nor mass (a massless mechanism: "
                "unconnected massless coordinates, a free massless part)")
    return "the shift is an eigenvalue of the model"


class ShiftInvert:
    """LU factorisation of A = K - sigma M (``matrix``), with ``solve(b) = A^-1 b``."""

    def __init__(self, K: sp.csr_array, M: sp.csr_array, sigma: float):
        self.sigma = float(sigma)
        try:
            # K - sigma M is symmetric (positive definite for sigma < 0): a symmetric fill
            # ordering with diagonal pivots has ~8x less fill than SuperLU's default COLAMD
            # and factorises ~15x faster on a 100k-coordinate frame (benchmarks/README.md).
            # For sigma < 0, A is positive definite and diagonal pivots are as stable as
            # Cholesky's: no threshold, which would otherwise reject a shell's drilling
            # diagonals (~1e-9 of the largest) and spoil the ordering (a 5,742-coordinate
            # panel: fill 8.3M against 0.63M; benchmarks/README.md). For sigma > 0 (A
            # indefinite) the threshold lets SuperLU pivot off a tiny diagonal.
            self.matrix = sp.csc_matrix(K - self.sigma * M)
            self._lu = spla.splu(
                self.matrix,
                permc_spec="MMD_AT_PLUS_A",
                diag_pivot_thresh=0.0 if self.sigma < 0 else 0.1,
                options={"SymmetricMode": True},
            )
        except RuntimeError:  # SuperLU's "Factor is exactly singular": say which part
            raise SingularMatrixError(f"K - sigma M is singular for sigma = {sigma:g}: "
                                      f"{_singular_cause(K, M, sigma)}") from None

    def solve(self, b: np.ndarray) -> np.ndarray:
        return self._lu.solve(np.asarray(b, dtype=float))

    def updated(self, rows: np.ndarray, dk: np.ndarray, dm: np.ndarray) -> ShiftInvert:
        """Operator of A + U diag(dk - sigma dm) U^T (additions at ``rows``) by Woodbury."""
        return _Woodbury(self, rows, np.asarray(dk) - self.sigma * np.asarray(dm))


class _Woodbury(ShiftInvert):
    # (A + U D U^T)^-1 b = y - Z (D^-1 + U^T Z)^-1 y[rows],  y = A^-1 b,  Z = A^-1 U.
    # Woodbury is not backward stable: on a 70-coordinate network with three grounded
    # springs it moved Lanczos' eigenvalues by 1.6e-10 (a fresh factorisation: 1e-14).
    # One step of iterative refinement against A + U D U^T restores a backward-stable
    # solve at the cost of a second base solve.
    def __init__(self, base: ShiftInvert, rows: np.ndarray, d: np.ndarray):
        rows, inverse = np.unique(rows, return_inverse=True)
        dsum = np.zeros(rows.size)
        np.add.at(dsum, inverse, d)
        keep = dsum != 0
        self.sigma, self._base, self._rows = base.sigma, base, rows[keep]
        U = np.zeros((base._lu.shape[0], self._rows.size))
        U[self._rows, np.arange(self._rows.size)] = 1.0
        self._Z = base.solve(U)
        self._d = dsum[keep]
        S = np.diag(1.0 / self._d) + self._Z[self._rows, :]
        self._S = scipy.linalg.lu_factor(S)

    def _once(self, b: np.ndarray) -> np.ndarray:
        y = self._base.solve(b)
        return y - self._Z @ scipy.linalg.lu_solve(self._S, y[self._rows])

    def solve(self, b: np.ndarray) -> np.ndarray:
        b = np.asarray(b, dtype=float)
        if self._rows.size == 0:
            return self._base.solve(b)
        x = self._once(b)
        r = b - self._base.matrix @ x
        r[self._rows] -= self._d * x[self._rows] if x.ndim == 1 else (
            self._d[:, None] * x[self._rows])
        return x + self._once(r)


def default_shift(K: sp.csr_array, M: sp.csr_array) -> float:
    """First guess of a negative shift: 1e-8 of the median diagonal ratio K_ii / M_ii.

    The diagonal ratio scales like the highest eigenvalue, so on fine meshes this guess
    can lie beyond the lowest elastic eigenvalue; :func:`base_operator` then corrects it.
    """
    k, m = K.diagonal(), M.diagonal()
    ok = (k > 0) & (m > 0)
    ratio = np.median(k[ok] / m[ok]) if ok.any() else 1.0
    return -1e-8 * ratio


@dataclass
class WarmStart:
    """What one sparse solve of the bare structure leaves for the next one at nearby
    parameter values (the iterations of an update), filled in by :func:`base_operator`.

    The shift is not carried over: the rounding of K - sigma M alone moves the lowest
    eigenvalues ~1e-10 relative (2.5e-10 on the 103k frame between shifts 2 % apart), and a
    warm solve should agree with a cold one to the solver's tolerance (2.2e-13 there).

    Attributes
    ----------
    start : Lanczos start vector, the sum of the computed modes (almost in the wanted
        subspace: ARPACK needs 45 solves instead of 54 at a 1 % change on the 103k frame).
    sturm_shift : the missed-mode check's shift, so the next check can factorise while
        Lanczos runs (:func:`usable_shift` decides whether it still fits).
    operator : the last solve's factorisation, for a reduced model built at that point;
        released when the next solve starts (never two held at once).
    """

    start: np.ndarray | None = None
    sturm_shift: float | None = None
    operator: ShiftInvert | None = None


def base_operator(K, M, n_modes: int, check: bool = True, warm: WarmStart | None = None
                  ) -> tuple[ShiftInvert, EigenSolution]:
    """Shift-invert operator for the sparse path and the solution it gives.

    Without ``check`` the caller runs the missed-mode check
    (``sturm_check(K, M, *sol.computed[:1], sol, op)``), e.g. while it solves the
    perturbed configurations. A ``warm`` start is used and then updated.

    Lanczos on (K - sigma M)^-1 converges fastest when |sigma| is well below the lowest
    elastic eigenvalue lambda_1 (the spectrum then maps like 1/lambda), while a shift
    much closer to 0 than lambda_1 only worsens the conditioning of a free structure's
    K - sigma M. If the first guess is not below lambda_1 / 10, refactorise at
    sigma = -lambda_1 / 10; for a structure with rigid-body modes also if it lies below
    lambda_1 / FREE_SHIFT_RATIO. There the rigid-body modes sit at 1 / |sigma| in the
    operator, and the Woodbury solves of perturbed configurations lose accuracy as
    1 / sigma^2: on a free-free frame of the benchmark's family (2,214 coordinates,
    sigma = lambda_1 / 750) a configuration's eigenvalues were 2.6e-6 off a dense solve,
    at lambda_1 / 90 2e-8, at lambda_1 / 10 3e-10; a fresh factorisation at the first
    guess gives 2.4e-11.
    """
    K, M = sp.csr_array(K), sp.csr_array(M)
    n = K.shape[0]
    start = None
    if warm is not None:
        warm.operator = None  # released before the next factorisation
        start = warm.start if warm.start is not None and warm.start.shape == (n,) else None
    op = ShiftInvert(K, M, default_shift(K, M))
    sol = _solve_sparse(K, M, n_modes, op, check=False, start=start)
    if sol.eigenvalues.size and (sol.eigenvalues[0] < 10 * abs(op.sigma) or (
            sol.n_rigid and sol.eigenvalues[0] > FREE_SHIFT_RATIO * abs(op.sigma))):
        op = ShiftInvert(K, M, -0.1 * sol.eigenvalues[0])
        sol = _solve_sparse(K, M, n_modes, op, check=False, start=start)
    if check:
        sturm_check(K, M, sol.computed[0], sol, op)
    if warm is not None:
        lam, phi = sol.computed
        warm.start, warm.sturm_shift = phi.sum(axis=1), sturm_shift(lam, sol)
        warm.operator = op
    return op, sol


def solve_elastic(
    K,
    M,
    n_modes: int,
    *,
    operator: ShiftInvert | None = None,
    dense: bool | None = None,
    n_rigid: int | None = None,
) -> EigenSolution:
    """The ``n_modes`` lowest elastic eigenpairs (and the next eigenvalue when available).

    Parameters
    ----------
    K, M : stiffness and mass, dense or sparse, symmetric; M positive definite on the
        dense path except for coordinates without any mass (condensed out statically),
        positive semi-definite on the sparse path.
    n_modes : number of elastic modes wanted.
    operator : a :class:`ShiftInvert` of these K and M (sparse path); built if None.
    dense : force the dense (True) or sparse (False) path; by default dense for small models.
    n_rigid : expected number of rigid-body modes (sparse path), e.g. the bare structure's
        for a perturbed configuration: it only sizes the first Lanczos request (default:
        room for six); if there are more, more eigenpairs are computed.

    Examples
    --------
    A free-free 2-mass chain (1 kg, 1 N/m, 1 kg): one rigid mode, one elastic at lambda = 2.

    >>> import numpy as np
    >>> sol = solve_elastic(np.array([[1., -1.], [-1., 1.]]), np.eye(2), 1)
    >>> sol.n_rigid, np.round(sol.eigenvalues, 12).tolist()
    (1, [2.0])
    """
    n = K.shape[0]
    if n_modes < 1:
        raise InputError("at least one mode is required")
    for name, a in (("stiffness", K), ("mass", M)):
        if not np.all(np.isfinite(a.data if sp.issparse(a) else np.asarray(a, dtype=float))):
            raise InputError(f"{name} matrix has non-finite entries (values out of range?)")
    if dense is None:
        dense = n <= DENSE_LIMIT and operator is None
    if dense:
        return _solve_dense(K, M, n_modes)
    return _solve_sparse(sp.csr_array(K), sp.csr_array(M), n_modes, operator, n_rigid)


def all_modes(K, M) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Every eigenpair of a small model, dense: (lambda ascending, mass-normalised phi,
    rigid-body mask)."""
    Kd = K.toarray() if sp.issparse(K) else np.asarray(K, dtype=float)
    Md = M.toarray() if sp.issparse(M) else np.asarray(M, dtype=float)
    massless = ~np.any(Md != 0, axis=1)
    if massless.any() and not massless.all():
        return _condensed(Kd, Md, massless)
    if np.count_nonzero(Md - np.diag(np.diag(Md))):
        # a singular M need not fail Cholesky (round-off leaves pivots of 1e-16): look
        # at its spectrum, else eigh returns eigenvalues of 1e40 for massless directions
        w = scipy.linalg.eigvalsh(Md)
        if w.min() <= 1e-12 * w.max():
            return _massless_directions(Kd, Md)
    lam, phi, info = _sygvd(Kd, Md)
    if info != 0:
        raise InputError(
            "mass matrix is not positive definite (a coordinate without mass?)")
    return lam, phi, rigid_mask(Kd, Md, lam)


def _sygvd(K: np.ndarray, M: np.ndarray) -> tuple[np.ndarray, np.ndarray, int]:
    """LAPACK dsygvd, the driver scipy.linalg.eigh(K, M) calls (hence its numbers, to the
    bit), without eigh's argument handling, which costs more than the solve on a model of
    a few coordinates; info != 0: M not positive definite or no convergence, where eigh
    raises LinAlgError."""
    global _SYGVD
    if K.size == 0 or not (np.isfinite(K).all() and np.isfinite(M).all()):
        try:  # eigh's own handling of these
            return (*scipy.linalg.eigh(K, M), 0)
        except np.linalg.LinAlgError:
            return np.empty(0), np.empty((0, 0)), 1
    if _SYGVD is None:
        _SYGVD = scipy.linalg.get_lapack_funcs("sygvd", (np.zeros((1, 1)),))
    lam, phi, info = _SYGVD(K, M, itype=1, jobz="V", uplo="L")
    return lam, phi, int(info)


_SYGVD = None


def _massless_directions(K: np.ndarray, M: np.ndarray):
    """Every finite eigenpair when M is singular without a zero row (a massless rotation
    about a bar's axis seen in a skewed displacement system): in M's eigenvector basis the
    null directions are massless coordinates, condensed out as :func:`_condensed` does."""
    w, q = scipy.linalg.eigh(M)
    null = w <= 1e-12 * max(w.max(initial=0.0), 0.0)
    if w.min(initial=0.0) < -1e-9 * max(w.max(initial=0.0), 0.0) or not null.any() \
            or null.all():
        raise InputError("mass matrix is not positive semi-definite (a negative mass?)")
    mq = np.diag(np.where(null, 0.0, w))
    kq = q.T @ K @ q
    lam, phi_q, rigid = _condensed(0.5 * (kq + kq.T), mq, null)
    return lam, q @ phi_q, rigid


def _condensed(K: np.ndarray, M: np.ndarray, massless: np.ndarray):
    """Every finite eigenpair when some coordinates carry no mass (lumped-mass rotations):
    static condensation onto the massive ones, as NASTRAN does; the massless coordinates
    carry only infinite eigenvalues, which are dropped."""
    a, b = np.flatnonzero(~massless), np.flatnonzero(massless)
    w, v = scipy.linalg.eigh(K[np.ix_(b, b)])
    null = w <= 1e-12 * max(w.max(initial=0.0), 0.0)
    # a massless motion with no stiffness (a free beam's lumped-mass rotation about its
    # own axis) carries no eigenvalue at all, provided it moves no massive coordinate
    if null.any() and np.abs(v[:, null].T @ K[np.ix_(b, a)]).max() > 1e-10 * np.abs(K).max():
        raise InputError(f"{int(null.sum())} massless mechanism(s): coordinates without mass "
                         f"and without stiffness of their own") from None
    vr = v[:, ~null]
    kba = vr @ ((vr.T @ K[np.ix_(b, a)]) / w[~null, None])
    kc = K[np.ix_(a, a)] - K[np.ix_(a, b)] @ kba
    kc = 0.5 * (kc + kc.T)
    lam, phi_a, rigid = all_modes(kc, M[np.ix_(a, a)])
    phi = np.empty((K.shape[0], lam.size))
    phi[a], phi[b] = phi_a, -kba @ phi_a
    return lam, phi, rigid


# one Lanczos run at a time: the missed-mode check may run one in a thread
_ARPACK = threading.Lock()


def _new_arpack_lock() -> None:
    global _ARPACK
    _ARPACK = threading.Lock()


parallel._AFTER_FORK.append(_new_arpack_lock)


def lowest_modes(K, M, k: int, op: ShiftInvert, start: np.ndarray | None = None
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The k lowest eigenpairs by shift-invert Lanczos: (lambda ascending, mass-normalised
    phi, rigid-body mask); ``start``: Lanczos start vector (default: a fixed random one)."""
    n = K.shape[0]
    linop = spla.LinearOperator((n, n), matvec=op.solve, dtype=float)
    # Ritz residuals of 1e-10 leave eigenvalue errors at round-off (they go with the
    # residual squared) and modes good to ~1e-10 / relative gap; ~20 % fewer solves than
    # ARPACK's machine-precision default.
    try:
        # a fixed start vector: the same eigenvectors (to round-off) on every run
        v0 = np.random.default_rng(0).standard_normal(n) if start is None else start
        with _ARPACK:
            lam, phi = spla.eigsh(K, k=min(k, n - 1), M=M, sigma=op.sigma, which="LM",
                                  OPinv=linop, tol=LANCZOS_RTOL, v0=v0)
    except spla.ArpackNoConvergence as exc:
        raise NotConvergedError(f"Lanczos did not converge: {len(exc.eigenvalues)} of {k} "
                                f"eigenpairs within its iteration limit") from None
    except spla.ArpackError as exc:  # "-9999: could not build an Arnoldi factorization"
        massive = int(np.count_nonzero(M.diagonal()))
        why = (f"the model has mass at only {massive} of its {n} coordinates, too few for "
               f"Lanczos to find {k} eigenpairs (the modes used, the rigid-body modes and "
               f"one more); give the massless coordinates mass or leave them out"
               if massive <= 2 * k + 1 else
               f"Lanczos found no basis for {k} eigenpairs (ARPACK info {exc.info}): K and "
               f"M may be inconsistent (a part with stiffness and no mass?)")
        raise InputError(why) from None
    order = np.argsort(lam)
    lam, phi = lam[order], phi[:, order]
    phi = phi / np.sqrt(np.einsum("ij,ij->j", phi, M @ phi))
    return lam, phi, rigid_mask(K, M, lam)


def _solve_dense(K, M, n_modes: int) -> EigenSolution:
    # No missed-mode check: all_modes returns every finite eigenvalue of the pencil (its
    # condensed branches drop only the massless coordinates' infinite ones), so the
    # count below any shift is the Sturm count by construction and no mode can be
    # skipped; an inertia count would only re-check scipy.linalg.eigh.
    lam, phi, rigid = all_modes(K, M)
    return _elastic(lam, phi, rigid, n_modes, complete=True)


def negative_count(A) -> int | None:
    """Number of negative eigenvalues of the symmetric matrix A (Sylvester's inertia),
    from a factorisation; None if the factorisation cannot tell.

    Dense: ``scipy.linalg.ldl`` (Bunch-Kaufman, 1x1 and 2x2 blocks). Sparse: SuperLU with
    a symmetric ordering and diagonal pivots; then P A P^T = L U with U = D L^T and the
    signs of diag(U) are the inertia. That holds only if SuperLU pivoted on the diagonal
    (row permutation = column permutation) and no pivot is zero: both are checked.

    >>> negative_count(np.diag([3.0, -1.0, 2.0, -5.0]))
    2
    >>> negative_count(sp.csr_array(np.array([[2.0, 1.0], [1.0, -3.0]])))
    1
    """
    if not sp.issparse(A):
        _, d, _ = scipy.linalg.ldl(np.asarray(A, dtype=float), check_finite=False)
        ev = np.linalg.eigvalsh(d)  # d is block diagonal (1x1, 2x2): eigenvalues are cheap
        if np.any(ev == 0) or not np.all(np.isfinite(ev)):
            return None
        return int(np.sum(ev < 0))
    try:
        lu = spla.splu(sp.csc_matrix(A), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                       options={"SymmetricMode": True})
    except RuntimeError:  # exactly singular
        return None
    d = lu.U.diagonal()
    if not np.array_equal(lu.perm_r, lu.perm_c) or np.any(d == 0) or not np.all(np.isfinite(d)):
        return None
    return int(np.sum(d < 0))


def sturm_shift(lam: np.ndarray, sol: EigenSolution) -> float | None:
    """The shift of the missed-mode check: halfway from the highest wanted eigenvalue to
    the next distinct computed one, far from both (None without wanted modes)."""
    if sol.eigenvalues.size == 0:
        return None
    top = float(sol.eigenvalues[-1])
    above = lam[lam > top * (1 + 1e-6) + 1e-300]
    return 0.5 * (top + float(above[0])) if above.size else top * (1 + 1e-6)


def usable_shift(sigma: float, lam: np.ndarray, sol: EigenSolution) -> bool:
    """Whether a count at ``sigma`` (chosen before ``lam`` was known: a warm start)
    checks this solution: above every wanted eigenvalue, below the highest computed
    one (no eigenvalue below it may be missing), and at least a tenth of the gap
    between its computed neighbours away from both (the cold shift sits halfway), so
    that rounding in the inertia cannot raise a false alarm."""
    if sol.eigenvalues.size == 0 or lam.size == 0:
        return False
    if not sol.eigenvalues[-1] < sigma < lam.max():
        return False
    lo, hi = float(np.max(lam[lam < sigma])), float(np.min(lam[lam >= sigma]))
    return bool(min(sigma - lo, hi - sigma) >= 0.1 * (hi - lo))


def sturm_check(K, M, lam: np.ndarray, sol: EigenSolution,
                operator: ShiftInvert | None = None,
                counted: tuple[float, int | None] | None = None) -> None:
    """Missed-mode check: the number of eigenvalues below a shift sigma just above the
    highest wanted one, counted from the inertia of K - sigma M (Sturm sequence, as
    NASTRAN's Lanczos does), must equal the number the solver found below sigma
    (``lam``: every computed eigenvalue, rigid ones included).

    A mode the solver skipped would silently renumber every mode above it; that is an
    error instead. If the factorisation cannot give the inertia (off-diagonal pivots),
    the sparse path repeats the Lanczos solve with more eigenpairs and checks that no
    new eigenvalue appears below sigma. Coordinates without mass (lumped-mass rotations)
    carry no finite eigenvalue; their stiffness block's negatives are subtracted.
    ``counted`` = (sigma, negative_count(K - sigma M)) made beforehand is used if
    :func:`usable_shift` accepts its sigma.
    """
    if sol.eigenvalues.size == 0:
        return
    if counted is not None and usable_shift(counted[0], lam, sol):
        sigma, count = counted
    else:
        sigma = sturm_shift(lam, sol)
        count = negative_count(K - sigma * M)
    expected = int(np.sum(lam < sigma))
    massless = np.asarray(abs(M).sum(axis=1)).ravel() == 0
    if count is not None and massless.any():
        # Haynsworth: In(K - sigma M) = In(K_bb) + In(Schur complement on the massive
        # coordinates); K_bb of the massless coordinates counts its own negatives, the
        # Schur complement the finite eigenvalues below sigma. Singular K_bb: cannot tell.
        kb = K[np.ix_(massless, massless)] if not sp.issparse(K) else \
            sp.csr_array(K)[massless][:, massless]
        kb_count = negative_count(kb)
        count = None if kb_count is None else count - kb_count
    if count is None and operator is not None:
        more = lowest_modes(K, M, min(lam.size + 6, K.shape[0] - 1), operator)[0]
        count = int(np.sum(more < sigma))
    if count is not None and count != expected and sol.n_rigid:
        # Lanczos may stop short of a large family of rigid-body modes (mechanisms of a
        # rod line); harmless to the numbering, which counts elastic modes only: compare
        # the elastic ones, those between the rigid-body threshold tau and sigma
        k, m = np.asarray(K.diagonal()), np.asarray(M.diagonal())
        tau = RIGID_RTOL * float(np.max(k[m > 0] / m[m > 0]))
        below_tau = negative_count(K - tau * M)
        if below_tau is not None:
            count -= below_tau
            expected = int(np.sum((lam < sigma) & (np.abs(lam) >= tau)))
    if count is not None and count != expected:
        raise InputError(
            f"missed-mode check failed: {count} eigenvalues lie below {sigma:.6g} (rad/s)^2 "
            f"(Sturm count of K - sigma M) but the eigen-solver found {expected}; the mode "
            f"numbering cannot be trusted (clustered or repeated eigenvalues?)")


def _solve_sparse(
    K, M, n_modes: int, operator: ShiftInvert | None, n_rigid: int | None = None,
    check: bool = True, start: np.ndarray | None = None,
) -> EigenSolution:
    if operator is None:
        return base_operator(K, M, n_modes)[1]
    n = K.shape[0]
    # room for the rigid-body modes and one extra elastic (repeated-eigenvalue check);
    # fewer wanted eigenpairs also means a smaller Lanczos basis, ~20 % faster at 100k
    k = n_modes + 1 + (6 if n_rigid is None else n_rigid)
    while True:
        k = min(k, n - 1)
        lam, phi, rigid = lowest_modes(K, M, k, operator, start)
        sol = _elastic(lam, phi, rigid, n_modes, complete=k == n - 1)
        if sol.next_eigenvalue is not None or k == n - 1:
            if check:
                sturm_check(K, M, lam, sol, operator)
            return replace(sol, computed=(lam, phi))
        k *= 2


def _elastic(lam, phi, rigid, n_modes: int, complete: bool) -> EigenSolution:
    if not np.all(np.isfinite(lam)):
        raise InputError("the eigen-solver returned non-finite eigenvalues (matrix entries "
                         "out of range?)")
    if np.any(lam[~rigid] < 0):
        raise InputError("stiffness matrix is not positive semi-definite (negative eigenvalue)")
    el = np.flatnonzero(~rigid)
    if el.size < n_modes and complete:
        raise InputError(
            f"mode {n_modes} requested but the model has only {el.size} elastic modes"
        )
    if el.size <= n_modes and not complete:
        return EigenSolution(lam[el], phi[:, el], int(rigid.sum()), None)
    nxt = float(lam[el[n_modes]]) if el.size > n_modes else None
    use = el[:n_modes]
    return EigenSolution(lam[use].copy(), phi[:, use].copy(), int(rigid.sum()), nxt)
