"""A measured natural frequency of one configuration and elastic mode, and the
eigenvalues and weights the estimators take from it (lambda = omega^2, rad^2/s^2)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from eigenupdate.errors import InputError


@dataclass(frozen=True)
class Measurement:
    """Frequency (Hz) of elastic mode ``mode`` of ``configuration`` ("base" = bare
    structure), with its standard deviation (Hz) where the method needs weights."""

    configuration: str
    mode: int
    frequency_hz: float
    std_hz: float | None = None


def select(
    measurements: Mapping[tuple[str, int], Measurement],
    rows: Sequence[tuple[str, int]],
    need_std: bool,
    source: str | None = None,
) -> tuple[np.ndarray, np.ndarray | None]:
    """Frequencies (and std) in the order of ``rows``; InputError names what is missing."""
    f, s = [], []
    for cfg, mode in rows:
        m = measurements.get((cfg, mode))
        if m is None:
            raise InputError(f"no measurement for configuration {cfg!r} mode {mode}", source=source)
        if need_std and m.std_hz is None:
            raise InputError(
                f"std_hz is empty for configuration {cfg!r} mode {mode}; weighted methods need it",
                source=source,
            )
        f.append(m.frequency_hz)
        s.append(m.std_hz)
    return np.array(f), (np.array(s, dtype=float) if need_std else None)


def eigenvalue_std(frequency_hz: np.ndarray, std_hz: np.ndarray) -> np.ndarray:
    """Standard deviation of lambda = (2 pi f)^2 from that of f: 8 pi^2 f sigma_f.

    >>> round(float(eigenvalue_std(np.array([100.0]), np.array([0.5]))[0]), 3)
    3947.842
    """
    return 8 * np.pi**2 * frequency_hz * std_hz


def to_eigenvalue(frequency_hz):
    """lambda = omega^2 = (2 pi f)^2, (rad/s)^2."""
    return (2 * np.pi * np.asarray(frequency_hz, dtype=float)) ** 2
