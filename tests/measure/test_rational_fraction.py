"""Tests of the global rational-fraction fit (eigenupdate.measure.rational_fraction)."""

from __future__ import annotations

import doctest

import numpy as np
import pytest
from _synth import (
    BEAM_IN_RANGE,
    Mode,
    assert_honest_over_seeds,
    beam_frf,
    errors_and_stds,
    receptance,
)

import eigenupdate.measure.rational_fraction
from eigenupdate.errors import InputError
from eigenupdate.measure.dobson import dobson_fit_modes
from eigenupdate.measure.peaks import propose_bands
from eigenupdate.measure.rational_fraction import rational_fraction_fit

BEAM_BAND = (20.0, 1600.0)


def test_noise_free_modes_with_residuals_are_exact():
    modes = [Mode(100.0, 0.01, 1.0 + 0.2j), Mode(180.0, 0.03, 0.5 - 0.1j),
             Mode(250.0, 0.005, 2.0)]
    freq = np.arange(10.0, 400.0, 0.5)
    alpha = receptance(freq, modes, rigid_body=1.5, residual=2e-7 + 1e-8j)
    fits = rational_fraction_fit(freq, alpha, (10.0, 400.0), n_modes=3)
    assert [fit.method for fit in fits] == ["rfp"] * 3
    for fit, mode in zip(fits, modes, strict=True):
        assert fit.frequency_hz == pytest.approx(mode.frequency_hz, rel=1e-9)
        assert fit.loss_factor == pytest.approx(mode.loss_factor, rel=1e-9)
        assert abs(fit.modal_constant - mode.modal_constant) < 1e-9 * abs(mode.modal_constant)
        assert fit.band_hz == (10.0, 400.0)


def test_two_modes_five_percent_apart():
    modes = [Mode(100.0, 0.01, 1.0), Mode(105.0, 0.01, 1.0)]
    freq = np.arange(50.0, 200.0, 0.1)
    for seed in range(10):
        alpha = receptance(freq, modes, noise=0.01, residual=2e-6, seed=seed)
        fits = rational_fraction_fit(freq, alpha, (80.0, 130.0), n_modes=2)
        for fit, mode in zip(fits, modes, strict=True):
            assert fit.frequency_hz == pytest.approx(mode.frequency_hz, rel=5e-4)
            assert fit.loss_factor == pytest.approx(mode.loss_factor, rel=0.05)


def test_modes_closer_than_their_bandwidth():
    # 0.5 % apart with eta = 1 %: a single merged peak that Dobson cannot split.
    modes = [Mode(100.0, 0.01, 1.0), Mode(100.5, 0.01, 0.7)]
    freq = np.arange(80.0, 120.0, 0.05)
    fits = rational_fraction_fit(freq, receptance(freq, modes), (90.0, 110.0), n_modes=2)
    for fit, mode in zip(fits, modes, strict=True):
        assert fit.frequency_hz == pytest.approx(mode.frequency_hz, rel=1e-8)


@pytest.mark.parametrize("seed", range(3))
def test_beam_like_frf(seed):
    freq, alpha = beam_frf(seed)
    fits = rational_fraction_fit(freq, alpha, BEAM_BAND, n_modes=3)
    for fit, mode in zip(fits, BEAM_IN_RANGE, strict=True):
        assert fit.frequency_hz == pytest.approx(mode.frequency_hz, rel=5e-4)
        assert fit.loss_factor == pytest.approx(mode.loss_factor, rel=0.10)
        assert abs(fit.modal_constant - mode.modal_constant) < 0.1 * abs(mode.modal_constant)


def test_standard_deviations_are_honest():
    rows = np.array([
        errors_and_stds(rational_fraction_fit(*beam_frf(seed), BEAM_BAND, n_modes=3),
                        BEAM_IN_RANGE)
        for seed in range(100)
    ])
    assert_honest_over_seeds(rows)


@pytest.mark.parametrize("seed", range(5))
def test_agrees_with_dobson(seed):
    freq, alpha = beam_frf(seed)
    rfp = rational_fraction_fit(freq, alpha, BEAM_BAND, n_modes=3)
    dobson = dobson_fit_modes(freq, alpha, propose_bands(freq, alpha))
    for a, b in zip(rfp, dobson, strict=True):
        combined = np.hypot(a.frequency_std_hz, b.frequency_std_hz)
        assert abs(a.frequency_hz - b.frequency_hz) <= 3.0 * combined
        assert abs(a.frequency_hz - b.frequency_hz) <= 5e-4 * a.frequency_hz
        assert abs(a.loss_factor - b.loss_factor) <= 3.0 * np.hypot(a.loss_factor_std,
                                                                    b.loss_factor_std)


def test_residual_terms_matter():
    # Without the rigid-body term the low band edge is misfitted and mode 1 is biased.
    freq, alpha = beam_frf(0, noise=0.0)
    good = rational_fraction_fit(freq, alpha, BEAM_BAND, n_modes=3)
    bad = rational_fraction_fit(freq, alpha, BEAM_BAND, n_modes=3, lower_residual=False)
    assert good[0].frequency_hz == pytest.approx(200.0, rel=1e-5)
    assert abs(bad[0].frequency_hz / 200.0 - 1.0) > 10 * abs(good[0].frequency_hz / 200.0 - 1.0)


def test_docstring_examples():
    result = doctest.testmod(eigenupdate.measure.rational_fraction)
    assert result.attempted >= 4
    assert result.failed == 0


def test_bad_input_raises():
    freq, alpha = beam_frf(0)
    with pytest.raises(InputError, match="n_modes"):
        rational_fraction_fit(freq, alpha, BEAM_BAND, n_modes=0)
    with pytest.raises(InputError, match="too few"):
        rational_fraction_fit(freq, alpha, (100.0, 105.0), n_modes=3)
    with pytest.raises(InputError, match="too narrow"):
        rational_fraction_fit(freq, alpha, (100.0, 101.0), n_modes=1)
    with pytest.raises(InputError, match="strictly increasing"):
        rational_fraction_fit(freq[::-1], alpha, BEAM_BAND, n_modes=3)
    with pytest.raises(InputError, match="above 0 Hz"):
        rational_fraction_fit(freq, alpha, (0.0, 1600.0), n_modes=3)
