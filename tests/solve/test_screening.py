"""The one screening engine (solve/screening.py screen_configurations) used by the planner:
against independent dense re-solves of every configuration (eigenvalues, Fox-Kapoor
sensitivities, next eigenvalue, and mode order by mass-weighted MAC from full modes)."""

import numpy as np
from test_perturbed import assert_matches, network, reference

import eigenupdate.solve.perturbed as perturbed
from eigenupdate.design.screen import screen_candidates
from eigenupdate.model.configurations import Addition, Configuration, mass_at
from eigenupdate.solve.eigen import solve_elastic
from eigenupdate.solve.screening import screen_configurations


def dense_order(model, configs, modes):
    """Mode order kept, from full dense modes (the reference of the coefficient test)."""
    K, M = model.stiffness(), model.mass()
    top = max(modes)
    bare = solve_elastic(K, M, top, dense=True).modes
    out = []
    for c in configs:
        dk, dm = c.delta(model)
        x = bare.T @ (M @ solve_elastic(K + dk, M + dm, top, dense=True).modes)
        out.append(all(int(np.argmax(x[:, k - 1] ** 2)) == k - 1 for k in modes))
    return np.array(out)


def test_sparse_screening_of_any_configuration_matches_dense_resolves(monkeypatch):
    monkeypatch.setattr("eigenupdate.solve.screening.DENSE_LIMIT", 40)
    model = network()
    modes = [1, 2, 4]
    configs = [mass_at(45, 5.0), mass_at(3, 0.5),
               Configuration("two", (Addition(10, mass=3.0), Addition(70, mass=2.0))),
               Configuration("spring", (Addition(30, stiffness=5e5),)),
               Configuration("both", (Addition(60, mass=1.0, stiffness=2e5),)),
               Configuration("seven", tuple(Addition(c, mass=0.5) for c in range(1, 8)))]
    s = screen_configurations(model, configs, modes)
    lam, J = reference(model, [Configuration("base"), *configs], modes)
    nm = len(modes)
    assert_matches(s.base_eigenvalues, s.base_J, lam[:nm], J[:nm])
    assert_matches(s.eigenvalues.ravel(), s.J.reshape(-1, s.J.shape[2]), lam[nm:], J[nm:])
    assert s.certified[:5].all() and not s.certified[5]  # seven rows: Lanczos
    assert np.nanmax(s.bound) <= perturbed.EIG_RTOL
    np.testing.assert_array_equal(s.order_kept, dense_order(model, configs, modes))
    K, M = model.stiffness(), model.mass()
    for i, c in enumerate(configs):
        dk, dm = c.delta(model)
        full = solve_elastic(K + dk, M + dm, max(modes) + 1, dense=True).eigenvalues
        np.testing.assert_allclose(s.all_eigenvalues[i], full[:max(modes)], rtol=1e-10)
        assert abs(s.next_eigenvalues[i] / full[max(modes)] - 1) < 1e-8  # NEXT_RTOL


def test_mode_order_from_ritz_coefficients_finds_a_reordering(monkeypatch):
    # heavy masses reorder modes of the network; the coefficients on the bare modes (the
    # mass-weighted correlations) see it as the full modes do
    monkeypatch.setattr("eigenupdate.solve.screening.DENSE_LIMIT", 40)
    model = network()
    modes = [1, 2, 3, 4, 5]
    configs = [mass_at(c, 60.0) for c in range(5, 90, 7)]
    s = screen_configurations(model, configs, modes)
    want = dense_order(model, configs, modes)
    assert not want.all() and want.any()  # the case has both
    np.testing.assert_array_equal(s.order_kept, want)


def test_planner_view_keeps_all_modes_and_the_next(monkeypatch):
    monkeypatch.setattr("eigenupdate.solve.screening.DENSE_LIMIT", 40)
    model = network()
    bare, (c,) = screen_candidates(model, [mass_at(45, 5.0)], [2, 4])
    assert bare.eigenvalues.size == c.eigenvalues.size == 4  # modes 1..4
    assert c.next_eigenvalue is not None and c.next_eigenvalue > c.eigenvalues[-1]
    assert bare.J.shape == c.J.shape == (2, len(model.updated))
