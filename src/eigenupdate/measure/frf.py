"""Frequency response functions (FRFs): the in-memory type and unit conversion.

An :class:`FRF` always holds *receptance* (displacement over force, m/N in SI) on a
strictly increasing frequency axis in Hz.  Measured mobility (velocity/force) or
accelerance (acceleration/force) is converted on input with :func:`to_receptance`.

Conventions
-----------
* Harmonic time dependence ``exp(+i w t)``, so velocity = ``i w`` x displacement and
  acceleration = ``-w**2`` x displacement, with ``w = 2 pi f``.
* Units are SI: Hz, m/N.  For rotational degrees of freedom the SI analogues apply
  (rad/N, m/(N m), rad/(N m)).
* Degrees of freedom are ``(node, direction)`` pairs with the direction codes of
  universal file dataset 58: 0 scalar, 1/2/3 = +X/+Y/+Z translation, 4/5/6 = +X/+Y/+Z
  rotation, negative codes for the negative directions.  No sign flip is applied
  for negative directions; the code is kept as read.

Files: :mod:`eigenupdate.io.frf_csv` (CSV) and :mod:`eigenupdate.io.uff` (universal files).
"""

from __future__ import annotations

import hashlib
import operator
import os
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from eigenupdate.choices import FRF_KINDS
from eigenupdate.errors import InputError

__all__ = [
    "FRF",
    "FRF_KINDS",
    "check_same_axis",
    "dof_label",
    "is_uniform",
    "to_receptance",
]

PathLike = str | os.PathLike[str]


_AXIS_RTOL = 1e-9
_DIRECTION_NAMES = {0: "S", 1: "X", 2: "Y", 3: "Z", 4: "RX", 5: "RY", 6: "RZ"}


def dof_label(dof: tuple[int, int]) -> str:
    """Return a short label such as ``'12+Z'`` or ``'3-RX'`` for a ``(node, direction)`` pair.

    Examples
    --------
    >>> dof_label((12, 3)), dof_label((3, -4)), dof_label((0, 0))
    ('12+Z', '3-RX', '0S')
    """
    node, direction = dof
    if direction == 0:
        return f"{node}S"
    sign = "+" if direction > 0 else "-"
    return f"{node}{sign}{_DIRECTION_NAMES.get(abs(direction), str(abs(direction)))}"


def _as_dof(value: object, name: str, source: str | None) -> tuple[int, int]:
    try:
        node, direction = (operator.index(v) for v in value)  # type: ignore[attr-defined]
    except (TypeError, ValueError):
        raise InputError(
            f"must be a (node, direction) pair of integers, got {value!r}",
            source=source,
            field=name,
        ) from None
    if not -6 <= direction <= 6:
        raise InputError(f"direction code {direction} is not in -6..6", source=source, field=name)
    return int(node), int(direction)


