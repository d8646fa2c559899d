"""Universal file dataset 58 / 58b: frequency response functions.

Parsing and formatting are done by `pyuff <https://github.com/ladisk/pyuff>`_ (see
:mod:`eigenupdate.io.uff._pyuff` for its quirks handled here); this module maps its dataset
dictionaries to :class:`~eigenupdate.measure.frf.FRF` and validates them.

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

pyuff quirks handled here (pyuff 2.5.8)
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import pyuff

from eigenupdate.errors import InputError
from eigenupdate.io.atomic import atomic_write
from eigenupdate.io.uff._pyuff import PathLike, _open_uff, _quiet, _read_set
from eigenupdate.measure.frf import (
    FRF,
    FRF_KINDS,
    dof_label,
    is_uniform,
    to_receptance,
)

__all__ = ["read_frfs", "write_frfs"]

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


