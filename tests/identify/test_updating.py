"""Updating: recovery from error-free data (property test), weighting, Bayesian anchoring,
and the safeguards of the iteration."""

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, example, given, settings
from hypothesis import strategies as st
from models import fig2, random_network

from eigenupdate.errors import InputError
from eigenupdate.identify.identifiability import check
from eigenupdate.identify.updating import PRECISION, STATUS_MESSAGES, Step, update
from eigenupdate.identify.weights import estimator_weights
from eigenupdate.measure.measurement import Measurement
from eigenupdate.model.configurations import Configuration, mass_at
from eigenupdate.solve.jacobian import linearise, solve_configurations


def simulate(model, configs, modes, noise_hz=0.0, std_hz=None, rng=None):
    sols = solve_configurations(model, configs, max(modes))
    out = {}
    for c, s in zip(configs, sols, strict=True):
        for k in modes:
            f = float(s.frequencies_hz[k - 1])
            if noise_hz:
                f += rng.normal(0, noise_hz)
            out[(c.name, k)] = Measurement(c.name, k, f, std_hz)
    return out


@settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(2, 5))
def test_error_free_data_recovers_random_networks(seed, n):
    rng = np.random.default_rng(seed)
    truth = random_network(rng, n)
    # Perturb every coordinate with about 5 % of its mass; use every mode.
    configs = [Configuration("base")] + [
        mass_at(c, 0.05 * truth.values[c - 1], f"at {c}") for c in range(1, n + 1)
    ]
    modes = list(range(1, n + 1))
    start = truth.with_values(truth.values * rng.uniform(0.92, 1.08, truth.values.size))
    plan = check(start, configs, modes)
    assume(plan.identifiable and plan.condition_JTJ < 1e11)
    res = update(start, configs, modes, simulate(truth, configs, modes), max_iterations=50)
    assert res.success, res.message
    got = np.array([res.parameters[n_] for n_ in truth.names])
    np.testing.assert_allclose(got, truth.values, rtol=1e-6)


FIG2_CONFIGS = [Configuration("base"), mass_at(1, 0.35), mass_at(2, 0.35), mass_at(4, 0.35)]
TRUTH = fig2(k=(1e6, 1e6, 1e6, 1e6, 1e6, 0.5e6), m=(10, 10, 5, 5))


def test_weighted_least_squares_with_noise_has_honest_std():
    rng = np.random.default_rng(1)
    data = simulate(TRUTH, FIG2_CONFIGS, [1, 2, 3, 4], noise_hz=0.005, std_hz=0.005, rng=rng)
    res = update(fig2(), FIG2_CONFIGS, [1, 2, 3, 4], data, method="weighted-least-squares")
    assert res.success
    z = [(res.parameters[n] - v) / res.std[n] for n, v in zip(TRUTH.names, TRUTH.values,
                                                              strict=True)]
    assert np.max(np.abs(z)) < 4.0  # errors within the posterior std


def test_bayesian_prior_dominates_unidentifiable_parameter():
    # Only perturbing 1 and 2: rank 9 (paper Table 1). Least squares cannot settle the
    # weakest combination; the Bayesian estimator keeps it near the prior.
    configs = [Configuration("base"), mass_at(1, 0.35), mass_at(2, 0.35)]
    model = fig2()
    model = model.with_values(model.values)
    from dataclasses import replace

    params = tuple(replace(p, std=0.1 * p.value) for p in model.parameters)
    model = type(model)(model.k0, model.m0, params, model.k_terms, model.m_terms)
    data = simulate(TRUTH, configs, [1, 2, 3, 4], std_hz=0.01)
    res = update(model, configs, [1, 2, 3, 4], data, method="bayesian")
    assert res.success
    assert all(s is not None and s > 0 for s in res.std.values())
    # Posterior variance never exceeds the prior variance.
    for p in params:
        assert res.std[p.name] <= p.std * (1 + 1e-9)


def test_bayesian_needs_a_prior():
    data = simulate(TRUTH, FIG2_CONFIGS, [1, 2, 3], std_hz=0.01)
    with pytest.raises(InputError, match="needs a std"):
        update(fig2(), FIG2_CONFIGS, [1, 2, 3], data, method="bayesian")


