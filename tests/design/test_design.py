"""Test planning (`eigenupdate design`): the search against the exhaustive optimum on the
paper's two examples, the predicted covariance against the updater's own, and refusals."""

import json
import math
from dataclasses import replace

import numpy as np
import pytest
from conftest import EXAMPLES
from hypothesis import given, settings
from hypothesis import strategies as st

from eigenupdate.design.covariance import posterior_covariance
from eigenupdate.design.plan import design_plan
from eigenupdate.design.search import PlanScorer, exhaustive, greedy_exchange
from eigenupdate.identify.updating import update
from eigenupdate.io.study import load_study
from eigenupdate.measure.measurement import Measurement
from eigenupdate.model.configurations import BASE, Configuration
from eigenupdate.solve.jacobian import solve_configurations

FIG2 = EXAMPLES / "paper_fig2" / "study.toml"
BEAM = EXAMPLES / "paper_beam" / "study.toml"


def test_fig2_designed_plan_is_the_exhaustive_optimum():
    # Paper Fig. 2 system: candidates 4 coordinates x {0.35, 1, 2} kg, 3 configurations,
    # modes 1-4, 0.01 Hz; the paper's plan (0.35 kg at 1, 2, 4) is the study's own
    s = load_study(FIG2)
    r = design_plan(s.model, s.design, s.method, s.configurations[1:])
    plans = {p.label: p for p in r.plans}
    assert plans["designed"].criterion == pytest.approx(plans["exhaustive optimum"].criterion,
                                                        rel=1e-12)
    assert plans["designed"].criterion < plans["study's plan"].criterion / 10
    assert (plans["every admissible candidate"].criterion < plans["designed"].criterion)


@pytest.mark.slow
def test_beam_designed_plan_within_one_percent_of_the_exhaustive_optimum():
    # Paper Section 7 beam, Bayesian: 9 translational coordinates x {0.1, 0.2, 0.5} kg,
    # 4 configurations of 27 candidates (17,550 plans enumerated), modes 1-2
    s = load_study(BEAM)
    r = design_plan(s.model, replace(s.design, prior_draws=0), s.method, s.configurations[1:])
    plans = {p.label: p for p in r.plans}
    assert len(r.candidates) == 27 and len(r.chosen) == 4
    assert plans["designed"].criterion <= 1.01 * plans["exhaustive optimum"].criterion


def test_exchange_passes_repair_a_greedy_trap():
    # greedy takes the strong row first, but the two weaker orthogonal rows are better
    rows = [np.array([[1.0, 1.0]]), np.array([[0.9, 0.0]]), np.array([[0.0, 0.9]])]
    s = PlanScorer([(r, np.ones(1)) for r in rows], (np.zeros((0, 2)), np.ones(0)),
                   np.zeros(2), "weighted-least-squares", "A", ["a", "b"])
    plan, swaps = greedy_exchange(s, [0, 1, 2], 2)
    best, value = exhaustive(s, [0, 1, 2], 2)
    assert plan == best == [1, 2] and swaps >= 1
    assert s.score(plan) == pytest.approx(value)


@pytest.mark.parametrize("method", ["least-squares", "weighted-least-squares", "bayesian"])
def test_scorer_agrees_with_the_svd_covariance(method):
    rng = np.random.default_rng(1)
    blocks = [(rng.normal(size=(3, 4)), rng.uniform(0.5, 2, 3)) for _ in range(4)]
    base = (rng.normal(size=(2, 4)), rng.uniform(0.5, 2, 2))
    prior = rng.uniform(0.1, 1, 4)
    s = PlanScorer(blocks, base, prior, method, "A", list("abcd"))
    J = np.vstack([base[0], blocks[1][0], blocks[3][0]])
    w = np.concatenate([base[1], blocks[1][1], blocks[3][1]])
    np.testing.assert_allclose(s.covariance([1, 3]), posterior_covariance(J, w, prior, method),
                               rtol=1e-9)


def test_singular_plan_scores_inf():
    J = np.array([[1.0, 1.0], [2.0, 2.0]])
    cov = posterior_covariance(J, np.ones(2), np.zeros(2), "weighted-least-squares")
    assert np.all(np.isinf(cov))


