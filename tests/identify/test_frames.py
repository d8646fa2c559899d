"""Updating space frames of the benchmark's family (``benchmarks/frame.py``: steel columns
and floor beams, 30 parameters E and rho of 15 element groups, truth +-3 % from steel,
start 2.5-5 % off the truth, 20 added masses of 1 % of the frame's mass, modes 1-10).

Source of every number: the frame's own simulated frequencies (error-free data, so the
update must return the truth; tolerance 1e-8 relative, against a converged fit's 1e-10).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from bounds import assert_eigenvalues_agree

from eigenupdate.identify.fit import Fit
from eigenupdate.identify.optimizers import INITIAL_REGION, Step
from eigenupdate.identify.updating import update
from eigenupdate.model.configurations import BASE, Configuration, mass_at
from eigenupdate.solve.jacobian import solve_configurations

BENCHMARKS = Path(__file__).parents[2] / "benchmarks"
sys.path.insert(0, str(BENCHMARKS))  # bench_family imports frame as the scripts do
import bench_family  # noqa: E402
import frame  # noqa: E402

frame_problem = bench_family.problem


def _error(res, model, truth):
    return float(np.max(np.abs(np.array([res.parameters[n] for n in model.names]) / truth - 1)))


def test_first_step_stays_within_the_initial_trust_region():
    """2 x 2 bays, 5 storeys, seed 3 (2,160 coordinates). SciPy's dogbox starts with a
    region of |z0|_inf, all of a parameter: its first step took a parameter by 100 % to
    the floor of its bounds, along a direction the data hardly see, and the fit crept
    back (not converged at the 20-iteration limit, 14 % off; 27 iterations to converge).
    From INITIAL_REGION: converged in 9 (measured)."""
    model, configs, modes, data, truth = frame_problem((2, 2, 5, 4), 3)
    res = update(model, configs, modes, data)
    assert res.success and _error(res, model, truth) <= 1e-8, res.message
    assert res.nit <= 12
    start, first = res.history[0].parameters, res.history[1].parameters
    change = max(abs(first[n] / start[n] - 1) for n in model.names)
    assert change <= INITIAL_REGION * (1 + 1e-12)


def test_a_group_of_close_modes_cut_by_the_last_measured_mode_is_tracked_not_summed():
    """Benchmark (b)'s frame (2 x 2 bays, 5 storeys, seed 1): in 18 of 21 configurations
    modes 9 and 10 are close and the model's mode 11 (not measured) as close. Fitted
    through the sums of 9 and 10 (which miss mode 11, and are not smooth where it crosses
    in), the update was 3.5 % off the truth at 20 iterations and converged at 30, after
    releasing the clusters. Tracked instead: converged in 18 (measured)."""
    model, configs, modes, data, truth = frame_problem((2, 2, 5, 4), 1)
    res = update(model, configs, modes, data, max_iterations=25)
    assert res.success and _error(res, model, truth) <= 1e-8, res.message
    cut = [n for n in res.pairing["notes"] if n["kind"] == "cut group"]
    assert len(cut) >= 10 and all(n["modes"] == [9, 10] for n in cut)
    assert "not fitted" in cut[0]["reason"]
    assert not any(c[1] == [9, 10] for c in res.pairing["clusters"])


def test_free_frame_configurations_agree_with_a_dense_solve():
    """Free-free frame, 1 x 1 bay, 3 storeys, 2 elements per member (240 coordinates), 6
    added masses. Source: LAPACK's dense solve of each configuration. The sparse path
    solves them from the bare structure's factorisation (Krylov subspaces, else Lanczos
    through Woodbury); about the first-guess shift (lambda_1 / 8,700 below zero) the
    rigid-body modes dominated that operator and the eigenvalues were up to 7.7e-6 off;
    about -lambda_1 / 10, 3e-11 (measured). Bound: both solvers' rounding floors
    (tests/bounds.py) plus the Lanczos residual tolerance, 1e-10 relative."""
    fr = frame.build_frame(1, 1, 3, 2, seed=1, supports="free", n_bands=3)
    model = fr.model.with_values(fr.truth)
    configs = [Configuration(BASE)] + [
        mass_at(c, 0.01 * fr.total_mass, name=f"m{i + 1}@{c}")
        for i, c in enumerate(frame.mass_sites(fr, 6, seed=2))]
    sparse = solve_configurations(model, configs, 10, dense=False)
    dense = solve_configurations(model, configs, 10, dense=True)
    K, M = model.stiffness(), model.mass()
    for c, got, ref in zip(configs, sparse, dense, strict=True):
        assert got.n_rigid == ref.n_rigid == 6
        dk, dm = c.delta(model)
        assert_eigenvalues_agree(got.eigenvalues, ref, K + dk, M + dm, certified=1e-10)


def test_the_first_steps_follow_the_mode_shapes():
    """1 x 1 bay, 5 storeys, seed 1 (600 coordinates, the sparse path). Gauss-Newton's
    trust-region steps stopped in a local minimum 3.2 % off the truth (bench_family before
    the reduced model); the step to the optimum of the reduced model that follows the mode
    shapes converges to the truth (10 iterations, measured). Without it (its step refused)
    the trust region takes over from the start."""
    model, configs, modes, data, truth = frame_problem((1, 1, 5, 3), 1)
    res = update(model, configs, modes, data)
    assert res.success and _error(res, model, truth) <= 1e-8, res.message
    assert res.history[1].kind is Step.REDUCED


def test_a_refused_reduced_step_leaves_the_trust_region_its_start(monkeypatch):
    """The reduced model's step refused (as where it would not lower the objective): the
    history has none, and the trust region converges from the start (the benchmark's own
    frame, 2 x 2 bays, 5 storeys, seed 3: converged in 9 before the reduced model)."""
    monkeypatch.setattr(Fit, "reduced_step", lambda self, point, rom: None)
    model, configs, modes, data, truth = frame_problem((2, 2, 5, 4), 3)
    res = update(model, configs, modes, data)
    assert res.success and _error(res, model, truth) <= 1e-8, res.message
    assert all(it.kind is not Step.REDUCED for it in res.history)


def test_a_basis_beyond_its_bound_is_not_built(monkeypatch):
    """The reduced model's basis is bounded before it is built (optimizers.MAX_ENTRIES):
    beyond it the progress says so and the trust region alone converges (1 x 1 bay, 5
    storeys, seed 3)."""
    from eigenupdate.identify import optimizers

    monkeypatch.setattr(optimizers, "MAX_ENTRIES", 0)
    lines = []
    model, configs, modes, data, truth = frame_problem((1, 1, 5, 3), 3)
    res = update(model, configs, modes, data, progress=lines.append)
    assert res.success and _error(res, model, truth) <= 1e-8, res.message
    assert all(it.kind is not Step.REDUCED for it in res.history)
    assert any("no reduced model" in line for line in lines)
