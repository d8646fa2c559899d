"""Robust mode pairing (issue 21): model modes tracked by MAC, and clusters of modes the
data cannot order fitted through the sum of their eigenvalues."""

import numpy as np
import pytest
from models import PAIRING_CONFIGS as CONFIGS
from models import PAIRING_MODES as MODES
from models import chains, swapped_case
from test_updating import simulate

import eigenupdate.identify.pairing as pairing_mod
from eigenupdate.identify.pairing import Pairing
from eigenupdate.identify.updating import update
from eigenupdate.model.configurations import Configuration, mass_at
from eigenupdate.model.parameters import Parameter
from eigenupdate.model.spring_mass import Mass, Spring, spring_mass_model
from eigenupdate.report.text import update_text
from eigenupdate.solve.jacobian import linearise, solve_configurations


def order_differs(a, b):
    """Configurations whose order-paired modes of a and b are different shapes."""
    out = []
    for c, s, t in zip(CONFIGS, solve_configurations(a, CONFIGS, 4),
                       solve_configurations(b, CONFIGS, 4), strict=True):
        if np.any(np.abs(np.diag(s.modes.T @ t.modes)) < 0.5):  # unit masses: plain MAC
            out.append(c.name)
    return out


def error(res, truth):
    return max(abs(res.parameters[n] / v - 1) for n, v in zip(truth.names, truth.values,
                                                             strict=True))


@pytest.mark.parametrize("optimizer", ["trust-region", "gauss-newton"])
@pytest.mark.parametrize(("seed", "swapped"), [(0, "at 1"), (5, "at 4")])
def test_modes_that_swap_order_between_start_and_truth(optimizer, seed, swapped, monkeypatch):
    # of seeds 0-59, 29 give one configuration whose modes swap order; with the pairing
    # of issue 21 both optimisers reach the truth in all 29, by order alone the trust
    # region in 16 and Gauss-Newton in 15 (a scan run once, not shipped); two cases where
    # order alone fails with both are checked here
    truth, start = swapped_case(seed)
    assert order_differs(start, truth) == [swapped]
    data = simulate(truth, CONFIGS, MODES)
    res = update(start, CONFIGS, MODES, data, optimizer=optimizer, max_iterations=50)
    assert res.success and error(res, truth) < 1e-6, res.message
    assert any(c == swapped for c, _ in res.pairing["clusters"])
    assert any(n["kind"] == "cluster" and n["configuration"] == swapped
               for n in res.pairing["notes"])
    assert res.to_dict()["pairing"]["equations"] < len(res.rows)
    text = update_text(res, dict(zip(start.names, start.values.tolist(), strict=True)), "")
    assert f"({optimizer})" in text and "sum of their eigenvalues" in text

    # the old pairing, by order alone, from the same start: a wrong basin, far from both
    # the truth and a fit of the data
    monkeypatch.setattr(pairing_mod, "KAPPA", 0.0)
    monkeypatch.setattr(Pairing, "match", lambda self, shapes: (np.arange(len(self.rows)), []))
    old = update(start, CONFIGS, MODES, data, optimizer=optimizer, max_iterations=50)
    assert error(old, truth) > 0.1 and old.cost > 1e6 * max(res.cost, 1e-3)


def test_cluster_sum_sensitivity_is_smooth_across_a_crossing():
    # the sum of a cluster's eigenvalues and its derivative (the sum of the Fox-Kapoor
    # rows) against central differences, at a point where the two modes cross exactly
    # (kA1 = kB1, equal masses: a repeated eigenvalue, where each eigenvalue alone has
    # no derivative): the step is taken off the crossing, the sum is differentiable
    model = chains((1e5, 1e5), (1e5 * (1 + 1e-3), 1e5))
    lin = linearise(model, [Configuration("base")], [1, 2])
    total = lin.J[0] + lin.J[1]  # 1e-3 off the crossing: Fox-Kapoor is defined
    x = model.values.copy()
    x[6] = 1e5  # kB1 onto the crossing
    for j in range(8):
        h = 1e-6 * x[j]
        up, dn = x.copy(), x.copy()
        up[j] += h
        dn[j] -= h
        s = [np.sum(solve_configurations(model, [Configuration("base")], 2, v)[0]
                    .eigenvalues) for v in (up, dn)]
        fd = (s[0] - s[1]) / (2 * h)
        # the sum at the crossing and 1e-3 off differ by O(1e-3) of the entry
        assert fd == pytest.approx(total[j], rel=3e-3, abs=1e-9 * np.max(np.abs(total))), j


def test_tracking_follows_the_shapes_not_the_order():
    rows = [("base", 1), ("base", 2)]
    lam = np.array([1.0, 2.0])
    p = Pairing(rows, lam, lam, np.zeros(2), np.ones(2), np.ones(2))
    e1, e2 = np.array([[1.0], [0.0]]), np.array([[0.0], [1.0]])
    p.accept(np.arange(2), [], (np.hstack([e1, e2]),), 0)
    perm, pending = p.match((np.hstack([e2, e1 + 0.1 * e2]),))  # the two have crossed
    assert perm.tolist() == [1, 0] and pending == []
    p.accept(perm, pending, (np.hstack([e2, e1]),), 3)
    assert [n.kind for n in p.notes] == ["re-paired"] and p.notes[0].iteration == 3
    # four modes mixed beyond recognition (every MAC 1/4): order, and the result says so
    rows = [("base", k) for k in (1, 2, 3, 4)]
    lam = np.arange(1.0, 5.0)
    p = Pairing(rows, lam, lam, np.zeros(4), np.ones(4), np.ones(4))
    p.accept(np.arange(4), [], (np.eye(4),), 0)
    hadamard = np.array([[1, 1, 1, 1], [1, -1, 1, -1], [1, 1, -1, -1], [1, -1, -1, 1]]) / 2
    perm, pending = p.match((hadamard,))
    assert perm.tolist() == [0, 1, 2, 3] and pending[0][0] == "tracking lost"


