"""The shear panel (model/shear_panel.py, NASTRAN-95's CSHEAR). Independent references:
the rectangle's shear energy G t S gamma^2 / 2 (the hand formula G t a / b), the
parallelogram's stress state under uniform edge shear flow (tau = q / t and the direct
stress 2 d tau that inclined edges need: Z = S / (2 G t) (1 + 2 d^2 / (1 + nu))), the
equilibrium of the corner forces (rigid motions store no energy), the four forms of Z
meeting as the taper vanishes, and the areas of NASTRAN-95's lumped mass."""

from __future__ import annotations

import numpy as np
import pytest

from eigenupdate.errors import InputError
from eigenupdate.model import shear_panel

NU = 0.33


def _rigid(xyz):
    out = np.zeros((12, 6))
    for i, p in enumerate(xyz):
        out[3 * i:3 * i + 3, :3] = np.eye(3)
        out[3 * i:3 * i + 3, 3:] = -np.array([[0, -p[2], p[1]], [p[2], 0, -p[0]],
                                              [-p[1], p[0], 0]])
    return out


SHAPES = {
    "rectangle": [[0, 0, 0], [2, 0, 0], [2, 1, 0], [0, 1, 0]],
    "parallelogram": [[0, 0, 0], [2, 0, 0], [2.5, 1, 0], [0.5, 1, 0]],
    "trapezoid 12||34": [[0, 0, 0], [2, 0, 0], [1.7, 1, 0], [0.2, 1, 0]],
    "trapezoid 23||14": [[0, 0, 0], [2, 0, 0], [2.3, 1.5, 0], [0.1, 1, 0]],
    "general": [[0, 0, 0], [2, 0.1, 0], [1.7, 1.2, 0], [0.2, 0.9, 0]],
}


def _turned(x):
    """The panel x turned and moved in space (any orientation)."""
    c, s = np.cos(0.7), np.sin(0.7)
    R = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]) @ np.array([[1, 0, 0], [0, c, s],
                                                                 [0, -s, c]])
    return np.asarray(x, float) @ R.T + [0.3, -1.0, 2.0]


@pytest.mark.parametrize("name", list(SHAPES))
def test_rigid_motions_store_no_energy_and_one_shear_mode(name):
    """Source: equilibrium. The corner forces of a shear flow balance (forces and
    moments), so K annihilates the six rigid motions of a flat panel in any orientation
    (to rounding: 1e-12 of |K| per unit length), and the panel has one stiffness (rank
    one, no direct stress of its own)."""
    x = _turned(SHAPES[name])
    K = shear_panel.shear_stiffness(x[None], np.array([NU]))[0]
    assert np.abs(K @ _rigid(x)).max() <= 1e-12 * np.abs(K).max() * 3
    w = np.linalg.eigvalsh(K)
    assert np.sum(w > 1e-12 * w.max()) == 1


def test_rectangle_is_the_hand_formula():
    """Source: a rectangle a x b in pure shear (u = gamma y) stores G t a b gamma^2 / 2;
    its side b held and the opposite side pushed along itself by F, it moves F b / (G t a)
    (the hand formula's stiffness G t a / b) when its sides may not stretch (their
    normal motions tied): the energy per unit G t, 1e-12."""
    a, b, gamma = 0.6, 0.4, 1e-3
    x = np.array([[0, 0, 0], [a, 0, 0], [a, b, 0], [0, b, 0]], float)
    K = shear_panel.shear_stiffness(x[None], np.array([NU]))[0]
    u = np.zeros(12)
    u[0::3] = gamma * x[:, 1]
    assert u @ K @ u / 2 == pytest.approx(a * b * gamma**2 / 2, rel=1e-12)
    # the sway stiffness: top nodes x by delta, nothing else: G t a / b
    d = np.zeros(12)
    d[[6, 9]] = 1.0
    assert d @ K @ d == pytest.approx(a / b, rel=1e-12)


