"""PSHEAR F1/F2: the shear panel's edge rods (model/shear_panel.py
edge_rod_stiffness, MSC's and NX's QRG PSHEAR remark: F <= 1.01 an effectiveness factor,
rods of area F T PA / (L12 + L34); F > 1.01 an effective width, area F T^2 / 2).
Independent references: the strain energy of a plate strip stretched along one side
(E T b a eps^2 / 2 with no Poisson coupling: the remark's "fully effective" F = 1), a
rod's E A delta^2 / (2 L) on a trapezoid, and equilibrium (rigid motions store no
energy in any orientation)."""

from __future__ import annotations

import numpy as np
import pytest
from test_shear_panel import SHAPES, _rigid, _turned

from eigenupdate.model import shear_panel

A, B = 2.0, 1.0
RECT = np.array([[[0.0, 0, 0], [A, 0, 0], [A, B, 0], [0, B, 0]]])


def _field(u_of_xy):
    """Corner translations (12,) of RECT from a displacement field (u, v)(x, y)."""
    out = np.zeros(12)
    for i, (x, y, _) in enumerate(RECT[0]):
        out[3 * i:3 * i + 2] = u_of_xy(x, y)
    return out


@pytest.mark.parametrize(("f1", "f2"), [(1.0, 1.0), (0.4, 0.0), (30.0, 1.0), (0.0, 12.0)])
def test_rectangle_strip_energies_are_the_hand_formula(f1, f2):
    """Source: a rectangle a x b (a along 1-2) with F1 = 1 is the whole section in
    extension along 1-2 (two rods of T b / 2): u = eps x stores E T a b eps^2 / 2; a
    factor F1 scales it, a width F1 > 1.01 is two rods of F1 T^2 / 2 and length a:
    E F1 T^2 a eps^2 / 2. F2 the same along 2-3 (v = eps y); in shear (u = gamma y, the
    rods only turn) they store nothing. Per unit E (T, T^2 apart): a few products, 1e-14."""
    lin, quad = (k[0] for k in shear_panel.edge_rod_stiffness(RECT, np.array([f1]),
                                                              np.array([f2])))
    eps = 1e-3

    def hand(f, side, across):  # (per E T, per E T^2) energy x 2 of a stretch along side
        return ((f * across * side * eps**2, 0.0) if f <= 1.01
                else (0.0, f * side * eps**2))

    for u, f, side, across in ((_field(lambda x, y: (eps * x, 0.0)), f1, A, B),
                               (_field(lambda x, y: (0.0, eps * y)), f2, B, A)):
        want = hand(f, side, across)
        assert u @ lin @ u == pytest.approx(want[0], rel=1e-14, abs=1e-14 * eps**2)
        assert u @ quad @ u == pytest.approx(want[1], rel=1e-14, abs=1e-14 * eps**2)
    shear = _field(lambda x, y: (eps * y, 0.0))
    assert abs(shear @ lin @ shear) + abs(shear @ quad @ shear) <= 1e-14 * eps**2 * 30


def test_trapezoid_factor_rods_follow_the_panel_area():
    """Source: the QRG remark's area F1 T PA / (L12 + L34) on a trapezoid (PA = (2 + 1.5)
    / 2 x 1 = 1.75, L12 = 2, L34 = 1.5: area per T 0.5 x 1.75 / 3.5 = 0.25): grid 2 moved
    d along 1-2 stretches that rod alone, energy x 2 E A d^2 / L12 (the rod on 2-3 is
    also stretched: F2 = 0 leaves it out), 1e-14."""
    x = np.array([[[0.0, 0, 0], [2, 0, 0], [1.75, 1, 0], [0.25, 1, 0]]])
    lin, _ = shear_panel.edge_rod_stiffness(x, np.array([0.5]), np.array([0.0]))
    u = np.zeros(12)
    u[3] = 1e-3
    assert u @ lin[0] @ u == pytest.approx(0.25 * 1e-6 / 2.0, rel=1e-14)


@pytest.mark.parametrize("name", list(SHAPES))
def test_edge_rods_store_no_energy_in_rigid_motions(name):
    """Source: equilibrium. Rods along the edges stretch in no rigid motion: K_F and K_W
    annihilate the six rigid motions of every panel shape in any orientation (rounding:
    1e-12 of |K| per unit length); with the shear panel, a rectangle with F1 = F2 = 1 has
    five members on 8 - 3 in-plane freedoms: in-plane rank 5, no mechanism."""
    x = _turned(SHAPES[name])
    for k in shear_panel.edge_rod_stiffness(x[None], np.array([0.8]), np.array([25.0])):
        assert np.abs(k[0] @ _rigid(x)).max() <= 1e-12 * np.abs(k[0]).max() * 3
    lin, quad = shear_panel.edge_rod_stiffness(RECT, np.array([1.0]), np.array([1.0]))
    K = (lin + shear_panel.shear_stiffness(RECT, np.array([0.3])))[0]
    plane = np.sort(np.r_[np.arange(0, 12, 3), np.arange(1, 12, 3)])
    w = np.linalg.eigvalsh(K[np.ix_(plane, plane)])
    assert np.sum(w > 1e-12 * w.max()) == 5
    assert not quad.any()
