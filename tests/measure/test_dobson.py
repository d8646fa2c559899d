"""Tests of Dobson's inverse-receptance line fit (eigenupdate.measure.dobson)."""

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

import eigenupdate.measure.dobson
from eigenupdate.errors import InputError
from eigenupdate.measure.dobson import ModalFit, dobson_fit, dobson_fit_modes
from eigenupdate.measure.peaks import propose_bands

BEAM_BANDS = [(185.0, 215.0), (535.0, 565.0), (1065.0, 1085.0)]


def _single(residual: complex = 0.0, noise: float = 0.0, seed: int = 0):
    mode = Mode(100.0, 0.01, 2.0 - 0.4j)
    freq = np.arange(50.0, 150.0, 0.25)
    return mode, freq, receptance(freq, [mode], residual=residual, noise=noise, seed=seed)


@pytest.mark.parametrize("residual", [0.0, 3e-5 - 1e-5j])
def test_noise_free_single_mode_is_exact(residual):
    # residual 3e-5 m/N is 30 % of the peak |alpha| = 2 / (0.01 * w_r**2) ~ 5e-5 ... 1e-4
    mode, freq, alpha = _single(residual=residual)
    fit = dobson_fit(freq, alpha, (90.0, 110.0))
    assert isinstance(fit, ModalFit)
    assert fit.method == "dobson"
    assert fit.band_hz == (90.0, 110.0)
    assert fit.frequency_hz == pytest.approx(mode.frequency_hz, rel=1e-9)
    assert fit.loss_factor == pytest.approx(mode.loss_factor, rel=1e-9)
    assert abs(fit.modal_constant - mode.modal_constant) < 1e-9 * abs(mode.modal_constant)
    assert fit.frequency_std_hz < 1e-9 * mode.frequency_hz


def test_constant_residual_does_not_bias_noisy_fit():
    # Same noise realisation with and without a large constant residual: the estimates
    # differ only through the selection of points, far below their standard deviation.
    _, freq, plain = _single(noise=0.01, seed=3)
    _, _, shifted = _single(noise=0.01, seed=3)
    shifted = shifted + (4e-5 + 2e-5j)
    a, b = (dobson_fit(freq, alpha, (90.0, 110.0)) for alpha in (plain, shifted))
    assert a.frequency_hz == pytest.approx(b.frequency_hz, rel=1e-12)
    assert a.loss_factor == pytest.approx(b.loss_factor, rel=1e-10)


def test_two_modes_five_percent_apart():
    modes = [Mode(100.0, 0.01, 1.0), Mode(105.0, 0.01, 1.0)]
    freq = np.arange(50.0, 200.0, 0.1)
    bands = [(97.0, 102.5), (102.5, 108.0)]
    # On exact data one band alone is visibly biased by the neighbour; the
    # subtract-and-refit iteration removes the bias completely.
    exact = receptance(freq, modes)
    alone = dobson_fit(freq, exact, bands[0])
    assert abs(alone.frequency_hz / 100.0 - 1.0) > 1e-5
    fits = dobson_fit_modes(freq, exact, bands)
    for fit, mode in zip(fits, modes, strict=True):
        assert fit.frequency_hz == pytest.approx(mode.frequency_hz, rel=1e-9)
        assert fit.loss_factor == pytest.approx(mode.loss_factor, rel=1e-8)
    for seed in range(10):
        noisy = receptance(freq, modes, noise=0.01, residual=2e-6, seed=seed)
        fits = dobson_fit_modes(freq, noisy, bands)
        for fit, mode in zip(fits, modes, strict=True):
            assert fit.frequency_hz == pytest.approx(mode.frequency_hz, rel=5e-4)


def test_close_modes_down_to_one_and_a_half_bandwidths():
    # Separation 1.5 % with eta = 1 %: 1.5 half-power bandwidths, the documented limit.
    modes = [Mode(100.0, 0.01, 1.0), Mode(101.5, 0.01, 1.0)]
    freq = np.arange(90.0, 115.0, 0.05)
    fits = dobson_fit_modes(freq, receptance(freq, modes), [(99.0, 100.75), (100.75, 103.0)])
    for fit, mode in zip(fits, modes, strict=True):
        assert fit.frequency_hz == pytest.approx(mode.frequency_hz, rel=1e-9)