def test_weighted_method_needs_std():
    data = simulate(TRUTH, FIG2_CONFIGS, [1, 2, 3])
    with pytest.raises(InputError, match="std_hz is empty"):
        update(fig2(), FIG2_CONFIGS, [1, 2, 3], data, method="weighted-least-squares")


def test_far_start_is_safeguarded_and_recorded():
    # Start up to 80 % off: the first plain Gauss-Newton step would make a parameter
    # negative and later ones overshoot; the iteration must bound and halve them, say
    # so, and still converge to the truth.
    f = np.array([0.54, 0.66, 1.37, 1.34, 1.3, 1.0, 1.8, 1.78, 1.39, 1.35])
    start = TRUTH.with_values(TRUTH.values * f)
    data = simulate(TRUTH, FIG2_CONFIGS, [1, 2, 3, 4])
    res = update(start, FIG2_CONFIGS, [1, 2, 3, 4], data, max_iterations=60,
                 optimizer="gauss-newton")
    kinds = {h.kind for h in res.history}
    assert {Step.BOUNDED, Step.HALVED} <= kinds, kinds
    assert all(v > 0 for h in res.history for v in h.parameters.values())
    objectives = [h.objective for h in res.history]
    assert all(b <= a for a, b in zip(objectives, objectives[1:], strict=False))
    assert res.success
    np.testing.assert_allclose([res.parameters[n] for n in TRUTH.names], TRUTH.values, rtol=1e-6)
    # the trust-region default from the same start: bounds instead of bounded steps
    tr = update(start, FIG2_CONFIGS, [1, 2, 3, 4], data, max_iterations=60)
    assert tr.success and tr.optimizer == "trust-region", tr.message
    assert all(v > 0 for h in tr.history for v in h.parameters.values())
    objectives = [h.objective for h in tr.history]
    assert all(b < a for a, b in zip(objectives, objectives[1:], strict=False))
    np.testing.assert_allclose([tr.parameters[n] for n in TRUTH.names], TRUTH.values, rtol=1e-6)


def test_a_refused_trial_step_is_halved_not_fatal(monkeypatch):
    # A full step that drives a density to its floor can leave near-massless coordinates
    # the eigen-solver refuses (seen on the 103k benchmark frame): that trial is a step
    # too long. Here every trial beyond half the Gauss-Newton step is refused.
    import eigenupdate.identify.updating as updating

    start = TRUTH.with_values(TRUTH.values * 1.05)
    data = simulate(TRUTH, FIG2_CONFIGS, [1, 2, 3, 4])
    calls = []

    def refusing(model, configs, modes, values=None, **kw):
        calls.append(values)
        if len(calls) == 2:  # the first trial point of the first iteration
            raise InputError("cannot separate rigid-body from elastic modes",
                             field="the bare structure")
        return linearise(model, configs, modes, values, **kw)

    monkeypatch.setattr(updating, "linearise", refusing)
    res = update(start, FIG2_CONFIGS, [1, 2, 3, 4], data, optimizer="gauss-newton")
    assert res.success and res.history[1].kind == Step.HALVED
    np.testing.assert_allclose([res.parameters[n] for n in TRUTH.names], TRUTH.values, rtol=1e-6)

    calls.clear()

    def always(model, configs, modes, values=None, **kw):
        calls.append(values)
        if len(calls) > 1:  # every trial point
            raise InputError("stiffness matrix is not positive semi-definite")
        return linearise(model, configs, modes, values, **kw)

    monkeypatch.setattr(updating, "linearise", always)
    res = update(start, FIG2_CONFIGS, [1, 2, 3, 4], data, optimizer="gauss-newton")
    assert res.status == 3 and res.nit == 1 and "trial step was refused" in res.message


