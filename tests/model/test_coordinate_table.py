"""CoordinateTable.from_arrays (large models: three arrays, records made on demand)
against the table built record by record, the reference of every other builder."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from eigenupdate.errors import InputError
from eigenupdate.model.coordinates import Coordinate, CoordinateTable


@given(st.sets(st.tuples(st.integers(1, 10**6), st.integers(1, 6)), min_size=1, max_size=40))
def test_from_arrays_is_the_record_by_record_table(points):
    node, direction = np.array(sorted(points)).T
    number = 10 * node + direction  # NASTRAN's numbering: unique with the points
    records = CoordinateTable(Coordinate(int(c), int(n), int(d))
                              for c, n, d in zip(number, node, direction, strict=True))
    table = CoordinateTable.from_arrays(number, node, direction)
    assert table == records and hash(table) == hash(records) and len(table) == len(records)
    assert table.coordinates == records.coordinates
    for c in records.coordinates:
        assert table[c.number] == c and c.number in table
        assert table.from_uff(c.uff_point) == c and table.label(c.number) == c.label


def test_from_arrays_refuses_what_the_records_refuse():
    with pytest.raises(InputError, match="direction code 7 of coordinate 12"):
        CoordinateTable.from_arrays([11, 12], [1, 1], [1, 7])
    with pytest.raises(InputError, match="must be unique"):
        CoordinateTable.from_arrays([11, 11], [1, 2], [1, 1])
    with pytest.raises(InputError, match="must be unique"):
        CoordinateTable.from_arrays([11, 12], [1, 1], [2, 2])
    with pytest.raises(InputError, match="unknown coordinate 13"):
        CoordinateTable.from_arrays([11, 12], [1, 1], [1, 2])[13]
