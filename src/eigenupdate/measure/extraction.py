"""From measured FRFs of one configuration to the natural frequencies the update uses.

Per configuration (the bare structure, or one perturbation) there may be several FRFs
(several response points). Candidate resonances are the peaks of each FRF, bands of the
same peak in different FRFs merged. Dobson's method is fitted in every band of every FRF,
and each fit must pass the tests of :mod:`eigenupdate.measure.validation` (a spike, a
harmonic or a leakage ripple fails them); candidates that fail in every FRF are listed
as rejected with the reason. The estimates of a mode are combined by inverse variance,
with a common extra variance when the FRFs disagree more than their own standard
deviations say. The rational-fraction fit over all bands at once is an independent
cross-check and one of the stability tests.

Numbering: :func:`extract_resonances` numbers the validated resonances by order;
:mod:`eigenupdate.measure.survey` renumbers them by the model's modes when there is a
model, so that a mode every FRF misses (all response points at its nodes) is reported
as missing instead of shifting the numbers above it.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from eigenupdate.errors import EigenupdateWarning, InputError
from eigenupdate.measure.dobson import MIN_PEAK_RISE_IN_STD, dobson_fit_modes
from eigenupdate.measure.frf import FRF, check_same_axis
from eigenupdate.measure.modal_fit import ModalFit, NoResonance, mode_receptance
from eigenupdate.measure.peaks import estimate_noise_std, propose_bands
from eigenupdate.measure.rational_fraction import rational_fraction_status
from eigenupdate.measure.validation import Verdict, strongest, validate_fit

DISAGREEMENT_WARNING = 4.0
"""Dobson and rational-fraction frequencies further apart than this many combined std
raise an :class:`~eigenupdate.errors.EigenupdateWarning`."""


@dataclass(frozen=True)
class ExtractedMode:
    """One elastic mode of one configuration, from all its FRFs.

    ``fits`` holds the Dobson fit of each FRF (None where that FRF shows no peak or its
    fit failed the tests of :mod:`eigenupdate.measure.validation`); ``check_hz`` and
    ``check_std_hz`` are the rational-fraction estimate (None if it failed);
    ``fit_quality`` the lowest fit quality of the accepted fits; ``under_resolved`` says
    that the half-power band holds fewer than 3 lines (the std then includes the spread
    of the second estimates); ``model_hz`` is the model frequency the mode was numbered
    against (None when numbered by order).
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
    fit_quality: float | None = None
    under_resolved: bool = False
    model_hz: float | None = None

    @property
    def disagreement(self) -> float | None:
        """|Dobson - rational fraction| in combined standard deviations."""
        if self.check_hz is None:
            return None
        s = np.hypot(self.std_hz, self.check_std_hz or 0.0)
        return float(abs(self.frequency_hz - self.check_hz) / s) if s > 0 else None


def combine(values: Sequence[float], stds: Sequence[float]) -> tuple[float, float]:
    """Inverse-variance mean and its std; when the values scatter more than their stds
    say, every std gets the same extra variance ``tau**2`` that makes the scatter
    consistent (the Paule-Mandel random-effects mean), so that one estimate with a
    small std cannot outvote the others that disagree with it.

    >>> m, s = combine([100.0, 100.1], [0.1, 0.1])   # consistent: std / sqrt(2)
    >>> round(m, 6), round(s, 4)
    (100.05, 0.0707)
    >>> m, s = combine([100.0, 101.0], [0.1, 0.1])   # inconsistent: scatter dominates
    >>> round(m, 6), round(s, 3)
    (100.5, 0.5)
    >>> m, s = combine([10.0, 10.2, 10.1], [0.01, 0.05, 0.05])   # no single outvoter
    >>> round(m, 3), round(s, 3)
    (10.092, 0.059)
    """
    v, s = np.asarray(values, float), np.asarray(stds, float)

    def mean_chi2(tau2: float) -> tuple[float, float, float]:
        w = 1.0 / (s**2 + tau2)
        mean = float(np.sum(w * v) / np.sum(w))
        return mean, float(np.sqrt(1.0 / np.sum(w))), float(np.sum(w * (v - mean) ** 2))

    mean, std, chi2 = mean_chi2(0.0)
    if v.size > 1 and chi2 > v.size - 1:
        from scipy.optimize import brentq

        top = float(np.ptp(v)) ** 2  # tau**2 = range**2 always over-explains the scatter
        tau2 = brentq(lambda t: mean_chi2(t)[2] - (v.size - 1), 0.0, top, xtol=1e-14 * top)
        mean, std, _ = mean_chi2(tau2)
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
    (one band's centre inside the other band) are merged, taking the median edges.
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
        a = clusters[-1][0] if clusters else None
        # either centre inside the other band: bands cut short on one side by a spike or
        # a ripple next to the peak are still the same resonance
        if a is not None and (a[0] <= centre <= a[1] or b[0] <= 0.5 * (a[0] + a[1]) <= b[1]):
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


@dataclass(frozen=True)
class Rejected:
    """A candidate resonance that is not a mode, and why."""

    configuration: str
    frequency_hz: float
    band_hz: tuple[float, float]
    reason: str
    narrow: bool = False  # a spike or harmonic, interpolated over in the data


@dataclass(frozen=True)
class ConfigurationExtraction:
    """Accepted modes (numbered by order, or by the model after
    :func:`eigenupdate.measure.numbering.number_configurations`) and rejected candidates
    of one configuration; ``unexpected`` are accepted resonances no model mode explains."""

    configuration: str
    modes: list[ExtractedMode]
    rejected: list[Rejected]
    line_spacing_hz: float
    frequency_range_hz: tuple[float, float]
    unexpected: list[ExtractedMode] = field(default_factory=list)
    missing: list[tuple[int, float]] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)


