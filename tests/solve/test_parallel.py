"""Threads (solve/parallel.py) and the warm start of an update's eigen-solves
(solve/eigen.py WarmStart): neither may change a number beyond round-off.

Reference: the same computation in one thread / started cold.
"""

import platform
import subprocess
import sys
import threading
import warnings

import numpy as np
import pytest
from bounds import eigenvalue_floor
from conftest import EXAMPLES
from test_perturbed import CONFIGS, assert_matches, network, reference

import eigenupdate.solve.krylov as krylov
import eigenupdate.solve.perturbed as perturbed
from eigenupdate.errors import InputError
from eigenupdate.model.configurations import mass_at
from eigenupdate.solve import parallel
from eigenupdate.solve.eigen import (
    EigenSolution,
    WarmStart,
    base_operator,
    sturm_check,
    usable_shift,
)
from eigenupdate.solve.jacobian import linearise


def test_thread_count_from_the_environment(monkeypatch):
    monkeypatch.setenv("EIGENUPDATE_THREADS", "3")
    assert parallel.threads() == 3
    for bad in ("0", "two", "-1", "100000", "\u0663"):
        monkeypatch.setenv("EIGENUPDATE_THREADS", bad)
        with pytest.raises(InputError, match="EIGENUPDATE_THREADS"):
            parallel.threads()
    monkeypatch.delenv("EIGENUPDATE_THREADS")
    assert 1 <= parallel.threads() <= parallel.MAX_THREADS


@pytest.mark.parametrize("threads", ["1", "3"])
def test_shares_keep_order_and_raise(monkeypatch, threads):
    monkeypatch.setenv("EIGENUPDATE_THREADS", threads)
    assert parallel.map_shares(lambda s: [x + 1 for x in s], range(7), 10**6) == list(range(1, 8))
    assert parallel.map_shares(lambda s: s, [], 10**6) == []

    def boom(share):
        raise ValueError("share failed")

    with pytest.raises(ValueError, match="share failed"):
        parallel.map_shares(boom, range(4), 10**6)
    with pytest.raises(ValueError, match="share failed"):
        parallel.in_background(boom, []).result()


def test_threads_change_nothing_beyond_round_off(monkeypatch):
    monkeypatch.setattr(parallel, "MIN_ROWS", 0)  # thread even this small model
    model = network()
    modes = [1, 2, 3, 4]
    out, where = {}, set()
    grow = krylov.Blocks.grow

    def spy(self, levels):
        where.add(threading.current_thread().name.split("_")[0])
        return grow(self, levels)

    monkeypatch.setattr(krylov.Blocks, "grow", spy)
    for threads in ("1", "3"):
        monkeypatch.setenv("EIGENUPDATE_THREADS", threads)
        out[threads] = linearise(model, CONFIGS, modes, dense=False)
    assert where == {"MainThread", "eigenupdate"}  # the pool did share the work
    # Each run's Ritz values are within the certified bound of the exact ones, plus the
    # rounding floor that any backward-stable solver carries (tests/bounds.py): the two
    # runs agree within the sum. Krylov blocks solved in other column groups differ in
    # the last digits.
    _, _, floor = reference(model, CONFIGS, modes, floor=True)
    bound = (out["1"].certificate.max_eig_bound + out["3"].certificate.max_eig_bound
             + 2 * floor)
    rel = np.abs(out["3"].eigenvalues - out["1"].eigenvalues) / np.abs(out["1"].eigenvalues)
    assert np.all(rel <= bound), (rel.max(), bound.min())
    np.testing.assert_allclose(out["3"].J, out["1"].J, rtol=1e-7,
                               atol=1e-9 * np.abs(out["1"].J).max())
    a, b = out["3"].certificate.as_dict(), out["1"].certificate.as_dict()
    for key in ("certified", "certified_with_extra_level", "fallback_lanczos"):
        assert a[key] == b[key]


def test_warm_start_counts_early_and_keeps_the_contract(monkeypatch):
    from eigenupdate.solve import jacobian

    monkeypatch.setenv("EIGENUPDATE_THREADS", "2")  # the early count needs a second thread
    model = network()
    modes = [1, 2, 3, 4, 5]
    counted = []
    check = jacobian.sturm_check

    def spy(K, M, lam, sol, op=None, given=None):
        counted.append(given)
        return check(K, M, lam, sol, op, given)

    monkeypatch.setattr(jacobian, "sturm_check", spy)
    warm = WarmStart()
    linearise(model, CONFIGS, modes, dense=False, warm=warm)
    assert warm.start is not None and warm.sturm_shift is not None
    assert counted == [None]  # cold: nothing counted early
    stepped = model.values * np.random.default_rng(3).uniform(0.97, 1.03, model.values.size)
    hot = linearise(model, CONFIGS, modes, stepped, dense=False, warm=warm)
    assert counted[-1] is not None  # warm: the count made while Lanczos ran was used
    # the numbers meet the fast path's contract against dense re-solves, warm or cold
    # (they differ from a cold run's within it: other Lanczos start, other round-off)
    assert_matches(hot.eigenvalues, hot.J, *reference(model.with_values(stepped), CONFIGS,
                                                      modes))


