"""The result type shared by the modal-extraction methods, and their input checks.

Both :mod:`eigenupdate.measure.dobson` and :mod:`eigenupdate.measure.rational_fraction` return
:class:`ModalFit` objects, so their results can be compared one to one.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from eigenupdate.errors import InputError

#: Fewest frequency points a band may hold for any of the fits.
MIN_BAND_POINTS = 7


@dataclass(frozen=True)
class ModalFit:
    """Modal properties of one mode of a receptance FRF.

    Receptance model near the mode (hysteretic damping)::

        alpha(w) = A_r / (w_r**2 - w**2 + 1j * eta_r * w_r**2) + residual terms

    Attributes
    ----------
    frequency_hz : float
        Natural frequency ``f_r = w_r / (2 pi)`` in Hz.
    loss_factor : float
        Hysteretic loss factor ``eta_r``.
    modal_constant : complex
        Modal constant ``A_r`` in m/N * (rad/s)**2.
    frequency_std_hz : float
        Standard deviation of ``frequency_hz`` estimated from the fit residuals.
    loss_factor_std : float
        Standard deviation of ``loss_factor`` estimated from the fit residuals.
    band_hz : tuple of float
        Frequency band (Hz) the mode was fitted in.
    method : str
        ``"dobson"`` or ``"rfp"``.
    """

    frequency_hz: float
    loss_factor: float
    modal_constant: complex
    frequency_std_hz: float
    loss_factor_std: float
    band_hz: tuple[float, float]
    method: str


@dataclass(frozen=True)
class NoResonance:
    """Status of a fit that found no usable resonance in a band (not an error: an FRF
    whose response point is near a node of the mode shows none). ``message`` says why.

    >>> NoResonance((90.0, 110.0), "band (90, 110) Hz has no resonance peak").band_hz
    (90.0, 110.0)
    """

    band_hz: tuple[float, float]
    message: str


def mode_receptance(fit, x: np.ndarray | float) -> np.ndarray | complex:
    """Receptance of one fitted mode alone at ``x = w**2`` (rad/s)**2.

    ``fit`` is a :class:`ModalFit` or any object with ``frequency_hz``, ``loss_factor``
    and ``modal_constant``. At resonance its magnitude is the peak height
    ``|A_r| / (eta_r w_r**2)``:

    >>> fit = ModalFit(100.0, 0.02, 2.0 + 0j, 0.0, 0.0, (90.0, 110.0), "dobson")
    >>> wr2 = (2 * np.pi * 100.0) ** 2
    >>> print(f"{abs(mode_receptance(fit, wr2)):.4e} = {2.0 / (0.02 * wr2):.4e}")
    2.5330e-04 = 2.5330e-04
    """
    wr2 = (2.0 * np.pi * fit.frequency_hz) ** 2
    return fit.modal_constant / (wr2 * (1.0 + 1j * fit.loss_factor) - x)


def validate_frf(
    frequency_hz: np.ndarray, receptance: np.ndarray, source: str | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Return ``frequency_hz`` as float and ``receptance`` as complex 1-D arrays, or raise.

    Raises :class:`~eigenupdate.errors.InputError` if the arrays are not 1-D, differ
    in length, or the frequency axis is not finite and strictly increasing.
    """
    freq = np.asarray(frequency_hz, dtype=float)
    rec = np.asarray(receptance, dtype=complex)
    if freq.ndim != 1 or rec.ndim != 1:
        raise InputError("frequency axis and receptance must be 1-D arrays", source=source,
                         field="frequency_hz")
    if freq.size != rec.size:
        raise InputError(
            f"frequency axis has {freq.size} points but receptance has {rec.size}",
            source=source, field="receptance",
        )
    if freq.size < 2 or not np.all(np.isfinite(freq)):
        raise InputError("frequency axis needs at least 2 finite values", source=source,
                         field="frequency_hz")
    if not np.all(np.diff(freq) > 0):
        raise InputError("frequency axis is not strictly increasing", source=source,
                         field="frequency_hz")
    return freq, rec


def select_band(
    frequency_hz: np.ndarray,
    receptance: np.ndarray,
    band_hz: tuple[float, float],
    source: str | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Validate the FRF and return the points with ``band_hz[0] <= f <= band_hz[1]``.

    Raises :class:`~eigenupdate.errors.InputError` for a malformed band, a band with
    fewer than :data:`MIN_BAND_POINTS` points, a band reaching 0 Hz or below, or
    non-finite receptance values inside the band.
    """
    freq, rec = validate_frf(frequency_hz, receptance, source)
    try:
        lo, hi = (float(v) for v in band_hz)
    except (TypeError, ValueError) as exc:
        raise InputError(f"band must be a pair of numbers, got {band_hz!r}", source=source,
                         field="band_hz") from exc
    if not (np.isfinite(lo) and np.isfinite(hi) and lo < hi):
        raise InputError(f"band ({lo:g}, {hi:g}) Hz must have finite edges with low < high",
                         source=source, field="band_hz")
    inside = (freq >= lo) & (freq <= hi)
    n_in = int(np.count_nonzero(inside))
    if n_in < MIN_BAND_POINTS:
        raise InputError(
            f"band ({lo:g}, {hi:g}) Hz is too narrow: {n_in} frequency points, "
            f"need at least {MIN_BAND_POINTS}",
            source=source, field="band_hz",
        )
    f_band, a_band = freq[inside], rec[inside]
    if f_band[0] <= 0.0:
        raise InputError(f"band ({lo:g}, {hi:g}) Hz must lie above 0 Hz", source=source,
                         field="band_hz")
    if not np.all(np.isfinite(a_band)):
        raise InputError(f"receptance has non-finite values in band ({lo:g}, {hi:g}) Hz",
                         source=source, field="receptance")
    return f_band, a_band
