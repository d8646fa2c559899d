"""Fast path for perturbed configurations (solve/perturbed.py): Rayleigh-Ritz in a Krylov
subspace of the base factorisation, certificate, fallback, screening.

Reference: independent full re-solves of every configuration with the dense solver
(scipy.linalg.eigh of K + dK, M + dM) and Fox-Kapoor on its modes (solve/sensitivity.py).
"""

from dataclasses import replace

import numpy as np
import pytest
import scipy.sparse as sp
from bounds import assert_eigenvalues_agree, eigenvalue_floor
from hypothesis import given, settings
from hypothesis import strategies as st

import eigenupdate.solve.jacobian as jacobian
import eigenupdate.solve.krylov as krylov
import eigenupdate.solve.perturbed as perturbed
from eigenupdate.identify.updating import update
from eigenupdate.measure.measurement import Measurement
from eigenupdate.model.beam import beam_model
from eigenupdate.model.configurations import Addition, Configuration, mass_at
from eigenupdate.model.parameters import Parameter
from eigenupdate.model.parametric import ParametricModel
from eigenupdate.model.spring_mass import Mass, Spring, spring_mass_model
from eigenupdate.solve.eigen import ShiftInvert, base_operator, default_shift, solve_elastic
from eigenupdate.solve.jacobian import linearise
from eigenupdate.solve.screening import screen
from eigenupdate.solve.sensitivity import eigenvalue_derivatives

N_MODES = 6