def test_a_warm_shift_is_used_only_where_it_checks_the_solution():
    sol = EigenSolution(np.array([4.0, 9.0]), np.empty((0, 2)), 0, 16.0)
    lam = np.array([4.0, 9.0, 16.0, 25.0])
    assert usable_shift(12.0, lam, sol)
    assert not usable_shift(8.0, lam, sol)  # below a wanted eigenvalue
    assert not usable_shift(30.0, lam, sol)  # above every computed one
    assert not usable_shift(16.0 * (1 + 1e-9), lam, sol)  # on an eigenvalue


def test_a_warm_count_is_the_count_used():
    model = network()
    K, M = model.stiffness(), model.mass()
    op, sol = base_operator(K, M, 4)
    lam = sol.computed[0]
    sigma = 0.5 * (lam[5] + lam[6])  # between elastic modes 5 and 6 (one rigid mode)
    true = int(np.sum(lam < sigma))
    sturm_check(K, M, lam, sol, op, counted=(sigma, true))  # consistent: passes
    # a count made beforehand that disagrees with the solution is what stops it (the
    # check's own count at its own shift would pass)
    with pytest.raises(InputError, match=f"eigenvalues lie below {sigma:.6g}"):
        sturm_check(K, M, lam, sol, op, counted=(sigma, true + 1))
    # and a count at a shift that does not check this solution is not used
    sturm_check(K, M, lam, sol, op, counted=(0.5 * (lam[2] + lam[3]), true + 1))


def test_a_widened_subspace_continues_the_first_one():
    model = network()
    K, M = model.stiffness(), model.mass()
    op, sol = base_operator(K, M, 4)
    base = krylov.make_base(K, M, op, *sol.computed)
    rows = (model.index(45),)
    fam = perturbed.families(base, [rows])[rows]
    perturbed.widen(base, [fam])
    fresh = krylov.build_subspaces(base, [np.array(rows)],
                                      krylov.LEVELS + krylov.EXTRA_LEVELS)[0]
    a = perturbed.ritz(base, fam.wider, np.array(rows), [0.0], [5.0], 4)
    b = perturbed.ritz(base, fresh, np.array(rows), [0.0], [5.0], 4)
    assert fam.wider.Q.shape == fresh.Q.shape
    # the same subspace built twice: equal within the two certified bounds
    rel = np.abs(a.solution.eigenvalues - b.solution.eigenvalues) / b.solution.eigenvalues
    dk, dm = mass_at(45, 5.0).delta(model)
    floor = eigenvalue_floor(K + dk, M + dm, b.solution.eigenvalues, b.solution.modes)
    assert np.all(rel <= a.eig_bound + b.eig_bound + 2 * floor), rel


def test_restricting_the_terms_leaves_the_model_alone():
    """The restricted terms are built in a thread while K(s) is assembled from the same
    matrices: building them must not touch the model's (explicit zeros included)."""
    import scipy.sparse as sp

    from eigenupdate.solve.restricted import RestrictedTerms

    term = sp.csr_array(np.array([[2.0, 0.0], [0.0, 3.0]]))
    term.data[0] = 0.0  # an explicit zero, as element assembly leaves them
    before = (term.indptr.copy(), term.indices.copy(), term.data.copy())
    RestrictedTerms([term], [None])
    for a, b in zip(before, (term.indptr, term.indices, term.data), strict=True):
        np.testing.assert_array_equal(a, b)


def test_a_trial_point_can_be_turned_down_before_the_fallbacks(monkeypatch):
    from eigenupdate.solve import jacobian

    model = network()
    seen = []

    def reject_all(known):
        seen.append(sorted(known))
        return True

    with pytest.raises(jacobian.Rejected):
        jacobian.solve_configurations(model, CONFIGS, 4, dense=False, reject=reject_all)
    assert seen == [["base"]]  # turned down on the bare structure alone
    # certificates that all fail: the certified rows (none) are shown before Lanczos
    monkeypatch.setattr(perturbed, "EIG_RTOL", 0.0)
    seen.clear()
    sols = jacobian.solve_configurations(model, CONFIGS, 4, dense=False,
                                         reject=lambda known: seen.append(sorted(known)))
    assert seen == [["base"], ["base"]] and len(sols) == len(CONFIGS)


def test_threads_keep_the_callers_floating_point_settings(monkeypatch):
    # the command line silences floating-point warnings; NumPy keeps that per thread
    monkeypatch.setenv("EIGENUPDATE_THREADS", "2")
    with np.errstate(all="ignore"):
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            out = parallel.in_background(lambda: np.array([1.0]) / np.array([0.0])).result()
    assert np.isinf(out[0])
    with np.errstate(divide="raise"), pytest.raises(FloatingPointError):
        parallel.in_background(lambda: np.array([1.0]) / np.array([0.0])).result()


def test_a_bad_thread_count_stops_the_command_at_once(monkeypatch, capsys):
    from eigenupdate import cli

    monkeypatch.setenv("EIGENUPDATE_THREADS", "9" * 5000)  # beyond int()'s digit limit too
    assert cli.main(["check", str(EXAMPLES / "paper_fig2" / "study.toml")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "EIGENUPDATE_THREADS" in err and "study.toml" not in err


@pytest.mark.skipif(platform.libc_ver()[0] != "glibc", reason="glibc's mallopt")
def test_the_command_keeps_freed_memory():
    # in a process of its own: the setting is process-wide and not undone
    code = "from eigenupdate.solve.memory import keep_freed_memory; print(keep_freed_memory())"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.strip() == "True"
