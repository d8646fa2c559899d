"""Universal file (UFF) input/output: FRFs (dataset 58 / 58b) and normal modes (dataset 55).

Parsing and formatting are done by `pyuff <https://github.com/ladisk/pyuff>`_; this module
maps its dataset dictionaries to :class:`~eigenupdate.measure.frf.FRF` and :class:`Mode`,
validates them and turns every failure on bad input into an
:class:`~eigenupdate.errors.InputError` naming the file and the field.

Dataset 58 fields used (pyuff names, record/field of the UFF 58 specification)
-----------------------------------------------------------------------------
``func_type`` (R6 F1)
    Must be 4 (frequency response function) for reading; other functions in the file
    (time responses, spectra, coherences, ...) are skipped.
``rsp_node``, ``rsp_dir``, ``ref_node``, ``ref_dir`` (R6 F6, F7, F9, F10)
    :attr:`FRF.response` and :attr:`FRF.reference`.
``ord_data_type`` (R7 F1)
    5 or 6 (complex single/double precision); real-only ordinates (2, 4) are rejected.
``num_pts``, ``abscissa_spacing``, ``abscissa_min``, ``abscissa_inc`` (R7 F2-F5)
    Number of values and the abscissa (even spacing: min + k inc; uneven: stored values).
``abscissa_spec_data_type``, ``abscissa_axis_units_lab`` (R8 F1, F6)
    Must be 18 (frequency), 0 (unknown) or 1 (general); the units label may be empty,
    ``NONE``, ``Hz``, ``kHz`` or ``rad/s``.
``ordinate_spec_data_type``, ``ordinate_axis_units_lab`` (R9 F1, F6)
    Response quantity of the numerator: 8 displacement (receptance), 11 velocity
    (mobility), 12 acceleration (accelerance).  For 0 (unknown) or 1 (general) the kind
    is taken from the units label if that is unambiguous (``m``, ``m/s``, ``m/s^2``,
    ``g``, ``(1/N)*(m/s^2)``, ``m/s^2/N``, ...), else from the ``default_kind`` argument
    of :func:`read_frfs` (the study option ``[measurement.frf_options] kind``).
``orddenom_spec_data_type``, ``orddenom_axis_units_lab`` (R10 F1, F6)
    Denominator: 13 (excitation force), 9 (reaction force) or 0 (unknown, assumed force).
``data``, ``x``
    Complex ordinate values and abscissa values.

Units
-----
Values are assumed SI (Hz, m, m/s, m/s^2, N; rad and N m for rotations) unless the
units label says otherwise.  Recognised labels are converted: lengths ``mm``, ``um``,
``cm``, ``in``, ``ft``; ``g`` (9.80665 m/s^2) for acceleration; ``kN``, ``lbf``, ``kgf``
for force; a combined numerator label such as ``g/N``, ``(m/s^2)/N``, ``m/s^2/N`` or
``(1/N)*(m/s^2)``.  ``²`` is read as ``^2``, also when a non-UTF-8 file turned it into a
replacement character.  An unrecognised label is rejected rather than guessed.  The unit
*exponents* of records 8-11 are ignored (the specification makes them relevant only for
"general" data).

Precision
---------
pyuff writes dataset 58 ASCII values with 12 significant digits (``%20.11e``) and the
abscissa (``abscissa_min``/``abscissa_inc``, or each value for uneven spacing) with 6
(``%13.5e``, as the UFF specification prescribes).  Binary 58b stores IEEE doubles, so
ordinates round-trip exactly; :func:`write_frfs` keeps the axis exact in 58b by using
uneven spacing when ``min + k inc`` with 6-digit values would not reproduce it.
Dataset 55 stores every real number with 6 significant digits (``%13.5e``).

pyuff quirks handled here (pyuff 2.5.8)
--------------------------------------
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
import math
import operator
import os
import re
import warnings
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np
import pyuff
from numpy.typing import ArrayLike

from eigenupdate.errors import InputError
from eigenupdate.io.atomic import atomic_write
from eigenupdate.measure.frf import (
    FRF,
    FRF_KINDS,
    dof_label,
    is_uniform,
    to_receptance,
)

__all__ = ["Mode", "read_frfs", "read_modes", "write_frfs", "write_modes"]

PathLike = str | os.PathLike[str]

# UFF 58 record 6 field 1.
_FUNC_NAMES = {
    0: "general/unknown",
    1: "time response",
    2: "auto spectrum",
    3: "cross spectrum",
    4: "FRF",
    5: "transmissibility",
    6: "coherence",
    7: "auto correlation",
    8: "cross correlation",
    9: "PSD",
    10: "ESD",
    11: "probability density",
    12: "spectrum",
    18: "mode indicator function",
}
# UFF 58 records 8-11 field 1 (specific data type).
_SPEC_NAMES = {
    0: "unknown",
    1: "general",
    2: "stress",
    3: "strain",
    5: "temperature",
    6: "heat flux",
    8: "displacement",
    9: "reaction force",
    11: "velocity",
    12: "acceleration",
    13: "excitation force",
    15: "pressure",
    16: "mass",
    17: "time",
    18: "frequency",
    19: "rpm",
    20: "order",
}
_FRF_FUNC = 4
_SPEC_TO_KIND = {8: "receptance", 11: "mobility", 12: "accelerance"}
_KIND_TO_QUANTITY = {
    "receptance": "displacement",
    "mobility": "velocity",
    "accelerance": "acceleration",
}
_UNKNOWN_SPECS = (0, 1)
_FORCE_SPECS = (0, 9, 13)
_FREQUENCY_SPECS = (0, 1, 18)

# Units labels, normalised by _norm_units, to factors to SI.
_LENGTH = {
    "m": 1.0,
    "mm": 1e-3,
    "um": 1e-6,
    "cm": 1e-2,
    "in": 0.0254,
    "ft": 0.3048,
    "rad": 1.0,
    "deg": math.pi / 180.0,
}
_RESPONSE_UNITS: dict[str, dict[str, float]] = {
    "receptance": dict(_LENGTH),
    "mobility": {f"{u}/s": s for u, s in _LENGTH.items()},
    "accelerance": {
        **{f"{u}/{t}": s for u, s in _LENGTH.items() for t in ("s^2", "s2", "s/s")},
        "g": 9.80665,
    },
}
_FORCE_UNITS = {
    "n": 1.0,
    "kn": 1e3,
    "lbf": 4.4482216152605,
    "kgf": 9.80665,
    "n*m": 1.0,
    "n.m": 1.0,
    "n-m": 1.0,
    "n·m": 1.0,
    "nm": 1.0,  # in a force slot: newton metre (moment)
}
_FREQUENCY_UNITS = {"hz": 1.0, "khz": 1e3, "rad/s": 1.0 / (2.0 * math.pi)}

#: How a user says what an unlabelled FRF is (named in the error messages).
KIND_OPTION_HINT = (
    'set the study option [measurement.frf_options] kind = "accelerance" (or "mobility", '
    '"receptance"; a table by file name for some files only)'
)
_KNOWN = "m/N, (m/s)/N, (m/s^2)/N = (1/N)*(m/s^2) = m/s^2/N, g/N, mm, in/s, ..."

# Tolerance for require_uniform: ASCII UFF stores an uneven abscissa with 6 digits.
_UNIFORM_RTOL = 1e-5
_AXIS_RTOL = 1e-9


# ----------------------------------------------------------------------------- helpers


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
    if Path(path).is_dir():
        raise InputError("is a directory, not a universal file", source=src)
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


def _norm_units(label: object) -> str | None:
    """Normalise a units label; None for an empty / 'NONE' label.

    A superscript two is written ``^2``; so is U+FFFD, which is what pyuff's UTF-8 decoding
    makes of a Latin-1 ``²`` byte (a units label has no other non-ASCII character there).

    >>> _norm_units(" (m/s\N{SUPERSCRIPT TWO})/N"), _norm_units("m/s\ufffd"), _norm_units("NONE")
    ('(m/s^2)/n', 'm/s^2', None)
    """
    s = str(label or "").strip().lower()
    s = s.replace(" ", "").replace("²", "^2").replace("\ufffd", "^2").replace("**", "^")
    s = s.replace("µ", "u").replace("μ", "u")
    while len(s) >= 2 and s[0] + s[-1] in ("()", "[]") and _balanced(s[1:-1]):
        s = s[1:-1]
    return None if s in ("", "none") else s


def _balanced(s: str) -> bool:
    depth = 0
    for c in s:
        depth += {"(": 1, ")": -1}.get(c, 0)
        if depth < 0:
            return False
    return depth == 0


def _split_combined(label: str, kind: str) -> tuple[float, float, str] | None:
    """Split a numerator label such as 'g/n', '(m/s^2)/n' or '(1/n)*(m/s^2)' into response
    and force parts."""
    product = _split_product(label, kind)
    if product is not None:
        return product
    for i in range(len(label) - 1, 0, -1):
        if label[i] != "/":
            continue
        resp, force = _norm_units(label[:i]), _norm_units(label[i + 1 :])
        if resp in _RESPONSE_UNITS[kind] and force in _FORCE_UNITS:
            return _RESPONSE_UNITS[kind][resp], _FORCE_UNITS[force], force
    return None


def _split_product(label: str, kind: str) -> tuple[float, float, str] | None:
    """'(1/n)*(m/s^2)' or '(m/s^2)*(1/n)': one factor '1/force', the other a response."""
    depth, cuts = 0, []
    for i, c in enumerate(label):
        depth += {"(": 1, ")": -1}.get(c, 0)
        if c == "*" and depth == 0:
            cuts.append(i)
    if len(cuts) != 1:
        return None
    parts = [_norm_units(label[: cuts[0]]), _norm_units(label[cuts[0] + 1 :])]
    for inv, resp in (parts, parts[::-1]):
        if inv is None or resp is None or not inv.startswith("1/"):
            continue
        force = _norm_units(inv[2:])
        if force in _FORCE_UNITS and resp in _RESPONSE_UNITS[kind]:
            return _RESPONSE_UNITS[kind][resp], _FORCE_UNITS[force], force
    return None


def _response_scale(label: str | None, kind: str) -> tuple[float, float, str | None] | None:
    """(response factor, force factor, force label in numerator) or None if no match."""
    if label is None:
        return 1.0, 1.0, None
    if label in _RESPONSE_UNITS[kind]:
        return _RESPONSE_UNITS[kind][label], 1.0, None
    return _split_combined(label, kind)


# ----------------------------------------------------------------------------- FRF (58)


def read_frfs(
    path: PathLike,
    *,
    default_kind: str | None = None,
    require_uniform: bool = False,
) -> list[FRF]:
    """Read all FRF datasets (type 58 / 58b, function type 4) of a universal file.

    Each FRF is converted to receptance in m/N according to its ordinate numerator type
    (displacement, velocity or acceleration) and its units labels; see the module notes.
    Type-58 datasets of other function types (time responses, spectra, coherence, ...)
    and datasets of other types are skipped.

    Parameters
    ----------
    path : str or path-like
        Universal file (ASCII and binary 58b datasets may be mixed).
    default_kind : {"receptance", "mobility", "accelerance"}, optional
        Kind assumed for an FRF whose ordinate type is unknown/general (0 or 1) and whose
        units label does not tell.  By default such an FRF is rejected.
    require_uniform : bool
        Also reject an FRF whose frequency axis is not evenly spaced (to a relative
        tolerance of 1e-5 of the largest frequency, the resolution of an ASCII abscissa).

    Returns
    -------
    list of FRF
        In file order, each with ``source=str(path)``.  A mobility or accelerance value at
        0 Hz cannot be converted and is NaN; drop that line before further use.

    Raises
    ------
    InputError
        If the file cannot be read, is not a universal file, holds no FRF dataset
        (``"no FRF dataset (type 58) in file"``), is truncated, or an FRF dataset cannot
        be parsed or has real-only ordinates, an unsupported ordinate/abscissa type or
        units label, a wrong number of values, or a frequency axis that is negative,
        non-finite or not strictly increasing (or not uniform, see ``require_uniform``).
        The message names the file, the pyuff field and the dataset number.
    """
    src = str(path)
    if default_kind is not None and default_kind not in FRF_KINDS:
        raise ValueError(f"default_kind must be one of {FRF_KINDS}, got {default_kind!r}")
    uff, types = _open_uff(path)
    frfs: list[FRF] = []
    skipped: dict[int, int] = {}
    for index, set_type in enumerate(types):
        if set_type != 58:
            continue
        header = _read_set(uff, index, set_type, src, header_only=True)
        func_type = int(header.get("func_type", -1))
        if func_type != _FRF_FUNC:
            skipped[func_type] = skipped.get(func_type, 0) + 1
            continue
        dset = _read_set(uff, index, set_type, src)
        frfs.append(_frf_from_58(dset, index, src, default_kind, require_uniform))
    if not frfs:
        if skipped:
            found = ", ".join(
                f"{n} x {t} ({_FUNC_NAMES.get(t, 'other')})" for t, n in sorted(skipped.items())
            )
            raise InputError(
                f"no FRF dataset (type 58) in file: the type-58 datasets are not FRFs "
                f"(function type 4); found function types {found}",
                source=src,
                field="func_type",
            )
        found = (
            "found dataset types " + ", ".join(str(t) for t in sorted(set(types)))
            if types
            else "no universal-file datasets found (not a UFF file?)"
        )
        raise InputError(f"no FRF dataset (type 58) in file; {found}", source=src)
    return frfs


def _frf_from_58(
    dset: dict,
    index: int,
    src: str,
    default_kind: str | None,
    require_uniform: bool,
) -> FRF:
    try:
        response = (int(dset["rsp_node"]), int(dset["rsp_dir"]))
        reference = (int(dset["ref_node"]), int(dset["ref_dir"]))
    except (KeyError, TypeError, ValueError):
        raise InputError(
            f"dataset {index + 1}: missing response/reference DOF", source=src, field="rsp_node"
        ) from None
    where = f"dataset {index + 1} ({dof_label(response)}/{dof_label(reference)})"

    def fail(field: str, message: str) -> InputError:
        return InputError(f"{where}: {message}", source=src, field=field)

    # --- ordinate precision / complexity
    ord_type = int(dset.get("ord_data_type", -1))
    if ord_type not in (5, 6):
        kind_text = {2: "real single", 4: "real double"}.get(ord_type, "unknown")
        raise fail(
            "ord_data_type",
            f"ordinate data type {ord_type} ({kind_text} precision) is not supported; an FRF "
            "must be complex (5 = complex single, 6 = complex double)",
        )

    # --- abscissa type and units
    x_spec = int(dset.get("abscissa_spec_data_type", 0))
    if x_spec not in _FREQUENCY_SPECS:
        raise fail(
            "abscissa_spec_data_type",
            f"abscissa type {x_spec} ({_SPEC_NAMES.get(x_spec, 'other')}) is not frequency (18)",
        )
    x_label = _norm_units(dset.get("abscissa_axis_units_lab"))
    if x_label is not None and x_label not in _FREQUENCY_UNITS:
        raise fail(
            "abscissa_axis_units_lab",
            f"abscissa units {dset.get('abscissa_axis_units_lab')!r} not recognised "
            "(expected Hz, kHz or rad/s)",
        )
    x_scale = 1.0 if x_label is None else _FREQUENCY_UNITS[x_label]

    # --- numerator: response quantity and units
    y_spec = int(dset.get("ordinate_spec_data_type", 0))
    y_label = _norm_units(dset.get("ordinate_axis_units_lab"))
    y_label_raw = dset.get("ordinate_axis_units_lab")
    if y_spec in _SPEC_TO_KIND:
        kind = _SPEC_TO_KIND[y_spec]
    elif y_spec in _UNKNOWN_SPECS:
        matches = [k for k in FRF_KINDS if y_label is not None and _response_scale(y_label, k)]
        if len(matches) == 1:
            kind = matches[0]
        elif default_kind is not None:
            kind = default_kind
        else:
            raise fail(
                "ordinate_axis_units_lab" if y_label else "ordinate_spec_data_type",
                f"neither response type {y_spec} ({_SPEC_NAMES[y_spec]}) nor units label "
                f"{y_label_raw!r} says whether the FRF is a receptance, mobility or "
                f"accelerance; {KIND_OPTION_HINT}",
            )
    else:
        raise fail(
            "ordinate_spec_data_type",
            f"response type {y_spec} ({_SPEC_NAMES.get(y_spec, 'other')}) is not displacement "
            "(8), velocity (11) or acceleration (12)",
        )
    scales = _response_scale(y_label, kind)
    if scales is None:
        raise fail(
            "ordinate_axis_units_lab",
            f"units {y_label_raw!r} not recognised as {_KIND_TO_QUANTITY[kind]} units "
            f"(known labels: {_KNOWN})",
        )
    resp_scale, force_scale, force_in_num = scales

    # --- denominator: force
    d_spec = int(dset.get("orddenom_spec_data_type", 0))
    if d_spec not in _FORCE_SPECS:
        raise fail(
            "orddenom_spec_data_type",
            f"denominator type {d_spec} ({_SPEC_NAMES.get(d_spec, 'other')}) is not a force "
            "(13 excitation force, 9 reaction force, 0 unknown)",
        )
    d_label = _norm_units(dset.get("orddenom_axis_units_lab"))
    if d_label is not None:
        if d_label not in _FORCE_UNITS:
            raise fail(
                "orddenom_axis_units_lab",
                f"force units {dset.get('orddenom_axis_units_lab')!r} not recognised "
                "(expected N, kN, lbf, kgf or N*m)",
            )
        if force_in_num is None:
            force_scale = _FORCE_UNITS[d_label]
        elif _FORCE_UNITS[d_label] != force_scale:
            raise fail(
                "orddenom_axis_units_lab",
                f"force units {dset.get('orddenom_axis_units_lab')!r} contradict the ordinate "
                f"units {y_label_raw!r}",
            )

    # --- values
    data = np.asarray(dset.get("data"), dtype=np.complex128).ravel()
    x = np.asarray(dset.get("x"), dtype=np.float64).ravel()
    num_pts = int(dset.get("num_pts", -1))
    if data.size != num_pts or x.size != num_pts:
        raise fail(
            "num_pts",
            f"header announces {num_pts} values but {data.size} were read (truncated or "
            "malformed data block)",
        )
    if num_pts < 1:
        raise fail("num_pts", "dataset holds no values")
    if int(dset.get("abscissa_spacing", 0)) == 1 and num_pts > 1:
        inc = float(dset.get("abscissa_inc", 0.0))
        if not inc > 0:
            raise fail("abscissa_inc", f"abscissa increment {inc:g} must be > 0")
    freq = x * x_scale
    if not np.isfinite(freq).all():
        raise fail("abscissa", "non-finite abscissa value")
    if freq[0] < 0:
        raise fail("abscissa", f"negative frequency {freq[0]:g} Hz")
    steps = np.diff(freq)
    if (steps <= 0).any():
        k = int(np.flatnonzero(steps <= 0)[0]) + 1
        raise fail(
            "abscissa",
            f"frequencies not strictly increasing: {freq[k]:.6g} Hz at point {k + 1} follows "
            f"{freq[k - 1]:.6g} Hz",
        )
    if require_uniform and not is_uniform(freq, rtol=_UNIFORM_RTOL):
        raise fail(
            "abscissa_spacing",
            "frequency axis is not uniformly spaced "
            f"(steps {steps.min():.6g}..{steps.max():.6g} Hz)",
        )
    if not np.isfinite(data).all():
        k = int(np.flatnonzero(~np.isfinite(data))[0])
        raise fail("data", f"non-finite value at point {k + 1} ({freq[k]:.6g} Hz)")
    receptance = to_receptance(freq, data * (resp_scale / force_scale), kind)
    return FRF(freq, receptance, response, reference, source=src)


def _e13(value: float) -> float:
    """The value as pyuff writes an abscissa (``%13.5e``), read back."""
    return float(f"{value:13.5e}")


def _frf_to_58(frf: FRF, binary: bool, number: int, path: str) -> dict:
    f, h = frf.frequency_hz, frf.receptance
    n = f.size
    what = f"{path}: FRF {number} ({dof_label(frf.response)}/{dof_label(frf.reference)})"
    if not np.isfinite(h).all():
        k = int(np.flatnonzero(~np.isfinite(h))[0])
        raise ValueError(
            f"{what}: receptance is not finite at {f[k]:g} Hz (index {k}); pyuff would write "
            "it as 0 - drop that line first"
        )
    if n < 2:
        raise ValueError(f"{what}: pyuff cannot write a dataset 58 with fewer than 2 lines")
    fmax = float(f[-1])
    even = is_uniform(f)
    x = f
    if even:
        x_even = _e13(float(f[0])) + np.arange(n) * _e13(float((f[-1] - f[0]) / (n - 1)))
        exact = bool(np.all(np.abs(x_even - f) <= _AXIS_RTOL * fmax))
        if binary and not exact:
            even = False  # 58b stores an uneven abscissa as doubles: exact
        else:
            x = x_even
    if not even and not binary:
        stored = np.array([_e13(v) for v in f.tolist()])
        if (np.diff(stored) <= 0).any():
            raise ValueError(
                f"{what}: frequency lines are too close for the 6-digit abscissa of an ASCII "
                "dataset 58 with uneven spacing; write with binary=True"
            )
    rotational = abs(frf.response[1]) >= 4
    moment = abs(frf.reference[1]) >= 4
    dset = pyuff.prepare_58(
        binary=1 if binary else 0,
        id1="eigenupdate FRF",
        id2=f"receptance {dof_label(frf.response)}/{dof_label(frf.reference)}",
        id3="NONE",
        id4="NONE",
        id5="NONE",
        func_type=_FRF_FUNC,
        ver_num=0,
        load_case_id=0,
        rsp_ent_name="NONE",
        rsp_node=int(frf.response[0]),
        rsp_dir=int(frf.response[1]),
        ref_ent_name="NONE",
        ref_node=int(frf.reference[0]),
        ref_dir=int(frf.reference[1]),
        abscissa_spacing=1 if even else 0,
        abscissa_spec_data_type=18,
        abscissa_axis_units_lab="Hz",
        ordinate_spec_data_type=8,
        ordinate_axis_units_lab="rad" if rotational else "m",
        orddenom_spec_data_type=13,
        orddenom_axis_units_lab="N*m" if moment else "N",
        z_axis_spec_data_type=0,
        data=np.array(h, dtype=np.complex128),
        x=np.array(x, dtype=np.float64),
    )
    dset["abscissa_axis_lab"] = "Frequency"
    dset["ordinate_axis_lab"] = "Displacement"
    dset["orddenom_axis_lab"] = "Force"
    return dset


def write_frfs(path: PathLike, frfs: Sequence[FRF], binary: bool = False) -> None:
    """Write FRFs as receptance datasets 58 (ASCII) or 58b (binary) to a universal file.

    Each FRF becomes one dataset with function type 4, complex double-precision ordinate
    (``ord_data_type`` 6), displacement over excitation force (specific data types 8 and
    13, units ``m`` / ``N``; ``rad`` / ``N*m`` for rotational DOFs) and frequency abscissa
    in Hz.  A uniform axis is written with even spacing (``abscissa_min``/``abscissa_inc``,
    6 significant digits); a non-uniform axis, or in 58b a uniform one that 6-digit min/inc
    would not reproduce to 1e-9, is written with uneven spacing.  ASCII ordinates carry 12
    significant digits; 58b values are exact doubles.  The file is replaced atomically.

    Parameters
    ----------
    path : str or path-like
        Destination universal file (overwritten).
    frfs : sequence of FRF
        FRFs to write; each needs at least 2 frequency lines and finite receptance.
    binary : bool
        Write binary 58b datasets instead of ASCII 58.

    Raises
    ------
    ValueError
        If ``frfs`` is empty, an FRF has NaN values (e.g. the unconverted 0 Hz line) or
        fewer than 2 lines, or (ASCII only) its lines are too close for 6 digits.
    OSError
        If the file cannot be written; the destination is then left unchanged.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> f = np.arange(1, 5) * 0.5
    >>> frf = FRF(f, 1.0 / (1e4 - (2 * np.pi * f) ** 2 + 50j), (3, 3), (1, 3))
    >>> with tempfile.TemporaryDirectory() as d:
    ...     write_frfs(pathlib.Path(d) / "a.uff", [frf], binary=True)
    ...     back = read_frfs(pathlib.Path(d) / "a.uff")[0]
    >>> bool(np.array_equal(back.receptance, frf.receptance)), back.response
    (True, (3, 3))
    """
    if len(frfs) == 0:
        raise ValueError(f"{path}: no FRFs to write")
    dsets = [_frf_to_58(frf, binary, k, str(path)) for k, frf in enumerate(frfs, start=1)]

    def _write(tmp: str) -> None:
        with _quiet():
            pyuff.UFF(tmp).write_sets(dsets, mode="add", force_double=True)

    atomic_write(path, _write)


# ----------------------------------------------------------------------------- modes (55)


@dataclass(frozen=True, eq=False, repr=False)
class Mode:
    """A real normal mode as stored in dataset 55 (analysis type 2, normal mode).

    Parameters
    ----------
    frequency_hz : float
        Natural frequency in Hz (``freq``, record 8 field 1), finite and ``>= 0``.
    loss_factor : float
        Hysteretic (structural) damping loss factor eta, written to ``modal_damp_his``
        ("modal hysteretic damping ratio", record 8 field 4).
    damping_ratio : float
        Viscous damping ratio zeta (``modal_damp_vis``, record 8 field 3); 0 if unused.
        For light damping eta ~ 2 zeta; the two are stored independently.
    modal_mass : float
        Modal mass (``modal_m``, record 8 field 2); 0 means unknown / not mass-normalised.
    node_nums : array_like of int, shape (m,)
        Node numbers of the shape (record 9).
    shape : array_like of float, shape (m, 3) or (m, 6), optional
        Shape values per node: translations X, Y, Z (``r1``-``r3``) and optionally
        rotations (``r4``-``r6``).  Default: zeros with 3 columns.
    mode_number : int
        Mode number (``mode_n``, record 7 field 4); 0 means "use the position in the list"
        when writing.
    source : str
        File the mode came from, used in error messages.
    label : str
        Free text kept in the dataset's third ID line, e.g. the test configuration.

    Notes
    -----
    Dataset 55 stores every number with 6 significant digits (``%13.5e``).

    Examples
    --------
    >>> m = Mode.point(12.5, 0.8, (7, -3), loss_factor=0.02)
    >>> m
    Mode(12.5 Hz, loss_factor=0.02, 1 node(s))
    >>> m.shape.tolist()
    [[0.0, 0.0, -0.8]]
    """

    frequency_hz: float
    loss_factor: float = 0.0
    damping_ratio: float = 0.0
    modal_mass: float = 0.0
    node_nums: ArrayLike = (1,)
    shape: ArrayLike | None = None
    mode_number: int = 0
    source: str = ""
    label: str = ""

    def __post_init__(self) -> None:
        src = self.source or None
        for name in ("frequency_hz", "loss_factor", "damping_ratio", "modal_mass"):
            try:
                value = float(getattr(self, name))
            except (TypeError, ValueError):
                raise InputError(
                    f"not a number: {getattr(self, name)!r}", source=src, field=name
                ) from None
            if not math.isfinite(value):
                raise InputError(f"non-finite value {value!r}", source=src, field=name)
            object.__setattr__(self, name, value)
        if self.frequency_hz < 0:
            raise InputError(
                f"negative frequency {self.frequency_hz:g} Hz", source=src, field="frequency_hz"
            )
        nodes = np.array(self.node_nums).ravel()
        if nodes.size == 0 or not np.issubdtype(nodes.dtype, np.integer):
            raise InputError(
                f"must be a non-empty sequence of integers, got {self.node_nums!r}",
                source=src,
                field="node_nums",
            )
        nodes = nodes.astype(np.int64)
        if self.shape is None:
            shape = np.zeros((nodes.size, 3))
        else:
            try:
                shape = np.array(self.shape, dtype=np.float64)
            except (TypeError, ValueError):
                raise InputError(
                    "must be real numbers (complex shapes are not supported)",
                    source=src,
                    field="shape",
                ) from None
            if shape.ndim == 1:
                shape = shape.reshape(1, -1)
        if shape.ndim != 2 or shape.shape[0] != nodes.size or shape.shape[1] not in (3, 6):
            raise InputError(
                f"must have shape ({nodes.size}, 3) or ({nodes.size}, 6), got {shape.shape}",
                source=src,
                field="shape",
            )
        if not np.isfinite(shape).all():
            raise InputError("non-finite value", source=src, field="shape")
        try:
            number = operator.index(self.mode_number)
        except TypeError:
            raise InputError(
                f"must be an integer, got {self.mode_number!r}", source=src, field="mode_number"
            ) from None
        nodes.flags.writeable = False
        shape.flags.writeable = False
        object.__setattr__(self, "node_nums", nodes)
        object.__setattr__(self, "shape", shape)
        object.__setattr__(self, "mode_number", int(number))
        object.__setattr__(self, "source", str(self.source))

    @classmethod
    def point(
        cls,
        frequency_hz: float,
        value: float,
        dof: tuple[int, int],
        *,
        loss_factor: float = 0.0,
        damping_ratio: float = 0.0,
        modal_mass: float = 0.0,
        mode_number: int = 0,
    ) -> Mode:
        """A mode known at one DOF only, e.g. a (real) modal constant from a point FRF.

        ``value`` is placed in the column of ``dof``'s direction (``r1``..``r6``) of a
        one-node shape, negated for a negative direction code.
        """
        node, direction = int(dof[0]), int(dof[1])
        if not 1 <= abs(direction) <= 6:
            raise ValueError(f"dof direction must be +-1..6, got {direction}")
        shape = np.zeros((1, 6 if abs(direction) > 3 else 3))
        shape[0, abs(direction) - 1] = value if direction > 0 else -value
        return cls(
            frequency_hz,
            loss_factor=loss_factor,
            damping_ratio=damping_ratio,
            modal_mass=modal_mass,
            node_nums=(node,),
            shape=shape,
            mode_number=mode_number,
        )

    def __repr__(self) -> str:
        return (
            f"Mode({self.frequency_hz:g} Hz, loss_factor={self.loss_factor:g}, "
            f"{np.asarray(self.node_nums).size} node(s))"
        )


def write_modes(path: PathLike, modes: Sequence[Mode]) -> None:
    """Write normal modes as datasets 55 (analysis type 2) to a universal file.

    Fields written per mode: ``freq`` = frequency_hz, ``modal_m`` = modal_mass,
    ``modal_damp_vis`` = damping_ratio, ``modal_damp_his`` = loss_factor, ``mode_n`` =
    mode_number (or the 1-based position when 0), ``load_case`` = 1, ``node_nums`` and
    ``r1``..``r3`` (``r1``..``r6`` with data characteristic 3 for 6-column shapes),
    specific data type 8 (displacement).  Values get 6 significant digits.  The file is
    replaced atomically.

    Raises
    ------
    ValueError
        If ``modes`` is empty.
    """
    if len(modes) == 0:
        raise ValueError(f"{path}: no modes to write")
    dsets = []
    for k, mode in enumerate(modes, start=1):
        shape = np.asarray(mode.shape)
        six = shape.shape[1] == 6
        cols = {f"r{j + 1}": shape[:, j].copy() for j in range(shape.shape[1])}
        dsets.append(
            pyuff.prepare_55(
                id1="eigenupdate normal mode",
                id2=f"mode {mode.mode_number or k}",
                id3=mode.label[:80] or "NONE",
                id4="NONE",
                id5="NONE",
                model_type=1,
                analysis_type=2,
                data_ch=3 if six else 2,
                spec_data_type=8,
                data_type=2,
                n_data_per_node=6 if six else 3,
                load_case=1,
                mode_n=int(mode.mode_number or k),
                freq=float(mode.frequency_hz),
                modal_m=float(mode.modal_mass),
                modal_damp_vis=float(mode.damping_ratio),
                modal_damp_his=float(mode.loss_factor),
                node_nums=np.asarray(mode.node_nums, dtype=np.int64),
                **cols,
            )
        )

    def _write(tmp: str) -> None:
        with _quiet():
            pyuff.UFF(tmp).write_sets(dsets, mode="add")

    atomic_write(path, _write)


def read_modes(path: PathLike) -> list[Mode]:
    """Read all normal-mode datasets (type 55, analysis type 2) of a universal file.

    The inverse of :func:`write_modes`; other datasets are skipped.

    Returns
    -------
    list of Mode
        In file order, with ``source=str(path)``.

    Raises
    ------
    InputError
        If the file cannot be read, holds no normal-mode dataset, or a dataset cannot be
        parsed or has complex or non-finite values.
    """
    src = str(path)
    uff, types = _open_uff(path)
    modes: list[Mode] = []
    other: set[int] = set()
    for index, set_type in enumerate(types):
        if set_type != 55:
            continue
        dset = _read_set(uff, index, set_type, src)
        analysis = int(dset.get("analysis_type", -1))
        if analysis != 2:
            other.add(analysis)
            continue
        where = f"dataset {index + 1}"
        if int(dset.get("data_type", 2)) != 2:
            raise InputError(
                f"{where}: complex mode shape data (data type {dset.get('data_type')}) in a "
                "normal-mode dataset is not supported",
                source=src,
                field="data_type",
            )
        ncol = 6 if "r4" in dset else 3
        try:
            shape = np.column_stack(
                [np.asarray(dset[f"r{j + 1}"], dtype=np.float64) for j in range(ncol)]
            )
            mode = Mode(
                frequency_hz=dset["freq"],
                loss_factor=dset.get("modal_damp_his", 0.0),
                damping_ratio=dset.get("modal_damp_vis", 0.0),
                modal_mass=dset.get("modal_m", 0.0),
                node_nums=np.asarray(dset["node_nums"], dtype=np.int64),
                shape=shape,
                mode_number=int(dset.get("mode_n", 0)),
                label="" if str(dset.get("id3", "NONE")).strip() == "NONE"
                else str(dset.get("id3", "")).strip(),
            )
        except (KeyError, TypeError, ValueError) as exc:  # InputError is a ValueError
            err = InputError(f"{where}: {exc}", source=src)
            err.field = getattr(exc, "field", None)
            raise err from None
        modes.append(replace(mode, source=src))
    if not modes:
        extra = (
            f"; the type-55 datasets have analysis types {sorted(other)}"
            if other
            else f"; found dataset types {sorted(set(types))}"
            if types
            else "; no universal-file datasets found"
        )
        raise InputError(
            f"no normal-mode dataset (type 55, analysis type 2) in file{extra}", source=src
        )
    return modes


def read_frf_files(
    paths: Sequence[PathLike], kinds: Sequence[str | None] | None = None
) -> list[FRF]:
    """FRFs of several files: ``.csv`` files by :func:`eigenupdate.io.frf_csv.read_frf_csv`
    (one receptance each), anything else as a universal file (:func:`read_frfs`, with
    ``kinds[i]`` as the ``default_kind`` of file ``i``)."""
    from eigenupdate.io.frf_csv import read_frf_csv

    out: list[FRF] = []
    for i, p in enumerate(paths):
        kind = None if kinds is None else kinds[i]
        if str(p).lower().endswith(".csv"):
            if kind not in (None, "receptance"):  # the CSV format holds receptance only
                raise InputError(f"an FRF CSV holds receptance (m/N); kind {kind!r} applies "
                                 f"to universal files", source=str(p), field="kind")
            out.append(read_frf_csv(p))
        else:
            out += read_frfs(p, default_kind=kind)
    return out
