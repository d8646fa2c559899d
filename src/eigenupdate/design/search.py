"""Choosing a subset of candidate configurations: greedy forward selection, Fedorov-style
exchange passes, and exhaustive enumeration to measure how far the heuristic is from the
optimum.

Each candidate adds information H_c = J_c^T W_c J_c to the plan (and, for the unweighted
least-squares estimate, H_c = J_c^T J_c and the sandwich's middle G_c = J_c^T Sigma_c J_c),
so a plan is scored from p x p sums without solving anything again.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from eigenupdate.design.criteria import criterion_value

RIDGE = 1e-6
"""Relative ridge that ranks plans which do not yet determine every parameter."""

EXHAUSTIVE_LIMIT = 100_000
"""Largest number of plans enumerated to find the exact optimum."""

EXHAUSTIVE_FLOPS = 2e10
"""Largest work (plans x p^3, one eigen-decomposition of the p x p information matrix
per plan) spent on the exact optimum: about a minute; beyond, it is skipped."""

EXHAUSTIVE_COVARIANCES = 200_000
"""Largest number of covariances (plans x draws of the prior) the exact optimum may cost:
each is a p x p eigen-decomposition and some Python. The beam's 17,550 plans x 64 draws
(1.1 million) took 57 s of CPU in the beam's design; this bound keeps the exact optimum to the
cases where it is cheap next to the screening."""

INFO_RTOL = 1e-13
"""The search scores plans through the information matrix J^T W J, whose round-off is
about 1e-16 of its largest eigenvalue: a plan with an eigenvalue below this fraction of
the largest (a singular value of the weighted J below about 3e-7 of the largest) scores
``inf``. The plan reported is then judged by
:func:`eigenupdate.design.covariance.posterior_covariance` (SVD, the rank rule of
``check``)."""


@dataclass
class PlanScorer:
    """Criterion of plans made of the bare structure and some candidates.

    Parameters
    ----------
    blocks : per candidate (J, w): sensitivities of its rows with respect to the normalised
        parameters, and 1 / sigma_lambda of each row.
    base : (J, w) of the bare structure, always in the plan.
    prior : s_j0 / sigma_s per parameter (zeros unless the method is ``bayesian``).
    method : estimator, as in :func:`eigenupdate.design.covariance.posterior_covariance`.
    criterion, names : see :func:`eigenupdate.design.criteria.criterion_value`.
    """

    blocks: Sequence[tuple[np.ndarray, np.ndarray]]
    base: tuple[np.ndarray, np.ndarray]
    prior: np.ndarray
    method: str
    criterion: str | Sequence[str]
    names: Sequence[str]
    _info: list = field(init=False, repr=False)

    def __post_init__(self) -> None:
        self._info = [self._block(J, w) for J, w in self.blocks]
        # the candidates' weighted rows, stacked for the low-rank updates of keys_adding
        rows = {J.shape[0] for J, _ in self.blocks}
        self._U = (np.stack([(w[:, None] * J).T for J, w in self.blocks])
                   if len(rows) == 1 and self.method != "least-squares" else None)
        h0, g0 = self._block(*self.base)
        prior = self.prior if self.method == "bayesian" else np.zeros_like(self.prior)
        self._h0, self._g0 = h0 + np.diag(prior**2), g0
        total = np.trace(self._h0) + sum(np.trace(h) for h, _ in self._info)
        self._ridge = RIDGE * max(float(total), 1e-300) / self._h0.shape[0]

    def _block(self, J: np.ndarray, w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        if self.method == "least-squares":
            return J.T @ J, (J / w[:, None] ** 2).T @ J
        Jw = w[:, None] * J
        h = Jw.T @ Jw
        return h, h

    def covariance(self, plan: Sequence[int], ridge: float = 0.0) -> np.ndarray:
        """Posterior covariance of the bare structure plus the candidates ``plan``."""
        H = self._h0 + sum((self._info[i][0] for i in plan), np.zeros_like(self._h0))
        p = H.shape[0]
        lam, v = np.linalg.eigh(H + ridge * np.eye(p))
        if lam[-1] <= 0 or lam[0] <= INFO_RTOL * lam[-1]:
            return np.full((p, p), np.inf)
        Hinv = (v / lam) @ v.T
        if self.method != "least-squares":
            return Hinv
        G = self._g0 + sum((self._info[i][1] for i in plan), np.zeros_like(self._g0))
        return Hinv @ G @ Hinv

    def score(self, plan: Sequence[int]) -> float:
        """Criterion of a plan (``inf`` when it does not determine every parameter)."""
        return criterion_value(self.covariance(plan), self.criterion, self.names)

    def variance_terms(self, plan: Sequence[int], candidates: Sequence[int]
                       ) -> np.ndarray | None:
        """Diagonal of the covariance of ``plan`` plus each one of ``candidates``, (N, p),
        by the Woodbury identity on plan's information matrix H: adding the rows U of a
        candidate, (H + U U^T)^-1 = H^-1 - A S^-1 A^T with A = H^-1 U, S = I + U^T A.
        None where that does not apply (the sandwich of least squares, candidates of
        different row counts, or an H that does not yet determine every parameter)."""
        if self._U is None or not len(candidates):
            return None
        H = self._h0 + sum((self._info[i][0] for i in plan), np.zeros_like(self._h0))
        lam, v = np.linalg.eigh(H)
        if lam[-1] <= 0 or lam[0] <= 1e3 * INFO_RTOL * lam[-1]:
            return None
        Hinv = (v / lam) @ v.T
        U = self._U[np.asarray(candidates)]
        A = Hinv @ U
        S = np.eye(U.shape[2]) + U.transpose(0, 2, 1) @ A
        X = np.linalg.solve(S, A.transpose(0, 2, 1))  # S^-1 A^T, (N, r, p)
        return np.diag(Hinv)[None, :] - np.einsum("npr,nrp->np", A, X)

    def keys_adding(self, plan: Sequence[int], candidates: Sequence[int]
                    ) -> list[tuple[float, float]]:
        """:meth:`key` of ``plan`` plus each one of ``candidates``, by low-rank updates
        where the criterion allows (A, or a list of parameters), else one by one."""
        if self.criterion in ("D", "E"):
            return [self.key([*plan, c]) for c in candidates]
        var = self.variance_terms(plan, candidates)
        if var is None:
            return [self.key([*plan, c]) for c in candidates]
        return [(v, v) for v in self._criterion_of_variances(var).tolist()]

    def _criterion_of_variances(self, var: np.ndarray) -> np.ndarray:
        if self.criterion == "A":
            return var.sum(axis=1)
        idx = [list(self.names).index(n) for n in self.criterion]
        return var[:, idx].sum(axis=1)

    def key(self, plan: Sequence[int]) -> tuple[float, float]:
        """Exact criterion, then the ridge-regularised one (which ranks undetermined plans)."""
        reg = criterion_value(self.covariance(plan, self._ridge), self.criterion, self.names)
        return self.score(plan), reg


def greedy_exchange(scorer: PlanScorer, candidates: Sequence[int], size: int,
                    max_passes: int = 50) -> tuple[list[int], int]:
    """Greedy forward selection of ``size`` candidates, then exchange passes.

    Each exchange pass makes the single swap (one chosen for one unused candidate) that
    lowers the criterion most, until none does. Returns (plan, number of swaps made).

    Examples
    --------
    Three one-row candidates for two parameters; the two orthogonal rows are best:

    >>> import numpy as np
    >>> rows = [np.array([[1.0, 0.0]]), np.array([[1.0, 0.01]]), np.array([[0.0, 1.0]])]
    >>> s = PlanScorer([(r, np.ones(1)) for r in rows], (np.zeros((0, 2)), np.ones(0)),
    ...                np.zeros(2), "weighted-least-squares", "A", ["a", "b"])
    >>> greedy_exchange(s, [0, 1, 2], 2)[0]
    [0, 2]
    """
    plan: list[int] = []
    pool = list(candidates)
    adding = getattr(scorer, "keys_adding", None) or (
        lambda base, cands: [scorer.key([*base, c]) for c in cands])
    for _ in range(size):
        free = [c for c in pool if c not in plan]
        keys = adding(plan, free)
        plan.append(free[min(range(len(free)), key=keys.__getitem__)])
    swaps = 0
    current = scorer.key(plan)
    for _ in range(max_passes):
        best_key, best_plan = current, None
        free = [c for c in pool if c not in plan]
        for i in range(size):
            rest = [*plan[:i], *plan[i + 1:]]
            for c, k in zip(free, adding(rest, free), strict=True):
                if k < best_key:
                    # confirm with the exact criterion (the update's round-off must not
                    # make a swap that is no improvement)
                    trial = [*plan[:i], c, *plan[i + 1:]]
                    exact = scorer.key(trial)
                    if exact < best_key:
                        best_key, best_plan = exact, trial
        if best_plan is None:
            break
        plan, current, swaps = best_plan, best_key, swaps + 1
    return sorted(plan), swaps


def exhaustive(scorer: PlanScorer, candidates: Sequence[int], size: int
               ) -> tuple[list[int], float] | None:
    """The optimal plan by enumeration, or None when there are more than EXHAUSTIVE_LIMIT
    plans or they would cost more than EXHAUSTIVE_FLOPS or EXHAUSTIVE_COVARIANCES (a
    scorer averaging over draws of the prior says how many covariances a plan costs in
    ``evaluations``)."""
    n_plans = math.comb(len(candidates), size)
    p = scorer.prior.size
    evaluations = n_plans * getattr(scorer, "evaluations", 1)  # one per draw of the prior
    if (n_plans > EXHAUSTIVE_LIMIT or evaluations * float(p) ** 3 > EXHAUSTIVE_FLOPS
            or evaluations > EXHAUSTIVE_COVARIANCES):
        return None
    best, best_value = None, math.inf
    for plan in itertools.combinations(candidates, size):
        v = scorer.score(plan)
        if v < best_value:
            best, best_value = list(plan), v
    return (best, best_value) if best is not None else None
