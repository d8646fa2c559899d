"""3-D frame element matrices (no pyNastran needed): rigid-body motions, symmetry, mass."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from eigenupdate.errors import InputError
from eigenupdate.model import frame3d

vec = st.lists(st.floats(-3, 3), min_size=3, max_size=3).map(np.array)


def _element(xa, xb, v, wa, wb, frame_a, frame_b):
    L, R = frame3d.local_axes(xa[None], xb[None], v[None])
    T = frame3d.element_transform(R, wa[None], wb[None], frame_a[None], frame_b[None])
    return L, T


def _rotation(seed):
    q, r = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    return q * np.sign(np.diag(r))


@settings(max_examples=50, deadline=None)
@given(xa=vec, d=vec, v=vec, wa=vec, wb=vec, seed=st.integers(0, 10**6))
def test_rigid_body_motions_are_stress_free(xa, d, v, wa, wb, seed):
    """Source: an elastic element stores no energy in a rigid-body motion, whatever its
    orientation, offsets and grid displacement frames (K T r = 0 for 6 rigid motions)."""
    if np.linalg.norm(d) < 0.1 or np.linalg.norm(np.cross(d, v)) < 0.1 * np.linalg.norm(d):
        return
    fa, fb = _rotation(seed), _rotation(seed + 1)
    ga, gb = xa - wa, xa + d - wb  # grids, the element ends sit at the offsets
    L, T = _element(xa, xa + d, v, wa, wb, fa, fb)
    parts = frame3d.stiffness_parts(L)
    k = sum(frame3d.to_global(p, T)[0] for p in parts.values())
    assert np.allclose(k, k.T, atol=1e-9 * abs(k).max())
    for axis in range(6):
        r = np.zeros(12)
        for g, frame, sl in ((ga, fa, slice(0, 6)), (gb, fb, slice(6, 12))):
            t = np.zeros(3)
            th = np.zeros(3)
            if axis < 3:
                t[axis] = 1.0
            else:
                th[axis - 3] = 1.0
                t = np.cross(th, g)  # rotation about the origin moves the grid
            r[sl] = np.concatenate([frame @ t, frame @ th])  # in the grid's frame
        assert np.abs(k @ r).max() <= 1e-8 * abs(k).max() * (1 + np.abs(r).max())


@pytest.mark.parametrize("consistent", [True, False])
def test_translational_mass_is_rigid_mass(consistent):
    """The mass matrix gives the element's mass rho A L for a rigid translation in any
    direction, for bars and rods alike."""
    L, T = _element(np.zeros(3), np.array([1.0, 2.0, 2.0]), np.array([0.0, 0.0, 1.0]),
                    np.zeros(3), np.zeros(3), np.eye(3), np.eye(3))
    for m in (frame3d.mass_parts(L, consistent)["translation"],
              frame3d.rod_mass_part(L, consistent)):
        mg = frame3d.to_global(m, T)[0]
        for axis in range(3):
            r = np.zeros(12)
            r[[axis, axis + 6]] = 1.0
            assert r @ mg @ r == pytest.approx(3.0, rel=1e-12)


def test_bad_geometry_names_the_element():
    with pytest.raises(InputError, match="CBAR 7: zero-length"):
        frame3d.local_axes(np.zeros((1, 3)), np.zeros((1, 3)), np.ones((1, 3)), ["CBAR 7"])
    with pytest.raises(InputError, match="CBAR 7: orientation vector"):
        frame3d.local_axes(np.zeros((1, 3)), np.ones((1, 3)), np.ones((1, 3)), ["CBAR 7"])


def test_consistent_mass_of_rigid_motions_with_offsets():
    """Source: the exact rigid-body inertia of a uniform line segment (ends p, q, axis e,
    mass L per unit mass per length, centre c): mass L, first moment L c, inertia about
    the origin L (|c|^2 1 - c c^T) + L^3 / 12 (1 - e e^T); the torsion part adds L e e^T.
    Cubic bending and linear axial shape functions move rigidly exactly, so R^T M R must
    equal it, with the segment carried by rigid offsets from its grids."""
    ga, gb = np.array([0.2, -0.1, 0.4]), np.array([1.5, 0.9, 1.1])
    wa, wb = np.array([0.05, 0.1, -0.2]), np.array([-0.1, 0.03, 0.15])
    p, q = ga + wa, gb + wb
    L, T = _element(p, q, np.array([0.3, -1.0, 0.5]), wa, wb, _rotation(1), _rotation(2))
    parts = frame3d.mass_parts(L, True)
    rigid = np.zeros((12, 6))  # columns: translations x, y, z, rotations about the origin
    for g, frame, sl in ((ga, _rotation(1), slice(0, 6)), (gb, _rotation(2), slice(6, 12))):
        for axis in range(6):
            t, th = np.zeros(3), np.zeros(3)
            if axis < 3:
                t[axis] = 1.0
            else:
                th[axis - 3] = 1.0
                t = np.cross(th, g)
            rigid[sl, axis] = np.concatenate([frame @ t, frame @ th])
    length = float(L[0])
    e, c = (q - p) / length, (p + q) / 2
    cx = frame3d.skew(c[None])[0]
    want = np.zeros((6, 6))
    want[:3, :3] = length * np.eye(3)
    want[:3, 3:] = -length * cx
    want[3:, :3] = length * cx
    want[3:, 3:] = length * (c @ c * np.eye(3) - np.outer(c, c)) + \
        length**3 / 12 * (np.eye(3) - np.outer(e, e))
    got = rigid.T @ frame3d.to_global(parts["translation"], T)[0] @ rigid
    assert np.allclose(got, want, rtol=1e-12, atol=1e-12)
    got_t = rigid.T @ frame3d.to_global(parts["torsion"], T)[0] @ rigid
    assert np.allclose(got_t[3:, 3:], length * np.outer(e, e), atol=1e-12)
