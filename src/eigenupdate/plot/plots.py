"""Figures of the paper, written to PNG, SVG or PDF files.

* :func:`plot_frf_comparison` - measured vs initial vs updated receptance (paper Fig. 7);
* :func:`plot_mass_sweep` - natural frequencies against the mass added at one
  coordinate (paper Fig. 4);
* :func:`plot_extraction_fit` - the single-mode fits of a modal extraction against the
  measured receptance, magnitude and Nyquist plane.

Figures are built as :class:`matplotlib.figure.Figure` objects on a non-interactive Agg
canvas; nothing touches pyplot's global state or the session's backend, so the
functions are safe in servers, threads and test runs without a display. The file
format follows the extension of ``path``; the file is written to a temporary file in
the same directory and renamed over ``path``, so a reader never sees half a figure.
"""

from __future__ import annotations

import os
import textwrap
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.layout_engine import ConstrainedLayoutEngine
from numpy.typing import ArrayLike

from eigenupdate.errors import InputError
from eigenupdate.io.atomic import atomic_write
from eigenupdate.measure.modal_fit import mode_receptance
from eigenupdate.solve.sweep import MassSweep

__all__ = [
    "FORMATS",
    "plot_extraction_fit",
    "plot_frf_comparison",
    "plot_mass_sweep",
]

#: File extensions understood by the plot functions.
FORMATS: tuple[str, ...] = (".png", ".svg", ".pdf")

_DPI = 150
# Measured data grey and thin (it is noisy), models in distinct colours and dash styles
# so the figure stays readable in greyscale print too.
_STYLE = {
    "measured": {"color": "0.45", "lw": 0.8, "ls": "-"},
    "initial": {"color": "tab:blue", "lw": 1.2, "ls": "--"},
    "updated": {"color": "tab:red", "lw": 1.4, "ls": "-"},
}
_PEAK_BAND_FRACTION = 0.05  # as eigenupdate.measure.synthetic: ignore the rigid-body rise at 0 Hz


# ------------------------------------------------------------------------- utilities


def _format(path: str | os.PathLike[str]) -> str:
    ext = Path(path).suffix.lower()
    if ext not in FORMATS:
        raise InputError(
            f"unsupported figure format {ext or '(none)'!r}; use one of {', '.join(FORMATS)}",
            source=str(path),
        )
    return ext[1:]


# Pads of the constrained layout (inches): the HTML report writes SVG text as text, which
# a browser sets in its own font and measures by line boxes, larger than matplotlib's
# glyph boxes (a log axis's 10^11 reached 3.5 px above the figure with 0.1 in); 0.15 in
# keeps every text inside (matplotlib's default is 3/72 in).
PAD_IN = 0.15


def new_figure(width: float, height: float) -> Figure:
    fig = Figure(figsize=(width, height), layout=ConstrainedLayoutEngine(
        w_pad=PAD_IN, h_pad=PAD_IN))
    FigureCanvasAgg(fig)  # explicit non-GUI canvas: no pyplot, no backend switch
    return fig


def fit_title(text: str, fig: Figure, size_pt: float) -> str:
    """``text`` wrapped, at its own line breaks and between words, to lines that fit the
    figure's width: a title wider than the figure is cut off on both sides, as constrained
    layout does not shrink it. A character is taken as 0.6 em, wider than the average of
    sans-serif fonts (DejaVu Sans: 0.55 em), so the estimate errs on the short side."""
    chars = max(20, int(fig.get_figwidth() * 72 / (0.6 * size_pt)))
    return "\n".join(textwrap.fill(line, chars) for line in text.splitlines())


FIGURE_CREATOR = "eigenupdate figure"
"""The Creator of every figure file (PNG text chunk, SVG dc:creator, PDF Info): what
makes it an earlier output that a command may replace without --force."""


def _save(fig: Figure, path: str | os.PathLike[str]) -> Path:
    fmt = _format(path)
    if not Path(path).parent.is_dir():
        raise InputError("directory does not exist", source=str(path))
    atomic_write(path, lambda tmp: fig.savefig(tmp, format=fmt, dpi=_DPI,
                                               metadata={"Creator": FIGURE_CREATOR}))
    return Path(path)