def extract_resonances(
    frfs: Sequence[FRF],
    configuration: str,
    *,
    bands_hz: Sequence[tuple[float, float]] | None = None,
    exclude_below_hz: float | None = None,
    cross_check: bool = True,
) -> ConfigurationExtraction:
    """Every validated resonance of one configuration, numbered by order, and every
    rejected candidate with its reason.

    Candidates are the peaks of the FRFs (or the given ``bands_hz``, band k = mode k).
    Each is fitted by Dobson's method in every FRF, with the other candidates' fits
    subtracted, and tested (:func:`eigenupdate.measure.validation.validate_fit`); the
    fits that pass are combined. When a candidate fails in every FRF it is rejected and
    the others are fitted again without it, so that a spike's "mode" is not subtracted
    from its neighbours.
    """
    where = f"configuration {configuration!r}"
    if not frfs:
        raise InputError(f"{where} has no FRF")
    axis = check_same_axis(list(frfs), where)
    given = bands_hz is not None
    if given:
        bands = [tuple(map(float, b)) for b in bands_hz]
        lo, hi = np.array(bands, dtype=float).reshape(-1, 2).T
        if not (len(bands) and np.all(np.isfinite(lo + hi)) and lo[0] >= 0
                and np.all(lo < hi) and np.all(hi[:-1] <= lo[1:])):
            # band k is mode k: bands out of order or overlapping would mislabel modes
            raise InputError(f"bands {bands} must be ascending and must not overlap "
                             f"(band k holds elastic mode k)", field=f"{where} bands_hz")
    else:
        bands = find_bands(frfs, 0, exclude_below_hz=exclude_below_hz, source=where)
    for x in frfs:
        big = np.abs(x.receptance) > MAX_RECEPTANCE
        if big.any():  # finite, but its square or fourth power overflows in the fits
            i = int(np.flatnonzero(big)[0])
            raise InputError(f"{where}: |receptance| {abs(x.receptance[i]):.3g} m/N at "
                             f"{x.frequency_hz[i]:g} Hz is beyond any real one (corrupted "
                             f"data?)", source=x.source or None)
    numbers = list(range(1, len(bands) + 1))
    rejected: list[Rejected] = []
    # The global fit (one pole per band, slow with many bands) joins once the Dobson
    # tests have thrown out the spikes; if its stability test rejects more, go round again.
    with_check = False
    while True:
        try:
            per_frf = [_dobson(x, bands, where) for x in frfs]
            checks = [_rational_fraction(x, bands) if with_check and bands else None
                      for x in frfs]
        except np.linalg.LinAlgError:  # e.g. SVD of a corrupted FRF did not converge
            raise InputError(f"{where}: the modal fit failed (its least-squares solve found "
                             f"no solution); the FRF data cannot be fitted (corrupted "
                             f"file?)", source=_sources(frfs)) from None
        verdicts = [_verdicts(x, fits, chk, bands)
                    for x, fits, chk in zip(frfs, per_frf, checks, strict=True)]
        bad = [k for k in range(len(bands))
               if not any(v[k] is not None and v[k].reason is None for v in verdicts)]
        if not bad and (with_check or not cross_check):
            break
        with_check = with_check or (cross_check and not bad)
        if not bad:
            continue
        found = {k: _rejection(configuration, bands[k], [v[k] for v in verdicts]) for k in bad}
        if any(r.narrow for r in found.values()):
            # Spikes and harmonics first: their fitted "modes" are subtracted from the
            # other bands, so the other verdicts of this pass are not to be trusted yet.
            bad = [k for k in bad if found[k].narrow]
        for k in bad:
            r = found[k]
            if r.narrow:  # a spike or a harmonic: take it out of the data the fits see
                frfs = [_despike(x, bands[k]) for x in frfs]
                r = replace(r, reason=r.reason + "; its lines were interpolated over")
            rejected.append(r)
        keep = [k for k in range(len(bands)) if k not in bad]
        bands, numbers = [bands[k] for k in keep], [numbers[k] for k in keep]
    out = []
    for i, band in enumerate(bands):
        fits = tuple(v[i].fit if v[i] is not None and v[i].reason is None else None
                     for v in verdicts)
        good = [v[i] for v in verdicts if v[i] is not None and v[i].reason is None]
        f, s = combine([v.fit.frequency_hz for v in good], [v.fit.frequency_std_hz for v in good])
        eta, eta_s = combine([v.fit.loss_factor for v in good],
                             [v.fit.loss_factor_std for v in good])
        ck = [c[i] for c in checks if c is not None and c[i] is not None]
        cf, cs = combine([c.frequency_hz for c in ck], [c.frequency_std_hz for c in ck]) \
            if ck else (None, None)
        if not np.all(np.isfinite([f, s, eta, eta_s])):
            raise InputError(f"{where}: resonance near {0.5 * sum(band):.5g} Hz: the fit gave "
                             f"f = {f:.6g} Hz, std {s:.3g}, loss factor {eta:.3g} (corrupted "
                             f"FRF data?)", source=_sources(frfs))
        if cf is not None and not np.isfinite([cf, cs]).all():
            cf, cs = None, None  # the cross-check failed: report the Dobson fit alone
        mode = ExtractedMode(
            configuration, numbers[i] if given else i + 1, f, s, eta, eta_s, band, fits, cf,
            cs, fit_quality=min(v.fit_quality for v in good),
            under_resolved=any(v.under_resolved for v in good))
        d = mode.disagreement
        if d is not None and d > DISAGREEMENT_WARNING:
            warnings.warn(f"{configuration} mode {mode.mode}: Dobson {f:.4f} Hz and rational "
                          f"fraction {cf:.4f} Hz differ by {d:.1f} std", EigenupdateWarning,
                          stacklevel=2)
        out.append(mode)
    rejected.sort(key=lambda r: r.frequency_hz)
    spacing = float(np.median(np.diff(axis))) if axis.size > 1 else float("nan")
    return ConfigurationExtraction(configuration, out, rejected, spacing,
                                   (float(axis[0]), float(axis[-1])))


