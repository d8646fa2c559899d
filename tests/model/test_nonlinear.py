"""Parameters that enter K and M nonlinearly (model/parametric.py ``Term``): a strip whose
bending stiffness is E b t^3 / 12 and mass rho b t, with E, t1, t2 the parameters.

Independent references: the same strip as a linear beam model with EI and rho A worked
out by hand (a second construction), central finite differences of K, M, the
eigenvalues and the Jacobian, and the scaling law of a beam (lambda ~ E t^2 / rho) for
which parameter combinations the bare structure cannot separate.
"""

import numpy as np
import pytest
import scipy.linalg
from models import thickness_strip

from eigenupdate.design.montecarlo import TrialSetup, montecarlo
from eigenupdate.design.plan import design_plan
from eigenupdate.design.spec import DesignSpec
from eigenupdate.errors import InputError
from eigenupdate.identify.identifiability import check
from eigenupdate.identify.updating import update
from eigenupdate.io.measurements import Measurement
from eigenupdate.model.configurations import Configuration, mass_at
from eigenupdate.model.parameters import Parameter
from eigenupdate.model.parametric import ParametricModel, Term
from eigenupdate.solve.jacobian import linearise, solve_configurations
from eigenupdate.solve.screening import screen_configurations

MODES = (1, 2, 3)
TRUTH = np.array([73e9, 0.0043, 0.0047])  # E, t1, t2 (initial 70e9, 0.004, 0.005)


