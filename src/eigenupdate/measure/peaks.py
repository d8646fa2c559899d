"""Automatic peak picking: propose one fitting band per resonance of a receptance FRF.

Peaks are found with :func:`scipy.signal.find_peaks` on ``|alpha|`` in dB.  Two things
keep false peaks out:

* a noise floor, estimated from the second differences of the complex FRF, is added
  in power before taking the logarithm, so random wiggles in anti-resonance troughs
  (deep in dB, but at noise level) have little prominence, and a peak must also rise
  six noise standard deviations above its surroundings in linear ``|alpha|``;
* the lowest bins are ignored, and a peak needs a real local maximum with prominence.
  The ``1/w**2`` rise of a free-free structure's rigid-body modes towards 0 Hz is
  monotonic and therefore never proposed.
"""

from __future__ import annotations

import numpy as np
from scipy.signal import find_peaks, peak_prominences

from eigenupdate.errors import InputError
from eigenupdate.measure.modal_fit import validate_frf

__all__ = ["propose_bands", "estimate_noise_std"]

#: Bins at the low end that are always ignored (DC bin, window leakage, 1/w**2 rise).
_SKIP_LOW_BINS = 3
#: The noise floor added to |alpha| before taking dB, in noise standard deviations.
_FLOOR_IN_STD = 3.0
#: Least prominence of a peak in linear |alpha|, in noise standard deviations.  Noise
#: alone swings |alpha| this far with a probability of about 1e-8 per pair of bins.
_MIN_PROMINENCE_IN_STD = 6.0


def propose_bands(
    frequency_hz: np.ndarray,
    receptance: np.ndarray,
    n_modes: int | None = None,
    min_prominence: float = 6.0,
    exclude_below_hz: float | None = None,
    *,
    bandwidth_multiple: float = 3.0,
    min_side_points: int = 5,
    source: str | None = None,
) -> list[tuple[float, float]]:
    """Propose one band per resonance peak, in increasing frequency.

    Each band reaches ``bandwidth_multiple`` half-power bandwidths to each side of the
    peak, but not past half-way to a neighbouring peak, and holds at least
    ``min_side_points`` points on each side of the peak.

    Parameters
    ----------
    frequency_hz : ndarray
        Frequency axis in Hz, strictly increasing.
    receptance : ndarray
        Complex receptance in m/N.
    n_modes : int, optional
        Keep only the ``n_modes`` lowest peaks; an error if fewer are found.
    min_prominence : float, optional
        Least prominence of a peak in dB, above the noise floor.
    exclude_below_hz : float, optional
        Ignore frequencies below this (the lowest 3 bins are always ignored).
    bandwidth_multiple : float, optional
        Half-width of a band in half-power bandwidths.
    min_side_points : int, optional
        Fewest frequency points on each side of a peak.
    source : str, optional
        Name of the data source, used in error messages.

    Returns
    -------
    list of (float, float)
        ``(low_hz, high_hz)`` band edges, at frequency points of ``frequency_hz``.

    Raises
    ------
    InputError
        If the arrays are malformed, or fewer than ``n_modes`` peaks are found.

    Examples
    --------
    >>> import numpy as np
    >>> f = np.arange(0.0, 400.0, 0.5)
    >>> x = (2 * np.pi * f) ** 2
    >>> alpha = sum(1.0 / ((2 * np.pi * fr) ** 2 * (1 + 0.01j) - x) for fr in (100.0, 250.0))
    >>> alpha[1:] -= 1.0 / x[1:]                       # rigid-body mode: not a peak
    >>> print(propose_bands(f, alpha))
    [(97.0, 103.0), (242.5, 257.5)]
    """
    freq, rec = validate_frf(frequency_hz, receptance, source)
    if n_modes is not None and n_modes < 1:
        raise InputError(f"n_modes must be >= 1, got {n_modes}", source=source,
                         field="n_modes")
    start = _first_used_bin(freq, exclude_below_hz)
    f, a = freq[start:], rec[start:]
    if f.size < 3:
        return _enough(n_modes, [], source)
    if not np.all(np.isfinite(a)):
        raise InputError("receptance has non-finite values above the excluded low bins",
                         source=source, field="receptance")

    noise = estimate_noise_std(a)
    mag = np.abs(a)
    level_db = 10.0 * np.log10(mag**2 + (_FLOOR_IN_STD * noise) ** 2 + np.finfo(float).tiny)
    peaks, _ = find_peaks(level_db, prominence=min_prominence)
    if peaks.size:
        # Deep troughs make dB prominence noisy; demand a clear rise above noise too.
        peaks = peaks[peak_prominences(mag, peaks)[0] >= _MIN_PROMINENCE_IN_STD * noise]
    # Bands of all peaks first: a neighbour above the n_modes-th still limits its band.
    bands = [_band(f, mag, list(peaks), i, bandwidth_multiple, min_side_points)
             for i in range(peaks.size)]
    return _enough(n_modes, bands, source)