def _curve(spec: Any, frequency_hz: np.ndarray | None, name: str) -> tuple[np.ndarray, np.ndarray]:
    """(frequency, complex values) of a curve given as values, (f, values) or an FRF."""
    if hasattr(spec, "frequency_hz") and hasattr(spec, "receptance"):
        f, h = spec.frequency_hz, spec.receptance
    elif isinstance(spec, tuple) and len(spec) == 2:
        f, h = spec
    else:
        f, h = frequency_hz, spec
    if f is None:
        raise InputError("no frequency axis given for this curve", field=name)
    f = np.asarray(f, dtype=float)
    h = np.asarray(h, dtype=complex)
    if f.ndim != 1 or h.shape != f.shape:
        raise InputError(
            f"values of shape {h.shape} do not match the frequency axis of shape {f.shape}",
            field=name,
        )
    return f, h


# ------------------------------------------------------------------ FRF comparison


def plot_frf_comparison(
    path: str | os.PathLike[str],
    frequency_hz: ArrayLike | None,
    measured: Any = None,
    initial: Any = None,
    updated: Any = None,
    *,
    title: str = "Receptance",
    labels: Mapping[str, str] | None = None,
    phase: bool = True,
) -> Path:
    """Measured, initial-model and updated-model receptance on one plot (paper Fig. 7).

    Parameters
    ----------
    path : str or path-like
        Output file, ``.png``, ``.svg`` or ``.pdf``; replaced atomically.
    frequency_hz : array_like or None
        Frequency axis (Hz) of the curves given as plain arrays.
    measured, initial, updated : optional
        Each curve is a complex array on ``frequency_hz``, a ``(frequency_hz, values)``
        tuple, or an object with ``frequency_hz`` and ``receptance`` attributes (an
        :class:`~eigenupdate.measure.frf.FRF`), so the measured data can have its own
        axis. Values are receptance in m/N; NaN points (0 Hz) are skipped.
    title : str
        Figure title, e.g. ``"response at coordinate 1, force at 11"``.
    labels : dict, optional
        Legend text for ``"measured"``, ``"initial"`` and/or ``"updated"``.
    phase : bool
        Add a phase panel (degrees) under the magnitude.

    Returns
    -------
    Path
        ``path``.

    Notes
    -----
    The magnitude axis is logarithmic. Its top is 3 x the largest ``|H|`` above 5 % of
    the band, so the resonances fill the plot; a free structure's rigid-body rise
    towards 0 Hz runs off the top instead of squeezing them.

    Examples
    --------
    >>> import numpy as np, tempfile, os
    >>> f = np.linspace(1.0, 200.0, 400)
    >>> h = 1.0 / ((2 * np.pi * 100.0) ** 2 * (1 + 0.02j) - (2 * np.pi * f) ** 2)
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     out = plot_frf_comparison(os.path.join(tmp, "frf.png"), f, measured=h,
    ...                               updated=1.01 * h, title="SDOF")
    ...     print(out.name, out.read_bytes()[:4])
    frf.png b'\\x89PNG'
    """
    _format(path)  # fail on a bad extension before any work
    freq_axis = None if frequency_hz is None else np.asarray(frequency_hz, dtype=float)
    names = {"measured": "measured", "initial": "initial model", "updated": "updated model"}
    if labels:
        unknown = set(labels) - set(names)
        if unknown:
            raise InputError(f"unknown curve name(s) {sorted(unknown)}", field="labels")
        names.update(labels)
    curves = {
        key: _curve(spec, freq_axis, key)
        for key, spec in (("measured", measured), ("initial", initial), ("updated", updated))
        if spec is not None
    }
    if not curves:
        raise InputError("nothing to plot: give measured, initial and/or updated", field="plot")

    fig = new_figure(8.0, 6.0 if phase else 4.5)
    if phase:
        ax_mag, ax_ph = fig.subplots(2, 1, sharex=True, height_ratios=[2.4, 1.0])
    else:
        ax_mag, ax_ph = fig.subplots(1, 1), None
    tops, bottoms = [], []
    f_max = max(float(np.nanmax(f)) for f, _ in curves.values())
    for key, (f, h) in curves.items():
        mag = np.abs(h)
        ok = np.isfinite(mag) & (mag > 0)
        style = _STYLE[key]
        ax_mag.semilogy(f[ok], mag[ok], label=names[key], **style)
        band = ok & (f >= _PEAK_BAND_FRACTION * f_max)
        if band.any():
            tops.append(mag[band].max())
            bottoms.append(mag[band].min())
        if ax_ph is not None:
            ax_ph.plot(*_wrapped_phase(f[ok], h[ok]), **style)
    if tops:
        top = 3.0 * max(tops)
        ax_mag.set_ylim(max(min(bottoms) / 2.0, top * 1e-6), top)
    ax_mag.set_xlim(0.0, f_max)
    ax_mag.set_ylabel("receptance |H| (m/N)")
    ax_mag.set_title(fit_title(title, fig, ax_mag.title.get_fontsize()))
    ax_mag.grid(True, which="major", alpha=0.4)
    ax_mag.grid(True, which="minor", alpha=0.15)
    ax_mag.legend(loc="best", fontsize="small")
    if ax_ph is not None:
        ax_ph.set_ylim(-190.0, 190.0)
        ax_ph.set_yticks([-180, -90, 0, 90, 180])
        ax_ph.set_ylabel("phase (deg)")
        ax_ph.grid(True, alpha=0.4)
        ax_ph.set_xlabel("frequency (Hz)")
    else:
        ax_mag.set_xlabel("frequency (Hz)")
    return _save(fig, path)


