"""Receptance prediction checked against closed forms and against each other.

Tolerances (tests/bounds.py): the closed forms have one or two coordinates and a loss
factor of at least 0.01, so the dynamic stiffness's condition stays below ~1e3 and a
backward-stable solve or modal sum is good to ~2e-12 (one coordinate: a division, a few
units of round-off); hence 1e-11 (1e-12, 1e-13 on one coordinate). Larger models compare
within the bound computed from their own condition numbers.
"""

from __future__ import annotations

import numpy as np
import pytest
from bounds import inverse_entry_error

from eigenupdate.errors import InputError, SingularMatrixError
from eigenupdate.model.beam import beam_model
from eigenupdate.model.configurations import Addition, Configuration, mass_at
from eigenupdate.model.parameters import Parameter
from eigenupdate.model.spring_mass import Mass, Spring, spring_mass_model
from eigenupdate.solve.eigen import solve_elastic
from eigenupdate.solve.response import (
    configuration_matrices,
    receptance,
)

NODES = [0, 0.09, 0.19, 0.29, 0.39, 0.49, 0.59, 0.69, 0.80]


def paper_beam(m_l: float = 0.0):
    return beam_model(NODES, 4557.0, 3.4, EI_std=150, mass_per_length_std=0.1,
                      point_masses=[(Parameter("m_L", m_l, std=0.1), 11)])


def sdof(m: float = 2.0, k: float = 800.0):
    return spring_mass_model([Mass(Parameter("m", m), 1)], [Spring(Parameter("k", k), (0, 1))])


def chain2(m1=1.5, m2=0.8, k1=1000.0, k2=600.0):
    """ground -k1- m1 -k2- m2"""
    P = Parameter
    return spring_mass_model([Mass(P("m1", m1), 1), Mass(P("m2", m2), 2)],
                             [Spring(P("k1", k1), (0, 1)), Spring(P("k2", k2), (1, 2))])


def w(f):
    return 2 * np.pi * np.asarray(f, dtype=float)


# ------------------------------------------------------------------- closed forms


@pytest.mark.parametrize("method", ["direct", "modal"])
def test_sdof_closed_form(method):
    m, k, eta = 2.0, 800.0, 0.02
    f = np.linspace(0.0, 10.0, 101)  # includes 0 Hz and the resonance region (3.18 Hz)
    H = receptance(sdof(m, k), f, 1, 1, loss_factor=eta, method=method)
    exact = 1.0 / (k * (1 + 1j * eta) - w(f) ** 2 * m)
    assert H.shape == f.shape
    np.testing.assert_allclose(H, exact, rtol=1e-12)
    assert H[0] == pytest.approx(1 / (k * (1 + 1j * eta)))  # grounded: finite static value


@pytest.mark.parametrize("method", ["direct", "modal"])
def test_two_dof_chain_closed_form(method):
    m1, m2, k1, k2, eta = 1.5, 0.8, 1000.0, 600.0, 0.03
    f = np.linspace(0.1, 8.0, 60)
    H = receptance(chain2(m1, m2, k1, k2), f, [1, 2], [1, 2], loss_factor=eta, method=method)
    k1c, k2c, x = k1 * (1 + 1j * eta), k2 * (1 + 1j * eta), w(f) ** 2
    det = (k1c + k2c - x * m1) * (k2c - x * m2) - k2c**2
    assert H.shape == (f.size, 2, 2)
    np.testing.assert_allclose(H[:, 0, 0], (k2c - x * m2) / det, rtol=1e-11)
    np.testing.assert_allclose(H[:, 1, 1], (k1c + k2c - x * m1) / det, rtol=1e-11)
    np.testing.assert_allclose(H[:, 0, 1], k2c / det, rtol=1e-11)
    np.testing.assert_allclose(H[:, 1, 0], k2c / det, rtol=1e-11)


