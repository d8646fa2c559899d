"""The shapes of MSC Nastran's standard beam library (PBARL/PBEAML GROUP MSCBML0) beyond
ROD, TUBE, BAR, BOX, I, T and CHAN: T1, T2, I1, CHAN1, CHAN2, H, Z, CROSS, TUBE2, BOX1, HEXA, HAT.

Axes as in :mod:`eigenupdate.model.sections`: y (plane 1) along the section's height, z
(plane 2) along its width. DIM order and figures: MSC Nastran QRG PBARL; the area formulas
MSC gives for each shape (quoted in pyNastran's ``PBARL`` area code) fix which dimension is
which, and MYSTRAN's ``BD_PBARL.f90`` and pyNastran's ``beam_connectivity.py`` outlines read
the figures the same way, except where noted.

Most shapes are a base shape with other dimensions (:func:`as_base`), turned over
(``"flip"``: y to -y) or on its side (``"swap"``: y and z exchanged):

* T1: a T on its side, the flange a vertical plate DIM1 high and DIM3 thick, the web DIM2
  long and DIM4 thick reaching towards -z from it;
* T2: a T upside down (flange DIM1 x DIM3 at the bottom, DIM2 high, web DIM4);
* I1 and CHAN1: an I and a channel given by the flange outstand DIM1, web DIM2, clear web
  height DIM3 and total height DIM4 (flanges (DIM4 - DIM3) / 2 thick);
* CHAN2: a channel on its side, a U opening towards +y: base DIM4 wide and DIM2 thick,
  legs DIM1 thick and DIM3 high (pyNastran's drawing; MYSTRAN turns it the other way,
  exchanging I1 and I2: :data:`CAVEATS`);
* H: an I on its side: two vertical plates DIM2 / 2 thick and DIM3 high, DIM1 apart,
  joined at mid-height by a web DIM4 thick;
* TUBE2: a TUBE given by its outer radius DIM1 and wall DIM2 (its values are computed
  from the wall, :func:`eigenupdate.model.sections.section_values`: TUBE's
  ro^2 - ri^2 would lose digits on a thin wall).

Z, CROSS, BOX1 and HAT are rectangles summed with the parallel-axis theorem
(:func:`rectangles`), HEXA a rectangle and two triangles (:func:`hexagon`).

* Z: web DIM2 thick between flanges (DIM4 - DIM3) / 2 thick and DIM1 + DIM2 wide, the top
  one reaching towards -z, the bottom one towards +z (I12 < 0; MYSTRAN's I12 and
  pyNastran's outline agree; :data:`CAVEATS`);
* CROSS: a vertical bar DIM2 x DIM3 with arms DIM1 / 2 long and DIM4 thick each side;
* BOX1: outside DIM1 wide and DIM2 high, walls DIM3 top, DIM4 bottom, DIM5 right, DIM6
  left (MSC's area formula puts DIM5, DIM6 on the full-height walls). A box with both
  pairs unequal has an I12 whose sign depends on axes not established here: refused;
* HEXA: DIM2 wide between the points, DIM3 high, the points' triangles DIM1 deep;
* HAT: a hat of one wall thickness DIM2, DIM1 high, its crown DIM3 wide on top, its feet
  reaching DIM4 beyond the webs at the bottom (symmetric about y: I12 = 0 whichever way z
  points; its shear centre is not computed here).

Torsion constants: the base shape's (open thin-walled ``sum l t^3 / 3`` on the walls'
mid-lines, Bredt for a box); Z, CROSS and HAT the same sum on mid-lines; BOX1 Bredt's
``4 Am^2 / sum(l / t)`` on the mid-line rectangle; HEXA the BAR formula on the rectangle of
the hexagon's height and area (MYSTRAN's choice; :data:`CAVEATS`).
"""

from __future__ import annotations

import numpy as np

