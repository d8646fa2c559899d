"""The dense fast path for small models (model/dense.py) against the sparse terms it
replaces: K(s), M(s), dK/ds_j, dM/ds_j and the configurations' additions are the same
sums in the same order, hence equal to the bit; eigenvalues and sensitivities through
solve/jacobian.py agree with the sparse-term path (eigenvalues to the bit: the same
LAPACK driver on the same matrices; sensitivities within the rounding bound of a dot
product)."""

import pickle
import sys
from pathlib import Path

import numpy as np
import pytest

from eigenupdate.errors import InputError
from eigenupdate.model import dense
from eigenupdate.model.configurations import BASE, Addition, Configuration, mass_at
from eigenupdate.model.dense import dense_model
from eigenupdate.model.parameters import Parameter
from eigenupdate.model.parametric import FunctionTerm, ParametricModel, Term
from eigenupdate.solve.jacobian import linearise, solve_configurations

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from models import random_network  # noqa: E402

EPS = np.finfo(float).eps


def _shear(x):
    """A coefficient that is no monomial: x0 x1^2 / (1 + x0) (complex-safe)."""
    return x[0] * x[1] ** 2 / (1.0 + x[0])


def _shear_gradient(x):
    return np.array([x[1] ** 2 / (1.0 + x[0]) ** 2, 2 * x[0] * x[1] / (1.0 + x[0])])


def _nonlinear(seed=5):
    """A random network's spring and mass matrices recombined: springs k1, k2 scaled by
    _shear(E, t), k3 by E t^3 (a Term), masses by t; parameters E, t, m."""
    net = random_network(np.random.default_rng(seed), 6)
    params = (Parameter("E", 2.0, 0.2), Parameter("t", 0.7, 0.07), Parameter("m", 1.5, 0.1))
    k = [t for t in net.k_terms if t is not None]
    m = [t for t in net.m_terms if t is not None]
    kp = [FunctionTerm(k[0], (0, 1), _shear), FunctionTerm(k[1], (0, 1), _shear),
          Term(k[2], ((0, 1.0), (1, 3.0)), 1e5)] + [Term(a, ((2, 1.0),), 3e5) for a in k[3:]]
    mp = [Term(a, ((1, 1.0),), 4.0) for a in m[:3]] + [Term(a, ((2, 1.0),)) for a in m[3:]]
    return ParametricModel.from_parts(net.k0, net.m0, params, kp, mp), kp, mp


def _networks():
    net = random_network(np.random.default_rng(3), 8)
    s = net.values * np.random.default_rng(4).uniform(0.7, 1.3, net.values.size)
    nl, _, _ = _nonlinear()
    return [(net, s), (nl, np.array([2.3, 0.61, 1.2]))]


@pytest.mark.parametrize("case", [0, 1], ids=["network", "function-terms"])
def test_dense_matrices_equal_the_sparse_sums(case):
    model, s = _networks()[case]
    d = dense_model(model)
    assert np.array_equal(d.stiffness(s), model.stiffness(s).toarray())
    assert np.array_equal(d.mass(s), model.mass(s).toarray())
    upd = model.updated
    kt, mt = d.derivatives(s, upd)
    at = model.at(s)
    for mine, theirs in ((kt, at.k_terms), (mt, at.m_terms)):
        for j, a in zip(upd, mine, strict=True):
            b = theirs[j]
            assert (a is None) == (b is None)
            if a is not None:
                assert np.array_equal(a, b.toarray())
    config = Configuration("two", (Addition(3, mass=0.4), Addition(5, mass=1.1, stiffness=2e4),
                                   Addition(3, mass=0.3)))
    K, M = d.stiffness(s), d.mass(s)
    dk, dm = config.delta(model)
    Ka, Ma = d.added(K, M, config, model)
    assert np.array_equal(Ka, (model.stiffness(s) + dk).toarray())
    assert np.array_equal(Ma, (model.mass(s) + dm).toarray())
    assert d.added(K, M, Configuration(BASE), model) == (K, M)


