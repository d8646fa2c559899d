"""Eigen-solutions: closed-form beam frequencies, rigid-body modes, sparse path, Woodbury."""

import numpy as np
import pytest
import scipy.sparse as sp
from bounds import BACKWARD, EPS, assert_eigenvalues_agree
from models import paper_beam

import eigenupdate.solve.perturbed as perturbed
from eigenupdate.errors import InputError
from eigenupdate.model.beam import beam_model
from eigenupdate.model.configurations import Configuration, mass_at
from eigenupdate.solve.eigen import ShiftInvert, default_shift, solve_elastic
from eigenupdate.solve.jacobian import solve_configurations

EI, RHOA, L = 70e9 * 0.05 * 0.025**3 / 12, 2700 * 0.05 * 0.025, 0.8


def closed_form_hz(beta_l):
    return np.asarray(beta_l) ** 2 * np.sqrt(EI / (RHOA * L**4)) / (2 * np.pi)


@pytest.mark.parametrize("dense", [True, False])
def test_free_free_beam_closed_form(dense):
    # Free-free Euler-Bernoulli beam: beta L = 4.7300, 7.8532, 10.9956; 40 elements,
    # non-uniform spacing, within 0.1 %.
    x = L * (1 - np.cos(np.linspace(0, np.pi, 41))) / 2
    model = beam_model(x, EI, RHOA)
    sol = solve_elastic(model.stiffness(), model.mass(), 3, dense=dense)
    assert sol.n_rigid == 2
    exact = closed_form_hz([4.730041, 7.853205, 10.995608])
    np.testing.assert_allclose(sol.frequencies_hz, exact, rtol=1e-3)


def test_cantilever_closed_form():
    model = beam_model(np.linspace(0, L, 31), EI, RHOA, restrained=[1, 2])
    sol = solve_elastic(model.stiffness(), model.mass(), 2)
    assert sol.n_rigid == 0
    np.testing.assert_allclose(sol.frequencies_hz, closed_form_hz([1.875104, 4.694091]), rtol=1e-3)


def test_mass_normalised_modes():
    model = paper_beam()
    sol = solve_elastic(model.stiffness(), model.mass(), 4)
    M = model.mass().toarray()
    np.testing.assert_allclose(sol.modes.T @ M @ sol.modes, np.eye(4), atol=1e-10)


def test_fine_mesh_free_beam_rigid_modes_detected():
    # 600 elements (1202 coordinates): sparse path, lambda_max / lambda_1 ~ 1e13.
    model = beam_model(np.linspace(0, L, 601), EI, RHOA)
    sol = solve_elastic(model.stiffness(), model.mass(), 3)
    assert sol.n_rigid == 2
    np.testing.assert_allclose(sol.frequencies_hz, closed_form_hz([4.730041, 7.853205, 10.995608]),
                               rtol=1e-4)


def test_woodbury_operator_matches_fresh_factorisation():
    model = beam_model(np.linspace(0, L, 301), EI, RHOA)
    K, M = model.stiffness(), model.mass()
    base = ShiftInvert(K, M, default_shift(K, M))
    rows = np.array([0, 300, 300])
    dk, dm = np.array([0.0, 1e4, 0.0]), np.array([0.2, 0.1, 0.05])
    upd = base.updated(rows, dk, dm)
    dK = sp.csr_array((dk, (rows, rows)), shape=K.shape)
    dM = sp.csr_array((dm, (rows, rows)), shape=K.shape)
    fresh = ShiftInvert(K + dK, M + dM, base.sigma)
    b = np.random.default_rng(0).normal(size=K.shape[0])
    x, ref = upd.solve(b), fresh.solve(b)
    # both are backward-stable solves of A x = b: each within BACKWARD eps cond(A) |x|
    # (normwise; an entry far below |x| carries no relative accuracy of its own). A wrong
    # Woodbury formula would differ by O(|x|).
    A = (K + dK - base.sigma * (M + dM)).toarray()
    bound = 2 * BACKWARD * EPS * np.linalg.cond(A) * np.abs(ref).max()
    assert np.abs(x - ref).max() <= bound


@pytest.mark.parametrize("hint", [0, 2, 6])
def test_rigid_hint_only_sizes_the_request(hint):
    # A wrong hint (0 for a free beam with 2 rigid-body modes) costs a second Lanczos
    # run but never shifts the mode numbering.
    model = beam_model(np.linspace(0, L, 41), EI, RHOA)
    K, M = model.stiffness(), model.mass()
    op = ShiftInvert(K, M, -100.0)
    sol = solve_elastic(K, M, 3, operator=op, n_rigid=hint)
    assert sol.n_rigid == 2 and sol.next_eigenvalue is not None
    exact = solve_elastic(K, M, 3, dense=True)
    np.testing.assert_allclose(sol.eigenvalues, exact.eigenvalues, rtol=1e-7)


def test_configurations_sparse_equal_dense():
    model = beam_model(np.linspace(0, L, 41), EI, RHOA)
    configs = [Configuration("base"), mass_at(1, 0.2), mass_at(41, 0.5)]
    d = solve_configurations(model, configs, 4, dense=True)
    s = solve_configurations(model, configs, 4, dense=False)
    # a free beam's eigenvalues have condition ~2e7: both solvers are good to their
    # rounding floor (tests/bounds.py, ~4e-8), the certified fast path within 1e-11 more
    for c, a, b in zip(configs, d, s, strict=True):
        dk, dm = c.delta(model)
        assert_eigenvalues_agree(b.eigenvalues, a, model.stiffness() + dk, model.mass() + dm,
                                 certified=perturbed.EIG_RTOL)


def test_too_many_modes_is_an_error():
    model = paper_beam()
    with pytest.raises(InputError, match="only 16 elastic modes"):
        solve_elastic(model.stiffness(), model.mass(), 17)


def test_grounded_spring_mass_has_no_rigid_mode():
    K = np.array([[2.0, -1.0], [-1.0, 1.0]]) * 1e-4  # very soft, but grounded
    sol = solve_elastic(K, np.eye(2), 2)
    assert sol.n_rigid == 0
