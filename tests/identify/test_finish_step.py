"""The last step taken without a further solve (optimizers.finish_step): its prediction of
the steps still to come is never below what a convergent iteration of order p >= 1 makes.

Source: the definition of convergence of order p (e_k+1 = C e_k^p) and the geometric
series; no number here comes from a run."""

import numpy as np
from hypothesis import assume, given
from hypothesis import strategies as st

from eigenupdate.identify.optimizers import Point, finish_step
from eigenupdate.solve.jacobian import Linearisation


def _point(n: int = 2) -> Point:
    lin = Linearisation([("base", k + 1) for k in range(n)], np.ones(n), np.eye(n),
                        np.ones(n), [f"s{k}" for k in range(n)])
    return Point(np.zeros(n), lin, np.arange(n), [], np.ones(n), -np.eye(n), float(n))


@given(order=st.floats(1.0, 2.0), c=st.floats(1e-3, 1e3), s0=st.floats(1e-6, 1e-1))
def test_prediction_bounds_the_steps_of_an_order_p_iteration(order, c, s0):
    """Steps s_k+1 = C s_k^p contracting at rate <= 1/2 from the first: the predicted sum
    of the steps after the third bounds their true sum."""
    steps = [s0]
    while len(steps) < 60 and steps[-1] > 1e-300:
        steps.append(c * steps[-1] ** order)
        if not steps[-1] < 0.5 * steps[-2]:
            assume(False)  # not contracting at the rate finish_step needs
    before, previous, last = steps[:3]
    done = finish_step(_point(), np.array([last, 0.0]), previous, np.inf, before)
    assert done is not None
    true_rest = sum(steps[3:])
    assert done[1] >= true_rest * (1 - 1e-12)


def test_linear_rate_without_an_earlier_step_or_a_rate_that_did_not_improve():
    """rho / (1 - rho) max|dz| with rho = max|dz| / previous (a geometric series), whether
    the step before is unknown or the contraction did not improve (0.1 then 0.1)."""
    for before in (None, 1e-2):
        done = finish_step(_point(), np.array([1e-4, 0.0]), 1e-3, np.inf, before)
        assert abs(done[1] - 0.1 / 0.9 * 1e-4) <= 1e-15


def test_improving_rate_predicts_its_square_over_the_last():
    """Rates 0.1 then 0.01: the next is taken as 0.01^2 / 0.1 = 1e-3."""
    done = finish_step(_point(), np.array([1e-5, 0.0]), 1e-3, np.inf, 1e-2)
    assert abs(done[1] - 1e-3 / (1 - 1e-3) * 1e-5) <= 1e-18


def test_no_last_step_when_not_contracting_or_above_xtol():
    p = _point()
    assert finish_step(p, np.array([0.6e-3, 0.0]), 1e-3, np.inf, 1e-2) is None  # rate 0.6
    assert finish_step(p, np.array([1e-4, 0.0]), 1e-3, 1e-6, 1e-2) is None  # 1.1e-5 > xtol
    assert finish_step(p, np.array([1e-4, 0.0]), None, np.inf, 1e-2) is None  # a cut step


def test_the_last_point_moves_eigenvalues_and_residuals_linearly():
    """The point p + dz carries the linearisation's eigenvalues and residuals moved by
    J dz (A dz), exact for this linear model."""
    point, dz = _point(), np.array([1e-5, -2e-5])
    final, _ = finish_step(point, dz, 1e-3, np.inf, 1e-2)
    assert np.array_equal(final.z, dz) and final.predicted
    np.testing.assert_allclose(final.lin.eigenvalues, 1 + dz, rtol=0, atol=1e-16)
    np.testing.assert_allclose(final.f, 1 - dz, rtol=0, atol=1e-16)