@pytest.mark.parametrize("optimizer", ["gauss-newton", "trust-region"])
def test_clusters_the_start_made_are_resolved_at_the_fit(optimizer):
    # Fig. 2 system with 25 % priors, truth drawn from them (trial 68 of a Monte Carlo
    # with seed 0): at the start the model's error makes modes 2 and 3 (84 and 94 Hz)
    # look exchangeable, and fitted through their sum the update converged 83 % off the
    # truth. At the fit their pairing is clear: released and refitted, the estimate is
    # within 1 % (the posterior std of the worst parameter is about 1.5 %).
    from models import fig2

    from eigenupdate.design.prior import draw_values
    from eigenupdate.measure.measurement import Measurement

    base = fig2()
    model = base.with_values(base.values)
    model = type(model)(model.k0, model.m0, tuple(
        p.__class__(p.name, p.value, 0.25 * p.value) for p in model.parameters),
        model.k_terms, model.m_terms, model.coordinates)
    configs = [Configuration("base"), mass_at(1, 2.0), mass_at(3, 1.0), mass_at(4, 1.0)]
    modes = [1, 2, 3, 4]
    rng = np.random.default_rng(np.random.SeedSequence(0).spawn(200)[68])
    truth = draw_values(model, rng)
    sols = solve_configurations(model, configs, 4, truth)
    meas = {(c.name, k): Measurement(c.name, k, float(s.frequencies_hz[k - 1]
                                                      + rng.normal(0.0, 0.01)), 0.01)
            for c, s in zip(configs, sols, strict=True) for k in modes}
    res = update(model, configs, modes, meas, method="bayesian", optimizer=optimizer)
    assert res.success
    assert np.max(np.abs(res.x / truth - 1)) < 0.01
    kinds = [n["kind"] for n in res.pairing["notes"]]
    assert "cluster resolved" in kinds and res.pairing["equations"] == 16
    # the refit numbers on and shares the iteration limit (it restarted at 1 before)
    numbers = [h.iteration for h in res.history]
    assert numbers == list(range(len(numbers))) and res.nit <= 20


def star(k, c, hub=3.0):
    """Five unit masses 1-5 each on a ground spring k_i and tied to mass 6 (``hub``) by
    c_i: four of its modes (2-5) lie within a fraction of a per cent when the k_i do."""
    ms = [Mass(Parameter(f"m{i}", 1.0, update=False), i) for i in range(1, 6)]
    ms.append(Mass(Parameter("m6", hub), 6))
    ks = [Spring(Parameter(f"k{i}", k[i - 1]), (0, i)) for i in range(1, 6)]
    ks += [Spring(Parameter(f"c{i}", c[i - 1]), (i, 6)) for i in range(1, 6)]
    return spring_mass_model(ms, ks, 6)


def test_measured_modes_ending_inside_a_group_of_close_modes_are_noted():
    """Source: the model's own eigenvalues. Eigenvalues 2-5 of this star lie within
    0.33 % (frequencies 0.16 %); measuring modes 1-4 cuts the group (mode 5, not
    measured, is as close), which the pairing notes ("cut group") for the configurations
    where it happens; measuring 1-5 takes the whole group (eigenvalue 6 is 5.8 % higher)
    and no such note is made."""
    rng = np.random.default_rng(3)
    truth = star(1e4 * (1 + 1e-3 * rng.standard_normal(5)),
                 2e3 * (1 + 1e-3 * rng.standard_normal(5)))
    lam = solve_configurations(truth, [Configuration("base")], 6)[0].eigenvalues
    assert (lam[4] - lam[1]) / lam[1] < 4e-3 < (lam[5] - lam[4]) / lam[4]
    start = truth.with_values(truth.values * np.where(
        [p.update for p in truth.parameters], rng.uniform(0.97, 1.03, truth.values.size), 1))
    configs = [Configuration("base")] + [mass_at(c, 0.1, f"at {c}") for c in range(1, 7)]
    notes = {}
    for first, n in ((1, 4), (1, 5), (2, 4)):
        modes = list(range(first, n + 1))
        res = update(start, configs, modes, simulate(truth, configs, modes),
                     max_iterations=30)
        notes[first, n] = [x for x in res.pairing["notes"] if x["kind"] == "cut group"]
    assert any(x["configuration"] == "base" and x["modes"][-1] == 4 for x in notes[1, 4])
    assert "mode 5 (not measured)" in notes[1, 4][0]["reason"]
    assert "leave it out (modes up to 1)" in notes[1, 4][0]["reason"]
    assert notes[1, 5] == []
    # measuring modes 2-4: a group from mode 2 leaves nothing below it to keep
    assert any(x["modes"][0] == 2 for x in notes[2, 4])
    for x in notes[2, 4]:
        assert ("leave it out" in x["reason"]) == (x["modes"][0] > 2), x
