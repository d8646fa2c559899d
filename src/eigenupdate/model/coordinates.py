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
from functools import cached_property

import numpy as np
from numpy.typing import ArrayLike

from eigenupdate.errors import InputError

DIRECTIONS = {1: "X", 2: "Y", 3: "Z", 4: "RX", 5: "RY", 6: "RZ"}
"""Universal-file direction codes (positive directions)."""
_FIELDS = ("number", "node", "direction")


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


class CoordinateTable:
    """Every coordinate of a model, by number; built by the model builders.

    The table holds three integer arrays (number, node, direction); a
    :class:`Coordinate` record is made when one is asked for, so that a large model's
    table costs a few array operations (:meth:`from_arrays`).

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

    def __init__(self, coordinates: Iterable[Coordinate]):
        coords = tuple(coordinates)
        self._set(*(np.fromiter((getattr(c, f) for c in coords), np.int64, len(coords))
                    for f in _FIELDS))
        self.__dict__["coordinates"] = coords

    @classmethod
    def from_arrays(cls, numbers: ArrayLike, nodes: ArrayLike,
                    directions: ArrayLike) -> CoordinateTable:
        """The table of coordinates ``numbers[i]`` at ``(nodes[i], directions[i])``.

        >>> CoordinateTable.from_arrays([11, 12], [1, 1], [1, 2]).label(12)
        'coordinate 12 (node 1, Y)'
        """
        table = cls.__new__(cls)
        table._set(*(np.asarray(a, dtype=np.int64).ravel() for a in (numbers, nodes,
                                                                       directions)))
        return table

    def _set(self, number: np.ndarray, node: np.ndarray, direction: np.ndarray) -> None:
        if not number.size == node.size == direction.size:
            raise InputError("coordinate numbers, nodes and directions differ in length",
                             field="coordinates")
        bad = np.flatnonzero((direction < 1) | (direction > 6))
        if bad.size:  # the record's own message
            Coordinate(int(number[bad[0]]), int(node[bad[0]]), int(direction[bad[0]]))
        # (node, direction) as one integer: directions are 1-6
        if (np.unique(number).size != number.size
                or np.unique(8 * node + direction).size != number.size):
            raise InputError("coordinate numbers and (node, direction) pairs must be unique",
                             field="coordinates")
        for a in (number, node, direction):
            a.flags.writeable = False
        self._number, self._node, self._direction = number, node, direction

    @cached_property
    def coordinates(self) -> tuple[Coordinate, ...]:
        """Every coordinate's record, in the table's order."""
        return tuple(map(Coordinate, *(a.tolist() for a in self._arrays)))

    @property
    def _arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return self._number, self._node, self._direction

    @cached_property
    def _by_number(self) -> dict[int, int]:
        return dict(zip(self._number.tolist(), range(self._number.size), strict=True))

    @cached_property
    def _by_point(self) -> dict[tuple[int, int], int]:
        return dict(zip(zip(self._node.tolist(), self._direction.tolist(), strict=True),
                        range(self._number.size), strict=True))

    def _record(self, i: int) -> Coordinate:
        return Coordinate(*(int(a[i]) for a in self._arrays))

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, CoordinateTable):
            return NotImplemented
        return all(np.array_equal(a, b) for a, b in zip(self._arrays, other._arrays,
                                                           strict=True))

    def __hash__(self) -> int:
        return hash(tuple(a.tobytes() for a in self._arrays))

    def __repr__(self) -> str:
        return f"CoordinateTable({self._number.size} coordinates)"

    @classmethod
    def translations(cls, numbers: Iterable[int]) -> CoordinateTable:
        """One X translation per coordinate, node = coordinate number (spring-mass models,
        assembled matrices)."""
        c = np.fromiter((int(c) for c in numbers), np.int64)
        return cls.from_arrays(c, c, np.ones_like(c))

    @classmethod
    def beam(cls, n_nodes: int) -> CoordinateTable:
        """Planar beam: node i has coordinate 2i-1 (Z translation) and 2i (RY rotation)."""
        node = np.repeat(np.arange(1, n_nodes + 1), 2)
        return cls.from_arrays(np.arange(1, 2 * n_nodes + 1), node,
                               np.tile([3, 5], n_nodes))

    def __getitem__(self, number: int) -> Coordinate:
        try:
            return self._record(self._by_number[int(number)])
        except (KeyError, TypeError, ValueError):
            raise InputError(f"unknown coordinate {number!r}", field="coordinate") from None

    def __contains__(self, number: object) -> bool:
        return number in self._by_number

    def __len__(self) -> int:
        return int(self._number.size)

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
        i = self._by_point.get(tuple(point))
        if i is not None:
            return self._record(i).label
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
        i = self._by_point.get((node, direction))
        if i is None:
            have = [DIRECTIONS[d] for d in np.unique(self._direction).tolist()]
            name = DIRECTIONS.get(abs(direction), str(direction))
            sign = "-" if direction < 0 else ""
            raise InputError(f"node {node}, direction {sign}{name} is not a coordinate of the "
                             f"model (its nodes have directions {', '.join(have)})",
                             field="point")
        return self._record(i)
