"""From measured FRFs of one configuration to the natural frequencies the update uses.

Per configuration (the bare structure, or one perturbation) there may be several FRFs
(several response points). The resonance bands are found once, on the sum of the FRFs
each normalised by its peak, so that a mode with a node at one response point is still
found at the others and elastic mode k is always the k-th resonance. Dobson's method is
fitted in every band of every FRF; the estimates of a mode are combined by inverse
variance, and the standard deviation is inflated when the FRFs disagree more than their
own standard deviations say. The rational-fraction fit over all bands at once is an
independent cross-check.

Caveat: a mode that every FRF misses (all response points at its nodes) cannot be seen;
the modes above it would then be numbered wrongly. Choose response points away from
nodes, as for any modal test.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from eigenupdate.errors import EigenupdateWarning, InputError
from eigenupdate.measure.dobson import MIN_PEAK_RISE_IN_STD, dobson_fit_modes
from eigenupdate.measure.frf import FRF, check_same_axis
from eigenupdate.measure.modal_fit import ModalFit, NoResonance, mode_receptance
from eigenupdate.measure.peaks import estimate_noise_std, propose_bands
from eigenupdate.measure.rational_fraction import rational_fraction_status

DISAGREEMENT_WARNING = 4.0
"""Dobson and rational-fraction frequencies further apart than this many combined std
raise an :class:`~eigenupdate.errors.EigenupdateWarning`."""


@dataclass(frozen=True)
class ExtractedMode:
    """One elastic mode of one configuration, from all its FRFs.

    ``fits`` holds the Dobson fit of each FRF (None where that FRF shows no peak);
    ``check_hz`` and ``check_std_hz`` are the rational-fraction estimate (None if it failed).
    """

    configuration: str
    mode: int
    frequency_hz: float
    std_hz: float
    loss_factor: float
    loss_factor_std: float
    band_hz: tuple[float, float]
    fits: tuple[ModalFit | None, ...]
    check_hz: float | None = None
    check_std_hz: float | None = None

    @property
    def disagreement(self) -> float | None:
        """|Dobson - rational fraction| in combined standard deviations."""
        if self.check_hz is None:
            return None
        s = np.hypot(self.std_hz, self.check_std_hz or 0.0)
        return float(abs(self.frequency_hz - self.check_hz) / s) if s > 0 else None


def combine(values: Sequence[float], stds: Sequence[float]) -> tuple[float, float]:
    """Inverse-variance mean and its std, inflated by the scatter when it exceeds the stds.

    >>> m, s = combine([100.0, 100.1], [0.1, 0.1])   # consistent: std / sqrt(2)
    >>> round(m, 6), round(s, 4)
    (100.05, 0.0707)
    >>> m, s = combine([100.0, 101.0], [0.1, 0.1])   # inconsistent: scatter dominates
    >>> round(m, 6), round(s, 3)
    (100.5, 0.5)
    """
    v, s = np.asarray(values, float), np.asarray(stds, float)
    w = 1.0 / s**2
    mean = float(np.sum(w * v) / np.sum(w))
    std = float(np.sqrt(1.0 / np.sum(w)))
    if v.size > 1:
        chi2 = float(np.sum(w * (v - mean) ** 2)) / (v.size - 1)
        std *= max(1.0, float(np.sqrt(chi2)))
    return mean, std


def find_bands(
    frfs: Sequence[FRF],
    n_modes: int,
    *,
    exclude_below_hz: float | None = None,
    source: str | None = None,
) -> list[tuple[float, float]]:
    """Bands of the ``n_modes`` lowest elastic resonances seen in any of the FRFs.

    Peaks are picked in each FRF; bands of different FRFs around the same resonance
    (one band's centre inside another's band) are merged, taking the median edges.
    """
    check_same_axis(list(frfs), source or "")
    found = []
    for x in frfs:
        f, h = _finite(x)
        found += propose_bands(f, h, exclude_below_hz=exclude_below_hz, source=source)
    found.sort(key=lambda b: b[0] + b[1])
    clusters: list[list[tuple[float, float]]] = []
    for b in found:
        centre = 0.5 * (b[0] + b[1])
        if clusters and clusters[-1][0][0] <= centre <= clusters[-1][0][1]:
            clusters[-1].append(b)
        else:
            clusters.append([b])
    bands = [(float(np.median([b[0] for b in c])), float(np.median([b[1] for b in c])))
             for c in clusters]
    if len(bands) < n_modes:
        raise InputError(
            f"found {len(bands)} resonance peak(s), elastic mode {n_modes} is used"
            + (f" (peaks at {', '.join(f'{0.5 * (a + b):.4g}' for a, b in bands)} Hz)"
               if bands else ""),
            source=source,
        )
    return bands


def extract_configuration(
    frfs: Sequence[FRF],
    modes: Sequence[int],
    configuration: str,
    *,
    bands_hz: Sequence[tuple[float, float]] | None = None,
    exclude_below_hz: float | None = None,
    cross_check: bool = True,
) -> list[ExtractedMode]:
    """Natural frequency, loss factor and their standard deviations of every elastic mode
    found, at least modes 1..max(modes) (an error if one of ``modes`` cannot be fitted).

    Parameters
    ----------
    frfs : receptances of this configuration, on one frequency axis.
    modes : elastic mode numbers to extract (1 = first elastic mode).
    configuration : its name, for messages and results.
    bands_hz : one (low, high) band per elastic mode from mode 1 on, at least up to
        max(modes); found automatically when None. Bands of higher modes help: their
        fitted contributions are subtracted when the lower modes are fitted.
    exclude_below_hz : ignore peaks below this frequency (e.g. suspension modes).
    cross_check : also run the rational-fraction fit.
    """
    where = f"configuration {configuration!r}"
    if not frfs:
        raise InputError(f"{where} has no FRF")
    n = max(modes)
    if bands_hz is None:
        bands = find_bands(frfs, n, exclude_below_hz=exclude_below_hz, source=where)
    else:
        bands = [tuple(map(float, b)) for b in bands_hz]
        if len(bands) < n:
            raise InputError(f"{len(bands)} bands given, elastic mode {n} is used",
                             field=f"{where} bands_hz")
        lo, hi = np.array(bands, dtype=float).T
        if not (np.all(np.isfinite(lo + hi)) and lo[0] >= 0 and np.all(lo < hi)
                and np.all(hi[:-1] <= lo[1:])):
            # band k is mode k: bands out of order or overlapping would mislabel modes
            raise InputError(f"bands {bands} must be ascending and must not overlap "
                             f"(band k holds elastic mode k)", field=f"{where} bands_hz")
    per_frf = [dobson_fit_modes(*_finite(x), bands, source=x.source or where, skip_missing=True)
               for x in frfs]
    checks = [_rational_fraction(x, bands) for x in frfs] if cross_check else []
    out = []
    for k in range(1, len(bands) + 1):
        fits = tuple(p[k - 1] for p in per_frf)
        good = [ft for ft in fits if ft is not None]
        if not good:
            if k not in modes:
                continue  # a mode the study does not use: report what could be fitted
            lo, hi = bands[k - 1]
            raise InputError(f"{where}: no FRF shows a resonance in {lo:.4g}-{hi:.4g} Hz "
                             f"(elastic mode {k})")
        f, s = combine([ft.frequency_hz for ft in good], [ft.frequency_std_hz for ft in good])
        eta, eta_s = combine([ft.loss_factor for ft in good], [ft.loss_factor_std for ft in good])
        ck = [c[k - 1] for c in checks if c is not None and c[k - 1] is not None]
        cf, cs = combine([c.frequency_hz for c in ck], [c.frequency_std_hz for c in ck]) \
            if ck else (None, None)
        mode = ExtractedMode(configuration, k, f, s, eta, eta_s, bands[k - 1], fits, cf, cs)
        d = mode.disagreement
        if d is not None and d > DISAGREEMENT_WARNING:
            warnings.warn(f"{configuration} mode {k}: Dobson {f:.4f} Hz and rational fraction "
                          f"{cf:.4f} Hz differ by {d:.1f} std", EigenupdateWarning, stacklevel=2)
        out.append(mode)
    return out


def _finite(frf: FRF) -> tuple[np.ndarray, np.ndarray]:
    ok = np.isfinite(frf.receptance) & (frf.frequency_hz > 0)
    return frf.frequency_hz[ok], frf.receptance[ok]


def _rational_fraction(frf: FRF, bands) -> list[ModalFit | None] | None:
    """Global fit with one pole per band, each pole assigned to the band it falls in.

    Where a mode hardly shows in this FRF (a response point near its node), its pole
    goes to fit noise somewhere else: a pole counts for mode k only if it lies in band
    k and its resonance rises above the noise as Dobson's peaks must (else None).
    """
    f, h = _finite(frf)
    fits = rational_fraction_status(f, h, (bands[0][0], bands[-1][1]), len(bands))
    if isinstance(fits, NoResonance):
        return None
    noise = estimate_noise_std(h)
    out: list[ModalFit | None] = []
    for lo, hi in bands:
        inside = [ft for ft in fits if lo <= ft.frequency_hz <= hi
                  and _peak(ft) >= MIN_PEAK_RISE_IN_STD * noise]
        out.append(max(inside, key=_peak) if inside else None)
    return out


def _peak(fit: ModalFit) -> float:
    """|receptance| of the fitted mode alone at its natural frequency."""
    return abs(mode_receptance(fit, (2.0 * np.pi * fit.frequency_hz) ** 2))


EXTRACTION_COLUMNS = (
    "configuration", "mode", "frequency_hz", "std_hz", "loss_factor", "loss_factor_std",
    "check_frequency_hz", "check_std_hz",
)


def extraction_csv(modes: Sequence[ExtractedMode]) -> str:
    """The study's measurement CSV (first four columns), with the loss factors and the
    rational-fraction cross-check as extra columns that ``update`` ignores."""
    import csv
    import io

    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(EXTRACTION_COLUMNS)
    for m in modes:
        w.writerow([m.configuration, m.mode, repr(m.frequency_hz), repr(m.std_hz),
                    repr(m.loss_factor), repr(m.loss_factor_std),
                    "" if m.check_hz is None else repr(m.check_hz),
                    "" if m.check_std_hz is None else repr(m.check_std_hz)])
    return buf.getvalue()