def test_per_mode_loss_factors_closed_form_modes():
    # Chain of equal masses m and springs k: lambda = (k/m)(3 -+ sqrt5)/2 and
    # phi = v / sqrt(m (1 + v2^2)) with v = (1, 2 - lambda m / k).
    m, k, etas = 2.0, 500.0, (0.01, 0.05)
    model = chain2(m, m, k, k)
    f = np.linspace(0.5, 10.0, 50)
    H = receptance(model, f, 1, [1, 2], loss_factor=etas)
    expected = np.zeros((f.size, 2), dtype=complex)
    for lam_unit, eta in zip(((3 - 5**0.5) / 2, (3 + 5**0.5) / 2), etas, strict=True):
        v = np.array([1.0, 2.0 - lam_unit])
        phi = v / np.sqrt(m * v @ v)
        lam = lam_unit * k / m
        expected += np.outer(1 / (lam * (1 + 1j * eta) - w(f) ** 2), phi[0] * phi)
    np.testing.assert_allclose(H, expected, rtol=1e-11)
    # Modes beyond the list take its last value; more values than modes is a mistake.
    np.testing.assert_allclose(receptance(model, f, 1, 2, loss_factor=[0.01]),
                               receptance(model, f, 1, 2, loss_factor=[0.01, 0.01]),
                               rtol=1e-13)
    with pytest.raises(InputError, match="3 loss factors given but the model has only 2"):
        receptance(model, f, 1, 2, loss_factor=[0.01, 0.01, 0.5])


def test_configuration_with_added_mass_and_spring():
    m, k, eta = 2.0, 800.0, 0.02
    cfg = Configuration("extra", (Addition(1, mass=0.5, stiffness=200.0),))
    f = np.linspace(0.1, 6.0, 30)
    for method in ("direct", "modal"):
        H = receptance(sdof(m, k), f, 1, 1, configuration=cfg, loss_factor=eta, method=method)
        np.testing.assert_allclose(H, 1 / ((k + 200) * (1 + 1j * eta) - w(f) ** 2 * 2.5),
                                   rtol=1e-12)


def test_values_as_sequence_or_dict():
    f = [1.0, 2.0]
    model = sdof(2.0, 800.0)
    a = receptance(model, f, 1, 1, values={"k": 900.0})
    b = receptance(model, f, 1, 1, values=[2.0, 900.0])
    np.testing.assert_allclose(a, 1 / (900 - w(f) ** 2 * 2.0), rtol=1e-13)
    np.testing.assert_allclose(a, b, rtol=1e-13)


# ------------------------------------------------------------- beam cross-checks


def test_beam_direct_equals_full_modal_sum():
    model = paper_beam(0.05)
    f = np.arange(2.0, 1600.0 + 1, 2.0)
    cfg = mass_at(7, 0.2)
    outputs = list(range(1, 19))
    # Point by point; undamped anti-resonances are deeper (|H| ~ 1e-9 m/N), where the
    # modal sum loses a few more digits to cancellation.
    for eta, rtol in ((0.01, 1e-8), (0.0, 1e-7)):
        Hd = receptance(model, f, [11, 3], outputs, configuration=cfg, loss_factor=eta,
                        method="direct")
        Hm = receptance(model, f, [11, 3], outputs, configuration=cfg, loss_factor=eta,
                        method="modal")
        assert Hd.shape == (f.size, 18, 2)
        rel = np.abs(Hd - Hm) / np.abs(Hd)
        assert rel.max() < rtol, rel.max()


def test_beam_reciprocity():
    model = paper_beam(0.076)
    f = np.linspace(5.0, 1600.0, 300)
    H = receptance(model, f, [11, 3, 12], [3, 11, 12], loss_factor=0.01)
    # H[:, j, k] = x(outputs[j]) / F(inputs[k]), each from its own solve of the symmetric
    # dynamic stiffness D: the two agree within two solves' error bound (tests/bounds.py;
    # at 5 Hz the free beam's D has condition ~1e6, elsewhere it is far smaller)
    K, M = configuration_matrices(model)
    K, M = K.toarray(), M.toarray()
    tol = np.array([2 * inverse_entry_error(K * (1 + 0.01j) - w(x) ** 2 * M)
                    for x in f])
    for a, b in (((0, 0), (1, 1)), ((2, 0), (1, 2)), ((0, 2), (2, 1))):  # 3<-11 == 11<-3 ...
        assert np.all(np.abs(H[:, a[0], a[1]] - H[:, b[0], b[1]]) <= tol)


