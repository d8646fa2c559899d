"""Synthetic measured FRFs: labels, noise level and reproducibility."""

from __future__ import annotations

import numpy as np
import pytest

from eigenupdate.errors import InputError
from eigenupdate.measure.frf import FRF
from eigenupdate.measure.synthetic import noise_reference, synthetic_frfs
from eigenupdate.model.beam import beam_model
from eigenupdate.model.configurations import mass_at
from eigenupdate.model.parameters import Parameter
from eigenupdate.model.spring_mass import Mass, Spring, spring_mass_model
from eigenupdate.solve.response import receptance

NODES = [0, 0.09, 0.19, 0.29, 0.39, 0.49, 0.59, 0.69, 0.80]
BEAM = beam_model(NODES, 4557.0, 3.4, point_masses=[(Parameter("m_L", 0.076), 11)])


def chain2():
    P = Parameter
    return spring_mass_model([Mass(P("m1", 1.5), 1), Mass(P("m2", 0.8), 2)],
                             [Spring(P("k1", 1000.0), (0, 1)), Spring(P("k2", 600.0), (1, 2))])


def test_noise_free_frfs_equal_model_and_carry_uff_labels():
    f = np.arange(2.0, 1600.0 + 1, 2.0)
    cfg = mass_at(7, 0.2)
    frfs = synthetic_frfs(BEAM, cfg, f, 11, [1, 15, 12], 0.01, noise=0.0)
    H = receptance(BEAM, f, 11, [1, 15, 12], configuration=cfg, loss_factor=0.01)
    assert all(isinstance(x, FRF) for x in frfs)
    assert [x.response for x in frfs] == [(1, 3), (8, 3), (6, 5)]
    assert all(x.reference == (6, 3) for x in frfs)
    assert frfs[1].source == "synthetic 0.2 kg at 7: 15/11"
    for j, x in enumerate(frfs):
        np.testing.assert_array_equal(x.frequency_hz, f)
        np.testing.assert_array_equal(x.receptance, H[:, j])


def test_spring_mass_labels_and_per_mode_loss_factors():
    f = np.linspace(0.5, 8.0, 50)
    frfs = synthetic_frfs(chain2(), None, f, 2, 1, [0.01, 0.05], noise=0.0)
    assert len(frfs) == 1
    assert frfs[0].response == (1, 1) and frfs[0].reference == (2, 1)
    np.testing.assert_array_equal(frfs[0].receptance,
                                  receptance(chain2(), f, 2, 1, loss_factor=[0.01, 0.05]))
    # the labels come from the model's coordinate table
    beam = synthetic_frfs(BEAM, None, f, 12, 15, 0.01, noise=0.0)
    assert beam[0].response == (8, 3) and beam[0].reference == (6, 5)


def test_noise_level_and_statistics():
    f = np.arange(1.0, 1600.0 + 0.25, 0.5)
    clean = synthetic_frfs(BEAM, None, f, 11, [1, 15], 0.01, noise=0.0)
    noisy = synthetic_frfs(BEAM, None, f, 11, [1, 15], 0.01, noise=0.02, seed=3)
    for c, n in zip(clean, noisy, strict=True):
        ref = noise_reference(f, c.receptance)
        # The reference is the first resonance peak, not the 1/w^2 rise near 0 Hz.
        above = f >= 80.0
        assert ref == pytest.approx(np.abs(c.receptance[above]).max(), rel=1e-12)
        assert ref < 0.05 * np.abs(c.receptance).max()
        e = n.receptance - c.receptance
        assert np.sqrt(np.mean(np.abs(e) ** 2)) == pytest.approx(0.02 * ref, rel=0.05)
        assert np.std(e.real) == pytest.approx(0.02 * ref / np.sqrt(2), rel=0.06)
        assert np.std(e.imag) == pytest.approx(0.02 * ref / np.sqrt(2), rel=0.06)
        assert abs(np.mean(e)) < 0.1 * 0.02 * ref
        assert abs(np.corrcoef(e.real, e.imag)[0, 1]) < 0.06


def test_seed_reproducibility():
    f = np.linspace(10.0, 800.0, 200)
    a = synthetic_frfs(BEAM, None, f, 11, [1, 15], 0.01, seed=7)
    b = synthetic_frfs(BEAM, None, f, 11, [1, 15], 0.01, seed=7)
    c = synthetic_frfs(BEAM, None, f, 11, [1, 15], 0.01, seed=8)
    for x, y, z in zip(a, b, c, strict=True):
        np.testing.assert_array_equal(x.receptance, y.receptance)
        assert not np.allclose(x.receptance, z.receptance)
    g = synthetic_frfs(BEAM, None, f, 11, 1, 0.01, seed=np.random.default_rng(7))
    np.testing.assert_array_equal(g[0].receptance, a[0].receptance)


def test_zero_hz_line_is_nan_for_a_free_beam():
    f = np.arange(0.0, 400.0 + 1, 2.0)
    frf = synthetic_frfs(BEAM, None, f, 11, 1, 0.01, noise=0.01, seed=0)[0]
    assert np.isnan(frf.receptance[0])
    assert np.all(np.isfinite(frf.receptance[1:]))


def test_noise_reference_ignores_low_band_and_nan():
    f = np.array([0.0, 1.0, 50.0, 100.0])
    assert noise_reference(f, [np.nan, 1e3, 2e-6, 5e-7]) == 2e-6


@pytest.mark.parametrize(
    "kwargs",
    [{"noise": -0.1}, {"noise": np.nan}, {"outputs": [0]}, {"outputs": [1, 99]}],
)
def test_bad_arguments(kwargs):
    args = {"outputs": [1], "noise": 0.01} | kwargs
    with pytest.raises(InputError):
        synthetic_frfs(BEAM, None, [10.0, 20.0], 11, args.pop("outputs"), 0.01, **args)


def test_relative_noise_is_a_fraction_of_each_frequency():
    """``noise_relative``: the recorded std is that fraction of each true frequency, and
    the noise divided by it is standard normal (Source: 400 draws, fixed seeds; the
    sample std of 400 standard normals has sd 0.035, so 0.15 is 4.2 sd (3e-5); the mean
    has sd 0.05, so 0.3 is 6 sd)."""
    from models import fig2

    from eigenupdate.measure.synthetic import simulate_measurements
    from eigenupdate.model.configurations import Configuration

    model, configs = fig2(), [Configuration("base")]
    exact = simulate_measurements(model, configs, [1, 2, 3, 4])
    z = []
    for seed in range(100):
        rows = simulate_measurements(model, configs, [1, 2, 3, 4], seed=seed,
                                     noise_relative=1e-3)
        for r, e in zip(rows, exact, strict=True):
            assert r.std_hz == pytest.approx(1e-3 * e.frequency_hz, rel=1e-12)
            z.append((r.frequency_hz - e.frequency_hz) / r.std_hz)
    assert abs(np.std(z) - 1) <= 0.15 and abs(np.mean(z)) <= 0.3
