"""PBARL section properties (model/sections.py) against closed forms written here in
another way: rectangles subtracted from their bounding box, or second moments integrated
from an outer edge (int y^2 dA = w (y1^3 - y0^3) / 3) less A ybar^2, instead of the
module's parallel-axis sum about the centroid."""

from __future__ import annotations

import math
import re

import pytest
from hypothesis import given
from hypothesis import strategies as st

from eigenupdate.errors import InputError
from eigenupdate.model.sections import (
    check_dimensions,
    shear_centre_offset,
    thin_walled_section,
    torsion_constant,
)


def _from_edge(strips):
    """A and the centroidal second moment of strips (width, s0, s1) stacked along s."""
    area = sum(w * (s1 - s0) for w, s0, s1 in strips)
    first = sum(w * (s1**2 - s0**2) / 2 for w, s0, s1 in strips)
    second = sum(w * (s1**3 - s0**3) / 3 for w, s0, s1 in strips)
    return area, second - first**2 / area


def test_symmetric_i_beam_by_subtraction():
    """Source: I1 = (b h^3 - (b - tw) hw^3) / 12, I2 = (2 tf b^3 + hw tw^3) / 12 (the
    doubly symmetric I, any steel handbook)."""
    h, b, tw, tf = 0.3, 0.15, 0.0071, 0.0107  # an IPE 300
    hw = h - 2 * tf
    a, i1, i2, i12 = thin_walled_section("I", [h, b, b, tw, tf, tf])
    assert a == pytest.approx(2 * b * tf + hw * tw, rel=1e-14)
    assert i1 == pytest.approx((b * h**3 - (b - tw) * hw**3) / 12, rel=1e-13)
    assert i2 == pytest.approx((2 * tf * b**3 + hw * tw**3) / 12, rel=1e-13)
    assert i12 == 0


def test_unsymmetric_i_beam_from_the_bottom_edge():
    """Source: int y^2 dA from the bottom edge less A ybar^2 (parallel axis), strips
    bottom flange (DIM2 x DIM5), web (DIM4), top flange (DIM3 x DIM6)."""
    h, a_, b, tw, ta, tb = 0.4, 0.2, 0.12, 0.01, 0.025, 0.015
    area, i1 = _from_edge([(a_, 0, ta), (tw, ta, h - tb), (b, h - tb, h)])
    a, j1, i2, _ = thin_walled_section("I", [h, a_, b, tw, ta, tb])
    assert a == pytest.approx(area, rel=1e-14)
    assert j1 == pytest.approx(i1, rel=1e-12)
    assert i2 == pytest.approx((ta * a_**3 + tb * b**3 + (h - ta - tb) * tw**3) / 12, rel=1e-13)


def test_tee_from_the_flange_edge():
    """Source: I1 integrated from the top edge (flange DIM1 x DIM3, then the web DIM4 down
    to DIM2); I2 = (tf b^3 + hw tw^3) / 12 (both parts centred on the y axis)."""
    b, h, tf, tw = 0.2, 0.3, 0.02, 0.01
    area, i1 = _from_edge([(b, 0, tf), (tw, tf, h)])
    a, j1, i2, i12 = thin_walled_section("T", [b, h, tf, tw])
    assert (a, j1, i2, i12) == pytest.approx((area, i1, (tf * b**3 + (h - tf) * tw**3) / 12,
                                              0.0), rel=1e-12)


def test_channel_by_subtraction_and_from_the_web():
    """Source: I1 = (b h^3 - (b - tw) (h - 2 tf)^3) / 12; I2 integrated from the web's
    outer face along z (the web, then two flanges)."""
    b, h, tw, tf = 0.1, 0.3, 0.01, 0.02
    area, i2 = _from_edge([(h, 0, tw), (2 * tf, tw, b)])
    a, i1, j2, i12 = thin_walled_section("CHAN", [b, h, tw, tf])
    assert a == pytest.approx(area, rel=1e-14)
    assert i1 == pytest.approx((b * h**3 - (b - tw) * (h - 2 * tf) ** 3) / 12, rel=1e-13)
    assert j2 == pytest.approx(i2, rel=1e-12)
    assert i12 == pytest.approx(0.0, abs=1e-14 * i1)


@pytest.mark.parametrize("ratio,beta", [(1, 0.141), (1.5, 0.196), (2, 0.229), (3, 0.263),
                                        (5, 0.291), (10, 0.312)])
def test_bar_torsion_constant_against_the_exact_series(ratio, beta):
    """Source: Timoshenko & Goodier, Theory of Elasticity, torsion of a rectangular bar,
    J = beta a b^3 (beta to 3 digits) from the exact series; NASTRAN's approximation
    stays within their rounding. Either side may be the long one."""
    for dim in ([ratio, 1.0], [1.0, ratio]):
        assert torsion_constant("BAR", dim) == pytest.approx(beta * ratio, rel=4e-3)