def test_trust_region_shrinks_on_a_refused_point_and_never_runs_away(monkeypatch):
    import eigenupdate.identify.updating as updating

    start = TRUTH.with_values(TRUTH.values * 1.05)
    data = simulate(TRUTH, FIG2_CONFIGS, [1, 2, 3, 4])
    calls = []

    def refusing(model, configs, modes, values=None, **kw):
        calls.append(values)
        if len(calls) == 2:  # the first trial point
            raise InputError("cannot separate rigid-body from elastic modes")
        return linearise(model, configs, modes, values, **kw)

    monkeypatch.setattr(updating, "linearise", refusing)
    res = update(start, FIG2_CONFIGS, [1, 2, 3, 4], data)
    assert res.success and res.history[1].kind == Step.SHRUNK
    np.testing.assert_allclose([res.parameters[n] for n in TRUTH.names], TRUTH.values, rtol=1e-6)

    calls.clear()

    def always(model, configs, modes, values=None, **kw):
        calls.append(values)
        if len(calls) > 1:  # every trial point
            raise InputError("stiffness matrix is not positive semi-definite")
        return linearise(model, configs, modes, values, **kw)

    monkeypatch.setattr(updating, "linearise", always)
    res = update(start, FIG2_CONFIGS, [1, 2, 3, 4], data, max_iterations=5)
    # the region shrinks until SciPy stops (its xtol, or its evaluation limit of 4 per
    # allowed iteration + 10): not converged, in SciPy's words and ours
    assert not res.success and res.nit == 0 and res.status in (0, 3)
    assert "refused: stiffness matrix" in res.message and len(calls) <= 1 + 4 * 5 + 10


def test_turning_trial_points_down_early_changes_no_iterate(monkeypatch):
    # the line search stops a trial point once the rows solved so far reach the current
    # objective (sparse path): the same iterates as evaluating every trial point fully
    import eigenupdate.identify.updating as updating
    from eigenupdate.model.parameters import Parameter
    from eigenupdate.model.spring_mass import Mass, Spring, spring_mass_model
    from eigenupdate.solve import jacobian

    n = 60  # a chain on the sparse path; four of its parameters unknown
    unknown = {"m1", "m30", "k2", "k45"}

    def chain(scale):
        ms = [Mass(Parameter(f"m{i}", 2.0 * scale.get(f"m{i}", 1.0), update=f"m{i}" in unknown),
                   i) for i in range(1, n + 1)]
        ks = [Spring(Parameter(f"k{i}", 1e5 * scale.get(f"k{i}", 1.0),
                               update=f"k{i}" in unknown), (i - 1, i)) for i in range(1, n + 1)]
        return spring_mass_model(ms, ks, n)

    monkeypatch.setattr(jacobian, "DENSE_LIMIT", 20)
    truth = chain({})
    start = chain({"m1": 1.6, "m30": 0.5, "k2": 0.4, "k45": 1.9})
    configs = [Configuration("base"), mass_at(1, 1.0), mass_at(30, 1.0), mass_at(50, 1.0)]
    modes = [1, 2, 3]
    data = simulate(truth, configs, modes)
    turned = []
    real = jacobian.solve_on_base

    def counting(*a, **kw):
        try:
            return real(*a, **kw)
        except jacobian.Rejected:
            turned.append(1)
            raise

    monkeypatch.setattr(jacobian, "solve_on_base", counting)
    early = update(start, configs, modes, data, max_iterations=60, optimizer="gauss-newton")
    monkeypatch.setattr(updating, "linearise",
                        lambda *a, reject=None, **kw: linearise(*a, **kw))
    full = update(start, configs, modes, data, max_iterations=60, optimizer="gauss-newton")
    assert turned, [h.kind for h in early.history]  # some trial points turned down early
    assert [h.kind for h in early.history] == [h.kind for h in full.history]
    np.testing.assert_allclose([h.objective for h in early.history],
                               [h.objective for h in full.history], rtol=1e-9, atol=1e-20)
    assert early.nit == full.nit and early.success

def test_fixed_parameters_are_not_updated():
    from dataclasses import replace

    model = fig2()
    params = tuple(replace(p, update=p.name != "k6") for p in model.parameters)
    model = type(model)(model.k0, model.m0, params, model.k_terms, model.m_terms)
    data = simulate(TRUTH, FIG2_CONFIGS, [1, 2, 3])
    res = update(model, FIG2_CONFIGS, [1, 2, 3], data)
    assert res.parameters["k6"] == 0.6e6
    assert "k6" not in res.std


