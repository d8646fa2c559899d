"""Shell materials of a deck: MAT1 (isotropic), MAT8 (orthotropic) and MAT2 (anisotropic)
as a PSHELL's MID1/MID2/MID3, MAT1 and MAT8 as PCOMP plies (MSC QRG PSHELL, MAT8, MAT2,
PCOMP).

A PSHELL's MAT8 is read in the element's material axes (THETA/MCID, as a PCOMP ply):
membrane T Q, bending (12I/T^3) T^3 / 12 Q, transverse shear (TS/T) T diag(G1Z, G2Z),
Q the plane-stress moduli of E1, E2, NU12, G12. A MAT1 keeps its E as the part's factor
(so MAT1 E is a parameter); a MAT8's part has factor 1 and its moduli in the matrices
(a MAT8's RHO is a parameter; its moduli are as PCOMP plies only:
:mod:`eigenupdate.io.nastran_plies`).

MAT8 G1Z/G2Z blank: MSC's default is an infinite transverse shear modulus. It is made
shear-rigid as a PSHELL with MID3 blank (:data:`RIGID_SHEAR` times a reference shear
modulus of the material, :func:`reference_shear`). Autodesk Nastran's default
(MAT8SHEAR = FLEXIBLE: G12) differs; MSC's is taken.
"""

from __future__ import annotations

import numpy as np

from eigenupdate.errors import InputError
from eigenupdate.io.nastran_fields import in_range, tied_shear_modulus, undefined_material
from eigenupdate.model import laminate, shells
from eigenupdate.model.ply_moduli import reference_shear

RIGID_SHEAR = 1e3
"""Transverse shear stiffness of a PSHELL with MID3 blank (shear-rigid in NASTRAN), as a
multiple of MID2's E / (2 (1 + NU)) T (:func:`reference_shear` for a MAT8)."""


def mat1(bdf, mid, where: str, solid: bool = False):
    """A MAT1 for a shell or solid, its fields checked: NU in (-1, 0.5] (QRG MAT1), 0.5
    refused for a ``solid`` (its bulk modulus E / (3 (1 - 2 NU)) infinite)."""
    mat = bdf.materials.get(mid)
    if mat is None:
        raise InputError(f"{where}: {undefined_material(bdf, mid)}")
    if mat.type != "MAT1":
        raise InputError(f"{where}: material {mat.type} {mid} is not supported here (MAT1 "
                         f"only)")
    for name in ("e", "g", "nu", "rho"):
        if getattr(mat, name) is not None:
            in_range(getattr(mat, name), f"MAT1 {mid}: {name.upper()}")
    if not (mat.e and mat.e > 0):
        raise InputError(f"MAT1 {mid}: E must be > 0 for a shell or solid, got {mat.e}")
    if mat.nu is None or not -1.0 < mat.nu <= 0.5 or (solid and mat.nu == 0.5):
        limits = "(-1, 0.5) for a solid" if solid else "(-1, 0.5] for a shell"
        raise InputError(f"MAT1 {mid}: NU = {mat.nu} must be in {limits}")
    if (mat.rho or 0.0) < 0:
        raise InputError(f"MAT1 {mid}: negative density RHO = {mat.rho:g}")
    if (mat.g or 0.0) < 0:
        raise InputError(f"MAT1 {mid}: negative shear modulus G = {mat.g:g}")
    return mat


def mat8_values(mat) -> np.ndarray:
    """A MAT8's E1, E2, NU12, G12, G1Z, G2Z (:data:`eigenupdate.model.ply_moduli.NAMES`),
    NU12 blank 0, G1Z/G2Z blank NaN (MSC's rigid); call after :func:`mat8` checked it."""
    blank = getattr(mat, "blank", ())
    return np.array([mat.e11, mat.e22, mat.nu12 or 0.0, mat.g12,
                     np.nan if "G1Z" in blank else mat.g1z,
                     np.nan if "G2Z" in blank else mat.g2z], float)


def mat8(bdf, mid: int) -> tuple[np.ndarray, np.ndarray, float, object]:
    """Plane moduli Q (3, 3), transverse shear moduli [G1Z, G2Z] (2,) (NaN where the card
    leaves it blank: MSC's infinite modulus), density and the card of a MAT8."""
    mat = bdf.materials[mid]
    vals = {k: getattr(mat, a) for k, a in (("E1", "e11"), ("E2", "e22"), ("NU12", "nu12"),
                                             ("G12", "g12"), ("G1Z", "g1z"), ("G2Z", "g2z"))}
    blank = getattr(mat, "blank", ())
    for k, v in vals.items():
        if k in ("G1Z", "G2Z") and k in blank:
            vals[k] = np.nan  # pyNastran's 1e8, where MSC's blank is rigid
        elif k != "NU12" and not (v is not None and in_range(v, f"MAT8 {mid}: {k}") > 0):
            raise InputError(f"MAT8 {mid}: {k} = {v} must be given and > 0")
    nu = in_range(vals["NU12"] or 0.0, f"MAT8 {mid}: NU12")
    if not nu**2 * vals["E2"] / vals["E1"] < 1:
        raise InputError(f"MAT8 {mid}: NU12 = {nu:g} makes the ply's moduli indefinite")
    if (mat.rho or 0.0) < 0:
        raise InputError(f"MAT8 {mid}: negative density RHO = {mat.rho:g}")
    q = laminate.orthotropic_plane(vals["E1"], vals["E2"], nu, vals["G12"])
    return q, np.array([vals["G1Z"], vals["G2Z"]], float), mat.rho or 0.0, mat


