"""CSHEAR with PSHEAR (NASTRAN-95's shear panel, :mod:`eigenupdate.model.shear_panel`)
of a deck: K = G T K_unit(geometry, NU) and the lumped M = WTMASS (RHO T + NSM) M_unit,
so PSHEAR T, MAT1 RHO and MAT1 E (when G follows it: G blank, NU given) are linear
parameters; two of them on one panel (a product) are refused. PSHEAR F1/F2 (extensional
effectiveness: MSC's rods on the edges) other than 0 are refused; MAT1 only."""

from __future__ import annotations

import numpy as np

from eigenupdate.errors import InputError
from eigenupdate.io.nastran_continuum import _add_all, _to_cd, fixed, scaled
from eigenupdate.io.nastran_fields import in_range, tied_shear_modulus
from eigenupdate.model import shear_panel
from eigenupdate.model.assembly import assemble_many


def _pshear(bdf, prop) -> tuple:
    """(MID, T, NSM, G, NU, RHO, tied) of a PSHEAR, validated."""
    where = f"PSHEAR {prop.pid}"
    for name in ("f1", "f2"):
        v = getattr(prop, name, 0.0)
        if v not in (None, 0, 0.0):
            raise InputError(f"{where}: {name.upper()} = {v:g} (extensional effectiveness of "
                             f"the edges) is not supported (0 or blank: shear only)")
    t = in_range(prop.t, f"{where}: T")
    if not t > 0:
        raise InputError(f"{where}: T = {t:g} must be > 0")
    nsm = in_range(prop.nsm or 0.0, f"{where}: NSM")
    mat = bdf.materials.get(prop.mid)
    if mat is None or mat.type != "MAT1":
        what = "is not defined" if mat is None else f"is {mat.type} (MAT1 only)"
        raise InputError(f"{where}: material {prop.mid} {what}")
    for name in ("e", "g", "nu", "rho"):
        if getattr(mat, name) is not None:
            in_range(getattr(mat, name), f"MAT1 {mat.mid}: {name.upper()}")
    g, nu, rho = mat.g or 0.0, mat.nu, mat.rho or 0.0
    if not g > 0:
        raise InputError(f"MAT1 {mat.mid}: G = {g:g}: a shear panel needs G > 0 (give G, or "
                         f"E and NU)")
    if nu is None or not -1.0 < nu <= 0.5:
        raise InputError(f"MAT1 {mat.mid}: NU = {nu} must be in (-1, 0.5] for a shear panel")
    if rho < 0 or rho * t + nsm < 0:
        raise InputError(f"{where}: its mass per area RHO T + NSM = {rho * t + nsm:g} is "
                         f"negative")
    return mat.mid, t, nsm, g, nu, rho, tied_shear_modulus(mat)


def assemble_shear(bdf, grid, xyz, frames, n_nodes, wtmass, pindex, values,
                   k0, m0, kj, mj) -> None:
    """Add the CSHEAR panels' K and M (and each parameter's K_j, M_j) to the triplets
    of :mod:`eigenupdate.io.nastran`. NASTRAN's panel mass is lumped whatever COUPMASS
    says (NASTRAN-95 emadtq.f; MSC/NX list no coupled mass for CSHEAR)."""
    elems = [e for _, e in sorted(bdf.elements.items()) if e.type == "CSHEAR"]
    if not elems:
        return
    labels = [f"CSHEAR {e.eid}" for e in elems]
    props: dict = {}
    for e, lab in zip(elems, labels, strict=True):
        prop = bdf.properties.get(e.pid)
        if prop is None or prop.type != "PSHEAR":
            raise InputError(f"{lab}: property PSHEAR {e.pid} is not defined")
        if e.pid not in props:
            props[e.pid] = _pshear(bdf, prop)
        if len(set(e.node_ids)) != 4:
            raise InputError(f"{lab}: a GRID appears twice among its nodes")
    nodes = np.array([[grid(g, lab) for g in e.node_ids] for e, lab in zip(elems, labels,
                                                                          strict=True)])
    rows = [props[e.pid] for e in elems]
    mid, t, nsm, g, nu, rho = (np.array([r[i] for r in rows]) for i in range(6))
    kfac, mfac = g * t, wtmass * (rho * t + nsm)
    dk: list = [None for _ in kj]
    dm: list = [None for _ in mj]
    pid = np.array([e.pid for e in elems])
    _refuse_products(pid, mid, pindex)
    for (card, cid), slots in pindex.items():
        on = (pid == cid) if card == "PSHEAR" else (mid == cid) if card == "MAT1" else None
        if on is None or not on.any():
            continue
        if card == "PSHEAR" and "T" in slots:
            dk[slots["T"]], dm[slots["T"]] = np.where(on, g, 0.0), np.where(on, wtmass * rho, 0.0)
        if card == "MAT1" and "E" in slots:
            mat = bdf.materials[cid]
            if "NU" in getattr(mat, "blank", ()) and "G" not in mat.blank:
                raise InputError(f"MAT1 {cid} field E: not a parameter of a shear panel's "
                                 f"material with NU blank (NASTRAN's NU = E / (2 G) - 1 "
                                 f"follows E, and the panel's K is not linear in it)")
            if rows[int(np.flatnonzero(on)[0])][6]:  # G = E / (2 (1 + NU)) follows E
                dk[slots["E"]] = np.where(on, g * t / mat.e, 0.0)
        if card == "MAT1" and "RHO" in slots:
            dm[slots["RHO"]] = np.where(on, wtmass * t, 0.0)
    kfac, mfac = fixed(kfac, dk, values), fixed(mfac, dm, values)
    xyz_e = xyz[nodes]

    def blocks(s: slice) -> list:
        ku = _to_cd(shear_panel.shear_stiffness(xyz_e[s], nu[s], labels[s]), frames,
                    nodes[s], 3)
        m = shear_panel.shear_mass(xyz_e[s])  # a node's m I: the same in any axes
        return scaled(ku, m, s, kfac, dk, mfac, dm)

    _add_all(assemble_many(nodes, blocks, 2 + len(kj) + len(mj), n_nodes, 3),
             k0, kj, m0, mj, 3)


def _refuse_products(pid, mid, pindex) -> None:
    """Two parameters on one panel (PSHEAR T with its MAT1 E or RHO) multiply: refused."""
    for (card, cid), slots in pindex.items():
        if card != "PSHEAR" or "T" not in slots:
            continue
        for m in sorted(set(mid[pid == cid].tolist())):
            other = pindex.get(("MAT1", int(m)), {})
            if other:
                name = sorted(other)[0]
                raise InputError(f"PSHEAR {cid} field T and MAT1 {m} field {name}: both "
                                 f"parameters of one shear panel (their product) are not "
                                 f"supported; make one of them a parameter")