def test_free_beam_low_frequency_rigid_body_asymptote():
    # Far below the first elastic mode a free beam moves as a rigid body:
    # w^2 H_jk -> -(1/m + (x_j - c)(x_k - c)/J), with rotations: -(x_j - c)/J and -1/J.
    rho, L, m_l, x11 = 3.4, 0.8, 0.076, NODES[5]
    m = rho * L + m_l
    c = (rho * L * L / 2 + m_l * x11) / m
    J = rho * L**3 / 12 + rho * L * (L / 2 - c) ** 2 + m_l * (x11 - c) ** 2
    f = np.array([0.05, 0.2])  # elastic modes add ~ (f / 200 Hz)^2 relative
    for method in ("direct", "modal"):
        H = receptance(paper_beam(m_l), f, 11, [1, 15, 11, 2], loss_factor=0.01,
                       method=method)
        w2H = H * w(f)[:, None] ** 2
        for col, x in enumerate((NODES[0], NODES[7], x11)):
            expected = -(1 / m + (x - c) * (x11 - c) / J)
            np.testing.assert_allclose(w2H[:, col].real, expected, rtol=2e-5)
        np.testing.assert_allclose(w2H[:, 3].real, -(x11 - c) / J, rtol=2e-5)  # rotation 1


def test_zero_frequency_is_nan_for_free_structures():
    f = [0.0, 10.0]
    for method in ("direct", "modal"):
        for eta in (0.0, 0.01):
            H = receptance(paper_beam(), f, 11, [1, 15], loss_factor=eta, method=method)
            assert np.all(np.isnan(H[0])) and np.all(np.isfinite(H[1]))


def test_truncated_sum_static_correction():
    # Cantilever (grounded): with the static correction two modes give the exact
    # static receptance and a much smaller error at 100 Hz than the plain truncated sum.
    model = beam_model(NODES, 4557.0, 3.4, restrained=[1, 2])
    f = np.array([0.0, 100.0])
    exact = receptance(model, f, 17, [17, 9], loss_factor=0.01, method="direct")
    corrected = receptance(model, f, 17, [17, 9], loss_factor=0.01, n_modes=2)
    plain = receptance(model, f, 17, [17, 9], loss_factor=0.01, n_modes=2,
                       static_correction=False)
    np.testing.assert_allclose(corrected[0], exact[0], rtol=1e-10)
    err_c = np.abs(corrected[1] - exact[1]) / np.abs(exact[1])
    err_p = np.abs(plain[1] - exact[1]) / np.abs(exact[1])
    assert np.all(err_c < 0.1 * err_p), (err_c, err_p)


def test_large_model_sparse_paths():
    # 402 coordinates: over the dense limit, so eigsh and sparse LU are used.
    nodes = np.linspace(0.0, 0.8, 201)
    model = beam_model(nodes, 4557.0, 3.4)
    f = np.linspace(5.0, 1600.0, 40)
    outputs = [1, 151]  # translations of nodes 1 and 76, x = 0 and x = 0.3
    K, M = configuration_matrices(model)
    # Truncated sum (rigid + 10 elastic) against the analytic rigid-body term plus the
    # elastic modes of the existing sparse eigen-solver.
    H = receptance(model, f, 1, outputs, loss_factor=0.01, n_modes=10,
                   static_correction=False)
    m, J = 3.4 * 0.8, 3.4 * 0.8**3 / 12
    rigid = -(1 / m + (np.array([0.0, 0.3]) - 0.4) * (0.0 - 0.4) / J)
    sol = solve_elastic(K, M, 10, dense=False)
    ref = rigid / w(f)[:, None] ** 2 + np.einsum(
        "fr,r,jr->fj", 1 / (sol.eigenvalues * (1 + 0.01j) - w(f)[:, None] ** 2),
        sol.modes[0], sol.modes[[0, 150]])
    np.testing.assert_allclose(H, ref, rtol=1e-6, atol=1e-14)  # two eigsh runs
    # Sparse direct against dense solves; default modal (+ static correction) close to it.
    Hd = receptance(model, f, 1, outputs, loss_factor=0.01, method="direct")
    Kd, Md = K.toarray(), M.toarray()
    for i in (17, 39):  # 700 and 1600 Hz
        x = np.linalg.solve(Kd * (1 + 0.01j) - w(f[i]) ** 2 * Md, np.eye(K.shape[0])[:, 0])
        D = Kd * (1 + 0.01j) - w(f[i]) ** 2 * Md
        assert np.all(np.abs(Hd[i] - x[[0, 150]]) <= 2 * inverse_entry_error(D))
    # At 5 Hz the free beam's dynamic stiffness has condition ~ lambda_max / w^2 ~ 1e11:
    # any direct solve loses ~5 digits there (documented); the modal sum does not.
    np.testing.assert_allclose(Hd[0], ref[0], rtol=1e-4)
    Ha = receptance(model, f, 1, outputs, loss_factor=0.01)
    assert np.max(np.abs(Ha - Hd) / np.abs(Hd)) < 5e-3


