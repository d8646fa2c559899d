"""Figures: files written atomically in the right format; the plotted numbers."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from _synth import Mode
from _synth import receptance as receptance_of_modes
from bounds import eigenvalue_floor

from eigenupdate.errors import InputError
from eigenupdate.measure.frf import FRF
from eigenupdate.model.beam import beam_model
from eigenupdate.model.configurations import mass_at
from eigenupdate.model.parameters import Parameter
from eigenupdate.model.spring_mass import Mass, Spring, spring_mass_model
from eigenupdate.plot.plots import plot_extraction_fit, plot_frf_comparison, plot_mass_sweep
from eigenupdate.solve.eigen import solve_elastic
from eigenupdate.solve.response import configuration_matrices, receptance
from eigenupdate.solve.sweep import MassSweep, mass_sweep

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
NODES = [0, 0.09, 0.19, 0.29, 0.39, 0.49, 0.59, 0.69, 0.80]
BEAM = beam_model(NODES, 4557.0, 3.4, point_masses=[(Parameter("m_L", 0.0), 11)])


def only_file(directory, name):
    """The figure exists, and no temporary file was left next to it."""
    assert sorted(p.name for p in directory.iterdir()) == [name]
    return (directory / name).read_bytes()


def sdof_frf(f, fr=100.0, eta=0.01, A=2.0):
    return receptance_of_modes(f, [Mode(fr, eta, A)])


# ------------------------------------------------------------------ FRF comparison


def test_frf_comparison_png_and_svg(tmp_path):
    f = np.arange(0.0, 1600.0 + 1, 8.0)
    initial = receptance(BEAM, f, 11, 1, loss_factor=0.01)  # NaN at 0 Hz is skipped
    updated = receptance(BEAM.with_values({"EI1": 4400.0}), f, 11, 1, loss_factor=0.01)
    measured = FRF(f[1:], updated[1:] * 1.01, (1, 3), (6, 3))  # its own axis
    (tmp_path / "fig7.png").write_bytes(b"old")  # replaced
    out = plot_frf_comparison(tmp_path / "fig7.png", f, measured=measured, initial=initial,
                              updated=updated, title="coordinate 1")
    assert out == tmp_path / "fig7.png"
    data = only_file(tmp_path, "fig7.png")
    assert data.startswith(PNG_MAGIC) and len(data) > 20_000
    svg = tmp_path / "fig7.svg"
    plot_frf_comparison(svg, None, measured=(f[1:], updated[1:]), phase=False,
                        labels={"measured": "test data"})
    text = svg.read_text()
    assert "<svg" in text and "test data" in text


@pytest.mark.parametrize(
    ("name", "kwargs"),
    [
        ("f.jpg", {"updated": "curve"}),
        ("f.png", {}),
        ("f.png", {"updated": "curve", "labels": {"model": "x"}}),
        ("f.png", {"updated": "short"}),
        ("missing/f.png", {"updated": "curve"}),
    ],
)
def test_frf_comparison_errors(tmp_path, name, kwargs):
    f = np.linspace(1.0, 200.0, 50)
    curves = {"curve": sdof_frf(f), "short": sdof_frf(f[:10])}
    kwargs = {k: curves.get(v, v) if isinstance(v, str) else v for k, v in kwargs.items()}
    with pytest.raises(InputError):
        plot_frf_comparison(tmp_path / name, f, **kwargs)
    assert list(tmp_path.iterdir()) == []


# ---------------------------------------------------------------------- mass sweep


def test_mass_sweep_sdof_closed_form():
    m, k = 2.0, 800.0
    model = spring_mass_model([Mass(Parameter("m", m), 1)], [Spring(Parameter("k", k), (0, 1))])
    sweep = mass_sweep(model, 1, 3.0, 1, n_points=7)
    dm = np.linspace(0.0, 3.0, 7)
    np.testing.assert_allclose(sweep.added_mass, dm)
    np.testing.assert_allclose(sweep.percent, 100 * dm / m)
    np.testing.assert_allclose(sweep.frequencies_hz[:, 0], np.sqrt(k / (m + dm)) / (2 * np.pi),
                               rtol=1e-12)
    np.testing.assert_allclose(sweep.eigenvalue_ratio[:, 0], m / (m + dm), rtol=1e-12)


def test_plot_mass_sweep_paper_beam(tmp_path):
    cfg = mass_at(15, 0.2)
    sweep = mass_sweep(BEAM, 1, 0.4, 3, configuration=cfg, n_points=5)
    plot_mass_sweep(tmp_path / "fig4.png", sweep)
    assert only_file(tmp_path, "fig4.png").startswith(PNG_MAGIC)
    K, M = configuration_matrices(BEAM, cfg)
    assert sweep.reference_mass == pytest.approx(3.4 * 0.09 * 156 / 420)  # consistent mass
    assert sweep.frequencies_hz.shape == (5, 3)
    # The middle point (0.2 kg at coordinate 1) against an independent eigen-solution.
    K2, M2 = configuration_matrices(BEAM.with_values({}), mass_at(1, 0.2))
    M2 = M2 + (M - BEAM.mass())  # plus the configuration's 0.2 kg at 15
    ref = solve_elastic(K2, M2, 3)
    # two solves, each within the eigenvalues' rounding floor (tests/bounds.py, up to
    # 1e-10 for this free beam); a frequency's relative error is half its eigenvalue's
    floor = eigenvalue_floor(K2, M2, ref.eigenvalues, ref.modes)
    rel = np.abs(sweep.frequencies_hz[2] - ref.frequencies_hz) / ref.frequencies_hz
    assert np.all(rel <= floor), (rel, floor)
    # Mass lowers every elastic frequency; a near-zero value would be a rigid-body mode
    # taken for elastic (eigen.rigid_mask threshold).
    assert np.all(np.diff(sweep.frequencies_hz, axis=0) < 0), sweep.frequencies_hz
    assert sweep.frequencies_hz.min() > 150.0


def test_plot_mass_sweep_rotation_and_errors(tmp_path):
    plot_mass_sweep(tmp_path / "rot.svg", mass_sweep(BEAM, 2, 1e-3, 2, n_points=3))
    text = (tmp_path / "rot.svg").read_text()
    assert "rotary inertia" in text and "coordinate 2 (node 1, RY)" in text
    for args in ((99, 0.1, 2), (1, 0.0, 2), (1, 0.1, 0), (1, 0.1, 99)):
        with pytest.raises(InputError):
            mass_sweep(BEAM, *args)
    with pytest.raises(InputError):
        plot_mass_sweep(tmp_path / "bad.txt", mass_sweep(BEAM, 1, 0.1, 2, n_points=3))
    assert not (tmp_path / "bad.txt").exists()


def test_mass_sweep_without_reference_mass_uses_kg():
    sweep = MassSweep(np.array([0.0, 1.0]), 0.0, np.array([[10.0], [9.0]]),
                      BEAM.coordinate_table[1])
    assert sweep.percent is None


# ------------------------------------------------------------------ extraction fits


def test_extraction_fit_plot(tmp_path):
    from eigenupdate.measure.dobson import dobson_fit

    f = np.arange(50.0, 400.0, 0.5)
    h = sdof_frf(f, 100.0, 0.02, 2.0) + sdof_frf(f, 300.0, 0.01, 5.0)
    fits = [
        # a real ModalFit, which has no residual: a display constant is estimated
        dobson_fit(f, h, (90.0, 110.0)),
        # a callable residual: the exact other mode, so the curve matches the data
        SimpleNamespace(frequency_hz=300.0, loss_factor=0.01, modal_constant=5.0 + 0j,
                        band_hz=(280.0, 320.0),
                        residual=lambda ff: sdof_frf(ff, 100.0, 0.02, 2.0)),
    ]
    plot_extraction_fit(tmp_path / "fits.png", f, h, fits, title="two modes")
    data = only_file(tmp_path, "fits.png")
    assert data.startswith(PNG_MAGIC) and len(data) > 20_000


def test_fitted_curve_formula_and_residuals():
    from eigenupdate.plot.plots import _fit_curve, _residual

    fit = SimpleNamespace(frequency_hz=100.0, loss_factor=0.02, modal_constant=2.0 - 1j)
    f = np.array([50.0, 100.0])
    wr2 = (2 * np.pi * 100.0) ** 2
    np.testing.assert_allclose(_fit_curve(fit, f),
                               (2.0 - 1j) / (wr2 - (2 * np.pi * f) ** 2 + 0.02j * wr2))
    assert _residual(fit, f) is None
    np.testing.assert_array_equal(_residual(SimpleNamespace(residual=1e-7j), f), [1e-7j] * 2)
    np.testing.assert_array_equal(_residual(SimpleNamespace(residual=lambda x: 2 * x), f),
                                  2 * f)


def test_extraction_fit_titles_name_the_modes(tmp_path):
    # An FRF that does not show mode 2 plots modes 1 and 3: the panels must say so.
    f = np.arange(50.0, 400.0, 0.5)
    h = sdof_frf(f, 100.0, 0.02, 2.0) + sdof_frf(f, 300.0, 0.01, 5.0)
    fits = [SimpleNamespace(frequency_hz=fr, loss_factor=eta, modal_constant=a,
                            band_hz=(fr - 15.0, fr + 15.0))
            for fr, eta, a in ((100.0, 0.02, 2.0), (300.0, 0.01, 5.0))]
    plot_extraction_fit(tmp_path / "fits.svg", f, h, fits, mode_numbers=[1, 3])
    text = (tmp_path / "fits.svg").read_text()
    assert "mode 1:" in text and "mode 3:" in text and "mode 2:" not in text


def test_extraction_fit_errors(tmp_path):
    f = np.linspace(80.0, 120.0, 20)
    with pytest.raises(InputError):
        plot_extraction_fit(tmp_path / "x.png", f, sdof_frf(f), [])
    with pytest.raises(InputError):
        plot_extraction_fit(tmp_path / "x.png", f, sdof_frf(f)[:5], [])
    fit = SimpleNamespace(frequency_hz=100.0, loss_factor=0.01, modal_constant=2.0,
                          band_hz=(90.0, 110.0))
    with pytest.raises(InputError, match="2 mode numbers for 1 fits"):
        plot_extraction_fit(tmp_path / "x.png", f, sdof_frf(f), [fit], mode_numbers=[1, 2])
    assert list(tmp_path.iterdir()) == []
