"""Tapered beam elements (model/tapered.py) against closed forms: the constant element,
a tapered rod and a tapered cantilever's tip flexibility by hand, the mass's moments, and
Kirchhoff's wedge cantilever under mesh refinement."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import optimize, special
from scipy.linalg import eigh

from eigenupdate.model import frame3d, tapered

EPS = np.finfo(float).eps


def _ones(q: int, n: int = 1) -> np.ndarray:
    return np.ones((n, q))


@pytest.mark.parametrize("phi", [0.0, 0.7])
def test_constant_section_is_the_constant_element(phi):
    """Source: frame3d's constant element (Euler-Bernoulli, or Przemieniecki's Timoshenko
    element with phi = 12 EI / (K G A L^2)): a section equal at every point gives it.
    The flexibility's 2 x 2 inverse has condition number below 1e3 at L = 2: rounding
    of 1e3 * 10 eps relative to the largest term."""
    L = np.array([2.0])
    s, w = tapered.gauss(3)
    S, W = s[None], w[None]
    ei1, ei2 = 3.0, 5.0
    kga1 = np.inf if phi == 0 else 12 * ei1 / (phi * L[0] ** 2)
    kga2 = np.inf if phi == 0 else 12 * ei2 / (phi * L[0] ** 2)
    got = tapered.stiffness(L, S, W, 7.0 * _ones(3), 11.0 * _ones(3), ei1 * _ones(3),
                            ei2 * _ones(3), kga1 * _ones(3), kga2 * _ones(3))
    want = frame3d.stiffness_parts(L, np.array([phi]), np.array([phi]))
    for name, scale in (("axial", 7.0), ("torsion", 11.0), ("bend1", ei1), ("bend2", ei2)):
        ref = scale * want[name][0]
        assert np.abs(got[name][0] - ref).max() <= 1e4 * EPS * np.abs(ref).max(), name


@pytest.mark.parametrize("consistent", [True, False])
def test_constant_mass_is_the_constant_element(consistent):
    """Source: frame3d.mass_parts (coupled Hermite / linear, or half the mass at each
    end): 4 Gauss points integrate the degree-6 products exactly; rounding only."""
    L = np.array([1.5])
    s, w = tapered.gauss(4)
    got = tapered.mass(L, s[None], w[None], 2.0 * _ones(4), 3.0 * _ones(4), consistent)
    want = frame3d.mass_parts(L, consistent)
    for name, scale in (("translation", 2.0), ("torsion", 3.0)):
        ref = scale * want[name][0]
        assert np.abs(got[name][0] - ref).max() <= 100 * EPS * np.abs(ref).max(), name


def test_tapered_rod_meets_the_closed_form():
    """Source: a rod of linear area, k = E (A_a - A_b) / (L ln(A_a / A_b)) by hand. With
    n Gauss points the flexibility int dx / (E A) is off by at most Gauss-Legendre's
    (n!)^4 / ((2n + 1) ((2n)!)^3) max |f^(2n)| on [0, 1], f^(2n) = (2n)! d^(2n) / A^(2n+1)
    (A = A_a + d s): the bound is checked for 3 points (MSC's rule) and 8."""
    E, L, aa, ab = 7e10, 0.5, 0.0075, 0.0040
    exact = E * (aa - ab) / (L * np.log(aa / ab))
    for n in (3, 8):
        s, w = tapered.gauss(n)
        a = aa + (ab - aa) * s[None]
        k = tapered.stiffness(np.array([L]), s[None], w[None], E * a, _ones(n), _ones(n),
                              _ones(n))["axial"][0, 0, 0]
        fact = np.prod(np.arange(1.0, n + 1))
        f2n = np.prod(np.arange(1.0, 2 * n + 1)) * abs(ab - aa) ** (2 * n) / ab ** (2 * n + 1)
        bound = fact**4 / ((2 * n + 1) * np.prod(np.arange(1.0, 2 * n + 1)) ** 3) * f2n
        flex_exact = np.log(aa / ab) / (aa - ab)  # int_0^1 ds / A
        assert abs(1 / (k * L / E) - flex_exact) <= bound + 10 * EPS * flex_exact, n
    assert abs(k / exact - 1) < 1e-12  # 8 points: the bound is 1e-14 here


def test_tapered_cantilever_tip_flexibility_by_hand():
    """Source: a cantilever of linear I = I_a + d s under a tip force P: the tip
    deflection P L^3 / E int (1 - s)^2 / I ds = P L^3 / (E d^3) [b^2 ln(b / a)
    - 2 b (b - a) + (b^2 - a^2) / 2] (a = I_a, b = I_b), and the tip rotation under a tip
    moment L / (E d) ln(b / a). 16 Gauss points: the pole of 1 / I sits 0.8 lengths past
    end B, Gauss-Legendre's error (about 5.7^(-32)) is below rounding."""
    E, L, a, b = 2e11, 1.2, 4e-6, 1e-6
    d = b - a
    s, w = tapered.gauss(16)
    k = tapered.stiffness(np.array([L]), s[None], w[None], _ones(16), _ones(16),
                          E * (a + d * s[None]), _ones(16))["bend1"][0]
    f = np.linalg.inv(k[np.ix_([7, 11], [7, 11])])  # end A held: end B's flexibility
    tip = L**3 / (E * d**3) * (b**2 * np.log(b / a) - 2 * b * (b - a) + (b**2 - a**2) / 2)
    rot = L / (E * d) * np.log(b / a)
    assert f[0, 0] == pytest.approx(tip, rel=1e-12)
    assert f[1, 1] == pytest.approx(rot, rel=1e-12)
    # equilibrium: the element's rows balance forces and moments (rigid motions free)
    rigid = np.zeros((12, 2))
    rigid[[1, 7], 0] = 1.0  # translation in y
    rigid[[1, 7], 1] = [0.0, L]  # rotation about z: v = x theta
    rigid[[5, 11], 1] = 1.0
    assert np.abs(k @ rigid).max() <= 1e3 * EPS * np.abs(k).max()


def test_lumped_ends_keep_the_first_moment():
    """Source: by hand, m(x) = m_a + (m_b - m_a) s: the ends take L (m_a / 3 + m_b / 6)
    and L (m_a / 6 + m_b / 3) (total and centre of gravity of the element kept)."""
    L, ma, mb = 0.5, 40.0, 10.0
    s, w = tapered.gauss(3)
    m = tapered.mass(np.array([L]), s[None], w[None], ma + (mb - ma) * s[None],
                     _ones(3), False)["translation"][0]
    assert m[0, 0] == pytest.approx(L * (ma / 3 + mb / 6), rel=1e-14)
    assert m[8, 8] == pytest.approx(L * (ma / 6 + mb / 3), rel=1e-14)


def _tapered_cantilever(n: int, points: int, p: int) -> float:
    """First bending frequency coefficient omega L^2 sqrt(rho A0 / (E I0)) of a sharp
    cantilever, A ~ x^(p - 2) and I ~ x^p from its free tip (x = 0) to its clamped root
    (x = L = 1), with n tapered elements of exact section at the points."""
    s, w = tapered.gauss(points)
    xs = np.arange(n)[:, None] / n + s[None] / n
    le = np.full(n, 1.0 / n)
    S, W = np.broadcast_to(s, (n, points)), np.broadcast_to(w, (n, points))
    one = np.ones((n, points))
    k = tapered.stiffness(le, S, W, one, one, xs**p, one)["bend1"]
    m = tapered.mass(le, S, W, xs ** (p - 2), 0 * one, True)["translation"]
    dof = [1, 5, 7, 11]
    K = np.zeros((2 * n + 2, 2 * n + 2))
    M = np.zeros_like(K)
    for e in range(n):
        g = [2 * e, 2 * e + 1, 2 * e + 2, 2 * e + 3]
        K[np.ix_(g, g)] += k[e][np.ix_(dof, dof)]
        M[np.ix_(g, g)] += m[e][np.ix_(dof, dof)]
    keep = slice(0, 2 * n)  # the root (last node) clamped
    lam = eigh(K[keep, keep], M[keep, keep], eigvals_only=True, subset_by_index=[0, 0])
    return float(np.sqrt(lam[0]))


@pytest.mark.parametrize("shape,p,order,published", [("wedge", 3, 1, 5.315),
                                                     ("cone", 4, 2, 8.719)])
def test_sharp_cantilevers_converge_to_kirchhoff(shape, p, order, published):
    """Source: Kirchhoff's wedge (depth linear to a sharp tip: I ~ x^3, A ~ x) and cone
    (I ~ x^4, A ~ x^2): (x^p w'')'' = k^4 x^(p-2) w has the tip-regular solutions
    w = x^(-order/2) {J, I}_order(z), z = 2 k sqrt(x), and the clamped root gives
    J_order(z) I_order+1(z) + J_order+1(z) I_order(z) = 0, omega L^2 sqrt(rho A0 / (E I0))
    = z^2 / 4: 5.315 and 8.719 (Blevins, Formulas for Natural Frequency, tapered beams).
    Meshes of tapered elements with MSC's 3-point rule converge to it: the error falls
    more than 8-fold per halving (third order or better) from 8 to 32 elements. (The
    sharp tip has I = 0: the exact integrals' tip element has no bending stiffness, and
    more points converge slowly towards that.)"""
    z = optimize.brentq(lambda t: special.jv(order, t) * special.iv(order + 1, t)
                        + special.jv(order + 1, t) * special.iv(order, t),
                        3.5 + order, 5.0 + order)
    exact = z**2 / 4
    assert exact == pytest.approx(published, abs=5e-4)
    err = [abs(_tapered_cantilever(n, 3, p) / exact - 1) for n in (8, 16, 32)]
    assert err[1] < err[0] / 8 and err[2] < err[1] / 8, err
