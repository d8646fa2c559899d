"""Parametric model: K(s) = K0 + sum_j s_j K_j, M(s) = M0 + sum_j s_j M_j.

Matrices are SciPy sparse CSR arrays. Coordinates are numbered from 1 as in the
user's model; restrained coordinates are removed, and ``coordinates`` keeps the
user's number of every remaining row. ``coordinate_table``
(:class:`~eigenupdate.model.coordinates.CoordinateTable`) says what each coordinate is.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from eigenupdate.errors import InputError
from eigenupdate.model.coordinates import CoordinateTable
from eigenupdate.model.parameters import Parameter, check_unique


def _csr(a, n: int) -> sp.csr_array:
    m = sp.csr_array(a, dtype=float)
    if m.shape != (n, n):
        raise InputError(f"matrix has shape {m.shape}, expected {(n, n)}")
    if not np.all(np.isfinite(m.data)):
        raise InputError("matrix has NaN or infinite entries (overflow?)")
    return m


@dataclass(frozen=True)
class ParametricModel:
    """Stiffness and mass matrices linear in named parameters.

    ``k_terms[j]`` and ``m_terms[j]`` are dK/ds_j and dM/ds_j (None when zero).

    Examples
    --------
    A single 2 kg mass on a 800 N/m spring to ground:

    >>> import numpy as np
    >>> model = ParametricModel(
    ...     k0=np.zeros((1, 1)), m0=np.zeros((1, 1)),
    ...     parameters=(Parameter("k", 800.0), Parameter("m", 2.0)),
    ...     k_terms=(np.ones((1, 1)), None), m_terms=(None, np.ones((1, 1))))
    >>> float(model.stiffness()[0, 0]), float(model.mass()[0, 0])
    (800.0, 2.0)
    """

    k0: sp.csr_array
    m0: sp.csr_array
    parameters: tuple[Parameter, ...]
    k_terms: tuple[sp.csr_array | None, ...]
    m_terms: tuple[sp.csr_array | None, ...]
    coordinates: np.ndarray = field(default=None)  # user coordinate number of each row
    coordinate_table: CoordinateTable = field(default=None)  # node and direction of each

    def __post_init__(self) -> None:
        n = np.shape(self.k0)[0]
        set_ = object.__setattr__
        set_(self, "k0", _csr(self.k0, n))
        set_(self, "m0", _csr(self.m0, n))
        set_(self, "parameters", tuple(self.parameters))
        check_unique(self.parameters)
        if not (len(self.k_terms) == len(self.m_terms) == len(self.parameters)):
            raise InputError("one K term and one M term (or None) per parameter are required")
        set_(self, "k_terms", tuple(None if t is None else _csr(t, n) for t in self.k_terms))
        set_(self, "m_terms", tuple(None if t is None else _csr(t, n) for t in self.m_terms))
        coords = np.arange(1, n + 1) if self.coordinates is None else np.asarray(self.coordinates)
        if coords.shape != (n,):
            raise InputError(f"{coords.size} coordinate numbers for {n} rows")
        set_(self, "coordinates", coords.astype(int))
        if self.coordinate_table is None:
            set_(self, "coordinate_table", CoordinateTable.translations(self.coordinates))
        missing = [c for c in self.coordinates.tolist() if c not in self.coordinate_table]
        if missing:
            raise InputError(f"coordinates {missing} are not in the coordinate table")

    @property
    def n(self) -> int:
        """Number of (unrestrained) coordinates."""
        return self.k0.shape[0]

    @property
    def names(self) -> list[str]:
        return [p.name for p in self.parameters]

    @property
    def values(self) -> np.ndarray:
        return np.array([p.value for p in self.parameters], dtype=float)

    @property
    def updated(self) -> np.ndarray:
        """Indices of the parameters that are updated (unknown)."""
        return np.array([i for i, p in enumerate(self.parameters) if p.update], dtype=int)

    def index(self, coordinate: int) -> int:
        """Row of a user coordinate number; InputError if the model has no such coordinate."""
        rows = np.flatnonzero(self.coordinates == coordinate)
        if rows.size == 0:
            # rows are 1..n minus the restrained coordinates: a gap is a restrained one
            gap = 1 <= coordinate <= self.coordinates.max(initial=0)
            what = f"coordinate {coordinate} is restrained" if gap else \
                f"unknown coordinate {coordinate}"
            raise InputError(f"{what} (the model has coordinates {_ranges(self.coordinates)})")
        return int(rows[0])

    def stiffness(self, values: Sequence[float] | None = None) -> sp.csr_array:
        return self._assemble(self.k0, self.k_terms, values)

    def mass(self, values: Sequence[float] | None = None) -> sp.csr_array:
        return self._assemble(self.m0, self.m_terms, values)

    def _assemble(self, base, terms, values) -> sp.csr_array:
        s = self.values if values is None else np.asarray(values, dtype=float)
        out = base.copy()
        for sj, t in zip(s, terms, strict=True):
            if t is not None and sj != 0:
                out = out + sj * t
        return sp.csr_array(out)

    def with_values(self, values: Sequence[float] | dict[str, float]) -> ParametricModel:
        """A copy whose parameters take new values (a sequence, or a dict by name)."""
        if isinstance(values, dict):
            unknown = set(values) - set(self.names)
            if unknown:
                raise InputError(f"unknown parameter(s) {sorted(unknown)}")
            new = [p.with_value(values.get(p.name, p.value)) for p in self.parameters]
        else:
            new = [p.with_value(v) for p, v in zip(self.parameters, values, strict=True)]
        return ParametricModel(
            self.k0, self.m0, tuple(new), self.k_terms, self.m_terms, self.coordinates,
            self.coordinate_table,
        )


def _ranges(coords: np.ndarray) -> str:
    """'1-4, 7' style summary of coordinate numbers for error messages."""
    c = np.sort(coords)
    if c.size == 0:
        return "none"
    parts, start, prev = [], c[0], c[0]
    for x in c[1:]:
        if x != prev + 1:
            parts.append(f"{start}-{prev}" if prev > start else f"{start}")
            start = x
        prev = x
    parts.append(f"{start}-{prev}" if prev > start else f"{start}")
    return ", ".join(parts)
