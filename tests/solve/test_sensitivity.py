"""Every analytic eigenvalue derivative against central finite differences."""

import numpy as np
import pytest
from models import fig2, paper_beam, random_network

from eigenupdate.model.configurations import Addition, Configuration, mass_at
from eigenupdate.solve.eigen import solve_elastic
from eigenupdate.solve.jacobian import linearise, solve_configurations
from eigenupdate.solve.sensitivity import RepeatedEigenvalueError, eigenvalue_derivatives


def finite_difference_J(model, configs, modes, rel=1e-3, dense=None):
    """Fourth-order central differences (truncation error ~ rel^4)."""
    s0 = model.values
    cols = []
    for j in model.updated:
        h = rel * model.parameters[j].scale
        lam = {}
        for step in (-2, -1, 1, 2):
            s = s0.copy()
            s[j] += step * h
            sols = solve_configurations(model, configs, max(modes), s, dense=dense)
            lam[step] = np.concatenate([sol.eigenvalues[np.array(modes) - 1] for sol in sols])
        cols.append((lam[-2] - 8 * lam[-1] + 8 * lam[1] - lam[2]) / (12 * h))
    return np.column_stack(cols)


def assert_matches_fd(model, configs, modes, dense=None):
    lin = linearise(model, configs, modes, dense=dense)
    fd = finite_difference_J(model, configs, modes, dense=dense)
    scale = np.abs(lin.J).max(axis=0)
    np.testing.assert_allclose(lin.J / scale, fd / scale, atol=2e-6)


def test_spring_mass_fig2_all_configurations():
    configs = [Configuration("base"), mass_at(1, 0.35), mass_at(4, 0.35),
               Configuration("k at 2", (Addition(2, stiffness=2e5),))]
    assert_matches_fd(fig2(), configs, [1, 2, 3, 4])


def test_beam_EI_rhoA_point_mass_and_rotary_inertia():
    configs = [Configuration("base"), mass_at(1, 0.2), mass_at(11, 0.2),
               Configuration("rot", (Addition(4, mass=2e-4), Addition(9, mass=0.1)))]
    assert_matches_fd(paper_beam(), configs, [1, 2, 3])


def test_restrained_beam():
    assert_matches_fd(paper_beam(restrained=[1, 2]), [Configuration("base"), mass_at(17, 0.3)],
                      [1, 2])


def test_sparse_path_matches_dense_and_fd():
    rng = np.random.default_rng(3)
    model = random_network(rng, 12)
    configs = [Configuration("base"), mass_at(3, 1.0), mass_at(7, 2.0)]
    dense = linearise(model, configs, [1, 2, 3], dense=True)
    sparse = linearise(model, configs, [1, 2, 3], dense=False)
    np.testing.assert_allclose(sparse.eigenvalues, dense.eigenvalues, rtol=1e-10)
    np.testing.assert_allclose(sparse.J, dense.J, rtol=1e-7, atol=1e-9 * np.abs(dense.J).max())
    assert_matches_fd(model, configs, [1, 2, 3], dense=False)


def test_single_dof_closed_form():
    k, m = 800.0, 2.0
    sol = solve_elastic(np.array([[k]]), np.array([[m]]), 1)
    d = eigenvalue_derivatives(sol, [1], [np.ones((1, 1)), None], [None, np.ones((1, 1))])
    np.testing.assert_allclose(d, [[1 / m, -k / m**2]])


def test_repeated_eigenvalue_is_refused():
    # Two identical uncoupled oscillators: lambda_1 = lambda_2, derivative undefined.
    K, M = np.diag([100.0, 100.0]), np.eye(2)
    sol = solve_elastic(K, M, 2)
    terms = [np.diag([1.0, 0.0])]
    with pytest.raises(RepeatedEigenvalueError, match="modes 1 and 2"):
        eigenvalue_derivatives(sol, [1], terms, [None])
    # A distinct mode next to nothing repeated is fine.
    sol3 = solve_elastic(np.diag([100.0, 100.0, 400.0]), np.eye(3), 3)
    eigenvalue_derivatives(sol3, [3], [np.diag([0.0, 0.0, 1.0])], [None])
