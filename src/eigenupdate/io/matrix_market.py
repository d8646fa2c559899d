"""Models assembled elsewhere (NASTRAN, FEMtools, ...) read from Matrix Market files:
K0, M0 and, per parameter, dK/ds_j and/or dM/ds_j."""

from __future__ import annotations

import re
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import scipy.io
import scipy.sparse as sp

from eigenupdate.budget import require, require_model_size
from eigenupdate.errors import InputError
from eigenupdate.io.inputs import require_regular
from eigenupdate.model.matrices import matrix_model
from eigenupdate.model.parameters import Parameter
from eigenupdate.model.parametric import ParametricModel

SYMMETRY_RTOL = 1e-10
MAX_LINE = 1024


def read_matrix(path: str | Path, n: int | None = None) -> sp.csr_array:
    """Read one square, symmetric, real matrix from a Matrix Market file."""
    path = Path(path)
    require_regular(path, "Matrix Market file")  # mminfo reads /dev/zero's "line" forever
    _check_header(path, n)
    try:
        a = scipy.io.mmread(path)
    except (OSError, ValueError, TypeError, IndexError, OverflowError, MemoryError) as exc:
        raise InputError(f"cannot read Matrix Market file: {exc}", source=str(path)) from None
    info = scipy.io.mminfo(path)
    if info[4] == "pattern":
        raise InputError("matrix is a pattern (no values); a real matrix is required",
                         source=str(path))
    if info[3] == "coordinate" and info[5] == "symmetric":
        _one_triangle(path, a)
    a = sp.csr_array(a)
    if np.iscomplexobj(a.data):
        raise InputError("matrix is complex; a real matrix is required", source=str(path))
    a = a.astype(float)
    if not np.all(np.isfinite(a.data)):
        raise InputError("matrix has NaN or infinite entries", source=str(path))
    if a.shape[0] != a.shape[1]:
        raise InputError(f"matrix is not square: shape {a.shape}", source=str(path))
    if n is not None and a.shape[0] != n:
        raise InputError(f"matrix is {a.shape[0]}x{a.shape[0]}, K0 is {n}x{n}", source=str(path))
    asym = abs(a - a.T).max() if a.nnz else 0.0
    if asym > SYMMETRY_RTOL * (abs(a).max() if a.nnz else 1.0):
        raise InputError(f"matrix is not symmetric (max |A - A^T| = {asym:.3g})", source=str(path))
    return a


def _one_triangle(path: Path, a) -> None:
    """A symmetric file stores each off-diagonal pair once; the reader mirrors every entry,
    so a file listing both triangles (as some exporters write) would double them. The
    reader's entries (mirrored, not summed) then hit some position twice."""
    coo = sp.coo_array(a)
    if coo.nnz == 0:
        return
    key = coo.row.astype(np.int64) * coo.shape[1] + coo.col
    _, first, counts = np.unique(key, return_index=True, return_counts=True)
    if np.any(counts > 1):
        k = first[np.argmax(counts > 1)]
        i, j = sorted((int(coo.row[k]) + 1, int(coo.col[k]) + 1))
        raise InputError(f"symmetric file gives entry ({i}, {j}) more than once (or also as "
                         f"({j}, {i})): a symmetric Matrix Market file stores one triangle, "
                         f"and the reader would add them", source=str(path))


def _check_header(path: Path, n: int | None) -> None:
    """Sizes the header declares, checked before anything of that size is allocated:
    square, n x n when K0 is, within the coordinate budget (:mod:`eigenupdate.budget`),
    and no more entries than the file can hold (a value takes at least 2 bytes, a
    coordinate entry at least 6)."""
    src = str(path)
    try:
        rows, cols, entries, fmt, _, symmetry = scipy.io.mminfo(path)
        size = path.stat().st_size
    except (OSError, ValueError, TypeError, IndexError, OverflowError) as exc:
        raise InputError(f"cannot read Matrix Market header: {exc}", source=src) from None
    if rows != cols:
        raise InputError(f"matrix is not square: the header declares {rows} x {cols}",
                         source=src)
    if n is not None and rows != n:
        raise InputError(f"the header declares {rows} x {rows}, K0 is {n} x {n}", source=src)
    require("coordinates", rows, f"the header declares {rows:,} x {rows:,}", source=src)
    # scipy's compiled reader trusts its input: a 140,000-byte token crashes it (SIGSEGV)
    data = path.read_bytes()
    if not data.isascii():
        i = next(i for i, b in enumerate(data) if b > 127)
        raise InputError(f"byte {i + 1} is not ASCII (Matrix Market files are ASCII text)",
                         source=src)
    long = re.search(rb"[^\n]{%d}" % (MAX_LINE + 1), data)
    if long:
        line = data.count(b"\n", 0, long.start()) + 1
        raise InputError(f"line {line} is longer than {MAX_LINE} characters", source=src)
    per_entry = 2 if fmt == "array" else 6
    if fmt == "array" and symmetry != "general":  # one triangle stored (mminfo counts n^2)
        entries = rows * (rows + 1) // 2 if symmetry != "skew-symmetric" else rows * (rows - 1) // 2
    if entries * per_entry > size:
        raise InputError(f"the header declares {entries} {fmt} entries but the file has only "
                         f"{size} bytes (truncated, or a wrong header)", source=src)


def read_matrix_model(
    k0: str | Path,
    m0: str | Path,
    parameters: Sequence[tuple[Parameter, str | Path | None, str | Path | None]],
    terms: Sequence[tuple[tuple[tuple[int, float], ...], float, str | Path | None,
                          str | Path | None]] = (),
) -> ParametricModel:
    """Model K = K0 + sum s_j K_j, M = M0 + sum s_j M_j from Matrix Market files, plus
    monomial ``terms``: (powers, coefficient, K file or None, M file or None), each adding
    coefficient * prod s_j^a_j times its matrix (:class:`~eigenupdate.model.parametric.Term`).

    ``parameters`` holds (parameter, K_j file or None, M_j file or None). The model is
    built by :func:`eigenupdate.model.matrices.matrix_model`.
    """
    K0 = read_matrix(k0)
    n = K0.shape[0]
    require_model_size(n, len(parameters) + len(terms), "model.parameter")
    M0 = read_matrix(m0, n)
    linear = []
    for p, kf, mf in parameters:
        linear.append((p, None if kf is None else read_matrix(kf, n),
                       None if mf is None else read_matrix(mf, n)))
    parts = [(pw, c, None if kf is None else read_matrix(kf, n),
              None if mf is None else read_matrix(mf, n)) for pw, c, kf, mf in terms]
    return matrix_model(K0, M0, linear, parts)