def test_box_torsion_constant_is_bredt():
    """Source: Bredt, closed thin-walled section J = 4 Am^2 / (contour integral ds / t) on
    the walls' mid-line."""
    b, h, t1, t2 = 0.1, 0.2, 0.01, 0.02  # DIM3 = t1 top and bottom, DIM4 = t2 sides
    am = (b - t2) * (h - t1)
    assert torsion_constant("BOX", [b, h, t1, t2]) == pytest.approx(
        4 * am**2 / (2 * (b - t2) / t1 + 2 * (h - t1) / t2), rel=1e-13)


def test_open_section_torsion_constant():
    """Source: open thin-walled section J = sum l t^3 / 3 over the walls' mid-line
    lengths l (Timoshenko & Goodier; the formulas of NASTRAN's PBARL tables)."""
    h, a, b, tw, ta, tb = 0.4, 0.2, 0.12, 0.01, 0.025, 0.015
    web = h - ta / 2 - tb / 2
    assert torsion_constant("I", [h, a, b, tw, ta, tb]) == pytest.approx(
        (a * ta**3 + b * tb**3 + web * tw**3) / 3, rel=1e-13)
    assert torsion_constant("T", [0.2, 0.3, 0.02, 0.01]) == pytest.approx(
        (0.2 * 0.02**3 + (0.3 - 0.01) * 0.01**3) / 3, rel=1e-13)
    assert torsion_constant("CHAN", [0.1, 0.3, 0.01, 0.02]) == pytest.approx(
        (2 * (0.1 - 0.005) * 0.02**3 + (0.3 - 0.02) * 0.01**3) / 3, rel=1e-13)


dims = st.floats(0.01, 1.0)


@given(h=dims, a=dims, b=dims, tw=dims, ta=st.floats(0.001, 0.3), tb=st.floats(0.001, 0.3))
def test_i_beam_upside_down_is_the_same(h, a, b, tw, ta, tb):
    """Swapping the flanges (DIM2, DIM5 <-> DIM3, DIM6) turns the section over: A, I1,
    I2 and J do not change."""
    h = h + ta + tb
    one = (*thin_walled_section("I", [h, a, b, tw, ta, tb]),
           torsion_constant("I", [h, a, b, tw, ta, tb]))
    two = (*thin_walled_section("I", [h, b, a, tw, tb, ta]),
           torsion_constant("I", [h, b, a, tw, tb, ta]))
    assert one[:3] == pytest.approx(two[:3], rel=1e-10)
    assert one[4] == pytest.approx(two[4], rel=1e-12)


@pytest.mark.parametrize("shape,dim,message", [
    ("I", [0.3, 0.1, 0.1, 0.01, 0.2, 0.1], "section I needs DIM1 > DIM5 + DIM6"),
    ("T", [0.2, 0.3, 0.02], "section T has 4 dimensions, got 3"),
    ("CHAN", [0.1, 0.3, 0.0, 0.02], "dimensions must be > 0"),
    ("BOX", [0.1, math.nan, 0.01, 0.01], "dimensions must be > 0"),
    ("TUBE", [0.05, 0.06], "section TUBE needs DIM1 > DIM2"),
])
def test_bad_dimensions(shape, dim, message):
    with pytest.raises(InputError, match=re.escape(message)):
        check_dimensions(shape, dim)


def test_shear_centre_of_monosymmetric_sections():
    """Shear centre less centroid on the walls' mid-lines, by hand: a T's at the flange's
    mid-line (its centroid from the bottom summed here); a channel's
    e = 3 b^2 tf / (6 b tf + h tw) behind the web (Roark's Formulas for Stress and Strain,
    Table 10.7, with b, h the mid-line flange length and web height); an I with unequal
    flanges at h I_top / (I_top + I_bot) above the bottom flange's mid-line, which tends
    to the T's junction as the bottom flange vanishes; a doubly symmetric I gives 0."""
    b, h, tf, tw = 0.15, 0.2, 0.012, 0.008  # T: flange on top, web below
    ybar = (b * tf * (h - tf / 2) + tw * (h - tf) ** 2 / 2) / (b * tf + tw * (h - tf))
    dy, dz = shear_centre_offset("T", [b, h, tf, tw])
    assert math.isclose(dy, h - tf / 2 - ybar, rel_tol=1e-12) and dz == 0.0
    b, h, tw, tf = 0.09, 0.26, 0.01, 0.014  # CHAN: web at the back, flanges towards +z
    bf = b - tw
    zbar = (h * tw * tw / 2 + 2 * bf * tf * (tw + bf / 2)) / (h * tw + 2 * bf * tf)
    bm, hm = b - tw / 2, h - tf
    e = 3 * bm**2 * tf / (6 * bm * tf + hm * tw)
    dy, dz = shear_centre_offset("CHAN", [b, h, tw, tf])
    assert dy == 0.0 and math.isclose(dz, tw / 2 - e - zbar, rel_tol=1e-12)
    assert shear_centre_offset("I", [0.3, 0.15, 0.15, 0.0071, 0.0107, 0.0107])[0] == \
        pytest.approx(0.0, abs=1e-15)
    tee = shear_centre_offset("T", [0.15, 0.3, 0.0107, 0.0071])[0]
    nearly = shear_centre_offset("I", [0.3, 1e-4, 0.15, 0.0071, 1e-6, 0.0107])[0]
    assert math.isclose(nearly, tee, rel_tol=1e-3)
