"""Which model mode each measured frequency is fitted to, and through which equation.

Pairing the k-th measured frequency of a configuration with the model's k-th eigenvalue
(order alone) fails where two modes come in a different order in the model than in the
structure: the fit then follows the other shape's sensitivities and may descend into
another basin. Two measures keep the pairing honest:

* **Tracking.** Model modes keep their identity as the parameters move: each new
  linearisation's modes of a configuration are matched to the same configuration's modes
  at the last accepted iterate by the modal assurance criterion (MAC, weighted by the
  diagonal of the initial mass matrix, an assignment maximising the total MAC), model to
  model, not by order. A mode that crosses a neighbour keeps its equation.
* **Clusters.** Where the order of two adjacent modes cannot be told from the data, the
  measured frequencies are not paired one by one: the cluster is fitted through the sum
  of its eigenvalues, which stays smooth where the modes cross (it is the trace of the
  stiffness over the cluster's invariant subspace) and whose exact sensitivity is the sum
  of the Fox-Kapoor derivatives. Adjacent modes k, k+1 of a configuration are
  clustered when pairing them the other way round would ask them to move against each
  other (relative to the measured values) by no more than ``KAPPA`` times the RMS of
  what the start model's error does to adjacent modes (the differences of their relative
  residuals, over every configuration), plus three measured standard deviations: then the
  data do not say which pairing is right. The updating clusters the most ambiguous pairs
  first, and only while the plan keeps its rank and at least half of its redundancy
  (equations beyond the parameters).

Where the highest measured mode of a configuration would be clustered with the modes
below it and the model's next mode (not measured) is as close by the same test, the
measurements end inside a group of close modes: a sum over the measured ones misses a
member and is not smooth where that mode crosses in. Such a group is not clustered: its
modes stay paired by order and tracked, and the pairing says so in a note ("cut
group"). On the 2,160-coordinate frame of benchmark (b), modes 9-11 of 18 configurations
lie that close: fitted through the sums of 9 and 10, the update ended 3.5 % off the truth
after 20 iterations (error-free data); tracked, it converges (benchmarks/README.md). On a
doubly symmetric frame whose modes 8-12 lie within 0.03 % (identical floor beams), the sums
"converged" 4 % off the truth, and leaving the groups out of the fit instead failed 3 of
10 near-symmetric spring systems.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.optimize import linear_sum_assignment

KAPPA = 3.0
"""A swapped pairing within KAPPA x the start's spread of adjacent residuals is ambiguous."""

MAC_MIN = 0.5
"""A tracked mode must keep at least this MAC with its previous shape; below it the
pairing falls back to order (and says so)."""


@dataclass(frozen=True)
class PairingNote:
    """One event of the pairing, for the result: ``kind`` "cluster", "re-paired" or
    "tracking lost"."""

    kind: str
    configuration: str
    modes: tuple[int, ...]
    iteration: int
    reason: str

    def to_dict(self) -> dict:
        return {"kind": self.kind, "configuration": self.configuration,
                "modes": list(self.modes), "iteration": self.iteration, "reason": self.reason}