@pytest.mark.parametrize("path, method", [
    (FIG2, "weighted-least-squares"),
    pytest.param(BEAM, "bayesian", marks=pytest.mark.slow),
])
def test_predicted_std_is_the_updaters_posterior_std(path, method):
    # A second code path: `update` on error-free data of the initial model stops at once and
    # reports its posterior std from the normal equations; the planner's SVD must agree.
    s = load_study(path)
    configs = s.configurations[:5]
    modes = list(s.design.modes)
    sols = solve_configurations(s.model, configs, max(modes))
    std_hz = dict(zip(modes, np.broadcast_to(s.design.frequency_std_hz, len(modes)),
                      strict=True))
    meas = {(c.name, k): Measurement(c.name, k, float(sol.frequencies_hz[k - 1]), std_hz[k])
            for c, sol in zip(configs, sols, strict=True) for k in modes}
    res = update(s.model, configs, modes, meas, method=method)
    assert res.nit == 0 and res.success
    spec = s.design
    r = design_plan(s.model, spec, method, configs[1:])
    own = next(p for p in r.plans if p.label == "study's plan")
    for name, v in own.linear_std.items():  # at the prior mean, as the update linearises
        if res.std[name] is None:
            assert math.isinf(v)
        else:
            assert v == pytest.approx(res.std[name], rel=1e-8)


def _study(tmp_path, path, design):
    text = path.read_text().split("[design]")[0] + design
    text = text.replace('frequencies = "measured.csv"', "")
    p = tmp_path / "s.toml"
    p.write_text(text)
    return p


def test_cli_design_writes_a_ready_study(tmp_path, run_cli):
    out = tmp_path / "plans" / "plan.toml"
    out.parent.mkdir()
    code, text, err = run_cli("design", FIG2, "-o", out, "--json")
    assert code == 0, err
    doc = json.loads(text)
    plan = load_study(out)
    chosen = [doc["candidates"][i] for i in doc["chosen"]]
    assert [c.name for c in plan.configurations[1:]] == [c["name"] for c in chosen]
    assert plan.modes == [1, 2, 3, 4] and plan.frequencies is None
    assert plan.configurations[1].additions[0].mass == chosen[0]["additions"][0]["mass"]
    labels = [p["label"] for p in doc["plans"]]
    assert labels == ["designed", "exhaustive optimum", "study's plan",
                      "every admissible candidate"]
    code, text, _ = run_cli("design", FIG2, "-o", tmp_path / "p2.toml")
    assert code == 0 and "predicted std" in text and "2 kg at 1" in text


def test_plan_keeps_matrix_files_reachable(tmp_path, run_cli):
    import scipy.io
    import scipy.sparse as sp
    k0 = sp.csr_array(np.array([[2.0, -1.0], [-1.0, 1.0]]) * 1e4)
    for name, m in (("K0.mtx", k0), ("M0.mtx", sp.eye_array(2)), ("K1.mtx", k0)):
        scipy.io.mmwrite(tmp_path / name, m)
    s = tmp_path / "s.toml"
    s.write_text('[model]\ntype = "matrices"\nK0 = "K0.mtx"\nM0 = "M0.mtx"\n'
                 '[[model.parameter]]\nname = "a"\nvalue = 1.0\nK = "K1.mtx"\n'
                 '[design]\ncoordinates = [1, 2]\nmasses = [0.1, 0.3]\nconfigurations = 1\n'
                 'modes = [1, 2]\nfrequency_std_relative = 1e-3\n')
    (tmp_path / "sub").mkdir()
    code, _, err = run_cli("design", s, "-o", tmp_path / "sub" / "plan.toml")
    assert code == 0, err
    plan = load_study(tmp_path / "sub" / "plan.toml")
    assert plan.model.n == 2 and len(plan.configurations) == 2


DESIGN = ("\n[design]\ncoordinates = {c}\nmasses = {m}\nconfigurations = 3\nmodes = [1, 2]\n"
          "frequency_std_hz = 0.01\ncriterion = {k}\n")


@pytest.mark.parametrize("coords, masses, crit, fragments", [
    ("[1, 9]", "[0.35]", '"A"', ["design.coordinates", "unknown coordinate 9"]),
    ("[1, 2]", "[0.35]", '["m1", "m9"]', ["design.criterion", "m9"]),
    ("[1, 2]", "[0.35]", '"B"', ["design.criterion"]),
    ("[1, 2]", "[-1.0]", '"A"', ["design.masses"]),
    ("[1, 2]", "[1e-5]", '"A"', ["design", "masses too small"]),
    ("[1, 2, 3, 4]", "[1000.0]", '"A"', ["design", "mode order", "masses too large"]),
    ("[1, 2, 3, 4]", "[0.35]", '"A"', ["design.configurations", "determines the 10"]),
])
def test_refusals(tmp_path, run_cli, coords, masses, crit, fragments):
    p = _study(tmp_path, FIG2, DESIGN.format(c=coords, m=masses, k=crit))
    code, out, err = run_cli("design", p, "-o", tmp_path / "plan.toml")
    assert code == 2 and "Traceback" not in err and len(err.strip().splitlines()) == 1, err
    for f in fragments:
        assert f in err, err
    assert not (tmp_path / "plan.toml").exists()