def mat2(bdf, mid: int) -> tuple[np.ndarray, np.ndarray, float, object]:
    """Plane moduli G (3, 3), transverse shear moduli (2, 2), density and the card of a
    MAT2 (MSC QRG MAT2: {s1, s2, t12} = G {e1, e2, g12} with G's upper triangle G11, G12,
    G13, G22, G23, G33; as a PSHELL MID3 the same G11, G12, G22 relate {t1z, t2z} to
    {g1z, g2z} and G13, G23, G33 are blank), in the element's material axes (THETA/MCID)
    as a MAT8's. A material system of its own (MCSID) is refused."""
    mat = bdf.materials[mid]
    label = f"MAT2 {mid}"
    if mat.mcsid not in (None, -1):
        raise InputError(f"{label}: MCSID {mat.mcsid} (a material system of its own) is not "
                         f"supported; leave it blank to use the element's THETA/MCID")
    g = {k: in_range(getattr(mat, k) or 0.0, f"{label}: {k}")
         for k in ("G11", "G12", "G13", "G22", "G23", "G33")}
    q = np.array([[g["G11"], g["G12"], g["G13"]], [g["G12"], g["G22"], g["G23"]],
                  [g["G13"], g["G23"], g["G33"]]])
    shear = q[:2, :2].copy()
    if (mat.rho or 0.0) < 0:
        raise InputError(f"{label}: negative density RHO = {mat.rho:g}")
    return q, shear, mat.rho or 0.0, mat


def _definite(m: np.ndarray, what: str) -> None:
    if not np.all(np.linalg.eigvalsh(m) > 0):
        raise InputError(f"{what} is not positive definite")


def _material(bdf, mid, where: str):
    """("MAT1", card), ("MAT8", (q, g, rho, card)) or ("MAT2", (q, g, rho, card)) of a
    PSHELL MIDi."""
    mat = bdf.materials.get(mid)
    if mat is not None and mat.type == "MAT8":
        return "MAT8", mat8(bdf, mid)
    if mat is not None and mat.type == "MAT2":
        return "MAT2", mat2(bdf, mid)
    return "MAT1", mat1(bdf, mid, where)


