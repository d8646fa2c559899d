"""CQUADR / CTRIAR (model/shells_drilling.py): Allman / Ibrahimbegovic-Taylor-Wilson
membrane with vertex rotations, Hughes-Brezzi drilling penalty, CQUAD4/CTRIA3 bending.

Sources: rigid-body kinematics (six zero-energy modes, the drilling rotation equal to the
in-plane rotation); MacNeal & Harder's membrane patch test (Finite Elem. Anal. Des. 1,
1985: a 0.24 x 0.12 patch of five distorted quadrilaterals, a linear displacement on its
boundary); Timoshenko beam theory for a slender in-plane cantilever."""

from __future__ import annotations

import numpy as np
import pytest

from eigenupdate.model import shells
from eigenupdate.model import shells_drilling as drill

_TURN = np.linalg.qr(np.array([[1.0, 0.4, -0.3], [0.2, 1.0, 0.5], [-0.6, 0.1, 1.0]]))[0]
# a distorted flat quadrilateral and a triangle, turned out of every basic plane
_QUAD = np.array([[0.0, 0.0, 0.0], [2.0, 0.2, 0.0], [2.3, 1.4, 0.0], [-0.2, 1.0, 0.0]]) @ _TURN
_TRIA = np.array([[0.0, 0.0, 0.0], [2.0, 0.3, 0.0], [0.4, 1.5, 0.0]]) @ _TURN


def _element_k(xyz, T=0.05):
    """K (6k, 6k) in global axes of one element of unit E, NU 0.3, thickness T."""
    m, b, s = shells.pshell_moduli(1.0, 0.3)
    R, parts = drill.local_parts(xyz[None], m, b, s)
    f = {"membrane": T, "drilling": T, "bending": T**3, "shear": T}
    return shells.combine(R, parts, {q: np.array([v]) for q, v in f.items()})[0]


@pytest.mark.parametrize("xyz", [_QUAD, _TRIA], ids=["CQUADR", "CTRIAR"])
def test_free_element_has_exactly_the_six_rigid_modes(xyz):
    """Rigid motions u = a + theta x r with every node's rotation theta (the drilling
    rotation equal to the in-plane one) do no work, and they are the only ones: six
    eigenvalues at rounding level (eps ||K|| times the size, 1e-12 of the largest) and the
    seventh far above it. Source: rigid-body kinematics."""
    K = _element_k(xyz)
    lam = np.linalg.eigvalsh(K)
    top = lam[-1]
    assert np.all(np.abs(lam[:6]) <= 1e-12 * top) and lam[6] > 1e-7 * top
    for a, theta in [(e, np.zeros(3)) for e in np.eye(3)] + [(np.zeros(3), e) for e in np.eye(3)]:
        d = np.zeros((xyz.shape[0], 6))
        d[:, :3] = a + np.cross(theta, xyz)
        d[:, 3:] = theta
        assert np.abs(K @ d.ravel()).max() <= 1e-12 * top * np.abs(d).max()


# MacNeal & Harder's patch: corners of 0.24 x 0.12, four inner nodes, five quadrilaterals
_PATCH = np.array([[0.0, 0.0], [0.24, 0.0], [0.24, 0.12], [0.0, 0.12],
                   [0.04, 0.02], [0.18, 0.03], [0.16, 0.08], [0.08, 0.08]])
_PATCH_QUADS = np.array([[0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7],
                         [4, 5, 6, 7]])


