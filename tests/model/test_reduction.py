"""Craig-Bampton reduction (model/reduction.py) of a spring-mass chain against the full
chain's eigenvalues: exact with every fixed-interface mode kept (the reduction is then a
change of coordinates), upper bounds with fewer (Rayleigh-Ritz), and its refusals."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sl
import scipy.sparse as sp

from eigenupdate.errors import InputError
from eigenupdate.model.reduction import craig_bampton, guyan

EPS = np.finfo(float).eps


def _chain(n: int = 9) -> tuple[sp.csr_array, sp.csr_array]:
    """A grounded chain of n masses (1.0 to 2.6 kg) on springs (1000 to 1800 N/m)."""
    ks = 1000.0 + 100.0 * np.arange(n)
    k = np.diag(ks + np.append(ks[1:], 0.0)) - np.diag(ks[1:], 1) - np.diag(ks[1:], -1)
    m = np.diag(1.0 + 0.2 * np.arange(n))
    return sp.csr_array(k), sp.csr_array(m)


def _eig(k, m) -> np.ndarray:
    return sl.eigh(_dense(k), _dense(m), eigvals_only=True)


def _dense(a) -> np.ndarray:
    return a.toarray() if sp.issparse(a) else np.asarray(a)


def _bound(k, m) -> float:
    """Relative eigenvalue error of a symmetric-definite pencil formed and solved in
    floating point: of order n eps cond(K) cond(M) (Golub & Van Loan 8.7); 10 times it."""
    n = k.shape[0]
    return 10 * n * EPS * np.linalg.cond(_dense(k)) * np.linalg.cond(_dense(m))


BOUNDARY = np.array([2, 6])  # two interior masses held: three omitted pieces


def test_every_fixed_interface_mode_kept_gives_the_full_eigenvalues():
    """Second method: the full chain's eigenvalues. With all 7 omitted modes kept, T is
    square and nonsingular, so K_r, M_r are congruent to K, M: the same eigenvalues, to
    the rounding bound of the two pencils' conditioning."""
    k, m = _chain()
    kr, mr, lam = craig_bampton(k, m, BOUNDARY, 7)
    assert kr.shape == (9, 9) and lam.size == 7
    full, reduced = _eig(k, m), _eig(kr, mr)
    tol = max(_bound(k, m), _bound(kr, mr))
    assert tol < 1e-8
    assert np.max(np.abs(reduced / full - 1)) < tol


def test_fixed_interface_modes_are_those_of_the_omitted_part():
    """Second method: the eigenvalues of K_oo, M_oo (the omitted rows, boundary held)
    solved directly; the modes are mass-normalised, so K_r's modal block is diag(lam)
    and M_r's the identity (Craig & Bampton 1968)."""
    k, m = _chain()
    omit = np.setdiff1d(np.arange(9), BOUNDARY)
    want = _eig(k.toarray()[np.ix_(omit, omit)], m.toarray()[np.ix_(omit, omit)])[:4]
    kr, mr, lam = craig_bampton(k, m, BOUNDARY, 4)
    tol = _bound(k, m)
    assert np.max(np.abs(lam / want - 1)) < tol
    assert np.allclose(kr.toarray()[2:, 2:], np.diag(lam), rtol=tol, atol=tol * lam[-1])
    assert np.allclose(mr.toarray()[2:, 2:], np.eye(4), atol=tol)
    assert np.allclose(kr.toarray()[:2, 2:], 0.0, atol=tol * lam[-1])  # K_bq = 0


