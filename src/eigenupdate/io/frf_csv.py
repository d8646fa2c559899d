"""FRF files in CSV: one receptance FRF per file.

Format (:func:`read_frf_csv`, :func:`write_frf_csv`)::

    # comment lines start with '#', blank lines are ignored
    frequency_hz,real,imag
    0.5,1.25e-06,-3.0e-08
    1.0,1.31e-06,-6.2e-08

The header line is required; the values are receptance in m/N.  The file carries no
degree-of-freedom information: ``response`` and ``reference`` are read as ``(0, 0)``.
"""

from __future__ import annotations

import math
import os

import numpy as np

from eigenupdate.errors import InputError
from eigenupdate.io.atomic import atomic_write
from eigenupdate.io.inputs import require_regular
from eigenupdate.io.numbers import parse_float
from eigenupdate.measure.frf import FRF, dof_label

__all__ = ["CSV_COLUMNS", "read_frf_csv", "write_frf_csv"]

PathLike = str | os.PathLike[str]

#: Required CSV header, in this order.
CSV_COLUMNS: tuple[str, str, str] = ("frequency_hz", "real", "imag")


def read_frf_csv(path: PathLike) -> FRF:
    """Read one receptance FRF from a CSV file with columns ``frequency_hz,real,imag``.

    Lines starting with ``#`` and blank lines are ignored; text after a ``#`` on a data
    line is a comment.  The first other line must be the header ``frequency_hz,real,imag``
    (case-insensitive, spaces allowed).  Values are receptance in m/N; ``response`` and
    ``reference`` of the result are ``(0, 0)``.

    Parameters
    ----------
    path : str or path-like
        CSV file (UTF-8, an optional BOM is accepted).

    Returns
    -------
    FRF
        With ``source`` set to ``str(path)``.

    Raises
    ------
    InputError
        If the file cannot be read, the header is missing or wrong, a line has the wrong
        number of columns or a non-numeric or non-finite value (the message names the line
        number), there are no data rows, or the frequencies are negative or not strictly
        increasing.
    """
    src = str(path)
    require_regular(path, "FRF file")
    try:
        with open(path, encoding="utf-8-sig", newline="") as fh:
            lines = fh.read().splitlines()
    except UnicodeDecodeError as exc:
        raise InputError(f"not a UTF-8 text file ({exc.reason})", source=src) from None
    except OSError as exc:
        raise InputError(f"cannot read file: {exc.strerror or exc}", source=src) from None

    header_seen = False
    rows: list[tuple[float, float, float]] = []
    linenos: list[int] = []
    for lineno, raw in enumerate(lines, start=1):
        text = raw.split("#", 1)[0].strip()
        if not text:
            continue
        cells = [c.strip() for c in text.split(",")]
        if not header_seen:
            names = tuple(c.lower() for c in cells)
            if names != CSV_COLUMNS:
                raise InputError(
                    f"expected header line {','.join(CSV_COLUMNS)!r}, got {text!r}",
                    source=src,
                    field=f"line {lineno}",
                )
            header_seen = True
            continue
        if len(cells) != len(CSV_COLUMNS):
            raise InputError(
                f"expected {len(CSV_COLUMNS)} columns ({','.join(CSV_COLUMNS)}), got {len(cells)}",
                source=src,
                field=f"line {lineno}",
            )
        values = []
        for name, cell in zip(CSV_COLUMNS, cells, strict=True):
            try:
                value = float(cell)
                if math.isfinite(value):  # and plain ASCII: no '1_000', no Unicode digits
                    value = parse_float(cell)
            except ValueError:
                raise InputError(
                    f"column {name}: non-numeric value {cell!r}", source=src, field=f"line {lineno}"
                ) from None
            if not math.isfinite(value):
                raise InputError(
                    f"column {name}: non-finite value {cell!r}", source=src, field=f"line {lineno}"
                )
            values.append(value)
        rows.append((values[0], values[1], values[2]))
        linenos.append(lineno)

    if not header_seen:
        raise InputError(
            f"no header line {','.join(CSV_COLUMNS)!r} (empty file?)", source=src, field="header"
        )
    if not rows:
        raise InputError("no data rows after the header", source=src, field="frequency_hz")
    data = np.array(rows, dtype=np.float64)
    freq = data[:, 0]
    if freq[0] < 0:
        raise InputError(
            f"column frequency_hz: negative frequency {freq[0]!r}",
            source=src,
            field=f"line {linenos[0]}",
        )
    steps = np.diff(freq)
    if (steps <= 0).any():
        k = int(np.flatnonzero(steps <= 0)[0]) + 1
        raise InputError(
            f"column frequency_hz: {float(freq[k])!r} Hz is not greater than the previous "
            f"{float(freq[k - 1])!r} Hz (line {linenos[k - 1]}); frequencies must be "
            f"strictly increasing",
            source=src,
            field=f"line {linenos[k]}",
        )
    return FRF(freq, data[:, 1] + 1j * data[:, 2], (0, 0), (0, 0), source=src)


def write_frf_csv(path: PathLike, frf: FRF) -> None:
    """Write one FRF as receptance to a CSV file readable by :func:`read_frf_csv`.

    Values are written with 17 significant digits, so a write/read round trip is exact.
    The file is replaced atomically: the data go to a temporary file in the same
    directory, which is then renamed over ``path``.

    Parameters
    ----------
    path : str or path-like
        Destination file.
    frf : FRF
        The FRF; its response/reference DOFs are written as a comment only.

    Raises
    ------
    ValueError
        If the receptance contains NaN (e.g. an unconverted 0 Hz line); drop it first.
    OSError
        If the file cannot be written (no partial file is left behind).
    """
    rec = frf.receptance
    if not np.isfinite(rec).all():
        bad = int(np.flatnonzero(~np.isfinite(rec))[0])
        raise ValueError(
            f"{path}: receptance is not finite at {frf.frequency_hz[bad]:g} Hz (index {bad}); "
            "drop that line before writing"
        )
    out = [
        "# eigenupdate FRF: receptance in m/N",
        f"# response={dof_label(frf.response)} reference={dof_label(frf.reference)}"
        + (f" source={frf.source}" if frf.source else ""),
        ",".join(CSV_COLUMNS),
    ]
    out.extend(
        f"{f!r},{h.real!r},{h.imag!r}"
        for f, h in zip(frf.frequency_hz.tolist(), rec.tolist(), strict=True)
    )
    text = "\n".join(out) + "\n"

    def _write(tmp: str) -> None:
        with open(tmp, "w", encoding="utf-8", newline="\n") as fh:
            fh.write(text)

    atomic_write(path, _write)


# ----------------------------------------------------------------------------- files
