"""The report's own figures: singular values of the plan, parameter changes with their
posterior std, the iteration history and measured vs model frequencies.

Each function returns a :class:`matplotlib.figure.Figure` on a non-interactive Agg
canvas (no pyplot state). The paper's figures (Fig. 4, Fig. 7, extraction fits) come
from :mod:`eigenupdate.plot.plots`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
from matplotlib.figure import Figure

from eigenupdate.plot.plots import new_figure


def _figure(width: float, height: float) -> Figure:
    return new_figure(width, height)  # the pads that keep browser-set text inside


def singular_values_figure(singular_values: Sequence[float]) -> Figure:
    """Singular values of the normalised J, descending, on a log axis.

    >>> fig = singular_values_figure([3.0, 1.0, 1e-3])
    >>> fig.axes[0].get_yscale(), len(fig.axes[0].lines[0].get_xdata())
    ('log', 3)
    """
    s = np.asarray(singular_values, dtype=float)
    fig = _figure(6.5, 3.2)
    ax = fig.subplots()
    k = np.arange(1, s.size + 1)
    shown = np.where(s > 0, s, np.nan)  # a zero singular value has no place on a log axis
    ax.semilogy(k, shown, "o-", color="tab:blue", ms=4)
    ax.set_xlabel("index")
    ax.set_ylabel("singular value of J (normalised)")
    ax.set_xticks(k if s.size <= 30 else k[:: max(1, s.size // 15)])
    ax.grid(True, which="both", alpha=0.3)
    return fig


def parameter_change_figure(
    names: Sequence[str],
    initial: Mapping[str, float],
    updated: Mapping[str, float],
    std: Mapping[str, float | None],
) -> Figure:
    """Change of each updated parameter in % of its initial value, with +-1 posterior std.

    A parameter whose initial value is 0 (e.g. an unknown point mass) has no percentage;
    it is left out of the chart (the table gives its value).

    >>> fig = parameter_change_figure(["k", "m"], {"k": 100.0, "m": 2.0},
    ...                               {"k": 110.0, "m": 2.0}, {"k": 5.0, "m": None})
    >>> [float(round(p.get_height(), 6)) for p in fig.axes[0].patches]
    [10.0, 0.0]
    """
    shown = [n for n in names if initial[n] != 0]
    pct = np.array([100.0 * (updated[n] - initial[n]) / initial[n] for n in shown])
    err = np.array([np.nan if std.get(n) is None else 100.0 * std[n] / initial[n]
                    for n in shown])
    fig = _figure(max(6.5, 0.35 * len(shown) + 1.5), 3.4)
    ax = fig.subplots()
    x = np.arange(len(shown))
    ax.bar(x, pct, color=np.where(pct >= 0, "tab:red", "tab:blue"), alpha=0.8)
    ax.errorbar(x, pct, yerr=np.nan_to_num(err), fmt="none", ecolor="black", capsize=3,
                lw=1.0, label="posterior std")
    ax.axhline(0.0, color="black", lw=0.8)
    ax.set_xticks(x, shown, rotation=90 if len(shown) > 10 else 0)
    ax.set_ylabel("change from initial (%)")
    ax.grid(True, axis="y", alpha=0.3)
    ax.legend(loc="best", fontsize="small")
    return fig


def history_figure(
    objective: Sequence[float | None],
    history: Sequence[Mapping[str, float]],
    names: Sequence[str],
) -> Figure:
    """Objective (log) and each updated parameter / its initial value against iteration.

    >>> fig = history_figure([4.0, 1.0, 0.5], [{"k": 1.0}, {"k": 2.0}, {"k": 2.5}], ["k"])
    >>> [ax.get_ylabel() for ax in fig.axes]
    ['objective', 'parameter / initial value']
    """
    it = np.arange(len(history))
    fig = _figure(9.0, 3.4)
    ax_o, ax_p = fig.subplots(1, 2)
    obj = np.array([np.nan if v is None else v for v in objective], dtype=float)
    if obj.size and np.any(obj > 0):
        ax_o.semilogy(np.arange(obj.size), np.where(obj > 0, obj, np.nan), "o-", ms=4)
    else:
        ax_o.plot(np.arange(obj.size), obj, "o-", ms=4)
    ax_o.set_xlabel("iteration")
    ax_o.set_ylabel("objective")
    # panel titles also give the top tick label of the log axis room above it
    ax_o.set_title("objective (log scale)", fontsize="medium")
    ax_p.set_title("updated parameters", fontsize="medium")
    ax_o.grid(True, which="both", alpha=0.3)
    for n in names:
        v0 = history[0][n]
        if v0 == 0:
            continue  # no ratio for a parameter that starts at 0
        ax_p.plot(it, [h[n] / v0 for h in history], "o-", ms=3, lw=1.0,
                  label=n if len(names) <= 12 else None)
    ax_p.set_xlabel("iteration")
    ax_p.set_ylabel("parameter / initial value")
    ax_p.grid(True, alpha=0.3)
    if len(names) <= 12:
        ax_p.legend(loc="best", fontsize="x-small", ncols=2)
    for ax in (ax_o, ax_p):
        ax.set_xticks(it if it.size <= 25 else it[:: max(1, it.size // 12)])
    return fig


def frequency_error_figure(
    labels: Sequence[str],
    measured_hz: Sequence[float],
    initial_hz: Sequence[float],
    updated_hz: Sequence[float] | None = None,
) -> Figure:
    """Error of the initial (and, in a second panel with its own scale, the updated) model
    frequencies against the measured ones in %, one bar per (configuration, mode).

    >>> fig = frequency_error_figure(["base 1"], [100.0], [102.0], [100.5])
    >>> [[float(round(p.get_height(), 6)) for p in ax.patches] for ax in fig.axes]
    [[2.0], [0.5]]
    """
    m = np.asarray(measured_hz, dtype=float)
    curves = {"initial model": np.asarray(initial_hz, dtype=float)}
    if updated_hz is not None:
        curves["updated model"] = np.asarray(updated_hz, dtype=float)
    colours = {"initial model": "tab:blue", "updated model": "tab:red"}
    fig = _figure(max(6.5, 0.25 * len(labels) + 1.5), 2.0 + 1.6 * len(curves))
    axes = np.atleast_1d(fig.subplots(len(curves), 1, sharex=True, squeeze=False)[:, 0])
    x = np.arange(len(labels))
    for ax, (name, f) in zip(axes, curves.items(), strict=True):
        ax.bar(x, 100.0 * (f - m) / m, 0.7, color=colours[name], alpha=0.85)
        ax.axhline(0.0, color="black", lw=0.8)
        ax.set_ylabel(f"{name}\nerror (%)")
        ax.grid(True, axis="y", alpha=0.3)
    axes[-1].set_xticks(x, labels, rotation=90,
                        fontsize="x-small" if len(labels) > 12 else None)
    return fig
