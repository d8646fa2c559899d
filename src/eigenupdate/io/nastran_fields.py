"""The card fields that can be parameters: where pyNastran keeps them, read and set."""

from __future__ import annotations

import math

import numpy as np

from eigenupdate.errors import InputError
from eigenupdate.io.study_table import in_limits
from eigenupdate.model import solids

# card -> field -> (pyNastran attribute, what it scales); the rest are refused with a reason
FIELDS = {
    "MAT1": {"E": "e", "RHO": "rho"},
    # a PCOMP ply's moduli (nonlinear: Q11 = E1 / (1 - NU12 NU21), ...) and density
    "MAT8": {"E1": "e11", "E2": "e22", "NU12": "nu12", "G12": "g12", "G1Z": "g1z",
             "G2Z": "g2z", "RHO": "rho"},
    "PBAR": {"A": "A", "I1": "i1", "I2": "i2", "J": "j"},
    "PBEAM": {"A": "A", "I1": "i1", "I2": "i2", "J": "j"},
    "PROD": {"A": "A", "J": "j"},
    "PELAS": {"K": "k"},
    "CELAS2": {"K": "k"},
    "CELAS4": {"K": "k"},
    "CMASS4": {"M": "mass"},
    "PBUSH": {f"K{i + 1}": ("_k", i) for i in range(6)},
    "CONM1": {f"M{i + 1}{j + 1}": ("mass_matrix", (i, j)) for i in range(6)
              for j in range(i + 1)},
    "CONM2": {"M": "mass"},
    "CMASS2": {"M": "mass"},
    "PMASS": {"M": "mass"},
    # section dimensions: A, I1, I2, J through the shape's formulas (nonlinear)
    "PBARL": {f"DIM{k + 1}": ("_dim", k) for k in range(10)},
    "PBEAML": {f"DIM{k + 1}": ("_dim", k) for k in range(10)},
    # thickness: membrane ~ T, bending ~ T^3, shear ~ T, mass ~ RHO T + NSM (nonlinear)
    "PSHELL": {"T": "t"},
    # NASTRAN-95's homogeneous plates: T as a PSHELL's (I = T^3 / 12, shear thickness T)
    "PQUAD2": {"T": "t"},
    "PTRIA2": {"T": "t"},
    # ply k's thickness (the card's k-th ply; LAM=SYM: and its mirror): A, D, H, mass
    "PCOMP": {f"T{k + 1}": ("_ply", k) for k in range(99)},
    # shear panel thickness: K ~ G T, mass ~ RHO T + NSM (linear)
    "PSHEAR": {"T": "t"},
}

def field_unit(card: str, field: str) -> str:
    """Dimension of a parameter field in the deck's own units: NASTRAN has no unit
    system, and a mass is as the deck enters it (before PARAM WTMASS). A scalar spring
    or mass on a rotation is force*length/rad or mass*length^2, which the field alone
    cannot tell.

    >>> field_unit("MAT1", "E"), field_unit("PBAR", "I1"), field_unit("CONM1", "M64")
    ('force/length^2', 'length^4', 'mass*length^2')
    """
    if card in ("MAT1", "MAT8"):
        return ("mass/length^3" if field == "RHO" else "" if field == "NU12" else
                "force/length^2")
    if card in ("PBAR", "PBEAM", "PROD"):
        return "length^2" if field == "A" else "length^4"
    if card in ("PBARL", "PBEAML", "PSHELL", "PCOMP", "PSHEAR", "PQUAD2", "PTRIA2"):
        return "length"
    if card == "PBUSH":
        return "force/length" if field in ("K1", "K2", "K3") else "force*length/rad"
    if card == "CONM1":
        rotations = sum(int(c) > 3 for c in field[1:])
        return ("mass", "mass*length", "mass*length^2")[rotations]
    return "force/length" if field == "K" else "mass" if field == "M" else ""


NOT_LINEAR = {
    ("MAT1", "NU"): "G = E / (2 (1 + NU)) is not linear in NU",
    ("MAT1", "G"): "give E (G follows it when the card leaves G blank)",
    **{(c, f): "membrane and mass follow T1, bending I and shear T3 do not (three fields); "
               "a PQUAD2/PTRIA2 T or a MAT1 E or RHO can be" for c in ("PQUAD1", "PTRIA1")
       for f in ("T1", "I", "T3")},
}


def stores(bdf) -> dict:
    return {"MAT1": bdf.materials, "MAT8": bdf.materials, "PBAR": bdf.properties,
            "PBEAM": bdf.properties,
            "PROD": bdf.properties,
            "PELAS": bdf.properties, "CELAS2": bdf.elements, "CELAS4": bdf.elements,
            "CMASS4": bdf.masses, "CONM2": bdf.masses, "CONM1": bdf.masses,
            "PBUSH": bdf.properties, "PBARL": bdf.properties, "PBEAML": bdf.properties,
            "PSHELL": bdf.properties, "PCOMP": bdf.properties, "PSHEAR": bdf.properties,
            "PQUAD2": bdf.properties, "PTRIA2": bdf.properties,
            "CMASS2": bdf.masses, "PMASS": bdf.properties_mass}