def test_restrained_candidate_is_refused(tmp_path, run_cli):
    text = BEAM.read_text().split("# 0.2 kg added")[0].replace("[model]\n",
                                                              "[model]\nrestrained = [1, 2]\n", 1)
    text += ('[measurement]\nmodes = [1, 2]\n[updating]\nmethod = "bayesian"\n'
             '[design]\ncoordinates = [1, 3]\nmasses = [0.1]\nconfigurations = 1\n'
             'frequency_std_hz = 0.5\n')
    p = tmp_path / "s.toml"
    p.write_text(text)
    code, _, err = run_cli("design", p, "-o", tmp_path / "plan.toml")
    assert code == 2 and "coordinate 1 is restrained" in err and "design.coordinates" in err


def test_missing_design_table_and_overwriting_the_study(tmp_path, run_cli):
    p = _study(tmp_path, FIG2, "")
    code, _, err = run_cli("design", p, "-o", tmp_path / "plan.toml")
    assert code == 2 and "no [design] table" in err
    before = p.read_bytes()
    code, _, err = run_cli("design", p, "-o", p)
    assert code == 2 and "is an input of this run" in err and p.read_bytes() == before


def test_modes_from_upper_frequency():
    s = load_study(FIG2)
    from dataclasses import replace
    spec = replace(s.design, modes=None, max_frequency_hz=110.0, configurations=3)
    r = design_plan(s.model, spec, s.method)
    f = solve_configurations(s.model, [Configuration(BASE)], 4)[0].frequencies_hz
    assert r.modes == [k + 1 for k in range(4) if f[k] <= 110.0] == [1, 2, 3]


def test_modes_from_upper_frequency_on_a_free_structure():
    """The free beam has 2 rigid-body modes: an upper frequency must not ask for more
    elastic modes than it has (review finding: 'mode 18 requested, only 16')."""
    from dataclasses import replace

    s = load_study(BEAM)
    spec = replace(s.design, modes=None, max_frequency_hz=600.0)
    from eigenupdate.design.plan import measured_modes

    f = solve_configurations(s.model, [Configuration(BASE)], 16)[0].frequencies_hz
    assert measured_modes(s.model, spec) == [k + 1 for k in range(16) if f[k] <= 600.0]


@pytest.mark.slow
def test_screening_on_a_local_cluster_gives_the_same_plan(tmp_path, run_cli):
    a = run_cli("design", BEAM, "-o", tmp_path / "a.toml", "--json")
    b = run_cli("design", BEAM, "-o", tmp_path / "b.toml", "--json", "--workers", 2)
    assert a[0] == b[0] == 0, b[2]
    da, db = json.loads(a[1]), json.loads(b[1])
    da.pop("draw_seconds"), db.pop("draw_seconds")
    assert da == db  # every figure identical (but the time the draws took)
    assert (tmp_path / "a.toml").read_bytes() == (tmp_path / "b.toml").read_bytes()


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(3, 7), size=st.integers(1, 3),
       crit=st.sampled_from(["A", "D", "E"]))
def test_search_is_a_local_optimum_never_better_than_exhaustive(seed, n, size, crit):
    rng = np.random.default_rng(seed)
    blocks = [(rng.normal(size=(2, 3)), rng.uniform(0.5, 2, 2)) for _ in range(n)]
    s = PlanScorer(blocks, (rng.normal(size=(2, 3)), np.ones(2)), np.ones(3), "bayesian", crit,
                   list("abc"))
    plan, _ = greedy_exchange(s, list(range(n)), size)
    _, best = exhaustive(s, list(range(n)), size)
    value = s.score(plan)
    assert best <= value + 1e-12 * abs(value)
    for i in range(size):
        for c in set(range(n)) - set(plan):
            assert s.score([*plan[:i], c, *plan[i + 1:]]) >= value - 1e-12 * abs(value)


def test_several_additions_per_configuration(tmp_path):
    from dataclasses import replace

    from eigenupdate.design.plan_io import plan_study_text
    s = load_study(FIG2)
    spec = replace(s.design, additions=2, configurations=2, max_added_mass=2.5)
    r = design_plan(s.model, spec, s.method)
    assert len(r.candidates) == 12 + 6 * (9 - 3)  # pairs above 2.5 kg (2+1, 1+2, 2+2) dropped
    plans = {p.label: p for p in r.plans}
    assert plans["designed"].criterion <= 1.01 * plans["exhaustive optimum"].criterion
    out = tmp_path / "plan.toml"
    out.write_text(plan_study_text(FIG2, r.configurations, r.modes, out))
    assert load_study(out).configurations[1:] == r.configurations