def test_function_term_derivatives_against_their_closed_form():
    """dK/dE, dK/dt of the FunctionTerm model from the closed-form gradient of x0 x1^2 /
    (1 + x0) and of 1e5 E t^3: the complex step is exact to round-off, so they agree
    within a few eps of the sum of the absolute terms."""
    model, kp, _ = _nonlinear()
    s = np.array([2.3, 0.61, 1.2])
    kt, _ = dense_model(model).derivatives(s, [0, 1])
    g = _shear_gradient(s[:2])
    for j in (0, 1):
        parts = [g[j] * kp[0].matrix.toarray(), g[j] * kp[1].matrix.toarray(),
                 (1e5 * s[1] ** 3 if j == 0 else 3e5 * s[0] * s[1] ** 2)
                 * kp[2].matrix.toarray()]
        bound = 8 * EPS * sum(np.abs(p) for p in parts)
        assert np.all(np.abs(kt[j] - sum(parts)) <= bound)


def test_dense_refuses_what_the_model_refuses():
    model, _, _ = _nonlinear()
    with pytest.raises(InputError, match="t.value"):
        dense_model(model).derivatives(np.array([2.0, -0.1, 1.0]), [0, 1, 2])


@pytest.mark.parametrize("case", [0, 1], ids=["network", "function-terms"])
def test_fast_linearisation_matches_the_sparse_terms(case, monkeypatch):
    """Eigenvalues to the bit (same LAPACK driver, same matrices); J within twice the
    error bound of phi^T (K_j - lambda M_j) phi by length-n dot products,
    (n + 2) eps |phi|^T (|K_j| + lambda |M_j|) |phi|."""
    model, s = _networks()[case]
    configs = [Configuration(BASE), mass_at(2, 1.5),
               Configuration("spring", (Addition(4, stiffness=3e5),))]
    fast = linearise(model, configs, [1, 2, 3], s)
    sols = solve_configurations(model, configs, 3, s)
    monkeypatch.setattr(dense, "DENSE_ENTRIES", 0)
    slow_model = ParametricModel(model.k0, model.m0, model.parameters, model.k_terms,
                                 model.m_terms, k_parts=model.k_parts, m_parts=model.m_parts)
    assert dense_model(slow_model) is None
    slow = linearise(slow_model, configs, [1, 2, 3], s)
    assert np.array_equal(fast.eigenvalues, slow.eigenvalues)
    at = slow_model.at(s)
    n = model.n
    for i, (c, k) in enumerate(fast.rows):
        sol = sols[[x.name for x in configs].index(c)]
        phi, lam = np.abs(sol.modes[:, k - 1]), sol.eigenvalues[k - 1]
        for col, j in enumerate(model.updated):
            size = 0.0
            for t, w in ((at.k_terms[j], 1.0), (at.m_terms[j], lam)):
                if t is not None:
                    size += w * phi @ np.abs(t.toarray()) @ phi
            assert abs(fast.J[i, col] - slow.J[i, col]) <= 2 * (n + 2) * EPS * size


def test_dense_copy_is_shared_by_values_and_not_pickled():
    model, s = _networks()[0]
    d = dense_model(model)
    assert dense_model(model.with_values(s)) is d
    back = pickle.loads(pickle.dumps(model))
    assert "_dense" not in back.__dict__
    assert np.array_equal(dense_model(back).stiffness(s), d.stiffness(s))


def _massless_cases():
    net = random_network(np.random.default_rng(8), 6)
    K, M = net.stiffness().toarray(), net.mass().toarray()
    Mz = M.copy()
    Mz[2, 2] = 0.0  # a coordinate without mass: static condensation
    q = np.linalg.qr(np.random.default_rng(9).standard_normal((6, 6)))[0]
    Ms = q @ np.diag([2.0, 1.0, 3.0, 1.5, 0.5, 0.0]) @ q.T  # singular, no zero row
    return [(K, M), (K, Mz), (K, 0.5 * (Ms + Ms.T))]


@pytest.mark.parametrize("case", [0, 1, 2], ids=["plain", "massless", "singular-M"])
def test_dense_path_returns_the_sturm_count(case):
    """Why the dense path needs no missed-mode check: below a shift halfway between any two
    computed eigenvalues, the count of computed ones equals the inertia of K - sigma M
    (Sylvester; minus the massless block's own negatives, Haynsworth), on each of
    all_modes' branches."""
    from eigenupdate.solve.eigen import all_modes, negative_count

    K, M = _massless_cases()[case]
    lam = all_modes(K, M)[0]
    assert lam.size == 6 - (case > 0)
    zero = ~np.any(M != 0, axis=1)
    for sigma in 0.5 * (lam[1:] + lam[:-1]):
        count = negative_count(K - sigma * M)
        if zero.any():
            count -= negative_count(K[np.ix_(zero, zero)])
        assert count == np.sum(lam < sigma)