@dataclass(frozen=True, eq=False, repr=False)
class FRF:
    """One measured or computed frequency response function, as receptance.

    Parameters
    ----------
    frequency_hz : ndarray, shape (n,)
        Frequency axis in Hz: finite, ``>= 0`` and strictly increasing.  It need not be
        uniformly spaced.
    receptance : ndarray, shape (n,), complex
        Displacement over force in m/N.  NaN is allowed (e.g. the undefined 0 Hz value
        produced by :func:`to_receptance`); infinities are not.
    response, reference : tuple of int
        ``(node, direction)`` with universal-file direction codes (see the module notes).
    source : str
        File the FRF came from, used in error messages; empty if none.

    Raises
    ------
    InputError
        If the arrays have the wrong shape or the frequency axis is not valid.  The
        message names ``source`` when it is set.

    Notes
    -----
    Both arrays are copied and made read-only.  Instances compare by identity (``eq`` is
    not generated because the fields are arrays).

    Examples
    --------
    >>> frf = FRF(np.array([1.0, 2.0]), np.array([1e-6 - 1e-7j, 2e-6 - 3e-7j]), (5, 3), (1, 3))
    >>> frf
    FRF(n=2, 1..2 Hz, response=5+Z, reference=1+Z)
    >>> float(frf.receptance[1].real)
    2e-06
    """

    frequency_hz: np.ndarray
    receptance: np.ndarray
    response: tuple[int, int] = (0, 0)
    reference: tuple[int, int] = (0, 0)
    source: str = ""

    def __post_init__(self) -> None:
        src = self.source or None
        try:
            freq = np.array(self.frequency_hz, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise InputError(f"not numeric: {exc}", source=src, field="frequency_hz") from None
        try:
            rec = np.array(self.receptance, dtype=np.complex128)
        except (TypeError, ValueError) as exc:
            raise InputError(f"not numeric: {exc}", source=src, field="receptance") from None
        if freq.ndim != 1 or freq.size == 0:
            raise InputError(
                f"must be a non-empty 1-D array, got shape {freq.shape}",
                source=src,
                field="frequency_hz",
            )
        if rec.shape != freq.shape:
            raise InputError(
                f"shape {rec.shape} does not match frequency_hz shape {freq.shape}",
                source=src,
                field="receptance",
            )
        _check_axis(freq, src)
        if np.isinf(rec).any():
            bad = int(np.flatnonzero(np.isinf(rec))[0])
            raise InputError(
                f"infinite value at index {bad} ({freq[bad]:g} Hz)", source=src, field="receptance"
            )
        freq.flags.writeable = False
        rec.flags.writeable = False
        object.__setattr__(self, "frequency_hz", freq)
        object.__setattr__(self, "receptance", rec)
        object.__setattr__(self, "response", _as_dof(self.response, "response", src))
        object.__setattr__(self, "reference", _as_dof(self.reference, "reference", src))
        object.__setattr__(self, "source", str(self.source))

    def fingerprint(self) -> str:
        """SHA-256 of the points and values: what a saved extraction's fits were fitted
        to (a file's name and size survive two files swapped; its values do not)."""
        h = hashlib.sha256(f"{self.response}{self.reference}".encode())
        h.update(self.frequency_hz.tobytes())
        h.update(self.receptance.tobytes())
        return h.hexdigest()

    def __repr__(self) -> str:
        f = self.frequency_hz
        src = f", source={self.source!r}" if self.source else ""
        return (
            f"FRF(n={f.size}, {f[0]:g}..{f[-1]:g} Hz, response={dof_label(self.response)}, "
            f"reference={dof_label(self.reference)}{src})"
        )


def _check_axis(freq: np.ndarray, source: str | None, field: str = "frequency_hz") -> None:
    """Raise InputError unless ``freq`` is finite, >= 0 and strictly increasing."""
    if not np.isfinite(freq).all():
        bad = int(np.flatnonzero(~np.isfinite(freq))[0])
        raise InputError(f"non-finite value at index {bad}", source=source, field=field)
    if freq[0] < 0:
        raise InputError(f"negative frequency {freq[0]:g} Hz", source=source, field=field)
    steps = np.diff(freq)
    if (steps <= 0).any():
        bad = int(np.flatnonzero(steps <= 0)[0])
        raise InputError(
            f"not strictly increasing: {float(freq[bad + 1])!r} Hz at index {bad + 1} follows "
            f"{float(freq[bad])!r} Hz",
            source=source,
            field=field,
        )


def is_uniform(frequency_hz: np.ndarray, rtol: float = _AXIS_RTOL) -> bool:
    """Return True if the axis is evenly spaced to within ``rtol`` times its largest value.

    Examples
    --------
    >>> is_uniform(np.linspace(0.0, 10.0, 11)), is_uniform(np.array([0.0, 1.0, 3.0]))
    (True, False)
    """
    f = np.asarray(frequency_hz, dtype=np.float64)
    if f.size < 3:
        return True
    ideal = np.linspace(f[0], f[-1], f.size)
    return bool(np.max(np.abs(f - ideal)) <= rtol * np.max(np.abs(f)))


def to_receptance(frequency_hz: ArrayLike, values: ArrayLike, kind: str) -> np.ndarray:
    """Convert mobility or accelerance to receptance (displacement/force).

    With ``w = 2 pi f`` and time dependence ``exp(i w t)``::

        H_disp = H_vel / (i w) = -H_acc / w**2

    Parameters
    ----------
    frequency_hz : array_like, shape (n,)
        Frequencies in Hz.
    values : array_like, shape (n,)
        FRF values in SI units (m/s/N for mobility, m/s**2/N for accelerance).
    kind : {"receptance", "mobility", "accelerance"}
        What ``values`` are (case-insensitive).

    Returns
    -------
    ndarray, complex, shape (n,)
        Receptance in m/N (a new array).  At 0 Hz the conversion from mobility or
        accelerance is undefined and the result is NaN there; callers should drop the
        0 Hz line.

    Raises
    ------
    ValueError
        If ``kind`` is unknown or the shapes differ.

    Examples
    --------
    Accelerance of an undamped SDOF (m = 1 kg, k = 100 N/m, so w_n = 10 rad/s) at
    w = 0 and 5 rad/s, converted back to receptance ``1 / (k - m w**2)``:

    >>> w = np.array([0.0, 5.0])
    >>> acc = -w**2 / (100.0 - w**2)
    >>> to_receptance(w / (2 * np.pi), acc, "accelerance").real
    array([       nan, 0.01333333])
    >>> 1 / (100.0 - 25.0)
    0.013333333333333334
    """
    key = kind.strip().lower()
    if key not in FRF_KINDS:
        raise ValueError(f"unknown FRF kind {kind!r}; expected one of {', '.join(FRF_KINDS)}")
    f = np.asarray(frequency_hz, dtype=np.float64)
    h = np.array(values, dtype=np.complex128)
    if f.shape != h.shape:
        raise ValueError(f"frequency shape {f.shape} does not match values shape {h.shape}")
    if key == "receptance":
        return h
    w = 2.0 * np.pi * f
    with np.errstate(divide="ignore", invalid="ignore"):
        out = h / (1j * w) if key == "mobility" else -h / (w * w)
    out[w == 0] = complex(np.nan, np.nan)
    return out


def check_same_axis(frfs: Sequence[FRF], source: PathLike = "") -> np.ndarray:
    """Check that all FRFs share one frequency axis and return it.

    Two axes are the same when they have the same length and every pair of values differs
    by at most ``1e-9`` times the largest frequency.  Note that ASCII universal files store
    the abscissa with 6 significant digits, so an axis read from such a file may not match
    the same axis read from CSV or binary UFF.

    Parameters
    ----------
    frfs : sequence of FRF
        FRFs to combine, e.g. the FRFs of one measurement set.
    source : str or path-like
        Name used in the error message (e.g. the set or file name).

    Returns
    -------
    ndarray
        The frequency axis of the first FRF (read-only).

    Raises
    ------
    InputError
        If ``frfs`` is empty or an axis differs; the message names both FRFs.

    Examples
    --------
    >>> a = FRF(np.array([1.0, 2.0]), np.ones(2), (1, 3), (1, 3))
    >>> b = FRF(np.array([1.0, 2.0]), np.ones(2), (2, 3), (1, 3))
    >>> check_same_axis([a, b], "set A")
    array([1., 2.])
    """
    src = str(source) or None
    if len(frfs) == 0:
        raise InputError("no FRFs to combine", source=src, field="frequency_hz")
    first = frfs[0]
    ref = first.frequency_hz
    scale = float(np.max(np.abs(ref)))
    for i, frf in enumerate(frfs[1:], start=2):
        f = frf.frequency_hz
        same = f.shape == ref.shape and bool(
            np.all(np.abs(f - ref) <= _AXIS_RTOL * max(scale, float(np.max(np.abs(f)))))
        )
        if not same:
            raise InputError(
                f"frequency axis of FRF {i} ({_describe(frf)}: {_axis_summary(f)}) differs "
                f"from FRF 1 ({_describe(first)}: {_axis_summary(ref)})",
                source=src,
                field="frequency_hz",
            )
    return ref


def _describe(frf: FRF) -> str:
    text = f"{dof_label(frf.response)}/{dof_label(frf.reference)}"
    return f"{text} from {frf.source}" if frf.source else text


def _axis_summary(f: np.ndarray) -> str:
    return f"{f.size} lines {f[0]:.9g}..{f[-1]:.9g} Hz"