def test_result_in_optimize_result_shape():
    data = simulate(TRUTH, FIG2_CONFIGS, [1, 2, 3, 4], std_hz=0.01)
    res = update(fig2(), FIG2_CONFIGS, [1, 2, 3, 4], data, method="weighted-least-squares")
    # trust-region: SciPy's status, -2 when our convergence test stopped it (then our
    # reason, not SciPy's words about its callback)
    assert res.success and res.optimizer == "trust-region" and res.status in (-2, 1, 2, 3, 4)
    assert res.message.startswith("converged") and "callback" not in res.message
    gn = update(fig2(), FIG2_CONFIGS, [1, 2, 3, 4], data, method="weighted-least-squares",
                optimizer="gauss-newton")
    assert gn.success and gn.status in (1, 2, 4) and gn.status in STATUS_MESSAGES
    assert res.names == TRUTH.names and res.nfev >= res.nit + 1
    # error-free data with a stated std: it stops once the next (Gauss-Newton) step, which
    # for zero residuals is the remaining error to first order, is below PRECISION of
    # every posterior std
    std = np.array([res.std[n] for n in res.names])
    assert np.all(np.abs(res.x - TRUTH.values) <= 2 * PRECISION * std)
    assert res.x.tolist() == [res.parameters[n] for n in res.names]
    assert res.jac.shape == (16, 10) and res.cov.shape == (10, 10)
    np.testing.assert_allclose(np.sqrt(np.diag(res.cov)), [res.std[n] for n in res.names])
    assert res.cost == pytest.approx(0.5 * res.history[-1].objective)
    assert [h.iteration for h in res.history] == list(range(res.nit + 1))
    # SciPy's mapping: res["x"] is res.x; fun is the residual vector whose half square
    # is cost (least_squares' definition), here (model - measured) lambda / sigma_lambda
    # with sigma_lambda = 8 pi^2 f sigma_f (no prior rows: the prior weights are 0)
    assert res["x"] is res.x and "fun" in res and "converged" not in res.keys()
    assert res.cost == pytest.approx(0.5 * res.fun @ res.fun, rel=1e-12)
    lam = (2 * np.pi * res.updated_hz) ** 2 - (2 * np.pi * res.measured_hz) ** 2
    np.testing.assert_allclose(res.fun[:16], lam / (8 * np.pi**2 * res.measured_hz * 0.01),
                               rtol=1e-6, atol=1e-9 * np.abs(lam).max())
    np.testing.assert_array_equal(res.fun[16:], 0.0)
    doc = res.to_dict()
    assert doc["schema"] == "eigenupdate.update/2"
    for key in ("parameters", "std", "success", "history", "frequencies", "x", "fun",
                "status", "nit", "nfev", "cov"):
        assert key in doc
    for old in ("converged", "iterations", "steps"):  # SciPy's names only, once each
        assert old not in doc
    with pytest.raises(AttributeError):
        res.nit = 0  # frozen


def test_posterior_covariance_is_the_inverse_normal_matrix():
    # the SVD route equals (A^T A)^-1, formed here the other way on a well-conditioned plan
    data = simulate(TRUTH, FIG2_CONFIGS, [1, 2, 3, 4], std_hz=0.01)
    res = update(fig2(), FIG2_CONFIGS, [1, 2, 3, 4], data, method="weighted-least-squares")
    lin = linearise(res.model, FIG2_CONFIGS, [1, 2, 3, 4])
    w = estimator_weights(res.model, "weighted-least-squares", res.rows, data).rows
    A = w[:, None] * lin.J
    np.testing.assert_allclose(res.cov, np.linalg.inv(A.T @ A), rtol=1e-6)