def extract_configuration(
    frfs: Sequence[FRF],
    modes: Sequence[int],
    configuration: str,
    *,
    bands_hz: Sequence[tuple[float, float]] | None = None,
    exclude_below_hz: float | None = None,
    cross_check: bool = True,
) -> list[ExtractedMode]:
    """Natural frequency, loss factor and their standard deviations of every validated
    elastic mode, numbered by order (an error if one of ``modes`` is not found).

    Parameters
    ----------
    frfs : receptances of this configuration, on one frequency axis.
    modes : elastic mode numbers to extract (1 = first elastic mode).
    configuration : its name, for messages and results.
    bands_hz : one (low, high) band per elastic mode from mode 1 on; found automatically
        when None. Bands of higher modes help: their fitted contributions are subtracted
        when the lower modes are fitted.
    exclude_below_hz : ignore peaks below this frequency (e.g. suspension modes).
    cross_check : also run the rational-fraction fit.
    """
    if bands_hz is not None and len(bands_hz) < max(modes):
        raise InputError(f"{len(bands_hz)} bands given, elastic mode {max(modes)} is used",
                         field=f"configuration {configuration!r} bands_hz")
    ex = extract_resonances(frfs, configuration, bands_hz=bands_hz,
                            exclude_below_hz=exclude_below_hz, cross_check=cross_check)
    problem = missing_used_modes(ex, modes)
    if problem:
        raise InputError(problem)
    return ex.modes


