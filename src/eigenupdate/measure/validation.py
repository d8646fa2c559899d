"""Is a fitted peak a mode? Tests that a noise spike, a mains harmonic or a leakage
artefact fails, and honest standard deviations for modes narrower than a line.

A candidate band's single-mode fit (:func:`eigenupdate.measure.dobson.dobson_fit`) on one
FRF becomes a mode only if

1. the peak of ``|alpha|`` rises :data:`RISE_IN_STD` local noise std above the band's
   floor (its lowest value), and a run of :data:`MIN_LINES_ABOVE` lines or more through
   the peak rises :data:`SKIRT_IN_STD`: a one-line spike has no skirts, a resonance has;
2. the loss factor is positive;
3. the natural frequency lies inside the band;
4. the single mode plus a constant explains the band: ``1 - |alpha - fit|**2 /
   |alpha - mean alpha|**2`` (the fit quality, R**2) is at least :data:`MIN_FIT_QUALITY`,
   or the residual is no larger than the noise (:data:`MAX_RESIDUAL_IN_STD`);
5. refits over a narrowed and a widened band, and the global rational-fraction fit where
   it has a pole in the band, agree with it within :data:`STABLE_IN_STD` combined std or
   :data:`STABLE_IN_LINES` line spacings, whichever is larger.

Every failed test gives a one-line reason, so a rejected candidate is listed, never
silently dropped.

Under-resolved modes (half-power bandwidth ``eta f`` below :data:`UNDER_RESOLVED_LINES`
line spacings) are fitted from the skirts of the peak, where the single-mode form, the
window and the residual terms matter more than the noise: their std is widened by the
largest disagreement with the second estimates of test 5 (added in quadrature).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from eigenupdate.errors import InputError
from eigenupdate.measure.dobson import dobson_fit
from eigenupdate.measure.modal_fit import MIN_BAND_POINTS, ModalFit, mode_receptance
from eigenupdate.measure.peaks import estimate_noise_std

__all__ = [
    "SKIRT_IN_STD",
    "MIN_FIT_QUALITY",
    "MIN_LINES_ABOVE",
    "RISE_IN_STD",
    "STABLE_IN_LINES",
    "STABLE_IN_STD",
    "UNDER_RESOLVED_LINES",
    "Verdict",
    "validate_fit",
]

#: Rise above the local floor, in noise std: the peak picker's least prominence, so noise
#: alone passes with a probability of about 1e-8 per line.
RISE_IN_STD = 6.0
#: Lines (the peak included) that must rise SKIRT_IN_STD: one line is a spike (or a
#: harmonic exactly on a line); even a mode far narrower than a line lifts a neighbour by
#: 1/3 of its peak or more.
MIN_LINES_ABOVE = 2
#: Rise of the skirt lines, in noise std: noise alone reaches it with a probability of
#: exp(-9) ~ 1e-4 per line, so a spike passes for a resonance about once in 4000.
SKIRT_IN_STD = 3.0
#: Least fit quality (R**2 of mode + constant over the band). Clean modes give > 0.99, also
#: at 1 line per 20 half-power bandwidths; a two-line harmonic with a flat phase or a
#: leakage ripple (alternating sign from line to line) cannot be fitted that well.
MIN_FIT_QUALITY = 0.9
#: ... unless the residual is noise (rms in noise std): a weak mode's band is mostly noise.
MAX_RESIDUAL_IN_STD = 1.5
#: Agreement of the second estimates, in combined standard deviations ...
STABLE_IN_STD = 4.0
#: ... or in line spacings, whichever is larger (a mode narrower than a line is located to
#: a fraction of a line by its skirts; a ripple or spike fit jumps by a line or more).
STABLE_IN_LINES = 0.25
#: Modes whose half-power bandwidth holds fewer lines than this are under-resolved.
UNDER_RESOLVED_LINES = 3.0
#: Lines on each side of a band used for the local noise estimate.
NOISE_WINDOW_LINES = 50


@dataclass(frozen=True)
class Verdict:
    """Outcome of the tests on one fit: ``reason`` is None when it is a mode.

    ``fit`` carries the (possibly widened) standard deviations; ``second`` the largest
    frequency difference to a second estimate (Hz), or None if none could be made.
    """

    fit: ModalFit
    reason: str | None
    fit_quality: float
    lines_above: int
    under_resolved: bool
    second_hz: float | None


def validate_fit(
    freq_hz: np.ndarray,
    receptance: np.ndarray,
    fit: ModalFit,
    *,
    check: ModalFit | None = None,
    neighbours_hz: tuple[float, float] | None = None,
) -> Verdict:
    """Run the tests of the module notes on ``fit`` (a Dobson fit of ``receptance``).

    Parameters
    ----------
    freq_hz, receptance : ndarray
        The whole FRF (finite values, f > 0), with the fitted contributions of the other
        modes already subtracted.
    fit : ModalFit
        The single-mode fit of the band ``fit.band_hz``.
    check : ModalFit, optional
        The global rational-fraction pole of this band, if any.
    neighbours_hz : (float, float), optional
        How far a widened band may reach (the neighbouring resonances); default the
        whole axis.

    Examples
    --------
    A resonance is a mode; a one-line spike on a smooth curve is not:

    >>> rng = np.random.default_rng(0)
    >>> f = np.arange(1.0, 200.0, 0.5)
    >>> x = (2 * np.pi * f) ** 2
    >>> mode = 1.0 / ((2 * np.pi * 100) ** 2 * (1 + 0.02j) - x)
    >>> noise = 1e-3 * abs(mode).max() * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size))
    >>> h = mode + noise
    >>> v = validate_fit(f, h, dobson_fit(f, h, (95.0, 105.0)))
    >>> print(v.reason, v.lines_above > 2, round(v.fit_quality, 3))
    None True 1.0
    >>> h[300] += 50 * 1e-3 * abs(mode).max()          # 150.5 Hz
    >>> v = validate_fit(f, h, dobson_fit(f, h, (148.0, 153.0)))
    >>> print(v.reason)
    peak 13.9 noise std above its floor, a single line (a spike, not a resonance)
    """
    f, h = np.asarray(freq_hz, float), np.asarray(receptance, complex)
    lo, hi = fit.band_hz
    inside = (f >= lo) & (f <= hi)
    fb, hb = f[inside], h[inside]
    k0, k1 = np.flatnonzero(inside)[[0, -1]]
    w0, w1 = max(k0 - NOISE_WINDOW_LINES, 0), min(k1 + NOISE_WINDOW_LINES + 1, f.size)
    sigma = estimate_noise_std(h[w0:w1])
    df = float(np.median(np.diff(fb)))

    mag = np.abs(hb)
    top = int(np.argmax(mag))
    floor = min(mag[:top].min(initial=mag[top]), mag[top + 1:].min(initial=mag[top]))
    rise = (mag - floor) / sigma if sigma > 0 else np.full(mag.shape, np.inf)
    lines_above = _run_through(top, rise > SKIRT_IN_STD) if rise[top] > RISE_IN_STD else 0

    x = (2.0 * np.pi * fb) ** 2
    modal = mode_receptance(fit, x)
    const = np.mean(hb - modal)
    spread = float(np.sum(np.abs(hb - hb.mean()) ** 2))
    resid = float(np.sum(np.abs(hb - modal - const) ** 2))
    quality = 1.0 - resid / spread if spread else 0.0
    rms = np.sqrt(resid / hb.size)

    bandwidth = fit.loss_factor * fit.frequency_hz
    under = bandwidth < UNDER_RESOLVED_LINES * df

    reason = None
    if lines_above < MIN_LINES_ABOVE:
        reason = (f"peak {rise[top]:.3g} noise std above its floor, "
                  + ("a single line (a spike, not a resonance)" if lines_above == 1 else
                     f"less than {RISE_IN_STD:g}"))
    elif not fit.loss_factor > 0:
        reason = f"loss factor {fit.loss_factor:.3g} is not positive"
    elif not lo < fit.frequency_hz < hi:
        reason = f"fitted frequency {fit.frequency_hz:.6g} Hz lies outside its band"
    elif quality < MIN_FIT_QUALITY and rms > MAX_RESIDUAL_IN_STD * sigma:
        reason = (f"one mode does not explain the band: fit quality {quality:.3f} < "
                  f"{MIN_FIT_QUALITY:g}, residual {rms / sigma:.3g} noise std")
    second_hz = None
    out = fit
    if reason is None:
        seconds = _second_estimates(f, h, fit, check, neighbours_hz)
        if seconds:
            tol = [max(STABLE_IN_STD * np.hypot(fit.frequency_std_hz, s.frequency_std_hz),
                       STABLE_IN_LINES * df) for s, _ in seconds]
            diffs = [s.frequency_hz - fit.frequency_hz for s, _ in seconds]
            worst = int(np.argmax([abs(d) / t for d, t in zip(diffs, tol, strict=True)]))
            second_hz = float(max(abs(d) for d in diffs))
            if abs(diffs[worst]) > tol[worst]:
                reason = (f"unstable: the {seconds[worst][1]} gives {diffs[worst]:+.3g} Hz "
                          f"(more than {tol[worst]:.3g} Hz)")
            elif under:
                d_eta = max(abs(s.loss_factor - fit.loss_factor) for s, _ in seconds)
                out = replace(fit, frequency_std_hz=float(np.hypot(fit.frequency_std_hz,
                                                                   second_hz)),
                              loss_factor_std=float(np.hypot(fit.loss_factor_std, d_eta)))
    return Verdict(out, reason, quality, lines_above, bool(under), second_hz)


def _run_through(k: int, above: np.ndarray) -> int:
    """Length of the run of True in ``above`` through index ``k`` (skirts touch the peak)."""
    lo = hi = k
    while lo > 0 and above[lo - 1]:
        lo -= 1
    while hi < above.size - 1 and above[hi + 1]:
        hi += 1
    return hi - lo + 1


def _second_estimates(f: np.ndarray, h: np.ndarray, fit: ModalFit, check: ModalFit | None,
                      neighbours_hz: tuple[float, float] | None
                      ) -> list[tuple[ModalFit, str]]:
    """Dobson refits over a narrowed and a widened band, and the global fit's pole."""
    lo, hi = fit.band_hz
    fr = fit.frequency_hz
    out: list[tuple[ModalFit, str]] = []
    reach = neighbours_hz or (float(f[0]), float(f[-1]))
    bands = {
        "narrowed-band refit": (fr - 0.6 * (fr - lo), fr + 0.6 * (hi - fr)),
        "widened-band refit": (max(lo - 0.5 * (hi - lo), 0.5 * (reach[0] + lo), f[0]),
                               min(hi + 0.5 * (hi - lo), 0.5 * (reach[1] + hi), f[-1])),
    }
    for name, band in bands.items():
        if np.count_nonzero((f >= band[0]) & (f <= band[1])) < MIN_BAND_POINTS:
            continue
        try:
            out.append((dobson_fit(f, h, band), name))
        except InputError:
            continue  # too narrow or no interior maximum there: no second estimate
    if check is not None:
        out.append((check, "rational-fraction fit"))
    return out


def strongest(verdicts: Sequence[Verdict | None]) -> Verdict | None:
    """The verdict of the FRF with the highest fitted peak (for a rejection reason)."""
    have = [v for v in verdicts if v is not None]
    if not have:
        return None
    return max(have, key=lambda v: abs(v.fit.modal_constant)
               / max(abs(v.fit.loss_factor), 1e-12) / v.fit.frequency_hz**2)