def get_field(card, spec) -> float:
    """A card's field value: ``spec`` is pyNastran's attribute, or (attribute, index)."""
    if isinstance(spec, str):
        return float(np.ravel(getattr(card, spec))[0])
    attr, index = spec
    if attr == "_k":
        return float(pbush_k(card)[index])
    if attr == "_ply":
        if index >= len(card.thicknesses):
            raise InputError(f"PCOMP {card.pid} field T{index + 1}: the card has plies "
                             f"1-{len(card.thicknesses)}")
        return float(card.thicknesses[index])
    if attr == "_dim":  # PBEAML: the first station's (constant sections only)
        return float(np.atleast_2d(np.asarray(card.dim, float))[0, index])
    return float(np.asarray(getattr(card, attr))[index])


def set_field(card, spec, value: float) -> None:
    """Put ``value`` in a card's field (:func:`get_field`'s ``spec``)."""
    if isinstance(spec, str):
        old = getattr(card, spec)
        setattr(card, spec, np.full_like(old, value) if isinstance(old, np.ndarray) else value)
    elif spec[0] == "_dim":
        if card.type == "PBEAML":
            for row in card.dim:
                row[spec[1]] = value
        else:
            card.dim[spec[1]] = value
    elif spec[0] == "_ply":
        card.thicknesses[spec[1]] = value
    elif spec[0] == "_k":
        ki = list(card.Ki) + [None] * (6 - len(card.Ki))
        ki[spec[1]] = value
        card.Ki = ki
    else:
        getattr(card, spec[0])[spec[1]] = value


def pbush_k(card) -> np.ndarray:
    """PBUSH K1-K6 (blank = 0)."""
    k = np.zeros(6)
    for i, v in enumerate(getattr(card, "Ki", None) or []):
        k[i] = v or 0.0
    return k


def in_range(value, what: str) -> float:
    """``value`` as a float; InputError unless it is finite and 0 or of magnitude 1e-100
    to 1e100 (as numbers in a study: beyond, K and M overflow or lose all precision)."""
    v = float("nan") if value is None else float(value)
    if not in_limits(v):
        raise InputError(f"{what} = {v:g} is out of range (0 or magnitude 1e-100 to 1e100)")
    return v


def tied_shear_modulus(mat) -> bool:
    """True when a MAT1's G follows its E: G blank and NU given (NASTRAN's G =
    E / (2 (1 + NU))). With NU blank and G given it is NU that follows (G stays); with both
    blank G is 0. ``mat.blank`` (the fields the card left blank) is recorded by
    :func:`eigenupdate.io.nastran_deck.load_deck`; a MAT1 made otherwise is judged by its
    numbers (G equal to E / (2 (1 + NU)) to 1e-12 taken as G blank)."""
    blank = getattr(mat, "blank", None)
    if blank is not None:
        return "G" in blank and "NU" not in blank
    g, nu = mat.g or 0.0, mat.nu
    return nu is not None and g > 0 and math.isclose(g, mat.e / (2 * (1 + nu)), rel_tol=1e-12)


_MAT9 = ("G11", "G12", "G13", "G14", "G15", "G16", "G22", "G23", "G24", "G25", "G26",
         "G33", "G34", "G35", "G36", "G44", "G45", "G46", "G55", "G56", "G66")


def mat9(bdf, mat, cordm, where: str) -> np.ndarray:
    """MAT9's moduli (xx, yy, zz, xy, yz, zx; engineering shear, MSC QRG MAT9) in basic,
    turned from the PSOLID's rectangular CORDM (0 or blank: basic)."""
    label = f"MAT9 {mat.mid}"
    c = np.zeros((6, 6))  # _MAT9 lists the upper triangle row by row
    c[np.triu_indices(6)] = [in_range(getattr(mat, g) or 0.0, f"{label}: {g}") for g in _MAT9]
    c += np.triu(c, 1).T
    if mat.rho is not None:
        in_range(mat.rho, f"{label}: RHO")
    if (mat.rho or 0.0) < 0:
        raise InputError(f"{label}: negative density RHO = {mat.rho:g}")
    if np.linalg.eigvalsh(c)[0] <= 1e-12 * np.abs(c).max():
        raise InputError(f"{label}: G11 ... G66 is not positive definite (no elastic material)")
    if cordm in (0, None):
        return c
    system = bdf.coords.get(cordm)
    if cordm == -1 or system is None or system.Type != "R":
        raise InputError(f"{where}: CORDM {cordm} with {label}: only a rectangular "
                         f"material system (or 0, basic) is supported")
    return solids.rotated_elasticity(c, system.beta())


def undefined_material(bdf, mid) -> str:
    """``material N is not defined``, saying why when the deck has heat-transfer materials
    (MAT4, MAT5: skipped, never read, so a thermal deck's PSOLID names one of them)."""
    thermal = [k for k in ("MAT4", "MAT5") if bdf.card_count.get(k)]
    note = (f" (the deck's {' and '.join(thermal)} are heat-transfer materials, not read for "
            f"K and M)") if thermal else ""
    return f"material {mid} is not defined{note}"
