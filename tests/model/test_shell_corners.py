"""Corner thickness profiles of the flat shells (model/shells.py, shells_drilling.py,
shell_offsets.py ``profile``: the thickness interpolated to each integration point).
Independent references: the uniform element scaled by the thickness's power, and closed
forms of the energy of constant strain, curvature and shear states on a tapered element,
which the element's integration rule integrates exactly."""

from __future__ import annotations

import numpy as np
import pytest

from eigenupdate.model import shell_offsets, shells, shells_drilling

E, NU = 2.0e11, 0.3
QUAD = np.array([[[0.0, 0, 0], [2, 0, 0], [2, 1, 0], [0, 1, 0]]])  # a 2 x 1 rectangle
TRIA = np.array([[[0.0, 0, 0], [2, 0, 0], [0, 1, 0]]])
MODULI = shells.pshell_moduli(E, NU)


def _parts(module, xyz, profile=None):
    _, parts = module.local_parts(xyz, *MODULI, labels=["e"], profile=profile)
    return {name: (c, b[0]) for name, (c, b) in parts.items()}


@pytest.mark.parametrize(("module", "xyz"), [(shells, QUAD), (shells, TRIA),
                                             (shells_drilling, QUAD), (shells_drilling, TRIA)],
                         ids=["CQUAD4", "CTRIA3", "CQUADR", "CTRIAR"])
def test_uniform_profile_scales_each_part_by_its_power(module, xyz):
    """Source: the uniform element. A profile c at every corner is the element of
    thickness c T: membrane, drilling and shear times c, bending c^3, the mass c
    (rounding of a few products: 1e-14); a profile of ones is the element itself."""
    c = 1.7
    ref, ones = _parts(module, xyz), _parts(module, xyz, np.ones((1, xyz.shape[1])))
    got = _parts(module, xyz, np.full((1, xyz.shape[1]), c))
    for name, (cols, block) in ref.items():
        power = shells.THICKNESS_POWER[name]
        assert np.array_equal(got[name][0], cols)
        scale = np.abs(block).max()
        assert np.abs(got[name][1] - c**power * block).max() <= 1e-14 * c**power * scale
        assert np.abs(ones[name][1] - block).max() <= 1e-14 * scale
    for lumped in (False, True):
        m = shells.shell_mass(xyz, lumped)
        assert np.abs(shells.shell_mass(xyz, lumped, profile=np.full((1, xyz.shape[1]), c))
                      - c * m).max() <= 1e-14 * c * np.abs(m).max()


def _field(xyz, u=0.0, w=0.0, ry=0.0):
    """Nodal values (6k,) of u = u x, w = w x, ry = ry x."""
    d = np.zeros((xyz.shape[1], 6))
    d[:, 0], d[:, 2], d[:, 4] = u * xyz[0, :, 0], w * xyz[0, :, 0], ry * xyz[0, :, 0]
    return d.ravel()


def _energy(parts, name, d):
    cols, block = parts[name]
    return 0.5 * d[cols] @ block @ d[cols]


G0, G1 = 1.0, 0.4  # the profile at x = 0 and x = 2: linear in x


def _linear(xyz):
    return (G0 + (G1 - G0) * xyz[0, :, 0] / 2.0)[None]


def test_tapered_bending_and_shear_energies_are_the_closed_forms():
    """Source: closed forms on the 2 x 1 CQUAD4 with thickness linear in x (G0 to G1):
    constant curvature ry = k x has the bending energy k^2 / 2 D11 integral of g^3
    = k^2 / 2 D11 2 (G1^4 - G0^4) / (4 (G1 - G0)) (the 2 x 2 rule is exact for the
    cubic), and the constant shear w = gamma x the shear energy gamma^2 / 2 H11
    integral of g = gamma^2 / 2 H11 2 (G0 + G1) / 2 (both per unit thickness power, as
    the parts; round-off 1e-13)."""
    parts = _parts(shells, QUAD, _linear(QUAD))
    k, gamma = 0.3, 0.2
    cube = 2 * (G1**4 - G0**4) / (4 * (G1 - G0))  # integral of g^3 over x in [0, 2], y in [0, 1]
    bend = _energy(parts, "bending", _field(QUAD, ry=k))
    assert abs(bend / (0.5 * k**2 * MODULI[1][0, 0, 0] * cube) - 1) <= 1e-13
    shear = _energy(parts, "shear", _field(QUAD, w=gamma))
    assert abs(shear / (0.5 * gamma**2 * MODULI[2][0, 0, 0] * (G0 + G1)) - 1) <= 1e-13


@pytest.mark.parametrize("module", [shells, shells_drilling], ids=["CTRIA3", "CTRIAR"])
def test_tapered_triangle_membrane_energy_is_the_closed_form(module):
    """Source: closed form on the right triangle (legs 2, 1) with thickness linear in x:
    the constant strain u = e x (rz = 0: Allman's edge bumps vanish) has the energy
    e^2 / 2 A11 integral of g, g's mean at the corners times the area (the 3-point rule
    is exact for linear g; round-off 1e-13)."""
    e = 1e-3
    parts = _parts(module, TRIA, _linear(TRIA))
    got = _energy(parts, "membrane", _field(TRIA, u=e))
    assert abs(got / (0.5 * e**2 * MODULI[0][0, 0, 0] * _linear(TRIA).mean() * 1.0) - 1) <= 1e-13


@pytest.mark.parametrize("xyz", [QUAD, TRIA], ids=["CQUAD4", "CTRIA3"])
def test_tapered_mass_is_the_integral_of_the_thickness(xyz):
    """Source: closed form: the total translational mass (consistent or lumped) of an
    element with a linear profile is its area times the profile's mean over it (the
    integration rules are exact for it: 1e-14), and its first and second moments under an
    offset carry the same profile (shell_offsets.offset_mass, the translational mass's
    blocks)."""
    g = _linear(xyz)
    area = 2.0 if xyz.shape[1] == 4 else 1.0
    mean = g.mean() if xyz.shape[1] == 3 else (G0 + G1) / 2
    for lumped in (False, True):
        m = shells.shell_mass(xyz, lumped, profile=g)[0, 0::6, 0::6]
        assert abs(m.sum() / (area * mean) - 1) <= 1e-14
        first, second = shell_offsets.offset_mass(xyz, lumped, profile=g)
        assert np.abs(first[0, 0::6, 4::6] - m).max() <= 1e-15 * m.max()
        assert np.abs(second[0, 3::6, 3::6] - m).max() <= 1e-15 * m.max()
