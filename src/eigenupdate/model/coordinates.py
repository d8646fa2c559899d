"""What each coordinate of a model is: a table of coordinate number, node and direction.

Users speak of coordinates by number (the study file, the CLI, the README). Universal
files and :class:`~eigenupdate.measure.frf.FRF` name a point by ``(node, direction)``
with the dataset-58 direction codes 1-6 (X, Y, Z, RX, RY, RZ). The model builders make
the table, so nothing else needs to know how a kind of model numbers its coordinates:

========================  ===========================  =====================
model                     coordinate                   node, direction
========================  ===========================  =====================
beam                      ``2 i - 1`` (translation)    node ``i``, Z
beam                      ``2 i`` (rotation)           node ``i``, RY
spring-mass, matrices     ``c``                        node ``c``, X
========================  ===========================  =====================

Messages name a coordinate as ``coordinate 15 (node 8, Z)``.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

from eigenupdate.errors import InputError

DIRECTIONS = {1: "X", 2: "Y", 3: "Z", 4: "RX", 5: "RY", 6: "RZ"}
"""Universal-file direction codes (positive directions)."""


@dataclass(frozen=True)
class Coordinate:
    """One coordinate: its number, the node it belongs to and its direction (UFF code).

    >>> c = Coordinate(15, 8, 3)
    >>> c.label, c.rotation, c.uff_point
    ('coordinate 15 (node 8, Z)', False, (8, 3))
    """

    number: int
    node: int
    direction: int

    def __post_init__(self) -> None:
        if self.direction not in DIRECTIONS:
            raise InputError(f"direction code {self.direction!r} of coordinate {self.number} "
                             f"must be one of 1-6 (X, Y, Z, RX, RY, RZ)", field="direction")

    @property
    def rotation(self) -> bool:
        """True for a rotational coordinate (its added mass is a rotary inertia)."""
        return self.direction >= 4

    @property
    def direction_name(self) -> str:
        return DIRECTIONS[self.direction]

    @property
    def uff_point(self) -> tuple[int, int]:
        """Universal-file ``(node, direction)``."""
        return (self.node, self.direction)

    @property
    def label(self) -> str:
        return f"coordinate {self.number} (node {self.node}, {self.direction_name})"


@dataclass(frozen=True)
class CoordinateTable:
    """Every coordinate of a model, by number; built by the model builders.

    Examples
    --------
    >>> table = CoordinateTable.beam(9)
    >>> table[15].label, table[12].label
    ('coordinate 15 (node 8, Z)', 'coordinate 12 (node 6, RY)')
    >>> table.from_uff((6, 3)).number
    11
    >>> CoordinateTable.translations(range(1, 5)).label(4)
    'coordinate 4 (node 4, X)'
    """

    coordinates: tuple[Coordinate, ...]

    def __post_init__(self) -> None:
        object.__setattr__(self, "coordinates", tuple(self.coordinates))
        numbers = [c.number for c in self.coordinates]
        points = [c.uff_point for c in self.coordinates]
        if len(set(numbers)) != len(numbers) or len(set(points)) != len(points):
            raise InputError("coordinate numbers and (node, direction) pairs must be unique",
                             field="coordinates")
        object.__setattr__(self, "_by_number", {c.number: c for c in self.coordinates})
        object.__setattr__(self, "_by_point", {c.uff_point: c for c in self.coordinates})

    @classmethod
    def translations(cls, numbers: Iterable[int]) -> CoordinateTable:
        """One X translation per coordinate, node = coordinate number (spring-mass models,
        assembled matrices)."""
        return cls(tuple(Coordinate(int(c), int(c), 1) for c in numbers))

    @classmethod
    def beam(cls, n_nodes: int) -> CoordinateTable:
        """Planar beam: node i has coordinate 2i-1 (Z translation) and 2i (RY rotation)."""
        return cls(tuple(Coordinate(2 * i - 1 + r, i, 5 if r else 3)
                         for i in range(1, n_nodes + 1) for r in (0, 1)))

    def __getitem__(self, number: int) -> Coordinate:
        try:
            return self._by_number[int(number)]
        except (KeyError, TypeError, ValueError):
            raise InputError(f"unknown coordinate {number!r}", field="coordinate") from None

    def __contains__(self, number: object) -> bool:
        return number in self._by_number

    def __len__(self) -> int:
        return len(self.coordinates)

    def label(self, number: int) -> str:
        """``coordinate 15 (node 8, Z)``; ``coordinate 99`` if the table has no such one."""
        return self[number].label if number in self else f"coordinate {number}"

    def point_label(self, point: tuple[int, int]) -> str:
        """Label of a universal-file point: the coordinate's if the model has it.

        >>> CoordinateTable.beam(9).point_label((8, 3))
        'coordinate 15 (node 8, Z)'
        >>> CoordinateTable.beam(9).point_label((8, -3))
        'node 8, direction -Z'
        """
        c = self._by_point.get(tuple(point))
        if c is not None:
            return c.label
        node, direction = point
        sign = "-" if direction < 0 else ""
        return f"node {node}, direction {sign}{DIRECTIONS.get(abs(direction), direction)}"

    def from_uff(self, point: tuple[int, int]) -> Coordinate:
        """The coordinate of a universal-file ``(node, direction)``, or an InputError
        that names the point and the table's directions.

        A response measured in a negative direction has the opposite sign; the caller
        must correct it before looking it up.
        """
        try:
            node, direction = (int(v) for v in point)
        except (TypeError, ValueError):
            raise InputError(f"expected a (node, direction) pair, got {point!r}",
                             field="point") from None
        c = self._by_point.get((node, direction))
        if c is None:
            have = sorted({d.direction_name for d in self.coordinates})
            name = DIRECTIONS.get(abs(direction), str(direction))
            sign = "-" if direction < 0 else ""
            raise InputError(f"node {node}, direction {sign}{name} is not a coordinate of the "
                             f"model (its nodes have directions {', '.join(have)})",
                             field="point")
        return c