def pshell(bdf, prop) -> dict:
    """A PSHELL's moduli per part (per unit factor E1, E2, G3 when MAT1) and mass."""
    where = f"{prop.type} {prop.pid}"  # NASTRAN-95's PQUAD1.. read as PSHELLs too
    if not prop.mid1:
        raise InputError(f"{where}: MID1 blank (no membrane) is not supported")
    if prop.mid4:
        raise InputError(f"{where}: MID4 (membrane-bending coupling) is not supported")
    if prop.t is None:
        raise InputError(f"{where}: T blank (thicknesses from the elements' T1-T4) is not "
                         f"supported")
    T = in_range(prop.t, f"{where}: T")
    if not T > 0:
        raise InputError(f"{where}: T = {T:g} must be > 0")
    k1, m1 = _material(bdf, prop.mid1, where + " MID1")
    if prop.mid2 in (None, 0):
        k2 = m2 = k3 = m3 = None
        if prop.mid3:
            raise InputError(f"{where}: MID3 needs MID2 (bending)")
    else:
        if prop.mid2 < 0:
            raise InputError(f"{where}: MID2 = {prop.mid2} (plane strain) is not supported")
        k2, m2 = _material(bdf, prop.mid2, where + " MID2")
        k3, m3 = _material(bdf, prop.mid3, where + " MID3") if prop.mid3 else (None, None)
    ratio = 1.0 if prop.twelveIt3 is None else in_range(prop.twelveIt3, f"{where}: 12I/T^3")
    # blank TS/T is 5/6 (QRG PSHELL); pyNastran fills in 0.833333, 4e-7 below it
    tst = 5.0 / 6.0 if prop.tst in (None, 0.833333) else in_range(prop.tst, f"{where}: TS/T")
    if m2 is not None and not (ratio > 0 and tst > 0):
        raise InputError(f"{where}: 12I/T^3 = {ratio:g} and TS/T = {tst:g} must be > 0")
    for k, m, use in ((k1, m1, "MID1"), (k2, m2, "MID2")):
        if k == "MAT2":  # the membrane's and bending's moduli
            _definite(m[0], f"{where} {use}: MAT2 {m[3].mid}'s G (G11 .. G33)")
    if k3 == "MAT2":
        if np.any(m3[0][2] != 0):
            raise InputError(f"{where} MID3: MAT2 {m3[3].mid}'s G13, G23, G33 must be blank "
                             f"for transverse shear (QRG MAT2)")
        _definite(m3[1], f"{where} MID3: MAT2 {m3[3].mid}'s G11, G12, G22")
    out = {"T": T, "E3": 1.0, "tied3": False, "laminate": None,
           "oriented": bool({"MAT8", "MAT2"} & {k1, k2, k3})}
    if k1 in ("MAT8", "MAT2"):
        out.update(cm=m1[0], E1=1.0, mid1=m1[3].mid)
        rho1, mid1 = m1[2], m1[3].mid
    else:
        out.update(cm=shells.plane_stress(1.0, m1.nu)[0], E1=m1.e, mid1=m1.mid)
        rho1, mid1 = m1.rho or 0.0, m1.mid
    if m2 is None:
        out.update(cb=np.zeros((3, 3)), E2=0.0, mid2=0)
    elif k2 in ("MAT8", "MAT2"):
        out.update(cb=m2[0] * ratio / 12, E2=1.0, mid2=m2[3].mid)
    else:
        out.update(cb=shells.plane_stress(1.0, m2.nu)[0] * ratio / 12, E2=m2.e, mid2=m2.mid)
    out.update(cs=np.zeros((2, 2)), G3=0.0, mid3=0)
    if m2 is not None and m3 is None:
        # MID3 blank: NASTRAN's shear-rigid (Kirchhoff) plate, as MID2's G times
        # RIGID_SHEAR: the frequencies then differ from the rigid limit by 1/RIGID_SHEAR
        # of the shear deformation's share, itself of order (T / L)^2
        if k2 in ("MAT8", "MAT2"):
            out.update(cs=np.eye(2) * RIGID_SHEAR * reference_shear(m2[0]), G3=1.0,
                       mid3=m2[3].mid)
        else:
            out.update(cs=np.eye(2) * RIGID_SHEAR, G3=m2.e / (2 * (1 + m2.nu)), E3=m2.e,
                       mid3=m2.mid, tied3=True)
    elif k3 == "MAT8":  # a blank G1Z/G2Z is rigid in its own direction
        g = m3[1]
        out.update(cs=np.diag(np.where(np.isnan(g), RIGID_SHEAR * reference_shear(m3[0]),
                                       tst * g)), G3=1.0, mid3=m3[3].mid)
    elif k3 == "MAT2":
        out.update(cs=tst * m3[1], G3=1.0, mid3=m3[3].mid)
    elif m3 is not None:
        if not (m3.g or 0.0) > 0:
            raise InputError(f"{where}: MID3's MAT1 {m3.mid} has G = {m3.g or 0.0:g} (E alone "
                             f"on the card: NASTRAN's G and NU are then 0): transverse shear "
                             f"needs G > 0")
        out.update(cs=np.eye(2) * tst, G3=m3.g, E3=m3.e, mid3=m3.mid,
                   tied3=tied_shear_modulus(m3))
    nsm = in_range(prop.nsm or 0.0, f"{where}: NSM")
    if rho1 * T + nsm < 0:
        raise InputError(f"{where}: NSM = {nsm:g} makes the mass per area RHO T + NSM "
                         f"negative")
    out.update(mass={mid1: (rho1, T)}, heights={mid1: 0.0}, nsm=nsm)
    return out


def ply(bdf, mid: int, where: str) -> tuple[np.ndarray, np.ndarray, float]:
    """Plane moduli (3, 3), transverse shear moduli (2, 2) (NaN where a MAT8 leaves
    G1Z/G2Z blank) and density of a PCOMP ply."""
    mat = bdf.materials.get(mid)
    if mat is None:
        raise InputError(f"{where}: {undefined_material(bdf, mid)}")
    if mat.type == "MAT1":
        m = mat1(bdf, mid, where)
        return shells.plane_stress(m.e, m.nu)[0], np.eye(2) * m.g, m.rho or 0.0
    if mat.type == "MAT8":
        q, g, rho, _ = mat8(bdf, mid)
        return q, np.diag(g), rho
    raise InputError(f"{where}: material {mat.type} {mid} is not supported (MAT1 or MAT8 "
                     f"plies)")


def rigid_plies(plies: list, mids, where: str) -> list:
    """The plies with a blank G1Z/G2Z made shear-rigid: every ply blank, the stack's
    H = RIGID_SHEAR sum G_ref t (one ply: the PSHELL with that MAT8 as MID2, MID3 blank);
    only some blank is refused (MSC's rule for such a stack is not documented)."""
    blank = [bool(np.isnan(np.diag(p[1])).any()) for p in plies]
    if not any(blank):
        return plies
    if not all(blank) or any(np.isnan(np.diag(p[1])).sum() == 1 for p in plies):
        i = blank.index(True)
        raise InputError(f"{where}: ply {i + 1}'s MAT8 {int(mids[i])} leaves G1Z/G2Z blank "
                         f"(rigid transverse shear) but not every ply's both: not supported")
    k = laminate.SHEAR_FACTOR
    return [(q, np.eye(2) * RIGID_SHEAR * reference_shear(q) / k, r) for q, _, r in plies]