def network(n: int = 90, seed: int = 5):
    """Free spring-mass network (one rigid-body mode): a chain plus random cross springs,
    random masses and stiffnesses, well conditioned (lambda_max / lambda_1 ~ 1e4) so that
    two solvers agree to round-off."""
    rng = np.random.default_rng(seed)
    masses = [Mass(Parameter(f"m{i}", rng.uniform(1, 3)), i) for i in range(1, n + 1)]
    pairs = [(i, i + 1) for i in range(1, n)]
    pairs += [tuple(sorted(rng.choice(np.arange(1, n + 1), 2, replace=False).tolist()))
              for _ in range(n // 3)]
    springs = [Spring(Parameter(f"k{j}", rng.uniform(0.5e6, 2e6)), p)
               for j, p in enumerate(dict.fromkeys(pairs), 1)]
    return spring_mass_model(masses, springs, n)


def beam(n_el: int = 40):
    """Clamped beam, non-uniform; node i (0-based) has w = 2i + 1 and theta = 2i + 2."""
    rng = np.random.default_rng(7)
    x = np.linspace(0, 0.8, n_el + 1)
    x[1:-1] += rng.uniform(-0.2, 0.2, n_el - 1) * 0.8 / n_el
    return beam_model(x, 4557.0 * rng.uniform(0.8, 1.2, n_el),
                      3.4 * rng.uniform(0.8, 1.2, n_el), restrained=[1, 2])


CONFIGS = [
    Configuration("base"),
    mass_at(45, 5.0),
    mass_at(90, 1.0),
    Configuration("two masses", (Addition(10, mass=3.0), Addition(70, mass=2.0))),
    Configuration("grounded spring", (Addition(30, stiffness=5e5),)),
    Configuration("mass and spring", (Addition(60, mass=1.0, stiffness=2e5),)),
    Configuration("same coordinate twice", (Addition(45, mass=1.0), Addition(45, mass=4.0))),
]


def reference(model, configs, modes, floor=False):
    """lambda and J of every configuration by dense re-solves; with ``floor`` also each
    eigenvalue's rounding floor (tests/bounds.py), the reference's own accuracy."""
    K, M = model.stiffness(), model.mass()
    kt = [model.k_terms[j] for j in model.updated]
    mt = [model.m_terms[j] for j in model.updated]
    lam, J, low = [], [], []
    for c in configs:
        dk, dm = c.delta(model)
        sol = solve_elastic(K + dk, M + dm, modes[-1], dense=True)
        use = np.asarray(modes) - 1
        lam.append(sol.eigenvalues[use])
        J.append(eigenvalue_derivatives(sol, modes, kt, mt))
        low.append(eigenvalue_floor(K + dk, M + dm, sol.eigenvalues[use], sol.modes[:, use]))
    out = np.concatenate(lam), np.vstack(J)
    return (*out, np.concatenate(low)) if floor else out


def assert_matches(lin_lam, lin_J, lam, J):
    np.testing.assert_allclose(lin_lam, lam, rtol=1e-10)
    err = np.abs(lin_J - J) / np.abs(J).max(axis=1, keepdims=True)
    assert err.max() < 1e-7, err.max()


def test_fast_path_matches_full_resolves(monkeypatch):
    # 90 coordinates: the sparse path, taken automatically
    monkeypatch.setattr(jacobian, "DENSE_LIMIT", 40)
    model = network()
    modes = list(range(1, N_MODES + 1))
    lin = linearise(model, CONFIGS, modes)
    rep = lin.certificate
    assert rep is not None and rep.configurations == len(CONFIGS) - 1
    assert rep.passed + rep.passed_extended == rep.configurations, rep.as_dict()
    assert rep.max_eig_bound <= perturbed.EIG_RTOL
    assert_matches(lin.eigenvalues, lin.J, *reference(model, CONFIGS, modes))


def test_rotary_inertia_on_a_beam():
    # Rotations and translations of a clamped beam. The beam's stiffness spans ~12
    # decades: its eigenvalues' condition numbers reach ~2e8, so the dense reference is
    # good only to its rounding floor (tests/bounds.py, up to 4e-7 here; measured
    # differences 6e-9 to 1.1e-8 across OpenBLAS kernels). Eigenvalues are compared within
    # the fast path's certified bound plus that floor. The
    # sensitivities of the two-addition configuration came out 1e-9 to 1.2e-7 from the
    # reference over repeated runs (ARPACK's random start): the bare modes enter the
    # subspace as ARPACK gives them (residual 1e-10), which the certificate does not
    # cover; the per-configuration Lanczos gets 1.3e-9. Compared at 3e-7.
    model = beam()
    configs = [Configuration("base"), mass_at(82, 2e-3, name="rotary inertia at tip"),
               mass_at(41, 0.4), Configuration("both", (Addition(81, mass=0.2),
                                                        Addition(82, mass=1e-3)))]
    modes = list(range(1, N_MODES + 1))
    lin = linearise(model, configs, modes, dense=False)
    assert lin.certificate.fallback == 0
    lam, J, floor = reference(model, configs, modes, floor=True)
    rel = np.abs(lin.eigenvalues - lam) / np.abs(lam)
    assert np.all(rel <= perturbed.EIG_RTOL + floor), (rel, floor)
    err = np.abs(lin.J - J) / np.abs(J).max(axis=1, keepdims=True)
    assert err.max() < 3e-7, err.max()


@settings(max_examples=12, deadline=None)
@given(seed=st.integers(0, 10_000), n_add=st.integers(1, 3))
def test_any_low_rank_addition_matches_dense_or_falls_back(seed, n_add):
    # Random free networks and random additions (masses, grounded springs, both; repeated
    # coordinates allowed): the sparse path's eigenvalues equal a dense re-solve's, and
    # every configuration is either certified or solved by Lanczos.
    rng = np.random.default_rng(seed)
    model = network(70, seed)
    configs = [Configuration("base")]
    for j in range(3):
        adds = []
        for _ in range(n_add):
            mass, spring = rng.choice([(1, 0), (0, 1), (1, 1)])
            adds.append(Addition(int(rng.integers(1, 71)), mass=mass * rng.uniform(0.1, 6),
                                 stiffness=spring * rng.uniform(1e4, 1e6)))
        configs.append(Configuration(f"c{j}", tuple(adds)))
    report = perturbed.CertificateReport()
    sols = jacobian.solve_configurations(model, configs, 4, dense=False, report=report)
    assert report.configurations == 3
    assert report.passed + report.passed_extended + report.fallback == 3
    K, M = model.stiffness(), model.mass()
    for c, sol in zip(configs, sols, strict=True):
        dk, dm = c.delta(model)
        exact = solve_elastic(K + dk, M + dm, 4, dense=True)
        assert sol.n_rigid == exact.n_rigid
        # certified (or a Lanczos re-solve, to its residual's square) plus rounding floors
        assert_eigenvalues_agree(sol.eigenvalues, exact, K + dk, M + dm,
                                 certified=perturbed.EIG_RTOL)


def test_grounded_spring_lifts_the_rigid_mode():
    sols = jacobian.solve_configurations(network(), [CONFIGS[0], CONFIGS[4]], N_MODES,
                                         dense=False)
    assert sols[0].n_rigid == 1 and sols[1].n_rigid == 0


def test_certificate_bounds_the_error_and_failures_fall_back(monkeypatch):
    model = network()
    K, M = model.stiffness(), model.mass()
    op, sol = base_operator(K, M, N_MODES)
    base = krylov.make_base(K, M, op, *sol.computed)
    rows = np.array([model.index(45)])
    dM = sp.csr_array(([5.0], (rows, rows)), shape=K.shape)
    exact = solve_elastic(K, M + dM, N_MODES, dense=True).eigenvalues
    for levels in (1, 2, 3):
        sub = krylov.build_subspaces(base, [rows], levels)[0]
        r = perturbed.ritz(base, sub, rows, [0.0], [5.0], N_MODES)
        # Ritz values are upper bounds; the bound covers the error (floor: the dense
        # reference's own round-off, ~1e-12 here)
        err = r.solution.eigenvalues / exact - 1
        assert np.all(err > -1e-11)
        assert np.all(err <= r.eig_bound + 1e-11), (levels, err, r.eig_bound)
    # a certificate that cannot hold: Lanczos takes over, the numbers stay right
    monkeypatch.setattr(perturbed, "EIG_RTOL", 0.0)
    modes = [1, 2, 3]
    lin = linearise(model, CONFIGS[:3], modes, dense=False)
    assert lin.certificate.fallback == 2
    assert_matches(lin.eigenvalues, lin.J, *reference(model, CONFIGS[:3], modes))


def test_interlacing_check():
    lam_base = np.array([1.0, 4.0, 9.0, 16.0])
    want = np.arange(3)
    eig = np.zeros(3)
    one, none = np.array([0.5]), np.array([0.0])
    # a mass lowers eigenvalue i, but not below bare eigenvalue i - 1
    assert perturbed._interlaces(lam_base, np.array([0.9, 3.0, 8.0, 15.0]), none, one, eig,
                                 want)
    assert not perturbed._interlaces(lam_base, np.array([0.9, 4.5, 8.0, 15.0]), none, one,
                                     eig, want)
    assert not perturbed._interlaces(lam_base, np.array([0.9, 3.0, 3.5, 15.0]), none, one,
                                     eig, want)
    # a spring raises it, but not above bare eigenvalue i + 1
    assert perturbed._interlaces(lam_base, np.array([2.0, 5.0, 10.0, 17.0]), one, none, eig,
                                 want)
    assert not perturbed._interlaces(lam_base, np.array([0.5, 5.0, 10.0, 17.0]), one, none,
                                     eig, want)


def test_screening_matches_full_resolves(monkeypatch):
    monkeypatch.setattr("eigenupdate.solve.screening.DENSE_LIMIT", 40)
    model = network()
    candidates = [(c, m) for c in (20, 45, 90, 3) for m in (0.5, 4.0)]
    modes = [1, 3, 5]
    s = screen(model, candidates, modes)
    assert s.certified.all() and np.nanmax(s.bound) <= perturbed.EIG_RTOL
    configs = [Configuration(f"{c}/{m}", (Addition(c, mass=m),)) for c, m in candidates]
    lam, J = reference(model, [Configuration("base")] + configs, modes)
    nm = len(modes)
    assert_matches(s.base_eigenvalues, s.base_J, lam[:nm], J[:nm])
    assert_matches(s.eigenvalues.ravel(), s.J.reshape(-1, s.J.shape[2]), lam[nm:], J[nm:])
    # the order of the candidates is kept when chunks group them by coordinate
    monkeypatch.setattr("eigenupdate.solve.screening.CHUNK", 1)
    s1 = screen(model, candidates, modes)
    np.testing.assert_allclose(s1.eigenvalues, s.eigenvalues, rtol=1e-9)  # own eigsh start


def test_update_reports_the_fast_path(monkeypatch):
    monkeypatch.setattr(jacobian, "DENSE_LIMIT", 40)
    truth = network()
    upd = {5, 100}  # one mass, one spring
    params = tuple(replace(p, update=i in upd, value=p.value * (1.03 if i in upd else 1.0))
                   for i, p in enumerate(truth.parameters))
    model = ParametricModel(truth.k0, truth.m0, params, truth.k_terms, truth.m_terms,
                            truth.coordinates, truth.coordinate_table)
    configs = CONFIGS[:3]
    modes = [1, 2, 3]
    sols = jacobian.solve_configurations(truth, configs, 3, dense=True)
    meas = {(c.name, k): Measurement(c.name, k, float(s.frequencies_hz[k - 1]))
            for c, s in zip(configs, sols, strict=True) for k in modes}
    res = update(model, configs, modes, meas)
    assert res.success
    for i in upd:
        assert res.parameters[truth.names[i]] == pytest.approx(truth.values[i], rel=1e-8)
    assert res.solver is not None and res.solver["fallback_lanczos"] == 0
    assert res.solver["certified"] == 2 * res.solver["linearisations"]


def test_krylov_level_norms_by_pythagoras():
    """Each Krylov level's |W|_M (W = A^-1 rhs before orthogonalisation) is taken from its
    Gram-Schmidt coefficients C and remainder R (|W|_M^2 = |C|^2 + |R|^2, V M-orthonormal)
    rather than from M W; it decides which levels get explicit products (rho > RHO_MAX).
    Reference: W solved and its M-norm formed directly. Each term is an inner product of
    n terms (relative rounding <= n eps, Higham's gamma_n) and a sum of m of them, so the
    two agree to (n + m) eps up to a small constant (4 here)."""
    model = network()
    K, M = model.stiffness(), model.mass()
    # about the first-guess shift, far closer to 0 than lambda_1 (base_operator moves a
    # free structure's to -lambda_1 / 10): the rigid-body mode dominates A^-1, the bare
    # modes nearly span A^-1 U, and level 0 cancels, so both kinds of level occur
    op = ShiftInvert(K, M, default_shift(K, M))
    sol = solve_elastic(K, M, N_MODES, operator=op)
    base = krylov.make_base(K, M, op, *sol.computed)
    n, kb = base.phi.shape
    rows = np.array([[10, 70], [30, 60], [44, 45]])
    blocks = krylov.Blocks(base, rows, krylov.LEVELS + 1)
    blocks.grow(krylov.LEVELS + 1)
    k = rows.shape[1]
    eps = np.finfo(float).eps
    explicit_seen = []
    for j in range(blocks.done):
        for g in range(rows.shape[0]):
            if j == 0:
                rhs = np.zeros((n, k))
                rhs[rows[g], np.arange(k)] = 1.0
            else:
                rhs = M @ blocks.QT[g, (j - 1) * k:j * k].T
            W = op.solve(rhs)
            direct = np.sqrt(np.einsum("ij,ij->j", W, M @ W))
            C, R = blocks.C[j][g], blocks.R[j][g]
            pyth = np.sqrt(np.sum(C**2, axis=0) + np.sum(R**2, axis=0))
            m = C.shape[0] + k
            np.testing.assert_allclose(pyth, direct, rtol=4 * (n + m) * eps)
            rho = direct.max() / np.linalg.svd(R, compute_uv=False).min()
            if rho > 10 * krylov.RHO_MAX or rho < krylov.RHO_MAX / 10:  # clear cases
                assert blocks.explicit[j][g] == (rho > krylov.RHO_MAX)
                explicit_seen.append(bool(blocks.explicit[j][g]))
    assert True in explicit_seen and False in explicit_seen  # both kinds of level occur