@pytest.mark.parametrize("triangles", [False, True], ids=["CQUADR", "CTRIAR"])
def test_membrane_patch_test(triangles):
    """A linear displacement (u, v) with the rotations theta = (v,x - u,y) / 2 held on
    the patch's corners: the inner nodes take the same linear field and rotation (to
    rounding: cond(K) eps ~ 1e-12), whence constant strain in every element. Source:
    MacNeal & Harder's membrane patch test."""
    els = (np.vstack([_PATCH_QUADS[:, [0, 1, 2]], _PATCH_QUADS[:, [0, 2, 3]]]) if triangles
           else _PATCH_QUADS)
    km, kd = drill.membrane_drilling(_PATCH[els], shells.plane_stress(1.0, 0.25))
    K = np.zeros((3 * 8, 3 * 8))
    for e, k in zip(els, km + kd, strict=True):
        dof = (3 * e[:, None] + np.arange(3)).ravel()
        K[np.ix_(dof, dof)] += k
    x, y = _PATCH.T
    exact = np.column_stack([1e-3 * (1 + 2 * x + 0.5 * y), 1e-3 * (-0.5 + x + 3 * y),
                             np.full(8, 1e-3 * (1 - 0.5) / 2)]).ravel()
    held = np.arange(12)
    free = np.arange(12, 24)
    got = -np.linalg.solve(K[np.ix_(free, free)], K[np.ix_(free, held)] @ exact[held])
    assert np.abs(got - exact[free]).max() <= 1e-9 * np.abs(exact).max()


def _cantilever_tip(n: int, triangles: bool, L=10.0, h=1.0, nu=0.25) -> float:
    """Tip deflection over Timoshenko's PL^3 / 3EI + PL / (5/6 G A) of an L x h
    cantilever (E = 1, unit thickness) of 5n x n elements, clamped at x = 0 (u, v, rz),
    a parabolic shear force P = 1 at x = L."""
    nx, ny = 5 * n, n
    xs, ys = np.linspace(0, L, nx + 1), np.linspace(0, h, ny + 1)
    pts = np.array([(a, b) for a in xs for b in ys])
    at = np.arange(pts.shape[0]).reshape(nx + 1, ny + 1)
    quads = np.column_stack([at[:-1, :-1].ravel(), at[1:, :-1].ravel(), at[1:, 1:].ravel(),
                             at[:-1, 1:].ravel()])
    els = np.vstack([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]]) if triangles else quads
    km, kd = drill.membrane_drilling(pts[els], shells.plane_stress(1.0, nu))
    K = np.zeros((3 * pts.shape[0],) * 2)
    for e, k in zip(els, km + kd, strict=True):
        dof = (3 * e[:, None] + np.arange(3)).ravel()
        K[np.ix_(dof, dof)] += k
    f = np.zeros(K.shape[0])
    q = 6 * ys * (h - ys) / h**3  # parabolic shear stress, resultant 1
    for j in range(ny):  # consistent loads of the linear interpolant
        dy = ys[j + 1] - ys[j]
        f[3 * at[nx, j] + 1] += dy * (2 * q[j] + q[j + 1]) / 6
        f[3 * at[nx, j + 1] + 1] += dy * (q[j] + 2 * q[j + 1]) / 6
    free = np.setdiff1d(np.arange(K.shape[0]), (3 * at[0][:, None] + np.arange(3)).ravel())
    u = np.zeros(K.shape[0])
    u[free] = np.linalg.solve(K[np.ix_(free, free)], f[free])
    exact = L**3 / (3 * h**3 / 12) + L / (5 / 6 / (2 * (1 + nu)) * h)
    return u[3 * at[nx, ny // 2] + 1] / exact


@pytest.mark.parametrize("triangles", [False, True], ids=["CQUADR", "CTRIAR"])
def test_in_plane_cantilever_converges_to_beam_theory(triangles):
    """Source: Timoshenko beam theory (shear factor 5/6), L/h = 10, meshes 10 x 2, 20 x 4,
    40 x 8. The membrane bends with the vertex rotations (a bilinear or linear membrane
    would lock: 0.3 or less on 10 x 2); the deflection converges monotonically, about
    quadratically (error ratio >= 3 per halving), and its Richardson extrapolation lies
    within 1 % of beam theory (whose own difference from the 2D clamped solution is of
    the order of the shear share, (E / 4 kappa G) (h / L)^2 = 0.75 %). Measured: quads
    0.733, 0.930, 0.981; triangles 0.558, 0.857, 0.959."""
    r = np.array([_cantilever_tip(n, triangles) for n in (2, 4, 8)])
    e = 1 - r
    assert np.all(np.diff(r) > 0) and r[-1] < 1.01
    ratio = e[1] / e[2]
    assert ratio >= 3 and e[0] / e[1] >= 3
    assert abs(r[2] + (r[2] - r[1]) / (ratio - 1) - 1) <= 0.01

