"""Section properties of NASTRAN's standard PBARL shapes that pyNastran does not give as
NASTRAN does.

Section axes as in NASTRAN's PBARL figures: y (plane 1, ``I1 = int y^2 dA``) along the
section's height, z (plane 2, ``I2 = int z^2 dA``) along its width. pyNastran 1.4 gives A,
I1 and I2 of ROD, TUBE, BAR and BOX (used as they are); here are

* :func:`thin_walled_section`: A, I1, I2, I12 of the I, T and CHAN shapes, as rectangles
  summed with the parallel-axis theorem (pyNastran's ``PBARL.I11()`` raises for them);
* :func:`torsion_constant`: NASTRAN's torsion constant J of BAR, BOX, I, T and CHAN. It is
  not the polar moment ``I1 + I2`` that pyNastran's ``PBARL.J()`` returns (0 for BAR):
  BAR uses Roark's series approximation of the solid rectangle, BOX Bredt's closed
  thin-walled formula, I, T and CHAN the open thin-walled ``sum b t^3 / 3`` over the
  walls' mid-lines (MSC/NX Nastran element library, PBARL section properties).

The other shapes of MSC's library that are assemblies of rectangles or closed forms (T1,
T2, I1, CHAN1, CHAN2, H, Z, CROSS, TUBE2, BOX1, HEXA, HAT) are in
:mod:`~eigenupdate.model.sections_library`; :func:`section_values` and
:func:`section_properties` give any of them.

Dimensions are the card's DIM1, DIM2, ...; a dimension that makes no section (a wall
thicker than its shape allows) is an :class:`~eigenupdate.errors.InputError`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from eigenupdate.errors import InputError
from eigenupdate.model import sections_library as library

THIN_WALLED = ("I", "T", "CHAN")
# DIM count, and the conditions that make a section (text for the message)
_SHAPES = {
    "ROD": (1, ()),
    "TUBE": (2, (("DIM1 > DIM2", lambda d: d[0] > d[1]),)),
    "BAR": (2, ()),
    "BOX": (4, (("DIM1 > 2 DIM4", lambda d: d[0] > 2 * d[3]),
                ("DIM2 > 2 DIM3", lambda d: d[1] > 2 * d[2]))),
    "I": (6, (("DIM1 > DIM5 + DIM6", lambda d: d[0] > d[4] + d[5]),)),
    "T": (4, (("DIM2 > DIM3", lambda d: d[1] > d[2]),)),
    "CHAN": (4, (("DIM1 > DIM3", lambda d: d[0] > d[2]),
                 ("DIM2 > 2 DIM4", lambda d: d[1] > 2 * d[3]))),
}
_ALL = {**_SHAPES, **library.SHAPES}
SHAPES = tuple(_ALL)
"""Every PBARL/PBEAML shape read (the others of MSC's library are refused)."""


def dimension_count(shape: str) -> int:
    """How many DIMs a shape has."""
    return _ALL[shape][0]


def check_dimensions(shape: str, dim: Sequence[float]) -> np.ndarray:
    """The dimensions as floats; InputError unless all are > 0 (1e-100 to 1e100) and make
    the shape.

    >>> check_dimensions("BOX", [0.1, 0.2, 0.01, 0.06])
    Traceback (most recent call last):
    ...
    eigenupdate.errors.InputError: section BOX needs DIM1 > 2 DIM4, got DIM = [0.1, 0.2, 0.01, 0.06]
    """
    d = np.asarray(dim, dtype=float)
    count, conditions = _ALL[shape]
    shown = [float(x) for x in d]
    if d.size != count:
        raise InputError(f"section {shape} has {count} dimensions, got {d.size}")
    positive = np.isfinite(d) & (d > 0)
    if shape == "TUBE":  # a zero inner radius is a ROD
        positive[1] = d[1] >= 0
    if not np.all(positive):
        raise InputError(f"section {shape} dimensions must be > 0, got DIM = {shown}")
    # as every number read (io.numbers): beyond, a dimension is more likely corrupted than
    # meant, and one of 1e-300 is a part left out that DIM = 0 would refuse
    if np.any((d != 0) & ((d < 1e-100) | (d > 1e100))):
        raise InputError(f"section {shape} dimensions must be 1e-100 to 1e100, got DIM = "
                         f"{shown}")
    for text, ok in conditions:
        if not ok(d):
            raise InputError(f"section {shape} needs {text}, got DIM = {shown}")
    return d


def _rectangles(shape: str, d: np.ndarray) -> np.ndarray:
    """Rows [width along z, height along y, z of centre, y of centre]."""
    if shape == "I":  # DIM1 height, DIM2/DIM5 bottom flange, DIM3/DIM6 top flange, DIM4 web
        h, a, b, tw, ta, tb = d
        return np.array([[a, ta, 0.0, ta / 2], [tw, h - ta - tb, 0.0, (h + ta - tb) / 2],
                         [b, tb, 0.0, h - tb / 2]])
    if shape == "T":  # DIM1/DIM3 flange on top, DIM2 total height, DIM4 web
        b, h, tf, tw = d
        return np.array([[b, tf, 0.0, h - tf / 2], [tw, h - tf, 0.0, (h - tf) / 2]])
    # CHAN: DIM1 width, DIM2 height, DIM3 web, DIM4 flanges
    b, h, tw, tf = d
    return np.array([[tw, h, tw / 2, h / 2], [b - tw, tf, (b + tw) / 2, tf / 2],
                     [b - tw, tf, (b + tw) / 2, h - tf / 2]])


def thin_walled_section(shape: str, dim: Sequence[float]) -> tuple[float, float, float, float]:
    """A, I1, I2, I12 about the centroid of an I, T or CHAN PBARL section.

    Examples
    --------
    A symmetric I-beam 300 mm high, 150 x 20 mm flanges, 10 mm web:

    >>> a, i1, i2, i12 = thin_walled_section("I", [0.3, 0.15, 0.15, 0.01, 0.02, 0.02])
    >>> print(f"{a:.6g} {i1:.6g} {i2:.6g} {i12:g}")
    0.0086 0.000132447 1.12717e-05 0
    """
    return tuple(float(x) for x in _thin(shape, check_dimensions(shape, dim)))


def _thin(shape: str, d: np.ndarray) -> tuple:
    return _sums(_rectangles(shape, d))


def _sums(rows: np.ndarray) -> tuple:
    """A, I1, I2, I12 about the centroid of rectangles (rows as :func:`_rectangles`)."""
    w, h, z, y = rows.T
    area = w * h
    a = area.sum()
    zc, yc = (area @ z) / a, (area @ y) / a
    i1 = np.sum(w * h**3 / 12 + area * (y - yc) ** 2)
    i2 = np.sum(h * w**3 / 12 + area * (z - zc) ** 2)
    i12 = np.sum(area * (y - yc) * (z - zc))
    return a, i1, i2, i12


def shear_centre_offset(shape: str, dim: Sequence[float]) -> tuple[float, float] | None:
    """(y, z) of the shear centre less the centroid of a section, thin-walled
    on the walls' mid-lines (0 for a doubly symmetric I): T at the flange's and web's
    junction; I between the flanges at h' I_top / (I_top + I_bot) from the bottom flange
    (I_flange = t w^3 / 12); CHAN e = 3 b'^2 tf / (6 b' tf + h' tw) behind the web's
    mid-line (b', h' the mid-line flange length and web height; Roark, Table 10.7).

    The library's shapes turn their base shape's offset with it; 0 for the doubly
    symmetric and point-symmetric shapes; None where it is not established
    (:func:`~eigenupdate.model.sections_library.shear_centre`).

    >>> dy, dz = shear_centre_offset("T", [0.02, 0.03, 0.002, 0.0025])
    >>> print(f"{dy:.6f} {dz:g}")
    0.009545 0
    >>> dy, dz = shear_centre_offset("T2", [0.02, 0.03, 0.002, 0.0025])   # T upside down
    >>> print(f"{dy:.6f} {dz:g}")
    -0.009545 0
    """
    return _offset(shape, check_dimensions(shape, dim))


def _offset(shape: str, d: np.ndarray) -> tuple[float, float] | None:
    base = library.as_base(shape, d)
    if base is not None:
        name, bd, turn = base
        dy, dz = _offset(name, bd)
        return {"": (dy, dz), "flip": (-dy, dz), "swap": (dz, dy)}[turn]
    if shape in library.SHAPES:
        return library.shear_centre(shape, d)
    if shape not in THIN_WALLED:
        return 0.0, 0.0
    w, h, z, y = _rectangles(shape, d).T
    area = w * h
    yc, zc = (area @ y) / area.sum(), (area @ z) / area.sum()
    if shape == "T":
        return float(d[1] - d[2] / 2 - yc), 0.0
    if shape == "I":
        hh, a, b, _, ta, tb = d
        bot, top = ta * a**3, tb * b**3
        return float(ta / 2 + (hh - (ta + tb) / 2) * top / (top + bot) - yc), 0.0
    b, hh, tw, tf = d  # CHAN
    bm, hm = b - tw / 2, hh - tf
    return 0.0, float(tw / 2 - 3 * bm**2 * tf / (6 * bm * tf + hm * tw) - zc)


def solid_section(shape: str, dim: Sequence[float]) -> tuple[float, float, float]:
    """A, I1, I2 of a ROD, TUBE, BAR or BOX section (closed forms; BAR and BOX: DIM1
    width along z, DIM2 height along y; BOX DIM3 the horizontal, DIM4 the vertical walls).

    >>> a, i1, i2 = solid_section("BAR", [2.0, 3.0])
    >>> print(a, i1, i2)
    6.0 4.5 2.0
    """
    return tuple(float(x) for x in _solid(shape, check_dimensions(shape, dim)))


def _solid(shape: str, d: np.ndarray) -> tuple:
    if shape in ("ROD", "TUBE"):
        ro, ri = d[0], (d[1] if shape == "TUBE" else 0.0)
        a = np.pi * (ro**2 - ri**2)
        i = np.pi / 4 * (ro**4 - ri**4)
        return a, i, i
    b, h = d[0], d[1]
    bi, hi = (b - 2 * d[3], h - 2 * d[2]) if shape == "BOX" else (0.0, 0.0)
    return b * h - bi * hi, (b * h**3 - bi * hi**3) / 12, (h * b**3 - hi * bi**3) / 12


def torsion_constant(shape: str, dim: Sequence[float]) -> float:
    """NASTRAN's torsion constant J of a PBARL section (the library's shapes:
    :mod:`~eigenupdate.model.sections_library`).

    Examples
    --------
    A square bar (Roark: 0.1406 a^4 exactly, the series gives 0.1408 a^4) and a
    10 mm walled 100 x 200 mm box (Bredt):

    >>> print(f"{torsion_constant('BAR', [1.0, 1.0]):.4f}")
    0.1408
    >>> print(f"{torsion_constant('BOX', [0.1, 0.2, 0.01, 0.01]):.6g}")
    2.08864e-05
    """
    return float(_all(shape, check_dimensions(shape, dim))[4])


def _torsion(shape: str, d: np.ndarray):
    if shape in ("ROD", "TUBE"):  # polar moment of the annulus
        return np.pi / 2 * (d[0] ** 4 - (d[1] if shape == "TUBE" else 0.0) ** 4)
    if shape == "BAR":  # long side a, short side b (compared by value: complex-step safe)
        a, b = (d[0], d[1]) if np.real(d[0]) >= np.real(d[1]) else (d[1], d[0])
        return a * b**3 * (1 / 3 - 0.21 * b / a * (1 - b**4 / (12 * a**4)))
    if shape == "BOX":  # mid-line rectangle (DIM1 - DIM4) x (DIM2 - DIM3)
        b, h, t1, t2 = d
        return (2 * t1 * t2 * (b - t2) ** 2 * (h - t1) ** 2
                / (b * t2 + h * t1 - t2**2 - t1**2))
    if shape == "I":  # web mid-line between the flanges' mid-lines
        h, a, b, tw, ta, tb = d
        return (a * ta**3 + b * tb**3 + (h - (ta + tb) / 2) * tw**3) / 3
    if shape == "T":
        b, h, tf, tw = d
        return (b * tf**3 + (h - tf / 2) * tw**3) / 3
    if shape == "CHAN":
        b, h, tw, tf = d
        return (2 * (b - tw / 2) * tf**3 + (h - tf) * tw**3) / 3
    raise InputError(f"no torsion constant for section {shape}")


def section_values(shape: str, dim: Sequence[float]) -> tuple[float, ...]:
    """A, I1, I2, I12, J of any PBARL shape read (:data:`SHAPES`), checked.

    >>> a, i1, i2, i12, j = section_values("Z", [0.03, 0.004, 0.08, 0.1])
    >>> print(f"{a:.6g} {i12:.6g}")    # I12 = -tf DIM1 (DIM1 + DIM2) (DIM3 + tf) / 2
    0.001 -4.59e-07
    """
    return tuple(float(x) for x in _all(shape, check_dimensions(shape, dim)))


def section_properties(shape: str, dim: np.ndarray) -> tuple:
    """A, I1, I2, J of a PBARL shape with NASTRAN's formulas, for real or complex
    ``dim`` (complex-step derivatives; no checks: :func:`check_dimensions` first).

    >>> a, i1, i2, j = section_properties("BAR", np.array([2.0, 3.0 + 1e-30j]))
    >>> float(a.imag / 1e-30), float(i1.imag / 1e-30)    # dA/dh = b, dI1/dh = b h^2 / 4
    (2.0, 4.5)
    """
    a, i1, i2, _, j = _all(shape, np.asarray(dim))
    return a, i1, i2, j


def _all(shape: str, d: np.ndarray) -> tuple:
    """A, I1, I2, I12, J of any shape (complex-step safe, unchecked)."""
    if shape == "TUBE2":  # TUBE's from its wall t: ro^2 - ri^2 = t (2 ro - t), no cancellation
        ro, t = d
        a = np.pi * t * (2 * ro - t)
        i = a * (ro**2 + (ro - t) ** 2) / 4
        return a, i, i, 0.0, 2 * i
    base = library.as_base(shape, d)
    if base is not None:
        name, bd, turn = base
        a, i1, i2, i12, j = _all(name, bd)
        if turn == "swap":  # exchanging y and z keeps int y z dA
            i1, i2 = i2, i1
        return a, i1, i2, i12, j  # 0: every base shape has an axis of symmetry
    if shape in library.RECTANGLES:
        a, i1, i2, i12 = _sums(library.rectangles(shape, d))
        # exactly 0 for a section with an axis of symmetry (the sum leaves round-off)
        return a, i1, i2, (i12 if shape == "Z" else 0.0), library.torsion(shape, d)
    if shape == "HEXA":
        return (*library.hexagon(d), 0.0, _torsion("BAR", library.hexagon_bar(d)))
    if shape in THIN_WALLED:
        return (*_thin(shape, d)[:3], 0.0, _torsion(shape, d))
    return (*_solid(shape, d), 0.0, _torsion(shape, d))


SHEAR_SHAPES = ("BAR", "ROD", "TUBE", "TUBE2", "BOX")
"""Shapes whose shear factors :func:`shear_factors` gives (NASTRAN gives the others
factors not modelled here)."""


def shear_factors(shape: str, d: np.ndarray, area):
    """K1, K2 of a PBARL/PBEAML section as MSC Nastran gives them: BAR 5/6, ROD 0.9 (the
    rectangle's and the circle's Timoshenko factors); TUBE 0.5 and BOX the walls parallel
    to the shear over the area, 2 (DIM2 - 2 DIM3) DIM4 / A in plane 1 and
    2 (DIM1 - 2 DIM4) DIM3 / A in plane 2, as the equivalent PBEAMs MSC Nastran 2005 wrote
    into the fmondsp deck's .op2 (complex-step safe). TUBE2, the TUBE given by its wall,
    takes TUBE's (assumed: no NASTRAN output of a TUBE2 was at hand).

    >>> k1, k2 = shear_factors("BOX", np.array([0.6, 0.2, 0.0025, 0.0025]), 0.003975)
    >>> round(float(k1), 6), round(float(k2), 7)      # fmondsp.op2's PBEAM 5
    (0.245283, 0.7484277)
    """
    if shape in _CONSTANT_SHEAR:
        return _CONSTANT_SHEAR[shape]
    b, h, t1, t2 = d
    return 2 * (h - 2 * t1) * t2 / area, 2 * (b - 2 * t2) * t1 / area


# circle 0.9 (NASTRAN's documentation; Simcenter's frequencies of the shared
# pyn_beam_modes deck agree to 1e-7, NASTRAN_CoFE's 0.85716 would be 0.96 % off), solid
# rectangle 5/6 (NASTRAN_CoFE's PBEAML), thin tube 0.5 (fmondsp.op2's PBEAMs)
_CONSTANT_SHEAR = {"BAR": (5.0 / 6.0, 5.0 / 6.0), "ROD": (0.9, 0.9), "TUBE": (0.5, 0.5),
                   "TUBE2": (0.5, 0.5)}


# the part coefficients of a frame element (model/frame3d.py parts), from its quantities
PARTS = ("k_axial", "k_torsion", "k_bend1", "k_bend2", "m_translation", "m_torsion")


@dataclass(frozen=True)
class SectionPart:
    """One part coefficient of a group of frame elements (one material and section) as a
    function of the parameters among its quantities, for
    :class:`~eigenupdate.model.parametric.FunctionTerm`: EA, GJ, EI1, EI2, wtmass
    (rho A + NSM), wtmass (rho (I1 + I2) + NSI) (the last 0 unless ``beam``); with
    ``shear`` a shear-flexible bending part's two factors EI / (1 + phi) and
    EI phi / (1 + phi) of elements of one ``length`` (:func:`frame3d.stiffness_parts`:
    K = EI (U0 + phi U1) / (1 + phi)).

    ``slots`` names what each argument is (``E``, ``RHO``, ``A``, ``I1``, ``I2``,
    ``J``, ``DIM1``...); the other quantities keep their ``fixed`` values. With a
    ``shape`` A, I1, I2, J come from its DIMs (:func:`section_properties`). G follows E
    when ``tied`` (MAT1 G blank).

    >>> f = SectionPart("k_bend1", ("E", "DIM2"), (("E", 2e11), ("G", 8e10), ("RHO", 7850.0),
    ...                 ("DIM1", 0.02), ("DIM2", 0.04)), "BAR", True, False, 1.0)
    >>> round(float(f(np.array([2e11, 0.04]))), 6)    # E b h^3 / 12
    21333.333333
    """

    part: str
    slots: tuple[str, ...]
    fixed: tuple[tuple[str, float], ...]
    shape: str | None
    tied: bool
    beam: bool
    wtmass: float
    shear: float = 0.0  # K1 (bend1) or K2 (bend2) of a shear-flexible section, else 0
    length: float = 0.0  # with ``shear``: the elements' length L
    which: int = 0  # with ``shear``: 0 the factor EI / (1 + phi), 1 EI phi / (1 + phi)

    def __call__(self, x: np.ndarray):
        q = dict(self.fixed)
        e0 = q["E"]
        q.update(zip(self.slots, x, strict=True))
        if self.shape is not None:
            d = np.array([q[f"DIM{k + 1}"] for k in range(dimension_count(self.shape))])
            check_dimensions(self.shape, d.real)  # a step may leave the shape's domain
            q["A"], q["I1"], q["I2"], q["J"] = section_properties(self.shape, d)
        e = q["E"]
        g = q["G"] * e / e0 if self.tied else q["G"]
        w = self.wtmass
        if self.shear:  # Timoshenko bending, phi = 12 E I / (K A G L^2)
            plane = 0 if self.part == "k_bend1" else 1
            ei = e * q["I1" if plane == 0 else "I2"]
            k = self.shear
            if self.shape in SHEAR_SHAPES:  # a BOX's K follows its dimensions
                k = shear_factors(self.shape, d, q["A"])[plane]
            phi = 12 * ei / (k * q["A"] * g * self.length**2)
            return ei * (phi if self.which else 1.0) / (1 + phi)
        return {"k_axial": lambda: e * q["A"], "k_torsion": lambda: g * q["J"],
                "k_bend1": lambda: e * q["I1"], "k_bend2": lambda: e * q["I2"],
                "m_translation": lambda: w * (q["RHO"] * q["A"] + q["NSM"]),
                "m_torsion": lambda: w * (q["RHO"] * (q["I1"] + q["I2"]) + q["NSI"])
                if self.beam else 0.0}[self.part]()
