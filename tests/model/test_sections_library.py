"""MSC beam-library shapes (model/sections_library.py) against an independent computation:
Green's theorem over each section's outline, the polygon written here vertex by vertex
from MSC's figure (y up, z across), not from the module's rectangles or base shapes.

Tolerances: the polygon sums and the module's closed forms are both exact in exact
arithmetic; each is a few tens of products of numbers of one size, and the outlines are
placed with the origin inside the section, so the centroidal moments lose at most about
one digit to cancellation: 1e-12 relative is well above 10 * 30 * eps."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from eigenupdate.errors import InputError
from eigenupdate.model.sections import (
    check_dimensions,
    section_properties,
    section_values,
    shear_centre_offset,
)


def _raw(points) -> np.ndarray:
    """A, int z, int y, int y^2, int z^2, int y z over a closed polygon of (z, y)
    vertices (Green's theorem), counter-clockwise positive."""
    z, y = np.array(points, float).T
    z1, y1 = np.roll(z, -1), np.roll(y, -1)
    c = z * y1 - z1 * y
    return np.array([c.sum() / 2, ((z + z1) * c).sum() / 6, ((y + y1) * c).sum() / 6,
                     ((y * y + y * y1 + y1 * y1) * c).sum() / 12,
                     ((z * z + z * z1 + z1 * z1) * c).sum() / 12,
                     ((z * y1 + 2 * z * y + 2 * z1 * y1 + z1 * y) * c).sum() / 24])


def polygon(outer, hole=None) -> tuple[float, float, float, float]:
    """A, I1 = int y^2, I2 = int z^2, I12 = int y z about the centroid of an outline
    (less a hole), each traversed either way."""
    r = _raw(outer) * np.sign(_raw(outer)[0])
    if hole is not None:
        r = r - _raw(hole) * np.sign(_raw(hole)[0])
    a, sz, sy, iyy, izz, iyz = r
    zc, yc = sz / a, sy / a
    return a, iyy - a * yc**2, izz - a * zc**2, iyz - a * yc * zc


def outline(shape: str, d: list[float]):
    """The section's outline (z, y) from MSC's figure for ``shape`` with DIMs ``d``; a
    second polygon is a hole."""
    if shape == "T1":  # vertical plate DIM1 x DIM3 at z >= 0, arm DIM2 x DIM4 towards -z
        h, arm, tp, ta = d
        return [(0, -h / 2), (tp, -h / 2), (tp, h / 2), (0, h / 2), (0, ta / 2),
                (-arm, ta / 2), (-arm, -ta / 2), (0, -ta / 2)], None
    if shape == "T2":  # flange DIM1 x DIM3 at the bottom, web DIM4 up to DIM2
        b, h, tf, tw = d
        return [(-b / 2, 0), (b / 2, 0), (b / 2, tf), (tw / 2, tf), (tw / 2, h),
                (-tw / 2, h), (-tw / 2, tf), (-b / 2, tf)], None
    if shape in ("I1", "CHAN1", "Z"):  # outstand DIM1, web DIM2, clear web DIM3, height DIM4
        f, tw, hw, h = d
        if shape == "I1":
            w = f / 2 + tw / 2
            return [(-w, -h / 2), (w, -h / 2), (w, -hw / 2), (tw / 2, -hw / 2),
                    (tw / 2, hw / 2), (w, hw / 2), (w, h / 2), (-w, h / 2), (-w, hw / 2),
                    (-tw / 2, hw / 2), (-tw / 2, -hw / 2), (-w, -hw / 2)], None
        if shape == "CHAN1":  # web at the back (z = 0), flanges towards +z
            return [(0, -h / 2), (f + tw, -h / 2), (f + tw, -hw / 2), (tw, -hw / 2),
                    (tw, hw / 2), (f + tw, hw / 2), (f + tw, h / 2), (0, h / 2)], None
        return [(-f - tw / 2, h / 2), (-f - tw / 2, hw / 2), (-tw / 2, hw / 2),
                (-tw / 2, -h / 2), (f + tw / 2, -h / 2), (f + tw / 2, -hw / 2),
                (tw / 2, -hw / 2), (tw / 2, h / 2)], None
    if shape == "CHAN2":  # a U: base DIM4 x DIM2, legs DIM1 thick up to DIM3
        tl, tb, h, w = d
        return [(0, 0), (w, 0), (w, h), (w - tl, h), (w - tl, tb), (tl, tb), (tl, h),
                (0, h)], None
    if shape == "H":  # plates DIM2 / 2 x DIM3, DIM1 apart, web DIM4 at mid-height
        gap, tt, h, tw = d
        o, i = gap / 2 + tt / 2, gap / 2
        return [(-o, -h / 2), (-i, -h / 2), (-i, -tw / 2), (i, -tw / 2), (i, -h / 2),
                (o, -h / 2), (o, h / 2), (i, h / 2), (i, tw / 2), (-i, tw / 2), (-i, h / 2),
                (-o, h / 2)], None
    if shape == "CROSS":  # vertical DIM2 x DIM3, arms DIM1 / 2 x DIM4 each side
        arms, tv, h, th = d
        o, v = arms / 2 + tv / 2, tv / 2
        return [(-v, -h / 2), (v, -h / 2), (v, -th / 2), (o, -th / 2), (o, th / 2),
                (v, th / 2), (v, h / 2), (-v, h / 2), (-v, th / 2), (-o, th / 2),
                (-o, -th / 2), (-v, -th / 2)], None
    if shape == "HEXA":  # points at z = +-DIM2 / 2, DIM1 deep, height DIM3
        a, w, h = d
        return [(-w / 2, 0), (-w / 2 + a, -h / 2), (w / 2 - a, -h / 2), (w / 2, 0),
                (w / 2 - a, h / 2), (-w / 2 + a, h / 2)], None
    if shape == "HAT":  # crown DIM3 on top, wall DIM2, feet DIM4 beyond the webs
        h, t, w, f = d
        return [(-w / 2 - f, 0), (-w / 2 + t, 0), (-w / 2 + t, h - t), (w / 2 - t, h - t),
                (w / 2 - t, 0), (w / 2 + f, 0), (w / 2 + f, t), (w / 2, t), (w / 2, h),
                (-w / 2, h), (-w / 2, t), (-w / 2 - f, t)], None
    # BOX1: outside DIM1 x DIM2; walls top DIM3, bottom DIM4, right DIM5, left DIM6
    b, h, tt, tb, tr, tl = d
    return ([(0, 0), (b, 0), (b, h), (0, h)],
            [(tl, tb), (b - tr, tb), (b - tr, h - tt), (tl, h - tt)])


CASES = {  # shape: DIMs (metres), every pair unequal where the shape allows it
    "T1": [0.12, 0.09, 0.011, 0.007], "T2": [0.1, 0.14, 0.012, 0.008],
    "I1": [0.09, 0.006, 0.2, 0.23], "CHAN1": [0.07, 0.008, 0.16, 0.19],
    "CHAN2": [0.006, 0.009, 0.07, 0.15], "H": [0.08, 0.018, 0.13, 0.007],
    "Z": [0.05, 0.005, 0.11, 0.13], "CROSS": [0.09, 0.012, 0.15, 0.008],
    "HEXA": [0.03, 0.16, 0.1], "HAT": [0.08, 0.004, 0.1, 0.03],
    "BOX1": [0.15, 0.22, 0.012, 0.009, 0.007, 0.007],
    "BOX1-sides": [0.15, 0.22, 0.01, 0.01, 0.006, 0.011],
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_moments_against_greens_theorem(case):
    shape = case.split("-")[0]
    a, i1, i2, i12, _ = section_values(shape, CASES[case])
    pa, p1, p2, p12 = polygon(*outline(shape, CASES[case]))
    assert (a, i1, i2) == pytest.approx((pa, p1, p2), rel=1e-12)
    assert i12 == pytest.approx(p12, abs=1e-12 * math.sqrt(p1 * p2))
    if shape != "Z":  # an axis of symmetry: I12 exactly 0 (not round-off), as the reader
        assert i12 == 0.0  # uses I12 != 0 to couple the planes


def test_z_product_of_inertia_by_hand():
    """Source: the two flanges' parallel-axis terms (the web's is 0), each A (-y_f z_f)
    with A = tf (DIM1 + DIM2), y_f = (DIM3 + tf) / 2, z_f = DIM1 / 2 (MYSTRAN's closed
    form -tf DIM1 (DIM1 + DIM2) (DIM3 + tf) / 2)."""
    f, tw, hw, h = CASES["Z"]
    tf = (h - hw) / 2
    assert section_values("Z", CASES["Z"])[3] == pytest.approx(
        -tf * f * (f + tw) * (hw + tf) / 2, rel=1e-13)


def test_tube2_is_the_annulus():
    """Source: pi (ro^4 - ri^4) / 4 with ri = DIM1 - DIM2; J the polar moment."""
    ro, t = 0.05, 0.004
    ri = ro - t
    i = math.pi * (ro**4 - ri**4) / 4
    assert section_values("TUBE2", [ro, t]) == pytest.approx(
        (math.pi * (ro**2 - ri**2), i, i, 0.0, 2 * i), rel=1e-13)


def test_hexagon_by_hand():
    """Source: a DIM3-high rectangle (DIM2 - 2 DIM1) wide and two triangles; I1 of a
    triangle about the perpendicular bisector of its base h^3 a / 48."""
    a, w, h = CASES["HEXA"]
    area, i1, *_ = section_values("HEXA", CASES["HEXA"])
    assert area == pytest.approx(h * (w - a), rel=1e-14)
    assert i1 == pytest.approx((w - 2 * a) * h**3 / 12 + h**3 * a / 24, rel=1e-13)


@pytest.mark.parametrize("shape,walls", [
    ("T1", (1, 2)), ("T2", (2, 3)), ("I1", (1,)), ("CHAN1", (1,)), ("CHAN2", (0, 1)),
    ("H", (1, 3)), ("Z", (1,)), ("CROSS", (1, 3)), ("HAT", (1,))])
def test_open_torsion_constant_thin_limit(shape, walls):
    """Source: open thin-walled section J = sum l t^3 / 3 (Timoshenko & Goodier): with the
    walls 1e-3 as thick the module's J (on mid-lines) tends to the sum over the outline's
    walls; the two differ by the walls' overlaps, O(t / l) = O(1e-3) relative."""
    d = list(CASES[shape])
    for k in walls:
        d[k] *= 1e-3
    if shape in ("I1", "CHAN1", "Z"):  # thin flanges: clear web height near the total
        d[2] = d[3] * (1 - 1e-4)
    j = section_values(shape, d)[4]
    pa, *_ = polygon(*outline(shape, d))
    t = {"T1": (d[2], d[3]), "T2": (d[2], d[3]), "CHAN2": (d[0], d[1]), "H": (d[1] / 2, d[3]),
         "CROSS": (d[1], d[3]), "HAT": (d[1],)}.get(shape, ((d[3] - d[2]) / 2, d[1]))
    walls_l = {  # wall lengths, thickness index into t
        "T1": ((d[0], 0), (d[1], 1)), "T2": ((d[0], 0), (d[1], 1)),
        "CHAN2": ((2 * d[2], 0), (d[3], 1)), "H": ((2 * d[2], 0), (d[0], 1)),
        "CROSS": ((d[2], 0), (d[0] + d[1], 1)), "HAT": ((2 * d[0] + d[2] + 2 * d[3], 0),),
    }.get(shape, ((2 * (d[0] + d[1]), 0), (d[3], 1)))
    if shape == "I1":  # two flanges each DIM1 + DIM2 wide
        walls_l = ((2 * (d[0] + d[1]), 0), (d[3], 1))
    thin = sum(length * t[k] ** 3 / 3 for length, k in walls_l)
    assert j == pytest.approx(thin, rel=5e-3)
    assert pa == pytest.approx(sum(length * t[k] for length, k in walls_l), rel=5e-3)


def test_box1_with_equal_walls_is_box():
    """BOX1 with DIM3 = DIM4 and DIM5 = DIM6 is BOX (DIM3 the horizontal, DIM4 the
    vertical walls), computed another way: BOX as its bounding rectangle less the hole,
    checked against Bredt in test_sections.py."""
    b, h, t1, t2 = 0.12, 0.2, 0.008, 0.011
    box = section_values("BOX", [b, h, t1, t2])
    box1 = section_values("BOX1", [b, h, t1, t1, t2, t2])
    assert box1 == pytest.approx(box, rel=1e-13)


def test_box1_torsion_constant_is_bredt():
    """Source: Bredt, J = 4 Am^2 / sum(l / t) over the mid-line rectangle, each wall its
    own thickness (written here from the walls, top, bottom, right, left)."""
    b, h, tt, tb, tr, tl = CASES["BOX1-sides"]
    bm, hm = b - (tr + tl) / 2, h - (tt + tb) / 2
    assert section_values("BOX1", CASES["BOX1-sides"])[4] == pytest.approx(
        4 * (bm * hm) ** 2 / (bm / tt + bm / tb + hm / tr + hm / tl), rel=1e-13)


def test_shear_centres_turn_with_their_shapes():
    """T2 is a T upside down (shear centre below the centroid by T's distance), T1 a T on
    its side (towards +z, its plate), CHAN1 the channel of its dimensions; Z, CROSS,
    HEXA, H, I1 symmetric enough for 0; HAT's is not computed (None)."""
    b, h, tf, tw = CASES["T2"]
    assert shear_centre_offset("T2", [b, h, tf, tw]) == pytest.approx(
        tuple(-x for x in shear_centre_offset("T", [b, h, tf, tw])))
    hp, arm, tp, ta = CASES["T1"]
    dy, dz = shear_centre_offset("T", [hp, arm + tp, tp, ta])
    assert shear_centre_offset("T1", CASES["T1"]) == pytest.approx((dz, dy))
    f, tw, hw, hh = CASES["CHAN1"]
    assert shear_centre_offset("CHAN1", CASES["CHAN1"]) == pytest.approx(
        shear_centre_offset("CHAN", [f + tw, hh, tw, (hh - hw) / 2]))
    for shape in ("Z", "CROSS", "HEXA", "H", "I1"):
        assert shear_centre_offset(shape, CASES[shape]) == pytest.approx((0.0, 0.0), abs=1e-15)
    assert shear_centre_offset("HAT", CASES["HAT"]) is None


@pytest.mark.parametrize("shape", ["T1", "T2", "CHAN2", "H", "Z", "CROSS", "HEXA", "HAT",
                                   "BOX1"])
def test_complex_step_matches_central_differences(shape):
    """The formulas are complex-step safe (parameters on DIMs): d(A, I1, I2, J)/dDIMk by
    complex step against central differences, step 1e-6 DIMk (truncation ~1e-12, round-off
    ~eps / 1e-6 = 2e-10 of the value's scale)."""
    d = np.array(CASES[shape])
    for k in range(d.size):
        dc = d.astype(complex)
        dc[k] += 1e-30j
        cs = np.array(section_properties(shape, dc)).imag / 1e-30
        up, dn = d.copy(), d.copy()
        step = 1e-6 * d[k]
        up[k] += step
        dn[k] -= step
        fd = (np.array(section_properties(shape, up)) - np.array(section_properties(shape, dn))
              ) / (2 * step)
        scale = np.abs(np.array(section_properties(shape, d))) / d[k]
        assert np.all(np.abs(cs - fd) <= 1e-7 * scale)


@pytest.mark.parametrize("shape,dim,message", [
    ("BOX1", [0.15, 0.22, 0.012, 0.009, 0.006, 0.011], "section BOX1 needs DIM3 = DIM4 or "
     "DIM5 = DIM6"),
    ("BOX1", [0.15, 0.22, 0.012, 0.009, 0.08, 0.08], "section BOX1 needs DIM1 > DIM5 + DIM6"),
    ("CHAN2", [0.08, 0.009, 0.07, 0.15], "section CHAN2 needs DIM4 > 2 DIM1"),
    ("T2", [0.01, 0.14, 0.012, 0.02], "section T2 needs DIM1 > DIM4"),
    ("Z", [0.05, 0.005, 0.13, 0.13], "section Z needs DIM4 > DIM3"),
    ("HAT", [0.008, 0.004, 0.1, 0.03], "section HAT needs DIM1 > 2 DIM2"),
    ("HEXA", [0.03, 0.16], "section HEXA has 3 dimensions, got 2"),
])
def test_bad_dimensions(shape, dim, message):
    with pytest.raises(InputError, match=re.escape(message)):
        check_dimensions(shape, dim)


def test_hexagon_torsion_constant_between_its_rectangles():
    """Source: torsional rigidity grows with the domain (Prandtl's stress function,
    Polya & Szego): the hexagon's J lies between those of its inscribed (DIM2 - 2 DIM1) x
    DIM3 and circumscribed DIM2 x DIM3 rectangles (Timoshenko & Goodier's beta a b^3,
    beta 0.1406 for a square, rising with the sides' ratio to 0.229 at 2:1)."""
    a, w, h = 0.03, 0.16, 0.1  # inscribed square 0.1, circumscribed 1.6:1 rectangle
    j = section_values("HEXA", [a, w, h])[4]
    assert 0.1406 * h**4 < j < 0.229 * w * h**3
