"""Dense K(s), M(s), their parameter derivatives and the configurations' additions for
small models (the dense eigen-solver's path).

On a model of a few coordinates, summing SciPy sparse terms costs far more than the
arithmetic: each sparse sum builds a new CSR array (index checks, pruning), some 30 us,
against under 1 us for the same dense sum. The checked virtual tests of ``design`` make
some 10^4 such sums each. :class:`DenseModel` keeps every fixed matrix dense once and
sums them in the order :meth:`ParametricModel.stiffness` does, so K(s) and M(s) are the
sparse path's to the last bit (a sparse sum adds the same numbers, entry by entry).
"""

from __future__ import annotations

import numpy as np

from eigenupdate.model.configurations import Configuration
from eigenupdate.model.parametric import ParametricModel, _check_powers

DENSE_ENTRIES = 2**21
"""Most matrix entries kept dense for one model (16 MB; a 400-coordinate model with up
to 11 parameter terms, a 100-coordinate one with 200). Beyond, the sparse terms are
used: a dense sum costs n^2 per term, which passes a sparse sum's fixed cost (~30 us)
near n = 200, and the derivatives' dense products would cost more than the solve."""

_DELTAS = 4096  # configurations' additions cached per model (a design's candidates)


class DenseModel:
    """Dense copies of a :class:`ParametricModel`'s fixed matrices.

    They do not depend on the parameters' values, so one copy serves the model at every
    value (:meth:`ParametricModel.with_values` passes it on; see :func:`dense_model`).
    """

    def __init__(self, model: ParametricModel):
        self.parameters = model.parameters
        self.nonlinear = model.nonlinear
        self.k0, self.m0 = model.k0.toarray(), model.m0.toarray()
        if self.nonlinear:
            self.k_parts = [(t, t.matrix.toarray()) for t in model.k_parts]
            self.m_parts = [(t, t.matrix.toarray()) for t in model.m_parts]
        else:
            self.k_terms = [None if t is None else t.toarray() for t in model.k_terms]
            self.m_terms = [None if t is None else t.toarray() for t in model.m_terms]
        self._deltas: dict[Configuration, tuple[np.ndarray, np.ndarray]] = {}
        self._stacks: dict[tuple[int, ...], tuple[np.ndarray, np.ndarray] | None] = {}

    @staticmethod
    def entries(model: ParametricModel) -> int:
        """Matrix entries a dense copy of ``model`` holds."""
        if model.nonlinear:
            count = len(model.k_parts) + len(model.m_parts)
        else:
            count = sum(t is not None for t in model.k_terms + model.m_terms)
        return (2 + count) * model.n ** 2

    def stiffness(self, s: np.ndarray) -> np.ndarray:
        """K(s), as :meth:`ParametricModel.stiffness` (same sums in the same order)."""
        return self._assemble(self.k0, "k", s)

    def mass(self, s: np.ndarray) -> np.ndarray:
        """M(s), as :meth:`ParametricModel.mass`."""
        return self._assemble(self.m0, "m", s)

    def _assemble(self, base: np.ndarray, which: str, s: np.ndarray) -> np.ndarray:
        out = base.copy()
        if self.nonlinear:
            parts = getattr(self, f"{which}_parts")
            _check_powers(self.parameters, [t for t, _ in parts], s)
            for t, a in parts:
                c = t.value(s)
                if c != 0:
                    out += c * a
            return out
        for sj, a in zip(s, getattr(self, f"{which}_terms"), strict=True):
            if a is not None and sj != 0:
                out += sj * a
        return out

    def derivatives(self, s: np.ndarray, indices) -> tuple[list, list]:
        """(dK/ds_j, dM/ds_j) at ``s`` for j in ``indices`` (None where zero), as the
        ``k_terms``, ``m_terms`` of ``model.at(s)`` (the same sums in the same order)."""
        if not self.nonlinear:
            return [self.k_terms[j] for j in indices], [self.m_terms[j] for j in indices]
        for p, v in zip(self.parameters, s, strict=True):
            p.with_value(v)  # refuses what model.at(s) refuses (a negative value)
        every = self.k_parts + self.m_parts
        _check_powers(self.parameters, [t for t, _ in every], s)
        out = []
        for parts in (self.k_parts, self.m_parts):
            d: list = [None] * len(self.parameters)
            for t, a in parts:
                for j in t.indices:
                    x = t.derivative(s, j) * a
                    d[j] = x if d[j] is None else d[j] + x
            out.append([d[j] for j in indices])
        return out[0], out[1]

    def stacks(self, indices) -> tuple[np.ndarray, np.ndarray] | None:
        """(terms, n, n) stacks of K_j and M_j for j in ``indices``, zero where a
        parameter does not enter; None for a nonlinear model (they depend on the
        values); no larger than the copy itself (:data:`DENSE_ENTRIES`)."""
        key = tuple(int(j) for j in indices)
        if key not in self._stacks:
            n = self.k0.shape[0]
            if self.nonlinear or 2 * len(key) * n * n > DENSE_ENTRIES:
                self._stacks[key] = None
            else:
                zero = np.zeros((n, n))
                self._stacks[key] = tuple(
                    np.stack([zero if terms[j] is None else terms[j] for j in key])
                    for terms in (self.k_terms, self.m_terms))
        return self._stacks[key]

    def added(self, K: np.ndarray, M: np.ndarray, configuration: Configuration,
              model: ParametricModel) -> tuple[np.ndarray, np.ndarray]:
        """(K + Delta K, M + Delta M) of a configuration (K, M themselves for the bare
        structure), as ``K + configuration.delta(model)[0]`` adds them."""
        if not configuration.additions:
            return K, M
        d = self._deltas.get(configuration)
        if d is None:
            rows = configuration.rows(model)
            dk, dm = np.zeros(K.shape[0]), np.zeros(K.shape[0])
            # duplicates summed first, as the sparse Delta K is built
            np.add.at(dk, rows, [a.stiffness for a in configuration.additions])
            np.add.at(dm, rows, [a.mass for a in configuration.additions])
            if len(self._deltas) >= _DELTAS:
                self._deltas.clear()
            d = self._deltas[configuration] = (dk, dm)
        diag = np.diag_indices(K.shape[0])
        K, M = K.copy(), M.copy()
        K[diag] += d[0]
        M[diag] += d[1]
        return K, M


def dense_model(model: ParametricModel) -> DenseModel | None:
    """The dense copy of ``model``, made on first use and kept with it; None when it
    would exceed :data:`DENSE_ENTRIES`."""
    cached = model.__dict__.get("_dense", False)
    if cached is False:
        cached = DenseModel(model) if DenseModel.entries(model) <= DENSE_ENTRIES else None
        object.__setattr__(model, "_dense", cached)
    return cached