# DIM count and the conditions that make a section (text for the message)
SHAPES = {
    "T1": (4, (("DIM1 > DIM4", lambda d: d[0] > d[3]),)),
    "T2": (4, (("DIM2 > DIM3", lambda d: d[1] > d[2]), ("DIM1 > DIM4", lambda d: d[0] > d[3]))),
    "I1": (4, (("DIM4 > DIM3", lambda d: d[3] > d[2]),)),
    "CHAN1": (4, (("DIM4 > DIM3", lambda d: d[3] > d[2]),)),
    "CHAN2": (4, (("DIM3 > DIM2", lambda d: d[2] > d[1]),
                  ("DIM4 > 2 DIM1", lambda d: d[3] > 2 * d[0]))),
    "H": (4, (("DIM3 > DIM4", lambda d: d[2] > d[3]),)),
    "Z": (4, (("DIM4 > DIM3", lambda d: d[3] > d[2]),)),
    "CROSS": (4, (("DIM3 > DIM4", lambda d: d[2] > d[3]),)),
    "TUBE2": (2, (("DIM1 >= DIM2", lambda d: d[0] >= d[1]),)),
    "BOX1": (6, (("DIM1 > DIM5 + DIM6", lambda d: d[0] > d[4] + d[5]),
                 ("DIM2 > DIM3 + DIM4", lambda d: d[1] > d[2] + d[3]),
                 ("DIM3 = DIM4 or DIM5 = DIM6 (with both pairs unequal its I12's sign "
                  "depends on axes not established here)",
                  lambda d: d[2] == d[3] or d[4] == d[5]))),
    "HEXA": (3, (("DIM2 > 2 DIM1", lambda d: d[1] > 2 * d[0]),)),
    "HAT": (4, (("DIM1 > 2 DIM2", lambda d: d[0] > 2 * d[1]),
                ("DIM3 > 2 DIM2", lambda d: d[2] > 2 * d[1]))),
}

RECTANGLES = ("Z", "CROSS", "BOX1", "HAT")

CAVEATS = {
    "Z": "its I12 < 0 (top flange towards -z) follows MSC's figure as MYSTRAN and "
         "pyNastran read it, not checked against NASTRAN's output",
    "CHAN2": "drawn as a U opening towards +y (pyNastran's reading of MSC's figure); "
             "MYSTRAN turns it on its side, exchanging I1 and I2: not checked against "
             "NASTRAN's output",
    "HEXA": "its torsion constant J is the BAR formula on the rectangle of the hexagon's "
            "height and area (MYSTRAN's), not a formula NASTRAN documents",
}
"""What is not established about a shape's values (a warning when a deck uses it)."""


def as_base(shape: str, d: np.ndarray):
    """(base shape, its dimensions, turn) of a shape that is a base shape turned: turn ""
    (as it is), "flip" (y to -y) or "swap" (y and z exchanged); None for the others.
    Complex-step safe."""
    if shape == "T1":  # T's flange DIM1 x DIM3 and web DIM4 over DIM2 + DIM3
        return "T", _dims(d[0], d[1] + d[2], d[2], d[3]), "swap"
    if shape == "T2":
        return "T", _dims(*d), "flip"
    if shape in ("I1", "CHAN1"):
        tf = (d[3] - d[2]) / 2
        if shape == "I1":
            return "I", _dims(d[3], d[0] + d[1], d[0] + d[1], d[1], tf, tf), ""
        return "CHAN", _dims(d[0] + d[1], d[3], d[1], tf), ""
    if shape == "CHAN2":  # CHAN's web the base, its flanges the legs
        return "CHAN", _dims(d[2], d[3], d[1], d[0]), "swap"
    if shape == "H":  # I's flanges the vertical plates
        return "I", _dims(d[0] + d[1], d[2], d[2], d[3], d[1] / 2, d[1] / 2), "swap"
    return None


def _dims(*values) -> np.ndarray:
    return np.array(values)