@pytest.mark.parametrize("seed", range(5))
def test_beam_like_frf(seed):
    freq, alpha = beam_frf(seed)
    fits = dobson_fit_modes(freq, alpha, propose_bands(freq, alpha))
    assert len(fits) == len(BEAM_IN_RANGE)
    for fit, mode in zip(fits, BEAM_IN_RANGE, strict=True):
        assert fit.frequency_hz == pytest.approx(mode.frequency_hz, rel=5e-4)
        assert fit.loss_factor == pytest.approx(mode.loss_factor, rel=0.10)
        assert abs(fit.modal_constant - mode.modal_constant) < 0.1 * abs(mode.modal_constant)


def test_standard_deviations_are_honest():
    rows = np.array([errors_and_stds(dobson_fit_modes(*beam_frf(seed), BEAM_BANDS),
                                     BEAM_IN_RANGE)
                     for seed in range(100)])
    assert_honest_over_seeds(rows)


def test_undersampled_light_damping_is_still_honest():
    # Half-power bandwidth 0.3 Hz at 0.5 Hz resolution: about one point per bandwidth.
    mode = Mode(150.0, 0.002, 1.0)
    freq = np.arange(100.0, 200.0, 0.5)
    rows = np.array([
        errors_and_stds([dobson_fit(freq, receptance(freq, [mode], noise=0.01, seed=seed),
                                    (145.0, 155.0))], [mode])
        for seed in range(100)
    ])
    assert_honest_over_seeds(rows)
    assert np.max(np.abs(rows[..., 0])) < 1e-4 * mode.frequency_hz


def test_docstring_examples():
    result = doctest.testmod(eigenupdate.measure.dobson)
    assert result.attempted >= 4
    assert result.failed == 0


@pytest.mark.parametrize(
    ("band", "match"),
    [
        ((60.0, 80.0), "no resonance peak"),       # rising towards the mode: max at edge
        ((120.0, 140.0), "no resonance peak"),     # falling away from the mode
        ((100.0, 101.0), "too narrow"),            # 5 points
        ((160.0, 190.0), "too narrow"),            # outside the data
        ((110.0, 90.0), "low < high"),
        ((-5.0, 110.0), "above 0 Hz"),
    ],
)
def test_bad_bands_raise(band, match):
    freq = np.arange(0.0, 150.0, 0.25)
    alpha = receptance(freq, [Mode(100.0, 0.01, 2.0)])
    with pytest.raises(InputError, match=match) as info:
        dobson_fit(freq, alpha, band)
    assert info.value.field == "band_hz"


def test_band_without_peak_between_modes():
    freq = np.arange(50.0, 300.0, 0.25)
    alpha = receptance(freq, [Mode(100.0, 0.01, 1.0), Mode(250.0, 0.01, 1.0)], noise=0.001)
    with pytest.raises(InputError, match="no resonance peak"):
        dobson_fit(freq, alpha, (150.0, 200.0))


def test_bad_frequency_axis_and_lengths_raise():
    _, freq, alpha = _single()
    swapped = freq.copy()
    swapped[[10, 11]] = swapped[[11, 10]]
    with pytest.raises(InputError, match="strictly increasing") as info:
        dobson_fit(swapped, alpha, (90.0, 110.0))
    assert info.value.field == "frequency_hz"
    repeated = freq.copy()
    repeated[11] = repeated[10]
    with pytest.raises(InputError, match="strictly increasing"):
        dobson_fit_modes(repeated, alpha, [(90.0, 110.0)])
    with pytest.raises(InputError, match="receptance has"):
        dobson_fit(freq, alpha[:-1], (90.0, 110.0))
    bad = alpha.copy()
    bad[200] = np.nan  # 100 Hz, inside the band
    with pytest.raises(InputError, match="non-finite"):
        dobson_fit(freq, bad, (90.0, 110.0))
    with pytest.raises(InputError, match="min_fraction"):
        dobson_fit(freq, alpha, (90.0, 110.0), min_fraction=1.5)


def test_error_message_names_source():
    _, freq, alpha = _single()
    with pytest.raises(InputError, match=r"^frf\.uff: band_hz: band \(60, 80\) Hz has no"):
        dobson_fit(freq, alpha, (60.0, 80.0), source="frf.uff")