def _plan(model):
    # masses at the strip's two ends and its middle (coordinates: node i Z is 2i - 1)
    nodes = model.coordinates.max() // 2
    return [Configuration("base"), mass_at(1, 0.05), mass_at(2 * (nodes // 2) + 1, 0.05),
            mass_at(2 * nodes - 1, 0.08)]


def _data(model, configs, values, std_hz=None):
    sols = solve_configurations(model, configs, max(MODES), values)
    return {(c.name, k): Measurement(c.name, k, float(np.sqrt(s.eigenvalues[k - 1]) / (2 * np.pi)),
                                     std_hz)
            for c, s in zip(configs, sols, strict=True) for k in MODES}


def _rel(a, b):
    return np.max(np.abs(a - b)) / np.max(np.abs(b))


def test_stiffness_and_mass_equal_the_hand_worked_linear_beam():
    model, unit = thickness_strip()
    b, rho = 0.05, 2700.0
    for s in (model.values, TRUTH):
        t = np.where(np.arange(8) < 4, s[1], s[2])
        ei, rho_a = s[0] * b * t**3 / 12, rho * b * t
        lin = unit.with_values(np.concatenate([ei, rho_a]))
        # the same sums in another order: round-off of a few ulps of the largest entry
        assert _rel(model.stiffness(s).toarray(), lin.stiffness().toarray()) < 1e-13
        assert _rel(model.mass(s).toarray(), lin.mass().toarray()) < 1e-13


@pytest.mark.parametrize("j", [0, 1, 2])
def test_dK_dM_match_central_differences(j):
    model, _ = thickness_strip()
    s = TRUTH
    at = model.with_values(s)
    h = 1e-4 * s[j]
    up, dn = s.copy(), s.copy()
    up[j] += h
    dn[j] -= h
    # K is cubic in t: the central difference's error is h^2 K''' / 6, relative
    # (h / t)^2 / 3 = 3e-9, and its round-off eps |K| / h is 2e-12 relative
    for exact, fun in ((at.k_terms[j], model.stiffness), (at.m_terms[j], model.mass)):
        if exact is None:
            assert np.abs((fun(up) - fun(dn)).toarray()).max() == 0
            continue
        fd = (fun(up) - fun(dn)).toarray() / (2 * h)
        assert _rel(exact.toarray(), fd) < 1e-8


@pytest.mark.parametrize(("n_el", "dense"), [(8, True), (40, False)])
def test_jacobian_matches_central_differences_of_the_eigenvalues(n_el, dense):
    # dense path, and the sparse path (restricted Fox-Kapoor products, perturbed solves)
    # forced; both evaluated at TRUTH, away from the model's own values
    model, _ = thickness_strip(n_el=n_el)
    configs = _plan(model)
    lin = linearise(model, configs, MODES, TRUTH, dense=dense)
    f = 1e-4  # relative step
    fd = np.empty_like(lin.J)
    for j in range(3):
        h = f * TRUTH[j]
        up, dn = TRUTH.copy(), TRUTH.copy()
        up[j] += h
        dn[j] -= h
        lu = linearise(model, configs, MODES, up, dense=dense).eigenvalues
        ld = linearise(model, configs, MODES, dn, dense=dense).eigenvalues
        fd[:, j] = (lu - ld) / (2 * h)
    # bound: truncation f^2, plus each eigenvalue's round-off eps * kappa relative
    # (kappa = lambda_max / lambda_1 of the strip, backward-stable solvers) over f
    lam = scipy.linalg.eigh(model.stiffness(TRUTH).toarray(), model.mass(TRUTH).toarray(),
                            eigvals_only=True)
    kappa = lam[-1] / lam[2]  # two rigid-body modes
    bound = f**2 + np.finfo(float).eps * kappa / f
    scale = np.abs(lin.eigenvalues)[:, None] / TRUTH[None, :]
    assert np.max(np.abs(lin.J - fd) / scale) < 2 * bound
    # J at TRUTH is not the J at the model's values (the linear shortcut would be)
    assert _rel(lin.J, linearise(model, configs, MODES, dense=dense).J) > 1e-2


def test_bare_structure_cannot_separate_E_from_t_but_masses_can():
    # K ~ E t^3, M ~ t: (E / beta^2, beta t) scales K and M alike and leaves every
    # eigenvalue of the bare strip, so its J has rank 2 of 3; added masses break it
    # (normalised direction (-2, 1, 1) / sqrt 6). The bare J is singular to within the
    # eigenvalues' round-off eps * kappa (kappa = lambda_max / lambda_1 ~ 3e4 here)
    model, _ = thickness_strip()
    bare = check(model, [Configuration("base")], MODES)
    s = np.array(bare.singular_values)
    assert s[-1] / s[0] < 100 * np.finfo(float).eps * 3e4
    w = np.array([bare.weakest[n] for n in model.names])
    assert np.abs(w @ np.array([-2.0, 1.0, 1.0]) / np.sqrt(6)) == pytest.approx(1.0, abs=1e-9)
    plan = check(model, _plan(model), MODES)
    assert plan.rank == 3 and plan.condition_J < 1e4


@pytest.mark.parametrize("optimizer", ["trust-region", "gauss-newton"])
def test_update_recovers_thicknesses_and_E_from_error_free_data(optimizer):
    model, _ = thickness_strip()
    configs = _plan(model)
    res = update(model, configs, MODES, _data(model, configs, TRUTH), optimizer=optimizer,
                 xtol=1e-12, max_iterations=30)
    assert res.success
    # error-free data: the fit is exact, limited by the eigen-solver's round-off
    # (1e-13 in lambda) over cond(J) (~1e4 here): far inside 1e-6
    assert np.max(np.abs(res.x / TRUTH - 1)) < 1e-6
    assert res.model.values == pytest.approx(TRUTH, rel=1e-6)


def test_bayesian_update_and_its_posterior_std():
    model, _ = thickness_strip(std=0.1)
    configs = _plan(model)
    data = _data(model, configs, TRUTH, std_hz=1e-3)
    res = update(model, configs, MODES, data, method="bayesian", xtol=1e-12)
    assert res.success
    std = np.array([res.std[n] for n in model.names])
    # error-free data, weak prior: the estimate lies within a posterior std of the truth
    assert np.all(np.abs(res.x - TRUTH) < std)
    # the posterior std is that of the linearised problem at the solution
    lin = linearise(model, configs, MODES, res.x)
    w = 1 / (8 * np.pi**2 * np.array([data[r].frequency_hz for r in lin.rows]) * 1e-3)
    A = np.vstack([w[:, None] * lin.J, np.diag(1 / (0.1 * model.values))])
    assert std == pytest.approx(np.sqrt(np.diag(np.linalg.inv(A.T @ A))), rel=1e-6)


def test_screening_at_other_values_matches_linearise():
    # screening re-forms the derivatives at its values on the sparse (projected) path
    model, _ = thickness_strip(n_el=250)
    configs = _plan(model)[1:]
    s = screen_configurations(model, configs, MODES, TRUTH)
    lin = linearise(model, [Configuration("base"), *configs], MODES, TRUTH, dense=True)
    J = lin.J.reshape(len(configs) + 1, len(MODES), 3)
    scale = lin.eigenvalues.reshape(J.shape[:2])[..., None] / TRUTH
    # the dense reference's own round-off: eps * kappa relative (kappa = lambda_max /
    # lambda_1 of the 250-element strip); the Ritz J of the perturbed configurations
    # carries the certified eigenvector error (~1e-10) besides
    lam = scipy.linalg.eigh(model.stiffness(TRUTH).toarray(), model.mass(TRUTH).toarray(),
                            eigvals_only=True)
    bound = np.finfo(float).eps * lam[-1] / lam[2]
    assert np.max(np.abs(s.base_J - J[0]) / scale[0]) < 10 * bound
    assert np.max(np.abs(s.J - J[1:]) / scale[1:]) < 10 * bound + 1e-8


def test_design_and_montecarlo_run_on_thickness_parameters():
    model, _ = thickness_strip(std=0.1)
    spec = DesignSpec(coordinates=(1, 5, 9, 13, 17), masses=(0.05,), configurations=2,
                      modes=MODES, frequency_std_relative=1e-3, prior_draws=0)
    r = design_plan(model, spec, "bayesian")
    assert len(r.chosen) == 2 and r.plans[0].std is not None
    configs = (Configuration("base"), *(r.candidates[i].configuration for i in r.chosen))
    std = {(c.name, k): 0.01 for c in configs for k in MODES}
    setup = TrialSetup(model, configs, MODES, std, "bayesian", 30, 1e-8, truth=TRUTH)
    mc = montecarlo(setup, 6, seed=1)
    assert all(t["converged"] for t in mc.trials)
    for t in mc.trials:  # each within 5 reported std (noise 0.01 Hz, Gaussian)
        assert np.all(np.abs(t["estimate"] - t["truth"]) < 5 * t["std"])


def test_linear_parts_make_the_plain_linear_model():
    k = np.eye(2)
    m = ParametricModel.from_parts(np.zeros((2, 2)), np.eye(2), (Parameter("a", 2.0),),
                                   [Term(k, ((0, 1.0),), 3.0)], [])
    assert not m.nonlinear and m.k_parts == ()
    assert m.k_terms[0].toarray() == pytest.approx(3 * k)


def test_refusals():
    z = np.zeros((1, 1))
    p = (Parameter("t", 0.0),)
    with pytest.raises(InputError, match="power 0.5: it must be > 0"):
        ParametricModel.from_parts(z, np.eye(1), p, [Term(np.eye(1), ((0, 0.5),))], [])
    with pytest.raises(InputError, match="each once"):
        ParametricModel.from_parts(z, np.eye(1), p, [Term(np.eye(1), ((0, 1.0), (0, 2.0)))],
                                   [])
    with pytest.raises(InputError, match="parameter indices"):
        ParametricModel.from_parts(z, np.eye(1), p, [Term(np.eye(1), ((1, 2.0),))], [])
    # a cube at 0 is fine: its derivative there is 0
    m = ParametricModel.from_parts(z, np.eye(1), p, [Term(np.eye(1), ((0, 3.0),))], [])
    assert m.k_terms[0].toarray()[0, 0] == 0 and m.at([2.0]).k_terms[0][0, 0] == 12.0