class Pairing:
    """Equations of the fit and the tracked identity of every model mode.

    Parameters
    ----------
    rows : (configuration, mode) of each measured frequency, configuration by
        configuration, modes ascending (the rows of :func:`linearise`).
    lam_meas : measured eigenvalues of the rows.
    lam0 : the start model's eigenvalues of the rows (order-paired).
    std_rel : relative standard deviation of each measured eigenvalue (0 if unknown).
    weights : sqrt of the weight of each row (1 / sigma_lambda, or 1).
    mass_diagonal : diagonal of the mass matrix (MAC weights); None: no tracking.
    lam_next : the start model's eigenvalue above each configuration's highest measured
        mode (NaN: not known), for the "cut group" note.
    """

    def __init__(self, rows: Sequence[tuple[str, int]], lam_meas: np.ndarray, lam0: np.ndarray,
                 std_rel: np.ndarray, weights: np.ndarray, mass_diagonal: np.ndarray | None,
                 lam_next: np.ndarray | None = None):
        self.rows = list(rows)
        self.notes: list[PairingNote] = []
        names = list(dict.fromkeys(c for c, _ in self.rows))
        self._block = {c: np.array([i for i, (n, _) in enumerate(self.rows) if n == c])
                       for c in names}
        rel = (lam_meas - lam0) / lam_meas
        pairs = [(int(a), int(b)) for idx in self._block.values()
                 for a, b in zip(idx[:-1], idx[1:], strict=True)
                 if self.rows[b][1] == self.rows[a][1] + 1]
        # how far the start model's error moves adjacent modes against each other
        self.spread = float(np.sqrt(np.mean([(rel[b] - rel[a]) ** 2 for a, b in pairs]))
                            ) if pairs else 0.0
        self._weights = np.asarray(weights, float)
        self._lam_meas = lam_meas
        # candidate pairs, most ambiguous first: (swapped differential / limit, a, b); paired
        # the other way round, b would have to move against a by about the sum of the
        # model's and the measured gaps
        cand = []
        for a, b in pairs:
            swapped = _swapped(lam_meas[a], lam0[a], lam_meas[b], lam0[b])
            limit = self._limit(std_rel[a], std_rel[b])
            if swapped <= limit:
                cand.append((swapped / limit if limit > 0 else 0.0, a, b))
        self.candidates = sorted(cand)
        if lam_next is not None:
            cut = self._cut_groups(lam_meas, lam0, std_rel, lam_next)
            self.candidates = [c for c in self.candidates if c[2] not in cut]
        self.cluster([])
        self._w2 = None if mass_diagonal is None else np.maximum(mass_diagonal, 0.0)
        self._ref: dict[str, np.ndarray] = {}
        self.perm = np.arange(len(self.rows))  # row -> row of a linearisation, accepted

    def cluster(self, pairs: Sequence[tuple[int, int]], refused: Sequence = ()) -> None:
        """Fit the rows joined by ``pairs`` (adjacent rows a, b) through their sums; the
        ``refused`` candidates are noted as kept paired by order."""
        parent = list(range(len(self.rows)))
        for a, b in sorted(pairs):
            parent[b] = parent[a]
        groups: dict[int, list[int]] = {}
        for i, p in enumerate(parent):
            groups.setdefault(p, []).append(i)
        self.groups = list(groups.values())
        self.group_of = {i: e for e, g in enumerate(self.groups) for i in g}
        # sum operator (equations x rows) and the equations' weights: the sum of
        # independent errors has variance sum(1 / w^2)
        self.S = np.zeros((len(self.groups), len(self.rows)))
        for e, g in enumerate(self.groups):
            self.S[e, g] = 1.0
        self.weights = 1.0 / np.sqrt(self.S @ (1.0 / self._weights**2))
        self.target = self.S @ self._lam_meas
        self.notes = [n for n in self.notes if n.kind != "cluster"]
        for g in self.groups:
            if len(g) > 1:
                self.notes.append(PairingNote(
                    "cluster", self.rows[g[0]][0], tuple(self.rows[i][1] for i in g), 0,
                    f"the swapped pairing is as plausible (within {KAPPA:g} x the start's "
                    f"spread of adjacent residuals, {self.spread:.2%}): fitted through the "
                    f"sum of their eigenvalues"))
        for _, a, b in refused:
            self.notes.append(PairingNote(
                "cluster refused", self.rows[a][0], (self.rows[a][1], self.rows[b][1]), 0,
                "ambiguous, but their sum would cost J its rank or half its redundancy: "
                "paired by order, tracked"))

    def _cut_groups(self, lam_meas, lam0, std_rel, lam_next) -> set[int]:
        """Note the configurations whose measured modes end inside a group of close
        modes: the highest measured row a is a cluster candidate with the row below,
        and the swap with the model's next mode b (its measured value estimated as
        lam0_b lam_meas_a / lam0_a) passes the candidates' test. Returns the rows of
        those groups."""
        below = {b: a for _, a, b in self.candidates}
        rows: set[int] = set()
        for (c, idx), nxt in zip(self._block.items(), lam_next, strict=True):
            a = int(idx[-1])
            if a not in below or not np.isfinite(nxt) or not lam0[a] > 0:
                continue
            est = nxt * lam_meas[a] / lam0[a]
            if _swapped(lam_meas[a], lam0[a], est, nxt) <= self._limit(std_rel[a], std_rel[a]):
                group = [a]
                while group[-1] in below:
                    group.append(below[group[-1]])
                rows.update(group)
                k = self.rows[a][1]
                modes = tuple(sorted(self.rows[i][1] for i in group))
                lowest = min(self.rows[int(i)][1] for i in idx)
                leave = f", or leave it out (modes up to {modes[0] - 1})" \
                    if modes[0] > lowest else ""  # else no measured mode lies below it
                self.notes.append(PairingNote(
                    "cut group", c, modes, 0,
                    f"the measured modes end inside a group of close modes: the model's "
                    f"mode {k + 1} (not measured) is as close to mode {k} as modes "
                    f"{list(modes)} are to each other, so their sum would miss a member "
                    f"and is not fitted (paired by order, tracked); measure the whole "
                    f"group{leave}"))
        return rows

    def _limit(self, std_a: float, std_b: float) -> float:
        """Largest swapped differential that leaves the order of two modes undecided."""
        return KAPPA * self.spread + 3 * (std_a + std_b)

    @property
    def clustered(self) -> bool:
        return any(len(g) > 1 for g in self.groups)

    def _reference(self, shapes: np.ndarray) -> np.ndarray:
        """W^2 phi / |W phi| per column: then MAC = (ref^T phi)^2 / |W phi|^2 takes one
        product and the weighted norms of the new shapes (at 103k coordinates and 21
        configurations, normalising both sides cost 0.2-0.4 s per linearisation)."""
        return shapes * self._w2[:, None] / np.sqrt(self._norms2(shapes))

    def _norms2(self, shapes: np.ndarray) -> np.ndarray:
        return (shapes * shapes).T @ self._w2

    def match(self, shapes: Sequence[np.ndarray] | None) -> tuple[np.ndarray, list]:
        """Permutation (row -> row of the linearisation whose mode shapes are ``shapes``,
        one array per configuration) that keeps each mode's identity, and the pending
        notes. Before the first :meth:`accept`, or without shapes: order."""
        perm, pending = np.arange(len(self.rows)), []
        if self._w2 is None or shapes is None or not self._ref:
            return perm, pending
        for (c, idx), phi in zip(self._block.items(), shapes, strict=True):
            mac = (self._ref[c].T @ phi) ** 2 / self._norms2(phi)  # identity x position
            ident, pos = linear_sum_assignment(-mac)
            if np.min(mac[ident, pos]) < MAC_MIN:
                pending.append(("tracking lost", c, idx,
                                f"best MAC {np.min(mac[ident, pos]):.2f} < {MAC_MIN}: "
                                f"paired by order"))
                continue
            perm[idx[ident]] = idx[pos]
        return perm, pending

    def accept(self, perm: np.ndarray, pending: list, shapes: Sequence[np.ndarray] | None,
               iteration: int) -> None:
        """Make a linearisation's modes (reordered by ``perm``) the reference."""
        for kind, c, idx, why in pending:
            self.notes.append(PairingNote(kind, c, tuple(self.rows[i][1] for i in idx),
                                          iteration, why))
        for c, idx in self._block.items():
            moved = [self.rows[i][1] for i in idx if perm[i] != self.perm[i]]
            if moved and iteration > 0:
                now = [self.rows[perm[i]][1] for i in idx if perm[i] != self.perm[i]]
                self.notes.append(PairingNote(
                    "re-paired", c, tuple(moved), iteration,
                    f"tracked by MAC: now the model's modes {now} by frequency"))
        self.perm = perm
        if self._w2 is not None and shapes is not None:
            for (c, idx), phi in zip(self._block.items(), shapes, strict=True):
                local = perm[idx] - idx[0]
                self._ref[c] = self._reference(phi[:, local])

    def paired(self, lam: np.ndarray, J: np.ndarray, perm: np.ndarray
               ) -> tuple[np.ndarray, np.ndarray]:
        """Model eigenvalue and J row of each measured row under ``perm``."""
        return lam[perm], J[perm]

    def equations(self, lam: np.ndarray, J: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Weighted residual (model - measured) and Jacobian of the equations, from paired
        eigenvalues and J rows."""
        w = self.weights
        return w * (self.S @ lam - self.target), w[:, None] * (self.S @ J)

    def by_row(self, lam_paired: np.ndarray) -> np.ndarray:
        """Model eigenvalue to show against each measured row: paired, and within a
        cluster ascending (its members are not told apart)."""
        out = lam_paired.copy()
        for g in self.groups:
            if len(g) > 1:
                out[g] = np.sort(lam_paired[g])
        return out

    def to_dict(self) -> dict:
        return {"equations": len(self.groups),
                "clusters": [[self.rows[i][0], [self.rows[j][1] for j in g]]
                             for g in self.groups if len(g) > 1 for i in g[:1]],
                "notes": [n.to_dict() for n in self.notes]}


def _swapped(meas_a: float, model_a: float, meas_b: float, model_b: float) -> float:
    """How far modes a < b would have to move against each other (relative to the
    measured values) if paired the other way round: about the sum of the model's and the
    measured gaps."""
    return (meas_b - model_a) / meas_b - (meas_a - model_b) / meas_a
