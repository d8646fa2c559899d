"""Measured natural frequencies: the CSV a study points at, one row per configuration
and elastic mode: ``configuration,mode,frequency_hz,std_hz`` ("base" = bare structure).
``std_hz`` may be empty when the method needs no weights (plain least squares)."""

from __future__ import annotations

import csv
import io
import unicodedata
from collections.abc import Iterable
from pathlib import Path

from eigenupdate.errors import InputError, shorten
from eigenupdate.io.atomic import write_text
from eigenupdate.io.inputs import require_regular
from eigenupdate.io.numbers import parse_float, parse_int
from eigenupdate.measure.measurement import Measurement

COLUMNS = ("configuration", "mode", "frequency_hz", "std_hz")
MAX_LINE_CHARS = 10_000
"""Longer lines are refused (the csv module's own field limit is 131,072)."""
MAX_FILE_BYTES = 100 * 2**20


def read_measurements(
    path: str | Path, configurations: Iterable[str] | None = None
) -> dict[tuple[str, int], Measurement]:
    """Read a measurement CSV into {(configuration, mode): Measurement}.

    ``configurations``, if given, are the names a row may use (others are an error).
    """
    path = Path(path)
    src = str(path)
    require_regular(path, "measurement file")
    try:
        if path.stat().st_size > MAX_FILE_BYTES:
            raise InputError(f"file is {path.stat().st_size} bytes; a measurement file is at "
                             f"most {MAX_FILE_BYTES}", source=src)
        text = path.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read measurement file: {exc}", source=src) from None
    lines = [(i, ln) for i, ln in enumerate(text.splitlines(), 1) if ln.strip()]
    for i, ln in lines:
        if len(ln) > MAX_LINE_CHARS:
            raise InputError(f"line {i} has {len(ln)} characters (at most {MAX_LINE_CHARS})",
                             source=src)
    lines = [(i, ln) for i, ln in lines if not ln.lstrip().startswith("#")]
    if not lines:
        raise InputError("measurement file is empty", source=src)
    header = [h.strip() for h in next(csv.reader([lines[0][1]]))]
    twice = sorted({h for h in header if h and header.count(h) > 1})
    if twice:
        raise InputError(f"line {lines[0][0]}: column(s) {twice} appear twice", source=src)
    missing = [c for c in COLUMNS[:3] if c not in header]
    if missing:
        raise InputError(
            f"line {lines[0][0]}: header lacks column(s) {missing}; expected {','.join(COLUMNS)}",
            source=src,
        )
    col = {name: header.index(name) for name in COLUMNS if name in header}
    known = None if configurations is None else set(configurations)
    out: dict[tuple[str, int], Measurement] = {}
    for lineno, row in zip(
        (i for i, _ in lines[1:]), csv.reader(ln for _, ln in lines[1:]), strict=True
    ):
        where = f"line {lineno}"
        if [c.strip() for c in row] == header:  # not a configuration called 'configuration'
            raise InputError(f"{where} repeats the header of line {lines[0][0]} (two files "
                             f"joined?)", source=src)
        if len(row) != len(header):
            raise InputError(f"{where}: {len(row)} fields, expected {len(header)}", source=src)
        cfg = row[col["configuration"]].strip()
        if known is not None and cfg not in known:
            same = [k for k in known if unicodedata.normalize("NFC", k)
                    == unicodedata.normalize("NFC", cfg)]
            if same:  # looks the same when printed: say how they differ
                raise InputError(f"{where}: configuration {ascii(cfg)} is the study's "
                                 f"{ascii(same[0])} in another Unicode form (composed and "
                                 f"decomposed accents); write it as the study does",
                                 source=src)
            raise InputError(f"{where}: configuration {shorten(cfg, 60)!r} is not in the study "
                             f"(known: {sorted(known)})", source=src)
        mode = _number(row[col["mode"]], int, src, where, "mode")
        f = _number(row[col["frequency_hz"]], float, src, where, "frequency_hz")
        std_txt = row[col["std_hz"]].strip() if "std_hz" in col else ""
        std = _number(std_txt, float, src, where, "std_hz") if std_txt else None
        if not cfg:
            raise InputError(f"{where}: empty configuration", source=src)
        if mode < 1:
            raise InputError(f"{where}: mode must be >= 1, got {mode}", source=src)
        if not 0 < f < 1e12:  # beyond, lambda = (2 pi f)^2 leaves any plausible model
            raise InputError(f"{where}: frequency_hz must be > 0 and < 1e12, got {f}",
                             source=src)
        if std is not None and not std > 0:
            raise InputError(f"{where}: std_hz must be > 0, got {std}", source=src)
        if std is not None and std >= f:  # 1e6 on 200 Hz: the Bayesian fit kept the prior
            raise InputError(f"{where}: std_hz {std:g} is not below frequency_hz {f:g}; a "
                             f"frequency's std is a small part of it (std in another unit, "
                             f"or a variance?)", source=src)
        if (cfg, mode) in out:
            raise InputError(f"{where}: second row for {cfg!r} mode {mode}", source=src)
        out[(cfg, mode)] = Measurement(cfg, mode, f, std)
    return out


def _number(text: str, kind, src: str, where: str, name: str):
    try:
        return parse_int(text) if kind is int else parse_float(text)
    except ValueError:
        what = "an integer" if kind is int else "a number (plain ASCII, e.g. 42.5 or 4.25e1)"
        raise InputError(f"{where}: {name} {shorten(text.strip(), 40)!r} is not {what}",
                         source=src) from None


SIMULATED = "# eigenupdate simulate:"
"""The first line of ``simulate -o``: its own earlier output, which it may replace."""


def write_measurements(path: str | Path, rows: Iterable[Measurement],
                       comment: str | None = None) -> None:
    """Write a measurement CSV at full precision, atomically (temporary file + rename),
    after ``comment`` (one line, without its '# ') if given."""
    buf = io.StringIO()
    if comment is not None:
        buf.write(f"# {comment}\n")
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(COLUMNS)
    for m in rows:
        std = "" if m.std_hz is None else repr(float(m.std_hz))
        w.writerow([m.configuration, m.mode, repr(float(m.frequency_hz)), std])
    write_text(path, buf.getvalue())
