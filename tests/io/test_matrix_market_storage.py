"""Matrix Market storage of symmetric matrices. The format (NIST, "The Matrix Market
Exchange Formats", 1996) stores one triangle of a symmetric matrix: n(n+1)/2 values in
array format, each off-diagonal pair once in coordinate format. Source: the tester's
acceptance run (issue 21): scipy's own dense symmetric file was refused as "truncated",
and a symmetric file listing both triangles, as some exporters write, was read with its
off-diagonal entries doubled (scipy mirrors every entry)."""

import numpy as np
import pytest
import scipy.io

from eigenupdate.errors import InputError
from eigenupdate.io.matrix_market import read_matrix

A = np.array([[4.0, -1.0, 0.5], [-1.0, 3.0, -2.0], [0.5, -2.0, 5.0]])


def test_dense_symmetric_array_reads_back(tmp_path):
    # a banded 40 x 40: scipy writes its 820 stored values, most of them "0", in fewer
    # bytes than 2 per entry of the full 1,600 the header's size implies
    big = np.diag(np.full(40, 2.0)) - np.diag(np.ones(39), 1) - np.diag(np.ones(39), -1)
    for m in (A, big):
        scipy.io.mmwrite(tmp_path / "a.mtx", m)
        assert "array real symmetric" in (tmp_path / "a.mtx").read_text().splitlines()[0]
        assert np.array_equal(read_matrix(tmp_path / "a.mtx").toarray(), m)


def _coordinate(path, symmetry, entries):
    lines = [f"%%MatrixMarket matrix coordinate real {symmetry}", f"3 3 {len(entries)}"]
    lines += [f"{i} {j} {float(v)!r}" for i, j, v in entries]
    path.write_text("\n".join(lines) + "\n")


def test_symmetric_file_with_both_triangles_is_refused(tmp_path):
    both = [(i + 1, j + 1, A[i, j]) for i in range(3) for j in range(3) if A[i, j]]
    _coordinate(tmp_path / "g.mtx", "general", both)
    assert np.array_equal(read_matrix(tmp_path / "g.mtx").toarray(), A)
    _coordinate(tmp_path / "s.mtx", "symmetric", both)
    # what the reader underneath makes of it: the off-diagonal entries doubled
    doubled = scipy.io.mmread(tmp_path / "s.mtx").toarray()
    assert doubled[0, 1] == 2 * A[0, 1]
    with pytest.raises(InputError, match=r"s\.mtx.*entry \(1, 2\) more than once"):
        read_matrix(tmp_path / "s.mtx")
    lower = [(i, j, v) for i, j, v in both if i >= j]
    _coordinate(tmp_path / "l.mtx", "symmetric", lower)
    assert np.array_equal(read_matrix(tmp_path / "l.mtx").toarray(), A)
