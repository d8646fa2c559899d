"""Figures of a Monte Carlo check of a test plan: empirical against predicted std, and the
histogram of z-scores (estimate - truth) / reported std against N(0, 1)."""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from eigenupdate.plot.plots import _save, new_figure


def plot_std_comparison(path: str | os.PathLike[str], names: Sequence[str],
                        empirical: np.ndarray, predicted: np.ndarray, title: str = "") -> Path:
    """Empirical std of the error against the predicted (linearised) std, per parameter,
    both relative to the predicted one (1 = agreement)."""
    fig = new_figure(max(6.0, 0.35 * len(names) + 2), 3.6)
    ax = fig.add_subplot()
    x = np.arange(len(names))
    ratio = np.asarray(empirical) / np.asarray(predicted)
    ax.bar(x, ratio, color="tab:blue", label="empirical / predicted std")
    ax.axhline(1.0, color="k", lw=1)
    for band in (0.85, 1.15):
        ax.axhline(band, color="0.5", lw=0.8, ls="--")
    top = np.nanmax(ratio, initial=1.0)
    ax.set_ylim(0, max(1.4, 1.1 * top) if np.isfinite(top) else 1.4)
    ax.set_xticks(x, names, rotation=60, ha="right")
    ax.set_ylabel("empirical / predicted std")
    ax.legend(loc="upper right", title="dashed: +-15 %")
    ax.set_title(title)
    return _save(fig, path)


def plot_zscores(path: str | os.PathLike[str], z: np.ndarray, title: str = "") -> Path:
    """Histogram of all z-scores (every parameter, every converged trial) with N(0, 1)."""
    fig = new_figure(6.0, 3.6)
    ax = fig.add_subplot()
    z = np.asarray(z, dtype=float).ravel()
    z = z[np.isfinite(z)]
    ax.hist(z, bins=np.linspace(-5, 5, 41), density=True, color="tab:blue", alpha=0.7,
            label=f"{z.size} z-scores")
    t = np.linspace(-5, 5, 201)
    ax.plot(t, np.exp(-t**2 / 2) / np.sqrt(2 * np.pi), "k", label="N(0, 1)")
    ax.set_xlabel("(estimate - truth) / reported std")
    ax.set_ylabel("density")
    ax.legend(loc="upper right")
    ax.set_title(title)
    return _save(fig, path)
