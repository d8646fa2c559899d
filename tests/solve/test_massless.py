"""Coordinates without mass (lumped-mass rotations): finite eigenvalues only, on the
dense (static condensation) and the sparse (shift-invert) path."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from bounds import assert_eigenvalues_agree

from eigenupdate.errors import InputError
from eigenupdate.solve.eigen import solve_elastic


def _chain(n):
    """n springs of 1000 N/m in series from ground, masses 2 kg on every other node."""
    k = sp.diags([2000.0 * np.ones(n), -1000.0 * np.ones(n - 1), -1000.0 * np.ones(n - 1)],
                 [0, 1, -1]).tolil()
    k[n - 1, n - 1] = 1000.0
    m = np.zeros(n)
    m[1::2] = 2.0
    return sp.csr_array(k), sp.diags_array(m).tocsr()


def test_springs_in_series_closed_form():
    """Source: two springs k in series hold a mass m: lambda = (k / 2) / m."""
    k, m = _chain(2)
    sol = solve_elastic(k, m, 1)
    assert sol.eigenvalues[0] == pytest.approx(500.0 / 2.0, rel=1e-12)
    # the massless coordinate follows statically: halfway
    assert sol.modes[0, 0] / sol.modes[1, 0] == pytest.approx(0.5, rel=1e-12)


def test_dense_and_sparse_agree():
    k, m = _chain(600)
    dense = solve_elastic(k, m, 5, dense=True)
    sparse = solve_elastic(k, m, 5, dense=False)
    assert_eigenvalues_agree(sparse.eigenvalues, dense, k, m)  # both to their rounding floor


def test_massless_mechanism_refused():
    """A massless coordinate joined to nothing massive by stiffness is a mechanism."""
    m = np.diag([1.0, 1.0, 0.0])
    k = np.array([[2.0, -1.0, 0.5], [-1.0, 1.0, 0.0], [0.5, 0.0, 0.0]])
    with pytest.raises(InputError, match="massless mechanism"):
        solve_elastic(k, m, 1, dense=True)