def rectangles(shape: str, d: np.ndarray) -> np.ndarray:
    """Rows [width along z, height along y, z of centre, y of centre] of Z, CROSS, BOX1,
    HAT."""
    if shape == "Z":  # web centred at the origin
        b, tw, hw, h = d
        tf = (h - hw) / 2
        yf = (hw + tf) / 2
        return np.array([[tw, hw, 0.0, 0.0], [b + tw, tf, -b / 2, yf],
                         [b + tw, tf, b / 2, -yf]])
    if shape == "CROSS":
        a, tv, hv, th = d
        zarm = (tv + a / 2) / 2
        return np.array([[tv, hv, 0.0, 0.0], [a / 2, th, zarm, 0.0], [a / 2, th, -zarm, 0.0]])
    if shape == "HAT":  # from the feet's underside; webs between the feet's top and crown
        h, t, w, f = d
        zw, zf = (w - t) / 2, (w + f) / 2
        return np.array([[w, t, 0.0, h - t / 2], [t, h - 2 * t, zw, h / 2],
                         [t, h - 2 * t, -zw, h / 2], [f + t, t, zf - t / 2, t / 2],
                         [f + t, t, -(zf - t / 2), t / 2]])
    # BOX1 from its bottom left corner: the side walls full height, top and bottom between
    b, h, tt, tb, tr, tl = d
    inner = b - tr - tl
    return np.array([[tl, h, tl / 2, h / 2], [tr, h, b - tr / 2, h / 2],
                     [inner, tt, tl + inner / 2, h - tt / 2],
                     [inner, tb, tl + inner / 2, tb / 2]])


def hexagon(d: np.ndarray) -> tuple:
    """A, I1, I2 of HEXA: a rectangle (DIM2 - 2 DIM1) x DIM3 and two triangles, base DIM3
    on its sides and apex DIM1 beyond (I of a triangle about its base's perpendicular
    bisector h^3 a / 48, about an axis parallel to its base through its centroid
    h a^3 / 36)."""
    a, b, h = d
    w = b - 2 * a
    tri = h * a / 2
    i1 = w * h**3 / 12 + 2 * h**3 * a / 48
    i2 = h * w**3 / 12 + 2 * (h * a**3 / 36 + tri * (w / 2 + a / 3) ** 2)
    return w * h + 2 * tri, i1, i2


def torsion(shape: str, d: np.ndarray):
    """J of Z, CROSS, BOX1 and HAT (module docstring)."""
    if shape == "Z":  # as CHAN1: flanges from the web's mid-line, web between flanges'
        b, tw, hw, h = d
        tf = (h - hw) / 2
        return (2 * (b + tw / 2) * tf**3 + (hw + tf) * tw**3) / 3
    if shape == "CROSS":  # both mid-lines full length
        a, tv, hv, th = d
        return (hv * tv**3 + (a + tv) * th**3) / 3
    if shape == "HAT":  # crown, webs and feet on their mid-lines
        h, t, w, f = d
        return (w - t + 2 * (h - t) + 2 * (f + t / 2)) * t**3 / 3
    if shape == "BOX1":
        b, h, tt, tb, tr, tl = d
        bm, hm = b - (tr + tl) / 2, h - (tt + tb) / 2
        return 4 * (bm * hm) ** 2 / (hm * (1 / tl + 1 / tr) + bm * (1 / tt + 1 / tb))
    raise ValueError(f"no torsion constant here for section {shape}")


def hexagon_bar(d: np.ndarray) -> np.ndarray:
    """The BAR (DIM1 width, DIM2 height) of HEXA's height and area, whose J is HEXA's."""
    return _dims(d[1] - d[0], d[2])


def shear_centre(shape: str, d: np.ndarray) -> tuple[float, float] | None:
    """(y, z) of the shear centre less the centroid of Z, CROSS, BOX1, HEXA, HAT; None where
    not established (HAT's, and a BOX1's with unequal opposite walls: its closed-cell
    shear centre, are not computed here)."""
    if shape == "HAT" or (shape == "BOX1" and (d[2] != d[3] or d[4] != d[5])):
        return None
    return 0.0, 0.0  # Z point-symmetric, CROSS and HEXA doubly symmetric