@pytest.mark.parametrize("n_modes", [1, 2, 3, 5, 6])
def test_fewer_modes_give_upper_bounds_that_fall_as_modes_are_added(n_modes):
    """Rayleigh-Ritz (Cauchy interlacing): the reduced model's i-th eigenvalue is at
    least the full model's i-th; the subspace with one mode more contains it, so its
    eigenvalues are no higher (to the rounding bound); Guyan (no mode) is the highest."""
    k, m = _chain()
    full = _eig(k, m)
    tol = _bound(k, m)
    this = _eig(*craig_bampton(k, m, BOUNDARY, n_modes)[:2])
    more = _eig(*craig_bampton(k, m, BOUNDARY, n_modes + 1)[:2])
    static = _eig(*guyan(k, m, BOUNDARY))
    assert np.all(this >= full[:this.size] * (1 - tol))
    assert np.all(more[:this.size] <= this * (1 + tol))
    assert np.all(this[:static.size] <= static * (1 + tol))


def test_boundary_coordinates_stay_physical():
    """Second method: the full chain's mode shapes. The boundary rows of T are the
    identity, so a reduced eigenvector's first rows are the physical boundary
    displacements: with every mode kept they are the full eigenvector's boundary rows
    (same mass normalisation, up to sign)."""
    k, m = _chain()
    kr, mr, _ = craig_bampton(k, m, BOUNDARY, 7)
    _, full = sl.eigh(k.toarray(), m.toarray())
    _, red = sl.eigh(kr.toarray(), mr.toarray())
    for i in range(3):
        a, b = full[BOUNDARY, i], red[:2, i]
        assert np.allclose(a * np.sign(a @ b), b, atol=1e-8 * np.abs(a).max())


def test_more_modes_than_omitted_coordinates_refused():
    k, m = _chain()
    with pytest.raises(InputError, match="8 fixed-interface modes asked of 7 omitted"):
        craig_bampton(k, m, BOUNDARY, 8)


def test_a_cut_through_a_repeated_fixed_interface_mode_refused():
    """Two equal masses on equal springs hung from one boundary mass: their fixed-
    interface modes have one frequency, so keeping one of them is arbitrary."""
    k = sp.csr_array([[3.0, -1.0, -1.0], [-1.0, 1.0, 0.0], [-1.0, 0.0, 1.0]])
    with pytest.raises(InputError, match="modes 1 and 2 have one frequency"):
        craig_bampton(k, sp.eye_array(3, format="csr"), np.array([0]), 1)
    kr, mr, lam = craig_bampton(k, sp.eye_array(3, format="csr"), np.array([0]), 2)
    assert lam == pytest.approx([1.0, 1.0], rel=1e-14)


def test_massless_omitted_coordinates_have_no_modes_to_give():
    """A massless omitted coordinate has no finite fixed-interface mode: with one mass
    among two omitted coordinates only one mode exists."""
    k, _ = _chain(3)
    m = sp.csr_array(np.diag([1.0, 0.0, 1.0]))
    craig_bampton(k, m, np.array([0]), 1)
    with pytest.raises(InputError, match="have 1 fixed-interface mode.s. with mass, fewer "
                                         "than the 2"):
        craig_bampton(k, m, np.array([0]), 2)



def _indefinite(n: int) -> sp.csr_array:
    """Boundary 0 on a unit spring; the omitted K_oo regular but indefinite: [[1, 2],
    [2, 1]] (eigenvalues 3 and -1 by hand) for n = 3, else diag(-1, 1, 2, ...)."""
    if n == 3:
        return sp.csr_array([[3.0, -1.0, 0.0], [-1.0, 1.0, 2.0], [0.0, 2.0, 1.0]])
    return sp.csr_array(sp.diags_array(np.r_[1.0, -1.0, np.arange(1.0, n - 1)]))


@pytest.mark.parametrize("n", [3, 2003])  # the dense path, and ARPACK's beyond 2000 rows
def test_an_indefinite_omitted_stiffness_refused(n):
    """review6: the dense path's Cholesky of K_oo failed with a LinAlgError traceback;
    the sparse one returned a negative fixed-interface eigenvalue."""
    with pytest.raises(InputError, match="K_oo is not positive definite"):
        craig_bampton(_indefinite(n), sp.eye_array(n, format="csr"), np.array([0]), 1)
