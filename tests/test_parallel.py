"""Threads (solve/parallel.py) and the warm start of an update's eigen-solves
(solve/eigen.py WarmStart): neither may change a number beyond round-off.

Reference: the same computation in one thread / started cold.
"""

import numpy as np
import pytest

import eigenupdate.solve.perturbed as perturbed
from eigenupdate.errors import InputError
from eigenupdate.solve import parallel
from eigenupdate.solve.eigen import (
    EigenSolution,
    WarmStart,
    base_operator,
    sturm_check,
    usable_shift,
)
from eigenupdate.solve.jacobian import linearise
from tests.test_perturbed import CONFIGS, assert_matches, network, reference


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
    out = {}
    for threads in ("1", "3"):
        monkeypatch.setenv("EIGENUPDATE_THREADS", threads)
        out[threads] = linearise(model, CONFIGS, modes, dense=False)
    # Ritz values are certified to EIG_RTOL, not to round-off: Krylov blocks solved in
    # other column groups differ in the last digits, and so, within the bound, do they
    np.testing.assert_allclose(out["3"].eigenvalues, out["1"].eigenvalues,
                               rtol=2 * perturbed.EIG_RTOL)
    np.testing.assert_allclose(out["3"].J, out["1"].J, rtol=1e-7,
                               atol=1e-9 * np.abs(out["1"].J).max())
    a, b = out["3"].certificate.as_dict(), out["1"].certificate.as_dict()
    for key in ("certified", "certified_with_extra_level", "fallback_lanczos"):
        assert a[key] == b[key]


def test_warm_start_gives_the_cold_numbers(monkeypatch):
    model = network()
    modes = [1, 2, 3, 4, 5]
    counts = []
    real = parallel.in_background

    def spy(f, *args):
        counts.append(getattr(f, "__name__", ""))
        return real(f, *args)

    monkeypatch.setattr(parallel, "in_background", spy)
    warm = WarmStart()
    linearise(model, CONFIGS, modes, dense=False, warm=warm)
    assert warm.start is not None and warm.sturm_shift is not None
    assert "negative_count" not in counts  # cold: nothing to start early
    stepped = model.values * np.random.default_rng(3).uniform(0.97, 1.03, model.values.size)
    counts.clear()
    hot = linearise(model, CONFIGS, modes, stepped, dense=False, warm=warm)
    assert "negative_count" in counts  # warm: the Sturm count started before Lanczos
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


def test_a_warm_count_still_catches_a_missed_mode():
    model = network()
    K, M = model.stiffness(), model.mass()
    op, sol = base_operator(K, M, 4)
    lam = sol.computed[0]
    sigma = 0.5 * (lam[5] + lam[6])  # between elastic modes 5 and 6 (one rigid mode)
    missing = np.delete(lam, 2)  # the solver "skipped" elastic mode 2
    with pytest.raises(InputError, match="missed-mode check"):
        sturm_check(K, M, missing, sol, op, counted=(sigma, int(np.sum(lam < sigma))))


def test_a_widened_subspace_continues_the_first_one():
    model = network()
    K, M = model.stiffness(), model.mass()
    op, sol = base_operator(K, M, 4)
    base = perturbed.make_base(K, M, op, *sol.computed)
    rows = (model.index(45),)
    fam = perturbed.families(base, [rows])[rows]
    perturbed.widen(base, [fam])
    fresh = perturbed.build_subspaces(base, [np.array(rows)],
                                      perturbed.LEVELS + perturbed.EXTRA_LEVELS)[0]
    a = perturbed.ritz(base, fam.wider, np.array(rows), [0.0], [5.0], 4)
    b = perturbed.ritz(base, fresh, np.array(rows), [0.0], [5.0], 4)
    assert fam.wider.Q.shape == fresh.Q.shape
    np.testing.assert_allclose(a.solution.eigenvalues, b.solution.eigenvalues, rtol=1e-12)


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