def test_check_and_update_agree_with_one_tiny_std():
    # Issue 7: with one tiny std, update took the rank of the weighted J (7 here) and check
    # that of the unweighted J^T J (10). Both now take it from the same SVD.
    data = simulate(TRUTH, FIG2_CONFIGS, [1, 2, 3, 4], std_hz=0.01)
    rows = [(c.name, k) for c in FIG2_CONFIGS for k in (1, 2, 3, 4)]
    for tiny, expected in ((1e-9, 10), (1e-15, 7)):
        data[("base", 1)] = Measurement("base", 1, data[("base", 1)].frequency_hz, tiny)
        w = estimator_weights(fig2(), "weighted-least-squares", rows, data)
        plan = check(fig2(), FIG2_CONFIGS, [1, 2, 3, 4], weights=w.rows, prior=w.prior)
        assert plan.rank == expected and plan.weighting == "measurement std"
        if plan.identifiable:
            res = update(fig2(), FIG2_CONFIGS, [1, 2, 3, 4], data,
                         method="weighted-least-squares")
            assert res.identifiability.rank == 10 and res.success
        else:
            with pytest.raises(InputError, match=f"rank {plan.rank} of J for 10"):
                update(fig2(), FIG2_CONFIGS, [1, 2, 3, 4], data, method="weighted-least-squares")


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(2, 5))
@example(seed=124674, n=5)  # a trial point turned down on the way (nfev > nit)
def test_last_step_without_a_solve_is_what_a_solve_gives(seed, n):
    # Where the trust region takes its last Gauss-Newton step without solving the point it
    # reaches (Step.FINAL), a solve there must agree with what it reported: the step
    # after it below xtol (the message's claim), and the eigenvalues, which it predicted
    # as lambda(z) + J(z) dz, within the trapezoid rule's bound |(J(z + dz) - J(z)) dz|
    # (plus the eigen-solver's 1e-12, dense path) of the solved ones.
    rng = np.random.default_rng(seed)
    truth = random_network(rng, n)
    configs = [Configuration("base")] + [
        mass_at(c, 0.05 * truth.values[c - 1], f"at {c}") for c in range(1, n + 1)
    ]
    modes = list(range(1, n + 1))
    start = truth.with_values(truth.values * rng.uniform(0.92, 1.08, truth.values.size))
    plan = check(start, configs, modes)
    assume(plan.identifiable and plan.condition_JTJ < 1e11)
    data = simulate(truth, configs, modes)
    res = update(start, configs, modes, data, max_iterations=50)
    assert res.success, res.message
    assume(res.history[-1].kind is Step.FINAL)
    x = np.array([res.parameters[n_] for n_ in start.names])
    before = np.array([res.history[-2].parameters[n_] for n_ in start.names])
    lin = linearise(start, configs, modes, x)
    lam_meas = np.array([(2 * np.pi * data[r].frequency_hz) ** 2 for r in lin.rows])
    dz = np.linalg.lstsq(lin.normalised, lam_meas - lin.eigenvalues, rcond=None)[0]
    assert np.max(np.abs(dz)) < 1e-8  # update's default xtol
    lam_reported = (2 * np.pi * res.updated_hz) ** 2
    bound = np.abs((lin.J - res.jac) @ (x - before)) + 1e-12 * lin.eigenvalues
    assert np.all(np.abs(lam_reported - lin.eigenvalues) <= bound)


def _noisy_network(seed, added, stated, n=6, noise=3e-3):
    """A random network of n masses, a bare test and one with ``added`` of each mass,
    every mode measured with relative noise ``noise`` and std ``stated`` (relative);
    a start 5 % off."""
    rng = np.random.default_rng(seed)
    truth = random_network(rng, n)
    configs = [Configuration("base")] + [
        mass_at(c, added * truth.values[c - 1], f"at {c}") for c in range(1, n + 1)]
    modes = list(range(1, n + 1))
    data = {k: Measurement(m.configuration, m.mode, m.frequency_hz * (1 + noise * rng.normal()),
                           stated * m.frequency_hz)
            for k, m in simulate(truth, configs, modes).items()}
    start = truth.with_values(truth.values * rng.uniform(0.95, 1.05, truth.values.size))
    return start, configs, modes, data