# --------------------------------------------------------------------- arguments


def test_output_shapes():
    f = np.array([10.0, 20.0, 30.0])
    model = paper_beam()
    assert receptance(model, f, 11, 1).shape == (3,)
    assert receptance(model, f, 11, [1]).shape == (3, 1)
    assert receptance(model, f, [11], [1, 15]).shape == (3, 2, 1)
    assert receptance(model, f, [11, 3], 1).shape == (3, 2)
    assert receptance(model, 100.0, 11, 1).shape == (1,)


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"outputs": 99}, "outputs"),
        ({"inputs": 0}, "inputs"),
        ({"inputs": 1.5}, "inputs"),
        ({"frequency_hz": [-1.0, 2.0]}, "frequency_hz"),
        ({"frequency_hz": [np.nan]}, "frequency_hz"),
        ({"loss_factor": -0.01}, "loss_factor"),
        ({"loss_factor": [0.01, 0.02], "method": "direct"}, "loss_factor"),
        ({"loss_factor": [0.01] * 17}, "loss_factor"),  # 16 elastic modes
        ({"method": "qr"}, "method"),
        ({"n_modes": 3, "method": "direct"}, "n_modes"),
        ({"n_modes": 0}, "n_modes"),
        ({"n_modes": 17}, "n_modes"),
    ],
)
def test_bad_arguments(kwargs, field):
    args = {"frequency_hz": [10.0], "inputs": 11, "outputs": 1} | kwargs
    with pytest.raises(InputError) as err:
        receptance(paper_beam(), args.pop("frequency_hz"), args.pop("inputs"),
                   args.pop("outputs"), **args)
    assert err.value.field == field


def test_undamped_resonance_hit_exactly_by_direct_method():
    f_n = np.sqrt(800.0 / 2.0) / (2 * np.pi)
    with pytest.raises(SingularMatrixError, match="undamped natural frequency"):
        receptance(sdof(), [1.0, f_n], 1, 1, method="direct")


# ---------------------------------------------------------------- UFF mapping


def test_coordinate_tables_of_the_models():
    beam, chain = paper_beam().coordinate_table, sdof().coordinate_table
    for c in range(1, 19):
        assert beam.from_uff(beam[c].uff_point).number == c
    assert [beam[c].uff_point for c in (1, 2, 15)] == [(1, 3), (1, 5), (8, 3)]
    assert beam[12].rotation and not beam[11].rotation
    assert beam[15].label == "coordinate 15 (node 8, Z)"
    assert chain[1].uff_point == (1, 1) and chain[1].label == "coordinate 1 (node 1, X)"


@pytest.mark.parametrize(
    ("table", "point"),
    [("beam", (3, 1)), ("beam", (3, -3)), ("chain", (3, 3)), ("chain", (0, 1)),
     ("chain", "x")],
)
def test_points_not_in_the_model(table, point):
    t = {"beam": paper_beam(), "chain": sdof()}[table].coordinate_table
    with pytest.raises(InputError, match="not a coordinate|expected a"):
        t.from_uff(point)
    with pytest.raises(InputError, match="unknown coordinate"):
        t[0]