def missing_used_modes(ex: ConfigurationExtraction, modes: Sequence[int]) -> str | None:
    """One line naming the configuration and the first used mode that was not found."""
    have = {m.mode for m in ex.modes}
    for k in sorted(modes):
        if k in have:
            continue
        text = f"configuration {ex.configuration!r}: elastic mode {k} was not found"
        expected = dict(ex.missing).get(k)
        if expected is not None:
            text += f" (the model expects it at {expected:.5g} Hz)"
        elif not ex.notes:
            text += f" ({len(ex.modes)} validated resonance(s))"
        if ex.rejected:
            text += "; rejected: " + "; ".join(
                f"{r.frequency_hz:.5g} Hz: {r.reason}" for r in ex.rejected[:3])
        return text
    return None


def _verdicts(frf: FRF, fits: list[ModalFit | None], checks: list[ModalFit | None] | None,
              bands) -> list[Verdict | None]:
    """Validate every band's fit on the FRF minus the other bands' fitted modes."""
    f, h = _finite(frf)
    x = (2.0 * np.pi * f) ** 2
    parts = [None if ft is None else mode_receptance(ft, x) for ft in fits]
    total = sum((p for p in parts if p is not None), np.zeros_like(h))
    out: list[Verdict | None] = []
    for k, ft in enumerate(fits):
        if ft is None:
            out.append(None)
            continue
        lo = 0.5 * sum(bands[k - 1]) if k > 0 else float(f[0])
        hi = 0.5 * sum(bands[k + 1]) if k + 1 < len(bands) else float(f[-1])
        out.append(validate_fit(f, h - (total - parts[k]), ft,
                                check=None if checks is None else checks[k],
                                neighbours_hz=(lo, hi)))
    return out


def _rejection(configuration: str, band: tuple[float, float],
               verdicts: list[Verdict | None]) -> Rejected:
    v = strongest(verdicts)
    if v is None:
        return Rejected(configuration, 0.5 * (band[0] + band[1]), band,
                        f"no FRF shows a resonance in {band[0]:.4g}-{band[1]:.4g} Hz")
    narrow = all(x is None or x.lines_above <= NARROW_LINES for x in verdicts)
    fit = v.fit
    if not np.isfinite([fit.frequency_hz, fit.loss_factor]).all():  # corrupted data
        return Rejected(configuration, 0.5 * (band[0] + band[1]), band,
                        "the fit gave no finite frequency or loss factor", narrow)
    return Rejected(configuration, fit.frequency_hz, band, v.reason or "", narrow)


#: A rejected candidate that rises above its floor at this many lines or fewer is a
#: spike or a harmonic (a resonance lifts its skirts over many more lines): its peak line
#: and the two beside it are replaced by a straight line between their neighbours, so
#: that it cannot mislead the fits of the resonances around it.
NARROW_LINES = 3


def _despike(frf: FRF, band: tuple[float, float]) -> FRF:
    f, h = frf.frequency_hz, np.array(frf.receptance)
    mag = np.abs(h)
    inside = np.flatnonzero((f >= band[0]) & (f <= band[1]) & np.isfinite(h))
    # the spike is the highest interior local maximum: the band's highest line may be the
    # skirt of a resonance next to it, which must stay
    inside = inside[(inside > 0) & (inside < f.size - 1)]
    peaks = inside[(mag[inside] >= mag[inside - 1]) & (mag[inside] >= mag[inside + 1])]
    if peaks.size == 0:
        return frf
    top = int(peaks[np.argmax(mag[peaks])])
    lo, hi = top - 2, top + 2
    if lo < 0 or hi >= f.size or not np.isfinite(h[[lo, hi]]).all():
        return frf
    t = (f[lo + 1:hi] - f[lo]) / (f[hi] - f[lo])
    h[lo + 1:hi] = h[lo] + t * (h[hi] - h[lo])
    return FRF(f, h, frf.response, frf.reference, frf.source)


MAX_RECEPTANCE = 1e30
"""Largest |receptance| (m/N) fitted; real ones are many orders of magnitude below."""


def _finite(frf: FRF) -> tuple[np.ndarray, np.ndarray]:
    ok = np.isfinite(frf.receptance) & (frf.frequency_hz > 0)
    return frf.frequency_hz[ok], frf.receptance[ok]


def _dobson(frf: FRF, bands, where: str) -> list[ModalFit | None]:
    """Dobson fits of every band; a band without a peak in this FRF gives None."""
    f, h = _finite(frf)
    return dobson_fit_modes(f, h, bands, source=frf.source or where, skip_missing=True)


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


def _sources(frfs: Sequence[FRF]) -> str | None:
    """The file(s) the FRFs came from, for messages."""
    names = sorted({x.source for x in frfs if x.source})
    return ", ".join(names) or None