@pytest.mark.parametrize("seed", [8, 26])
def test_noisy_fit_stops_at_the_data_precision(monkeypatch, seed):
    """Issue 21 item 5: with 0.3 % noise on 2 % added masses the trust region creeps (its
    steps cut to a tenth of Gauss-Newton's); these two seeds ran to the limit at 20 with
    the test on each parameter's step alone (below 0.01 std) though the fit was done.
    Source of the check: the same fit continued to its optimum (the joint
    test off, 200 iterations); the stop claims the optimum lies within JOINT posterior std,
    that is, at most JOINT^2 = 0.01 data variances below the stopped objective (exact for
    the Gauss-Newton model; what it gives here is the bound checked)."""
    from eigenupdate.identify import fit as fit_module
    start, configs, modes, data = _noisy_network(seed, 0.02, 3e-3)
    res = update(start, configs, modes, data, method="weighted-least-squares")
    assert res.success and res.nit <= 20, res.message
    assert "data's precision" in res.message
    joint = fit_module.JOINT
    monkeypatch.setattr(fit_module, "JOINT", 0.0)
    best = update(start, configs, modes, data, method="weighted-least-squares",
                  max_iterations=200)
    assert best.success and best.nit > res.nit, best.message
    assert 0 <= 2 * res.cost - 2 * best.cost <= joint**2, (res.cost, best.cost)


def test_no_precision_claim_where_the_residual_is_not_the_stated_noise(monkeypatch):
    """The joint test stands on the stated std: with 0.3 % noise stated as 0.1 % the
    objective lies far above its chi-square, the residual is not that noise, and
    "converged at the data's precision" is not said; without the chi-square test (its
    quantile at 1) the same fit says it, so the check can fail."""
    from eigenupdate.identify import fit as fit_module
    start, configs, modes, data = _noisy_network(16, 0.2, 1e-3)
    res = update(start, configs, modes, data, method="weighted-least-squares")
    dof = res.fun.size - len(res.names)
    assert 2 * res.cost > 3 * dof
    assert "data's precision" not in res.message
    monkeypatch.setattr(fit_module, "CHI2_LEVEL", 1.0)
    res = update(start, configs, modes, data, method="weighted-least-squares")
    assert "data's precision" in res.message


@pytest.mark.parametrize("optimizer", ["gauss-newton", "trust-region"])
def test_a_fit_at_the_eigen_solvers_precision_is_converged(optimizer):
    """Source: the model's own eigenvalues (error-free data). With the step and decrease
    tests off (xtol = ftol = 0) the fit runs until no step lowers the objective, which
    happens where the residuals are the eigen-solver's own rounding: then the objective
    lies below what eigenvalue errors of SOLVER_RTOL give (Fit.solver_floor), and that is
    convergence, not the "no step lowers the objective" failure (status 3) it was. Data
    that no parameters fit (one frequency 1 % off) end far above that floor, and the
    floor claims nothing there (Gauss-Newton stops at the least-squares minimum by its
    decrease test, the trust region still fails by the line search)."""
    from eigenupdate.identify.optimizers import SOLVER_RTOL

    truth = fig2()
    start = truth.with_values(truth.values * 1.03)
    modes = [1, 2, 3, 4]
    data = simulate(truth, FIG2_CONFIGS, modes)
    res = update(start, FIG2_CONFIGS, modes, data, optimizer=optimizer, xtol=0.0, ftol=0.0,
                 max_iterations=40)
    assert res.success, res.message
    assert "eigen-solver's precision" in res.message
    lam = np.array([(2 * np.pi * m.frequency_hz) ** 2 for m in data.values()])
    assert 2 * res.cost <= float(np.sum((SOLVER_RTOL * lam) ** 2))
    got = np.array([res.parameters[n] for n in truth.names])
    assert np.max(np.abs(got / truth.values - 1)) <= 1e-6

    key = next(iter(data))
    bad = dict(data)
    bad[key] = Measurement(key[0], key[1], data[key].frequency_hz * 1.01)
    res = update(start, FIG2_CONFIGS, modes, bad, optimizer=optimizer, xtol=0.0, ftol=0.0,
                 max_iterations=40)
    assert "precision" not in res.message
    assert 2 * res.cost > 1e6 * float(np.sum((SOLVER_RTOL * lam) ** 2))