def _wrapped_phase(f: np.ndarray, h: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Phase in (-180, 180] deg with a NaN gap at each wrap, so no vertical line is drawn
    across the panel where the phase passes +-180 deg."""
    ph = np.angle(h, deg=True)
    jumps = np.flatnonzero(np.abs(np.diff(ph)) > 180.0) + 1
    return np.insert(f, jumps, np.nan), np.insert(ph, jumps, np.nan)


# ------------------------------------------------------------------------ mass sweep


def plot_mass_sweep(path: str | os.PathLike[str], sweep: MassSweep, *,
                    title: str | None = None) -> Path:
    """Natural frequency of each elastic mode against added mass (paper Fig. 4), written
    to ``path`` (``.png``, ``.svg`` or ``.pdf``, replaced atomically), which is returned.

    ``sweep`` comes from :func:`eigenupdate.solve.sweep.mass_sweep`; ``title`` is written
    before the default title, which names what is added where.

    Notes
    -----
    As in the paper the added mass is shown as a percentage of "the mass at the
    perturbed coordinate", taken here as the diagonal term ``M[c, c]`` of the mass
    matrix of the configuration. For a lumped model that is the lumped mass; for a
    beam it is the consistent-mass diagonal term of the node (156/420 of each adjacent
    element's mass, plus point masses), not a lumped share of the beam. A massless
    coordinate has no such reference: the axis is then in kg and labelled so (this
    needs a large model on the sparse eigen-solver; the dense solver used for models
    up to 400 coordinates rejects a singular mass matrix).

    The left panel shows the frequencies (Hz), one line per mode; the right panel the
    eigenvalues normalised by their value without added mass, ``lambda / lambda_0``,
    which shows how far from linear in the added mass each mode is.

    Examples
    --------
    The paper's beam with up to 0.4 kg at coordinate 1 (its Table 7 lists 183.3 and
    514.1 Hz with 0.2 kg there):

    >>> import tempfile, os
    >>> from eigenupdate.model.beam import beam_model
    >>> from eigenupdate.solve.sweep import mass_sweep
    >>> beam = beam_model([0, 0.09, 0.19, 0.29, 0.39, 0.49, 0.59, 0.69, 0.80], 4557.0, 3.4)
    >>> sweep = mass_sweep(beam, 1, 0.4, 2)
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     out = plot_mass_sweep(os.path.join(tmp, "sweep.svg"), sweep)
    >>> print(f"M[1,1] = {sweep.reference_mass:.4f} kg; 0.2 kg = {sweep.percent[20]:.0f} %")
    M[1,1] = 0.1137 kg; 0.2 kg = 176 %
    >>> print(sweep.frequencies_hz[[0, 20]].round(1))
    [[203.7 561.8]
     [183.2 513.9]]
    """
    _format(path)
    coordinate = sweep.coordinate.number
    rotational = sweep.coordinate.rotation
    what = "added rotary inertia" if rotational else "added mass"
    unit = "kg m$^2$" if rotational else "kg"
    if sweep.percent is not None:
        x = sweep.percent
        xlabel = (f"{what} (% of M[{coordinate},{coordinate}] = "
                  f"{sweep.reference_mass:.4g} {unit})")
    else:
        x = sweep.added_mass
        xlabel = f"{what} ({unit}; coordinate {coordinate} has no mass of its own)"

    fig = new_figure(10.0, 4.2)
    ax_f, ax_r = fig.subplots(1, 2)
    for r in range(sweep.frequencies_hz.shape[1]):
        label = f"mode {r + 1} ({sweep.frequencies_hz[0, r]:.1f} Hz)"
        (line,) = ax_f.plot(x, sweep.frequencies_hz[:, r], marker="o", ms=2.5, label=label)
        ax_r.plot(x, sweep.eigenvalue_ratio[:, r], color=line.get_color(), label=label)
    ax_f.set_xlabel(xlabel)
    ax_f.set_ylabel("natural frequency (Hz)")
    ax_f.set_title("natural frequencies")
    ax_r.set_xlabel(xlabel)
    ax_r.set_ylabel(r"$\lambda / \lambda_0$ (eigenvalue / without added mass)")
    ax_r.set_title("normalised eigenvalues")
    ref = sweep.reference_mass
    for ax in (ax_f, ax_r):
        ax.grid(True, alpha=0.4)
        ax.set_xlim(x[0], x[-1])
        if sweep.percent is not None:  # the same axis in kg on top
            top = ax.secondary_xaxis("top", functions=(lambda p: p * ref / 100.0,
                                                       lambda m: m * 100.0 / ref))
            top.set_xlabel(f"{what} ({unit})")
    ax_f.legend(loc="best", fontsize="small")
    ax_r.legend(loc="best", fontsize="small")
    config = f" ({sweep.configuration})" if sweep.configuration is not None else ""
    heading = f"Effect of {what} at {sweep.coordinate.label}{config}"
    text = f"{title}: {heading}" if title else heading
    fig.suptitle(fit_title(text, fig, 12.0))  # figure.titlesize "large"
    _save(fig, path)
    return sweep


# ------------------------------------------------------------------ extraction fits


def _fit_curve(fit: Any, f: np.ndarray) -> np.ndarray:
    """One fitted mode alone at frequencies f (Hz)."""
    return mode_receptance(fit, (2 * np.pi * f) ** 2)


def _residual(fit: Any, f: np.ndarray) -> np.ndarray | None:
    res = getattr(fit, "residual", None)
    if res is None:
        return None
    if callable(res):
        return np.asarray(res(f), dtype=complex)
    return np.broadcast_to(np.asarray(res, dtype=complex), f.shape)


def plot_extraction_fit(
    path: str | os.PathLike[str],
    frequency_hz: ArrayLike,
    receptance: ArrayLike,
    fits: Sequence[Any],
    *,
    title: str = "Modal extraction",
    mode_numbers: Sequence[int] | None = None,
    estimate_residual: bool = True,
    n_curve: int = 400,
) -> Path:
    """Measured receptance against each fitted single-mode curve, |H| and Nyquist plane.

    Parameters
    ----------
    path : str or path-like
        Output ``.png``, ``.svg`` or ``.pdf``; replaced atomically.
    frequency_hz, receptance : array_like
        Measured FRF: frequency (Hz) and complex receptance (m/N).
    fits : sequence
        One object per mode with ``frequency_hz``, ``loss_factor``, ``modal_constant``
        (complex, m/N (rad/s)^2) and ``band_hz`` = (low, high) attributes, e.g.
        :class:`eigenupdate.measure.modal_fit.ModalFit`. An optional ``residual`` attribute (a
        complex constant, or a function of frequency in Hz) is added to the curve.
    title : str
        Figure title.
    mode_numbers : sequence of int, optional
        Elastic mode number of each fit, for the panel titles (default 1, 2, ...; give
        them when a mode this FRF does not show is left out).
    estimate_residual : bool
        For a fit without ``residual``: add the constant that best matches the data in
        the band (mean of measured minus fitted mode), labelled as a display estimate.
        The other modes shift the measured circle; without the offset the fitted circle
        would be drawn away from the data. False draws the bare mode.
    n_curve : int
        Points of each fitted curve across its band.

    Returns
    -------
    Path
        ``path``.

    Notes
    -----
    One row per mode: left, ``|H|`` in the fitted band (measured points, fitted curve,
    a dotted line at the fitted natural frequency); right, the Nyquist plot (Re vs Im,
    equal scales) with the fitted natural frequency marked.

    Examples
    --------
    >>> import numpy as np, tempfile, os
    >>> from types import SimpleNamespace
    >>> f = np.arange(80.0, 120.0, 0.25)
    >>> h = 2.0 / ((2 * np.pi * 100.0) ** 2 * (1 + 0.01j) - (2 * np.pi * f) ** 2)
    >>> fit = SimpleNamespace(frequency_hz=100.0, loss_factor=0.01, modal_constant=2.0,
    ...                       band_hz=(90.0, 110.0))
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     out = plot_extraction_fit(os.path.join(tmp, "fit.png"), f, h, [fit])
    ...     print(out.stat().st_size > 10_000)
    True
    """
    _format(path)
    freq = np.asarray(frequency_hz, dtype=float)
    data = np.asarray(receptance, dtype=complex)
    if freq.ndim != 1 or data.shape != freq.shape:
        raise InputError(
            f"receptance of shape {data.shape} does not match frequency axis {freq.shape}",
            field="receptance",
        )
    fits = list(fits)
    if not fits:
        raise InputError("no fitted modes to plot", field="fits")
    numbers = list(range(1, len(fits) + 1) if mode_numbers is None else mode_numbers)
    if len(numbers) != len(fits):
        raise InputError(f"{len(numbers)} mode numbers for {len(fits)} fits",
                         field="mode_numbers")
    fig = new_figure(10.0, 3.3 * len(fits) + 0.6)
    axes = np.atleast_2d(fig.subplots(len(fits), 2, width_ratios=[1.6, 1.0], squeeze=False))
    for r, (fit, (ax_m, ax_n)) in enumerate(zip(fits, axes, strict=True)):
        lo, hi = (float(v) for v in fit.band_hz)
        inside = (freq >= lo) & (freq <= hi) & np.isfinite(data)
        f_d, h_d = freq[inside], data[inside]
        f_c = np.linspace(lo, hi, int(n_curve))
        if float(fit.frequency_hz) not in f_c and lo < float(fit.frequency_hz) < hi:
            f_c = np.sort(np.append(f_c, float(fit.frequency_hz)))  # the exact peak
        curve = _fit_curve(fit, f_c)
        residual = _residual(fit, f_c)
        fit_label = "fitted mode"
        if residual is not None:
            curve = curve + residual
            fit_label = "fitted mode + residual"
        elif estimate_residual and f_d.size:
            offset = np.mean(h_d - _fit_curve(fit, f_d))
            curve = curve + offset
            fit_label = "fitted mode + constant (display estimate)"

        ax_m.semilogy(f_d, np.abs(h_d), "o", ms=3, color="0.35", label="measured")
        ax_m.semilogy(f_c, np.abs(curve), "-", color="tab:red", lw=1.4, label=fit_label)
        ax_m.axvline(float(fit.frequency_hz), color="tab:red", ls=":", lw=1.0)
        ax_m.set_xlim(lo, hi)
        ax_m.set_xlabel("frequency (Hz)")
        ax_m.set_ylabel("|H| (m/N)")
        A = complex(fit.modal_constant)
        ax_m.set_title(
            f"mode {numbers[r]}: $f_r$ = {float(fit.frequency_hz):.2f} Hz, "
            f"$\\eta$ = {float(fit.loss_factor):.4f}, A = {A.real:.4g}{A.imag:+.3g}j "
            r"m/N (rad/s)$^2$",
            fontsize="medium",
        )
        ax_m.grid(True, which="both", alpha=0.3)
        ax_m.legend(loc="best", fontsize="small")
        if f_d.size == 0:
            ax_m.text(0.5, 0.5, "no measured points in the band", transform=ax_m.transAxes,
                      ha="center", va="center", color="tab:red")

        ax_n.plot(h_d.real, h_d.imag, "o", ms=3, color="0.35")
        ax_n.plot(curve.real, curve.imag, "-", color="tab:red", lw=1.4)
        k = int(np.argmin(np.abs(f_c - float(fit.frequency_hz))))
        ax_n.plot(curve.real[k], curve.imag[k], "x", color="tab:red", ms=8, mew=2,
                  label=f"{f_c[k]:.2f} Hz")
        ax_n.set_aspect("equal", adjustable="datalim")
        ax_n.set_xlabel("Re H (m/N)")
        ax_n.set_ylabel("Im H (m/N)")
        ax_n.set_title("Nyquist plot", fontsize="medium")
        ax_n.ticklabel_format(style="sci", scilimits=(-3, 3))
        ax_n.grid(True, alpha=0.3)
        ax_n.legend(loc="best", fontsize="small")
    fig.suptitle(fit_title(title, fig, 12.0))  # rcParams' figure.titlesize: "large"
    return _save(fig, path)