@pytest.mark.parametrize("skew", [0.5, -0.3])
def test_parallelogram_flexibility_is_its_stress_state(skew):
    """Source: under uniform shear flow q on its edges a parallelogram of skew d (cot of
    its angle; sides 1-2 along x) carries tau = q / t and, for the inclined edges'
    equilibrium, sigma_x = 2 d tau; its complementary energy is S q^2 / (2 G t) (1 +
    2 d^2 / (1 + nu)) (E = 2 G (1 + nu)). The corner forces of that flow (half of each
    adjacent edge times q: q/2 times the diagonal from the corner) applied to K give it:
    f^T K^+ f / 2, 1e-12."""
    a, b = 2.0, 1.0
    x = np.array([[0, 0, 0], [a, 0, 0], [a + skew * b, b, 0], [skew * b, b, 0]], float)
    K = shear_panel.shear_stiffness(x[None], np.array([NU]))[0]
    q = 1.0
    f = np.zeros(12)
    for i in range(4):
        # the flow runs round the panel: each corner gets q/2 of its two edges
        out = (x[(i + 1) % 4] - x[i]) if i % 2 == 0 else (x[(i - 1) % 4] - x[i])
        back = (x[(i - 1) % 4] - x[i]) if i % 2 == 0 else (x[(i + 1) % 4] - x[i])
        f[3 * i:3 * i + 3] = (q / 2) * (out + back) * (1 if i % 2 == 0 else -1)
    energy = f @ np.linalg.pinv(K, rcond=1e-10) @ f / 2
    S = a * b
    assert energy == pytest.approx(S * q * q / 2 * (1 + 2 * skew**2 / (1 + NU)), rel=1e-12)


@pytest.mark.parametrize("kind", ["12||34", "23||14", "general"])
def test_tapered_forms_meet_the_parallelogram_as_the_taper_vanishes(monkeypatch, kind):
    """Source: NASTRAN-95's four forms of the flexibility (trapezoids and the general
    quadrilateral with their logarithms; the parallelogram) describe one panel: forced
    to the tapered form (no branch threshold), a panel of taper eps differs from the
    parallelogram form by O(eps) (measured 1.5 to 2.04 eps: the first-order taper
    terms the parallelogram form leaves out), vanishing with eps: below 3 eps at eps =
    1e-2 ... 1e-5."""
    monkeypatch.setattr(shear_panel, "BRANCH", 1e-300)
    for eps in (1e-2, 1e-3, 1e-4, 1e-5):
        x = {"12||34": [[0, 0, 0], [2, 0, 0], [2 - eps, 1, 0], [eps, 1, 0]],
             "23||14": [[0, 0, 0], [2, 0, 0], [2, 1 + eps, 0], [0, 1 - eps, 0]],
             "general": [[0, 0, 0], [2, 0, 0], [2 - eps, 1 + eps, 0], [eps, 1 - eps, 0]],
             }[kind]
        _, c, area = shear_panel.panel_geometry(np.array([x], float))
        tapered = shear_panel._flexibility(*c, area, np.array([NU]))[0]
        monkeypatch.setattr(shear_panel, "BRANCH", 1.0)
        flat = shear_panel._flexibility(*c, area, np.array([NU]))[0]
        monkeypatch.setattr(shear_panel, "BRANCH", 1e-300)
        assert abs(tapered / flat - 1) <= 3 * eps, (eps, tapered, flat)


def test_lumped_mass_is_nastrans_areas():
    """Source: NASTRAN-95 emadtq.f: grid i gets (S_i + S) / 6 per unit mass per area,
    S_i the triangle of the grid and its neighbours, S the panel (half the diagonals'
    cross product); the total is S on a flat panel. Trapezoid (0,0), (2,0), (1.5,1),
    (0.5,1): S = 1.5, S_1 = S_2 = 1, S_3 = S_4 = 0.5."""
    x = np.array([[[0, 0, 0], [2, 0, 0], [1.5, 1, 0], [0.5, 1, 0]]], float)
    m = np.diag(shear_panel.shear_mass(x)[0])
    assert m[0::3].tolist() == pytest.approx([2.5 / 6, 2.5 / 6, 2 / 6, 2 / 6], rel=1e-14)
    assert np.array_equal(m[0::3], m[1::3]) and np.array_equal(m[0::3], m[2::3])
    assert m[0::3].sum() == pytest.approx(1.5, rel=1e-14)


@pytest.mark.parametrize(("x", "words"), [
    ([[0, 0, 0], [2, 0, 0], [0.5, 0.5, 0], [0, 2, 0]], "not convex"),
    ([[0, 0, 0], [2, 0, 0], [0, 1, 0], [2, 1, 0]], "not convex|zero area"),
    ([[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0]], "zero area"),
    ([[0, 0, 0], [1, 0, 0.2], [1, 1, 0], [0, 1, 0.2]], "warped"),
])
def test_bad_panels_are_refused(x, words):
    """One line naming the element: a concave panel, one numbered across itself, zero
    area, a warped one (as CQUAD4: the projection would change the answer unnoticed)."""
    with pytest.raises(InputError, match=f"CSHEAR 7: ({words})"):
        shear_panel.shear_stiffness(np.array([x], float), np.array([NU]), ["CSHEAR 7"])
