"""Tests of the automatic peak picking (eigenupdate.measure.peaks)."""

from __future__ import annotations

import doctest

import numpy as np
import pytest
from _synth import BEAM_IN_RANGE, BEAM_RIGID_BODY, Mode, beam_frf, receptance

import eigenupdate.measure.peaks
from eigenupdate.errors import InputError
from eigenupdate.measure.peaks import estimate_noise_std, propose_bands


# Seed 40 has a noise spike with 6 dB prominence in the anti-resonance near 110 Hz.
@pytest.mark.parametrize("seed", [*range(20), 40])
def test_beam_bands_hold_one_mode_each(seed):
    freq, alpha = beam_frf(seed)
    bands = propose_bands(freq, alpha)
    assert len(bands) == len(BEAM_IN_RANGE)
    for (lo, hi), mode in zip(bands, BEAM_IN_RANGE, strict=True):
        assert lo < mode.frequency_hz < hi
    highs = [hi for _, hi in bands]
    lows = [lo for lo, _ in bands]
    assert all(h <= lo for h, lo in zip(highs[:-1], lows[1:], strict=True))


def test_beam_band_widths_follow_the_damping():
    freq, alpha = beam_frf(0, noise=0.0)
    bands = propose_bands(freq, alpha)
    for (lo, hi), mode in zip(bands, BEAM_IN_RANGE, strict=True):
        half_power = mode.loss_factor * mode.frequency_hz
        # 3 half-power bandwidths to each side, to within a bin or two.
        assert hi - lo == pytest.approx(6.0 * half_power, abs=2.0)
        assert (lo + hi) / 2 == pytest.approx(mode.frequency_hz, abs=1.0)


def test_rigid_body_rise_is_not_a_peak():
    # Only rigid-body modes, with a low DC bin below the 1/w**2 rise, plus noise.
    freq = np.arange(0.0, 500.0, 0.5)
    x = (2.0 * np.pi * freq) ** 2
    alpha = -BEAM_RIGID_BODY * np.divide(1.0, x, out=np.zeros_like(x), where=x > 0)
    assert propose_bands(freq, alpha) == []
    rng = np.random.default_rng(1)
    noisy = alpha + 1e-6 * (rng.standard_normal(freq.size) + 1j * rng.standard_normal(freq.size))
    assert propose_bands(freq, noisy) == []
    # Without skipping the lowest bins, the DC bin makes 0.5 Hz a local maximum.
    assert np.abs(alpha[1]) > np.abs(alpha[0]) and np.abs(alpha[1]) > np.abs(alpha[2])


def test_noise_only_has_no_peaks():
    freq = np.arange(0.0, 1000.0, 0.5)
    for seed in range(20):
        rng = np.random.default_rng(seed)
        noise = rng.standard_normal(freq.size) + 1j * rng.standard_normal(freq.size)
        assert propose_bands(freq, 1e-8 * noise) == []
        assert propose_bands(freq, 1e-6 + 1e-8 * noise) == []


def test_n_modes_takes_the_lowest_peaks():
    freq, alpha = beam_frf(0)
    all_bands = propose_bands(freq, alpha)
    assert propose_bands(freq, alpha, n_modes=2) == all_bands[:2]
    with pytest.raises(InputError, match="found 3 resonance peaks but n_modes=4"):
        propose_bands(freq, alpha, n_modes=4)
    with pytest.raises(InputError, match="n_modes"):
        propose_bands(freq, alpha, n_modes=0)


def test_exclude_below_hz():
    freq, alpha = beam_frf(0)
    assert propose_bands(freq, alpha, exclude_below_hz=300.0) == propose_bands(freq, alpha)[1:]


def test_close_modes_split_half_way():
    modes = [Mode(100.0, 0.01, 1.0), Mode(105.0, 0.01, 1.0)]
    freq = np.arange(50.0, 200.0, 0.1)
    alpha = receptance(freq, modes)
    (lo1, hi1), (lo2, hi2) = propose_bands(freq, alpha)
    # The second peak limits the first band even when only one mode is asked for.
    assert propose_bands(freq, alpha, n_modes=1) == [(lo1, hi1)]
    assert hi1 == pytest.approx(102.5, abs=0.11)
    assert lo2 == pytest.approx(102.5, abs=0.11)
    assert lo1 == pytest.approx(97.0, abs=0.3)    # 3 bandwidths of 1 Hz
    assert hi2 == pytest.approx(108.15, abs=0.3)


def test_minimum_points_each_side():
    # Bandwidth 0.2 Hz at 0.5 Hz resolution: 3 bandwidths is under one bin.
    freq = np.arange(50.0, 150.0, 0.5)
    (lo, hi), = propose_bands(freq, receptance(freq, [Mode(100.0, 0.002, 1.0)]))
    assert (lo, hi) == (97.5, 102.5)


def test_estimate_noise_std():
    freq = np.arange(0.0, 1600.0, 0.5)
    clean = receptance(freq, BEAM_IN_RANGE)
    rng = np.random.default_rng(7)
    noise = 1e-5 * (rng.standard_normal(freq.size) + 1j * rng.standard_normal(freq.size))
    # sqrt(E|n|^2) = 1e-5 * sqrt(2)
    assert estimate_noise_std(clean + noise) == pytest.approx(np.sqrt(2.0) * 1e-5, rel=0.1)


def test_bad_input_raises():
    freq, alpha = beam_frf(0)
    with pytest.raises(InputError, match="strictly increasing"):
        propose_bands(freq[::-1], alpha)
    with pytest.raises(InputError, match="receptance has"):
        propose_bands(freq, alpha[:10])
    bad = alpha.copy()
    bad[1000] = np.inf
    with pytest.raises(InputError, match="non-finite"):
        propose_bands(freq, bad)


def test_docstring_examples():
    result = doctest.testmod(eigenupdate.measure.peaks)
    assert result.attempted >= 4
    assert result.failed == 0
