"""pyuff underneath the universal-file readers and writers: one dataset read at a time,
its prints and warnings silenced, every failure an InputError naming the file.

* ``UFF.write_sets(mode="overwrite")`` with a binary 58b set truncates the file it has
  just written (the header is lost) - files are always written in ``"add"`` mode to a
  fresh temporary file which then replaces the destination.
* ``UFF.write_sets`` silently replaces NaN/inf data by 0/huge numbers
  (``np.nan_to_num``) - :func:`write_frfs` refuses non-finite data instead.
* The 58b header field "number of bytes" is written as ``8 * num_pts`` although complex
  data take 16 (even) or 24 (uneven) bytes per point; pyuff's reader ignores it.
* ``UFF.get_set_formats`` always reports ASCII (it compares a byte to ``'b'``); the
  ``binary`` key of the read dataset is correct.
* ``UFF.read_sets`` returns a dict for one set and a list otherwise, and replaces every
  parse error by ``Exception('Error when reading data-set(s).')``; a file cut inside its
  last dataset is silently read without it.  Sets are read one at a time here and a
  file that does not end with the ``-1`` delimiter is rejected as truncated.
* A 58b set written with ``force_double=False`` (single precision, ``ord_data_type`` 5)
  gets 8-byte doubles under a single-precision header and reads back as twice as many
  garbage values; the ``num_pts`` check here rejects such files, and :func:`write_frfs`
  always writes double precision.
* ``UFF.write_sets`` re-reads the whole file after every dataset (quadratic in the
  number of datasets), and labels longer than 20 characters shift the fixed columns;
  the labels written here are short.
* pyuff may ``print``; its output and warnings are suppressed while it runs (by
  redirecting ``sys.stdout``, which is process-wide).
"""

from __future__ import annotations

import contextlib
import io
import os
import re
import warnings
from collections.abc import Iterator
from typing import Any

import numpy as np
import pyuff

from eigenupdate.errors import InputError
from eigenupdate.io.inputs import require_regular

PathLike = str | os.PathLike[str]

@contextlib.contextmanager
def _quiet() -> Iterator[None]:
    """Silence pyuff's prints and warnings."""
    with (
        contextlib.redirect_stdout(io.StringIO()),
        warnings.catch_warnings(),
        np.errstate(all="ignore"),
    ):
        warnings.simplefilter("ignore")
        yield


def _read_bytes(path: PathLike) -> bytes:
    src = str(path)
    if os.path.isdir(path):
        raise InputError("is a directory, not a universal file", source=src)
    require_regular(path, "universal file")
    try:
        with open(path, "rb") as fh:
            return fh.read()
    except OSError as exc:
        raise InputError(f"cannot read file: {exc.strerror or exc}", source=src) from None


def _open_uff(path: PathLike) -> tuple[Any, list[int]]:
    """Read the file into bytes (for the checks) and index its datasets with pyuff."""
    src = str(path)
    raw = _read_bytes(path)
    try:
        with _quiet():
            uff = pyuff.UFF(os.fspath(path))
            types = [int(t) for t in uff.get_set_types()]
    except Exception as exc:  # pyuff raises bare Exception
        raise InputError(f"not a readable universal file ({exc})", source=src) from None
    _check_datasets(raw, uff, src)
    if types and not raw.rstrip(b" \t\r\n\x00\x1a").endswith(b"-1"):
        raise InputError(
            "file ends inside a dataset (truncated?): no closing '    -1' delimiter after the "
            f"last of {len(types)} complete dataset(s)",
            source=src,
        )
    return uff, types


_TYPE = re.compile(rb"[ \t]*(\d+)b?(?:[ \t].*)?\r?")


def _check_datasets(raw: bytes, uff: Any, src: str) -> None:
    """pyuff pairs the '    -1' tags of the file in order and reads the line after each
    opening tag as the dataset type: a blank line there makes it skip the dataset without
    a word. That is refused here, on pyuff's own pairing (``_block_ind``, pyuff 2.5), so
    the file never reads as a shorter list."""
    blocks = getattr(uff, "_block_ind", None)
    if blocks is None:  # pragma: no cover - another pyuff: nothing to check against
        return
    starts = [int(b[0]) for b in blocks]
    for k, s in enumerate(starts):
        line_end = raw.find(b"\n", s)
        nxt = raw.find(b"\n", line_end + 1) if line_end >= 0 else -1
        head = raw[line_end + 1: nxt if nxt >= 0 else len(raw)] if line_end >= 0 else b""
        if _TYPE.fullmatch(head) is None:
            line = raw.count(b"\n", 0, s) + 2
            what = "a blank line" if not head.strip() else "no dataset type"
            raise InputError(f"line {line}: {what} after the '-1' delimiter that opens dataset "
                             f"{k + 1}, where its type (such as 58) must be; the dataset would "
                             f"be skipped", source=src, field=f"dataset {k + 1}")


def _read_set(uff: Any, index: int, set_type: int, src: str, header_only: bool = False) -> dict:
    try:
        with _quiet():
            dset = uff.read_sets(index, header_only=header_only)
    except Exception as exc:
        raise InputError(
            f"dataset {index + 1} (type {set_type}): pyuff cannot parse it ({exc})",
            source=src,
            field=f"dataset {index + 1}",
        ) from None
    if not isinstance(dset, dict):  # pragma: no cover - pyuff returns a dict for one set
        raise InputError(f"dataset {index + 1}: unexpected pyuff result", source=src)
    return dset

