"""CQUAD8 and CTRIA6 with a thickness profile (model/shells_quadratic.py ``nodal_profile``,
``local_parts(..., profile=)``, ``shell_mass(..., profile=)``: NASTRAN's corner
thicknesses T1-T4). Independent references: the bilinear / linear interpolation of the
corners written out by hand, and the integrands' scaling by hand (a uniform profile c
multiplies each part by c to its power at every point). The deck-level checks (a
Timoshenko beam, CalculiX, central differences): tests/io/test_nastran_corners_quadratic.py."""

from __future__ import annotations

import numpy as np
import pytest
from quadratic_meshes import cylinder_mesh, drop_mid_sides, plate_mesh

from eigenupdate.model import shells
from eigenupdate.model import shells_quadratic as sq

MODULI = shells.pshell_moduli(2.1e11, 0.3)[:3]


@pytest.mark.parametrize("k", [8, 6])
def test_nodal_profile_interpolates_the_corners_field(k):
    """Source: hand calculation, the corners' bilinear field sum (1 + xi_i xi)(1 + eta_i
    eta) / 4 t_i (CQUAD8) and linear field (1 - r - s) t1 + r t2 + s t3 (CTRIA6): the
    element's shape functions on :func:`nodal_profile`'s nodal values give it at any
    point (round-off, 1e-14)."""
    rng = np.random.default_rng(3)
    c = rng.uniform(0.2, 1.5, (1, 4 if k == 8 else 3))
    nodal = sq.nodal_profile(c)[0]
    for p, q in rng.uniform(-1.0 if k == 8 else 0.0, 1.0, (20, 2)):
        if k == 6 and p + q > 1:  # folded into the unit triangle
            p, q = 1 - p, 1 - q
        if k == 8:
            xi, eta = np.array([-1, 1, 1, -1]), np.array([-1, -1, 1, 1])
            exact = np.sum((1 + xi * p) * (1 + eta * q) / 4 * c[0])
        else:
            exact = (1 - p - q) * c[0, 0] + p * c[0, 1] + q * c[0, 2]
        assert sq.shape(k, p, q)[0] @ nodal == pytest.approx(exact, rel=1e-14)


def _elements(triangles):
    """Curved elements of a cylinder and flat ones with some mid-side nodes blank
    (transition elements)."""
    xyz, el = cylinder_mesh(6, 1, 1.0, 1.0, triangles)
    curved = xyz[el][:4]
    if triangles:  # CTRIA6 is projected flat: keep its mid-sides near its corners' plane
        curved = curved[:0]
    xyz, el = plate_mesh(2, 1.0, 0.7, triangles)
    blank = drop_mid_sides(xyz, el, "random", seed=1)[0]
    return np.concatenate([curved, xyz[el], blank])


@pytest.mark.parametrize("triangles", [False, True], ids=["CQUAD8", "CTRIA6"])
def test_uniform_profile_scales_each_part_by_its_power(triangles):
    """Source: hand calculation: a profile c at every node is c at every integration
    point, so membrane, drilling and shear scale by c, bending by c^3 and the mass
    (coupled and HRZ-lumped) by c, on curved, flat and transition elements (round-off,
    1e-13 of the largest entry); None and all ones give the same parts (the shape
    functions sum to one within a few eps: 1e-14)."""
    x = _elements(triangles)
    n, k = x.shape[:2]
    c = 0.7
    _, plain = sq.local_parts(x, *MODULI)
    _, ones = sq.local_parts(x, *MODULI, profile=np.ones((n, k)))
    _, scaled = sq.local_parts(x, *MODULI, profile=np.full((n, k), c))
    for name, (_, block) in plain.items():
        top = np.abs(block).max()
        assert np.abs(ones[name][1] - block).max() <= 1e-14 * top
        power = shells.THICKNESS_POWER[name]
        assert np.abs(scaled[name][1] - c**power * block).max() <= 1e-13 * top, name
    for lumped in (False, True):
        m = sq.shell_mass(x, lumped)
        got = sq.shell_mass(x, lumped, profile=np.full((n, k), c))
        assert np.abs(got - c * m).max() <= 1e-13 * np.abs(m).max()


def test_profile_with_a_laminate_coupling_is_not_formed():
    """The laminate's coupling with a taper is refused (io/nastran_corners.py names the
    element); the model says so rather than forming it wrongly."""
    x = _elements(False)
    with pytest.raises(ValueError, match="coupling with a profile"):
        sq.local_parts(x, *MODULI, coupling=np.zeros((3, 3)),
                       profile=np.ones(x.shape[:2]))
