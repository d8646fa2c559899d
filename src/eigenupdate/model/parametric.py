"""Parametric model: K(s) = K0 + sum_j s_j K_j, M(s) = M0 + sum_j s_j M_j, or, when
parameters enter nonlinearly (a shell's thickness, a section's dimensions, a product
E * A), sums of fixed matrices times monomials of the parameters
(:class:`Term`: K(s) = K0 + sum_t c_t prod_j s_j^a_tj K_t).

Matrices are SciPy sparse CSR arrays. Coordinates are numbered from 1 as in the
user's model; restrained coordinates are removed, and ``coordinates`` keeps the
user's number of every remaining row. ``coordinate_table``
(:class:`~eigenupdate.model.coordinates.CoordinateTable`) says what each coordinate is.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
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
class Term:
    """One part of K(s) or M(s): ``coefficient * prod_j s_j ** a_j * matrix``.

    ``powers`` holds (parameter index, exponent a_j) pairs, exponents real and non-zero
    (``((0, 1.0), (1, 3.0))`` is s_0 s_1^3, a shell's E t^3).

    Examples
    --------
    >>> t = Term(None, ((0, 1.0), (1, 3.0)), 2.0)
    >>> t.value(np.array([3.0, 2.0])), t.derivative(np.array([3.0, 2.0]), 1)
    (48.0, 72.0)
    """

    matrix: sp.csr_array | None
    powers: tuple[tuple[int, float], ...]
    coefficient: float = 1.0

    def value(self, s: np.ndarray) -> float:
        return float(self.coefficient * math.prod(s[j] ** a for j, a in self.powers))

    def derivative(self, s: np.ndarray, j: int) -> float:
        """d value / d s_j (exact: no division by s_j, so s_j = 0 is fine for a >= 1)."""
        a = dict(self.powers).get(j)
        if a is None:
            return 0.0
        rest = math.prod(s[k] ** b for k, b in self.powers if k != j)
        return float(self.coefficient * a * s[j] ** (a - 1) * rest)

    @property
    def linear(self) -> bool:
        """True for ``coefficient * s_j`` (one parameter, power 1)."""
        return len(self.powers) == 1 and self.powers[0][1] == 1

    @property
    def indices(self) -> tuple[int, ...]:
        return tuple(j for j, _ in self.powers)

    def replaced(self, matrix) -> Term:
        return Term(matrix, tuple((int(j), float(a)) for j, a in self.powers),
                    float(self.coefficient))


# complex step: Im f(x + i h) / h is f'(x) to round-off (no difference of two values)
_STEP = 1e-30


@dataclass(frozen=True)
class FunctionTerm:
    """One part of K(s) or M(s): ``function(s[indices]) * matrix`` for a coefficient
    that is no monomial (a section's J, a centroid's shift).

    ``function`` takes the parameters' values as an array, returns a number, and must be
    analytic in them written with complex-safe arithmetic (no ``float()``, comparisons
    on ``.real``): d/ds_j is then the complex-step derivative Im f(x + i h e_j) / h,
    exact to round-off. It must be picklable (a module-level function or a dataclass
    instance) for the Monte Carlo workers.

    Examples
    --------
    >>> t = FunctionTerm(None, (0, 1), lambda x: x[0] / x[1])
    >>> t.value(np.array([3.0, 2.0])), t.derivative(np.array([3.0, 2.0]), 1)
    (1.5, -0.75)
    """

    matrix: sp.csr_array | None
    indices: tuple[int, ...]
    function: Callable[[np.ndarray], complex]

    linear = False

    def value(self, s: np.ndarray) -> float:
        return float(np.real(self.function(np.asarray(s, dtype=float)[list(self.indices)])))

    def derivative(self, s: np.ndarray, j: int) -> float:
        if j not in self.indices:
            return 0.0
        x = np.asarray(s, dtype=float)[list(self.indices)].astype(complex)
        k = self.indices.index(j)
        h = _STEP * max(abs(x[k].real), 1e-200)
        x[k] += 1j * h
        return float(np.imag(self.function(x)) / h)

    def replaced(self, matrix) -> FunctionTerm:
        return FunctionTerm(matrix, tuple(int(j) for j in self.indices), self.function)


@dataclass(frozen=True)
class ParametricModel:
    """Stiffness and mass matrices that depend on named parameters.

    ``k_terms[j]`` and ``m_terms[j]`` are dK/ds_j and dM/ds_j at the current values
    (None when zero). A linear model (``k_parts`` and ``m_parts`` empty) is
    K = K0 + sum_j s_j k_terms[j]; a nonlinear one (see :meth:`from_parts`) is
    K = K0 + sum over ``k_parts`` of term value x matrix, and :meth:`with_values`
    re-forms its derivatives at the new values.

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
    k_parts: tuple[Term | FunctionTerm, ...] = ()  # nonlinear: K(s) = K0 + sum of these
    m_parts: tuple[Term | FunctionTerm, ...] = ()

    def __post_init__(self) -> None:
        n = np.shape(self.k0)[0]
        set_ = object.__setattr__
        set_(self, "k0", _csr(self.k0, n))
        set_(self, "m0", _csr(self.m0, n))
        set_(self, "parameters", tuple(self.parameters))
        check_unique(self.parameters)
        if self.nonlinear:
            self._form_derivatives(n)
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

    @classmethod
    def from_parts(
        cls, k0, m0, parameters: Sequence[Parameter], k_parts: Sequence[Term],
        m_parts: Sequence[Term], coordinates: np.ndarray | None = None,
        coordinate_table: CoordinateTable | None = None,
    ) -> ParametricModel:
        """Model K(s) = K0 + sum c_t prod s_j^a_tj K_t (likewise M) from its parts.

        When every part is linear (``c s_j K_t``) the result is the plain linear model
        (K_j the sum of its parts times c), so that case costs what it always did.

        Examples
        --------
        A plate strip's bending stiffness E t^3 with t a parameter:

        >>> p = (Parameter("t", 0.5),)
        >>> m = ParametricModel.from_parts(np.zeros((1, 1)), np.eye(1), p,
        ...                                [Term(np.eye(1), ((0, 3.0),), 8.0)], [])
        >>> float(m.stiffness()[0, 0]), float(m.k_terms[0][0, 0])  # 8 t^3, 24 t^2
        (1.0, 6.0)
        """
        n = np.shape(k0)[0]
        k_parts, m_parts = tuple(k_parts), tuple(m_parts)
        for t in k_parts + m_parts:
            if isinstance(t, FunctionTerm):
                if not t.indices or any(not 0 <= j < len(parameters) for j in t.indices):
                    raise InputError(f"a term's indices {t.indices} must be parameter "
                                     f"indices 0..{len(parameters) - 1}")
                continue
            bad = [j for j, a in t.powers if not (0 <= j < len(parameters)
                                                  and math.isfinite(a) and a != 0)]
            twice = len({j for j, _ in t.powers}) != len(t.powers)
            if bad or twice or not t.powers or not math.isfinite(t.coefficient):
                raise InputError(f"a term's powers {t.powers} need parameter indices "
                                 f"0..{len(parameters) - 1}, each once, and finite non-zero "
                                 f"exponents")
        if all(t.linear for t in k_parts + m_parts):
            kt, mt = [], []
            for parts, out in ((k_parts, kt), (m_parts, mt)):
                by = {}
                for t in parts:
                    by.setdefault(t.powers[0][0], []).append(t)
                for j in range(len(parameters)):
                    mine = by.get(j, [])
                    if len(mine) == 1 and mine[0].coefficient == 1:
                        out.append(mine[0].matrix)  # as given: no copy
                        continue
                    mine = [t.coefficient * _csr(t.matrix, n) for t in mine]
                    out.append(sum(mine[1:], mine[0]) if mine else None)
            return cls(k0, m0, tuple(parameters), tuple(kt), tuple(mt), coordinates,
                       coordinate_table)
        none = (None,) * len(parameters)
        return cls(k0, m0, tuple(parameters), none, none, coordinates, coordinate_table,
                   tuple(t.replaced(_csr(t.matrix, n)) for t in k_parts),
                   tuple(t.replaced(_csr(t.matrix, n)) for t in m_parts))

    @property
    def nonlinear(self) -> bool:
        """True when some parameter enters K or M other than linearly."""
        return bool(self.k_parts or self.m_parts)

    def _form_derivatives(self, n: int) -> None:
        s = self.values
        _check_powers(self.parameters, self.k_parts + self.m_parts, s)
        for name, parts in (("k_terms", self.k_parts), ("m_terms", self.m_parts)):
            out: list = [None] * len(self.parameters)
            for t in parts:
                for j in t.indices:
                    x = t.derivative(s, j) * t.matrix
                    out[j] = x if out[j] is None else out[j] + x
            object.__setattr__(self, name, tuple(None if d is None else sp.csr_array(d)
                                                 for d in out))

    def at(self, values: Sequence[float] | None) -> ParametricModel:
        """This model with ``values``, when its derivatives depend on them (nonlinear);
        else itself (a linear model's K_j, M_j hold at every value)."""
        if values is None or not self.nonlinear or np.array_equal(values, self.values):
            return self
        return self.with_values(values)

    @property
    def n(self) -> int:
        """Number of (unrestrained) coordinates."""
        return self.k0.shape[0]

    @property
    def names(self) -> list[str]:
        return [p.name for p in self.parameters]

    @property
    def units(self) -> dict[str, str]:
        """The stated unit of each parameter that has one, by name."""
        return {p.name: p.unit for p in self.parameters if p.unit}

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
            what = _nastran_gap(self.coordinate_table, coordinate)
            if what is None:
                # rows are 1..n minus the restrained coordinates: a gap is a restrained one
                gap = 1 <= coordinate <= self.coordinates.max(initial=0)
                what = f"coordinate {coordinate} is restrained" if gap else \
                    f"unknown coordinate {coordinate}"
            raise InputError(f"{what} (the model has coordinates {_ranges(self.coordinates)})")
        return int(rows[0])

    def stiffness(self, values: Sequence[float] | None = None) -> sp.csr_array:
        """K(s) at ``values`` (default: the current ones), exact for nonlinear terms."""
        return self._assemble(self.k0, self.k_terms, self.k_parts, values)

    def mass(self, values: Sequence[float] | None = None) -> sp.csr_array:
        """M(s) at ``values`` (default: the current ones), exact for nonlinear terms."""
        return self._assemble(self.m0, self.m_terms, self.m_parts, values)

    def _assemble(self, base, terms, parts, values) -> sp.csr_array:
        s = self.values if values is None else np.asarray(values, dtype=float)
        out = base.copy()
        if self.nonlinear:
            _check_powers(self.parameters, parts, s)
            for t in parts:
                c = t.value(s)
                if c != 0:
                    out = out + c * t.matrix
            return sp.csr_array(out)
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
        out = ParametricModel(
            self.k0, self.m0, tuple(new), self.k_terms, self.m_terms, self.coordinates,
            self.coordinate_table, self.k_parts, self.m_parts,
        )
        if "_dense" in self.__dict__:  # the same fixed matrices: their dense copy holds
            object.__setattr__(out, "_dense", self._dense)
        return out

    def __getstate__(self) -> dict:
        # the dense copy (model/dense.py) is remade where needed, not sent to workers
        return {k: v for k, v in self.__dict__.items() if k != "_dense"}


def _check_powers(parameters, parts, s: np.ndarray) -> None:
    """InputError for a parameter at 0 that enters with a power below 1 or not whole
    (its term or derivative is infinite or undefined there)."""
    for t in parts:
        for j, a in getattr(t, "powers", ()):
            if s[j] <= 0 and not (a >= 1 and float(a).is_integer()):
                raise InputError(f"parameter {parameters[j].name!r} = {s[j]:g} enters K or M "
                                 f"with power {a:g}: it must be > 0")


def _nastran_gap(table, coordinate: int) -> str | None:
    """Why ``coordinate`` is missing when the model numbers 10 * GRID + component (a
    NASTRAN deck), else None. Such numbers have gaps that are no coordinate at all:
    6011 (GRID 601) and 60117 (component 7) were both called 'restrained'."""
    records = table.coordinates
    if not records or any(c.number != 10 * c.node + c.direction for c in records):
        return None
    grid, component = divmod(coordinate, 10)
    if not 1 <= component <= 6:
        return (f"coordinate {coordinate} is no GRID component (10 * GRID + component, "
                f"component 1-6)")
    if grid not in {c.node for c in records}:
        return (f"coordinate {coordinate}: GRID {grid} has no free coordinate (not in the "
                f"deck, or every component restrained)")
    return (f"coordinate {coordinate}: GRID {grid} component {component} is restrained or "
            f"has neither stiffness nor mass")


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