def estimate_noise_std(alpha: np.ndarray) -> float:
    """Robust standard deviation ``sqrt(E|n|**2)`` of white complex noise on an FRF.

    Uses the median of ``|second difference|``: smooth parts of the FRF drop out, and
    the few bins at sharp resonances do not move the median.
    """
    second = np.abs(np.diff(np.asarray(alpha, dtype=complex), n=2))
    if second.size == 0:
        return 0.0
    # |second difference| of circular noise is Rayleigh with E|.|^2 = 6 E|n|^2,
    # whose median is sqrt(3 * 2 ln 2) * sqrt(E|n|^2).
    return float(np.median(second) / np.sqrt(6.0 * np.log(2.0)))


def _first_used_bin(freq: np.ndarray, exclude_below_hz: float | None) -> int:
    start = _SKIP_LOW_BINS
    if exclude_below_hz is not None:
        start = max(start, int(np.searchsorted(freq, exclude_below_hz, side="left")))
    return start


def _enough(n_modes: int | None, bands: list[tuple[float, float]],
            source: str | None) -> list[tuple[float, float]]:
    """The bands of the ``n_modes`` lowest peaks (all if ``n_modes`` is None)."""
    if n_modes is None:
        return bands
    if len(bands) < n_modes:
        raise InputError(f"found {len(bands)} resonance peaks but n_modes={n_modes}",
                         source=source, field="n_modes")
    return bands[:n_modes]


def _band(f: np.ndarray, mag: np.ndarray, peaks: list[int], i: int, multiple: float,
          min_side: int) -> tuple[float, float]:
    """Band around peak ``i``: narrower of the bandwidth rule and the neighbour midpoints."""
    k = peaks[i]
    half_bw = multiple * _half_power_bandwidth(f, mag, k)
    lo_hz, hi_hz = f[k] - half_bw, f[k] + half_bw
    if i > 0:
        lo_hz = max(lo_hz, 0.5 * (f[peaks[i - 1]] + f[k]))
    if i < len(peaks) - 1:
        hi_hz = min(hi_hz, 0.5 * (f[k] + f[peaks[i + 1]]))
    lo = min(int(np.searchsorted(f, lo_hz, side="left")), k - min_side)
    hi = max(int(np.searchsorted(f, hi_hz, side="right")) - 1, k + min_side)
    lo, hi = max(lo, 0), min(hi, f.size - 1)
    return float(f[lo]), float(f[hi])


def _half_power_bandwidth(f: np.ndarray, mag: np.ndarray, k: int) -> float:
    """Width (Hz) where ``|alpha|`` is above ``peak / sqrt(2)``, interpolated linearly.

    A single bin below the level with the next one above it again is taken as a noise
    dip, not as the edge of the peak.
    """
    level = mag[k] / np.sqrt(2.0)
    lo = k
    while lo > 0 and (mag[lo - 1] > level or (lo > 1 and mag[lo - 2] > level)):
        lo -= 1
    hi = k
    last = mag.size - 1
    while hi < last and (mag[hi + 1] > level or (hi < last - 1 and mag[hi + 2] > level)):
        hi += 1
    left = _crossing(f, mag, lo - 1, lo, level) if lo > 0 else f[0]
    right = _crossing(f, mag, hi + 1, hi, level) if hi < mag.size - 1 else f[-1]
    return float(right - left)


def _crossing(f: np.ndarray, mag: np.ndarray, outside: int, inside: int,
              level: float) -> float:
    """Frequency between two bins where ``mag`` passes ``level``."""
    t = (mag[inside] - level) / (mag[inside] - mag[outside])
    return float(f[inside] + t * (f[outside] - f[inside]))
