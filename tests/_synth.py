"""Synthetic receptance FRFs shared by the tests (imported as ``_synth``): hysteretic modes,
a viscous SDOF, the beam-like test case."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Mode:
    """One hysteretically damped mode: ``A / (w_r**2 (1 + i eta) - w**2)``."""

    frequency_hz: float
    loss_factor: float
    modal_constant: complex = 1.0


def receptance(
    frequency_hz: np.ndarray,
    modes: Sequence[Mode],
    *,
    rigid_body: float = 0.0,
    residual: complex = 0.0,
    noise: float = 0.0,
    seed: int = 0,
) -> np.ndarray:
    """Sum of modes, a rigid-body term ``-rigid_body / w**2`` and a constant residual.

    ``noise`` is the standard deviation (``sqrt(E|n|**2)``) of the added circular complex
    Gaussian noise as a fraction of the largest resonance peak ``|alpha|``.  At 0 Hz
    the rigid-body term is left out (it is infinite there).
    """
    freq = np.asarray(frequency_hz, dtype=float)
    x = (2.0 * np.pi * freq) ** 2
    alpha = _modal_sum(x, modes) + residual
    if rigid_body:
        alpha = alpha - rigid_body * np.divide(1.0, x, out=np.zeros_like(x), where=x > 0)
    if noise:
        x_res = np.array([(2.0 * np.pi * m.frequency_hz) ** 2 for m in modes])
        peak = np.max(np.abs(_modal_sum(x_res, modes) + residual - rigid_body / x_res))
        rng = np.random.default_rng(seed)
        scale = noise * peak / np.sqrt(2.0)
        alpha = alpha + scale * (rng.standard_normal(freq.size)
                                 + 1j * rng.standard_normal(freq.size))
    return alpha


def viscous_sdof(frequency_hz: np.ndarray, m: float, k: float, c: float) -> np.ndarray:
    """Receptance of m x'' + c x' + k x = F (viscous damping), m/N."""
    w = 2.0 * np.pi * np.asarray(frequency_hz, dtype=float)
    return 1.0 / (k - m * w**2 + 1j * c * w)


def _modal_sum(x: np.ndarray, modes: Sequence[Mode]) -> np.ndarray:
    out = np.zeros(x.shape, dtype=complex)
    for m in modes:
        wr2 = (2.0 * np.pi * m.frequency_hz) ** 2
        out += m.modal_constant / (wr2 * (1.0 + 1j * m.loss_factor) - x)
    return out


#: Free-free beam driven at its end (unit mass: modal constants 4, rigid-body term 4),
#: three modes in 0..1600 Hz and a fourth just above the measured range.
BEAM_MODES = (
    Mode(200.0, 0.02, 4.0),
    Mode(550.0, 0.008, 4.0),
    Mode(1075.0, 0.002, 4.0),
    Mode(1780.0, 0.005, 4.0),
)
BEAM_RIGID_BODY = 4.0
BEAM_IN_RANGE = BEAM_MODES[:3]


def beam_frf(seed: int = 0, noise: float = 0.01) -> tuple[np.ndarray, np.ndarray]:
    """Beam-like receptance at 0.5 Hz resolution, 0..1600 Hz, 1 % noise by default."""
    freq = np.arange(0.0, 1600.0 + 0.25, 0.5)
    return freq, receptance(freq, BEAM_MODES, rigid_body=BEAM_RIGID_BODY, noise=noise,
                            seed=seed)


def errors_and_stds(fits: Sequence, modes: Sequence[Mode]) -> np.ndarray:
    """Rows ``(f error, f std, eta error, eta std)`` (Hz, Hz, -, -), one per mode."""
    return np.array([
        (fit.frequency_hz - mode.frequency_hz, fit.frequency_std_hz,
         fit.loss_factor - mode.loss_factor, fit.loss_factor_std)
        for fit, mode in zip(fits, modes, strict=True)
    ])


def assert_honest(errors: np.ndarray, stds: np.ndarray) -> None:
    """Per column (mode): >= 95 % of errors within 3 std, RMS error / mean std in [0.5, 2]."""
    coverage = np.mean(np.abs(errors) <= 3.0 * stds, axis=0)
    ratio = np.sqrt(np.mean(errors**2, axis=0)) / np.mean(stds, axis=0)
    assert np.all(coverage >= 0.95), coverage
    assert np.all((ratio > 0.5) & (ratio < 2.0)), ratio


def assert_honest_over_seeds(rows: np.ndarray) -> None:
    """``rows[seed, mode]`` from :func:`errors_and_stds`: check frequency and loss factor."""
    assert_honest(rows[..., 0], rows[..., 1])
    assert_honest(rows[..., 2], rows[..., 3])
