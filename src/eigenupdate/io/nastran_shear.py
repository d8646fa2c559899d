"""CSHEAR with PSHEAR (NASTRAN-95's shear panel, :mod:`eigenupdate.model.shear_panel`)
of a deck: K = G T K_unit(geometry, NU) and the lumped M = WTMASS (RHO T + NSM) M_unit,
so PSHEAR T, MAT1 RHO and MAT1 E (when G follows it: G blank, NU given) are linear
parameters; two of them on one panel (a product) are refused. PSHEAR F1/F2 (extensional
effectiveness, MSC's and NX's convention: rods of MAT1 E on the edges,
:func:`eigenupdate.model.shear_panel.edge_rod_stiffness`) add E T K_F (F <= 1.01) and
E T^2 K_W (F > 1.01, an effective width): MAT1 E stays linear, PSHEAR T is linear with
factors and a T^2 term with widths. MAT1 only."""

from __future__ import annotations

import numpy as np

from eigenupdate.errors import InputError
from eigenupdate.io.nastran_continuum import _add, _add_all, _to_cd, fixed, scaled
from eigenupdate.io.nastran_fields import in_range, tied_shear_modulus, undefined_material
from eigenupdate.model import shear_panel
from eigenupdate.model.assembly import assemble_many
from eigenupdate.model.parametric import Term


def _pshear(bdf, prop) -> tuple:
    """(MID, T, NSM, G, NU, RHO, tied, F1, F2, E) of a PSHEAR, validated."""
    where = f"PSHEAR {prop.pid}"
    f12 = []
    for name in ("f1", "f2"):
        v = in_range(getattr(prop, name, 0.0) or 0.0, f"{where}: {name.upper()}")
        if v < 0:
            raise InputError(f"{where}: {name.upper()} = {v:g} (extensional effectiveness "
                             f"of the edges) must be >= 0")
        f12.append(v)
    t = in_range(prop.t, f"{where}: T")
    if not t > 0:
        raise InputError(f"{where}: T = {t:g} must be > 0")
    nsm = in_range(prop.nsm or 0.0, f"{where}: NSM")
    mat = bdf.materials.get(prop.mid)
    if mat is None or mat.type != "MAT1":
        what = (undefined_material(bdf, prop.mid) if mat is None
                else f"material {prop.mid} is {mat.type} (MAT1 only)")
        raise InputError(f"{where}: {what}")
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
    e = mat.e or 0.0
    if any(f12) and not e > 0:
        raise InputError(f"{where}: F1 = {f12[0]:g}, F2 = {f12[1]:g} (extensional rods "
                         f"on the edges) need MAT1 {mat.mid} E > 0, not {e:g}")
    return mat.mid, t, nsm, g, nu, rho, tied_shear_modulus(mat), *f12, e


def assemble_shear(bdf, grid, xyz, frames, wtmass, pindex, values, k0, m0, kj, mj,
                   extra) -> None:
    """Add the CSHEAR panels' K and M (and each parameter's K_j, M_j; PSHEAR T's
    T^2 part of effective-width rods to ``extra``) to the triplets of
    :mod:`eigenupdate.io.nastran` (one node a row of ``xyz``). NASTRAN's panel mass is
    lumped whatever COUPMASS says (NASTRAN-95 emadtq.f; MSC/NX list no coupled mass for
    CSHEAR)."""
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
    mid, t, nsm, g, nu, rho, _, f1, f2, e = (np.array([r[i] for r in rows])
                                             for i in range(10))
    # K = G T K_shear + E T K_factor + E T^2 K_width: three unit matrices per panel
    kfac = [g * t, e * t, e * t * t]
    mfac = wtmass * (rho * t + nsm)
    n = len(kj)
    dk: list = [[None] * n for _ in range(3)]
    dm: list = [None] * len(mj)
    width_terms: list = []  # (mask, Term): PSHEAR T's E T^2
    pid = np.array([el.pid for el in elems])
    _refuse_products(pid, mid, pindex)
    for (card, cid), slots in pindex.items():
        on = (pid == cid) if card == "PSHEAR" else (mid == cid) if card == "MAT1" else None
        if on is None or not on.any():
            continue
        if card == "PSHEAR" and "T" in slots:
            j = slots["T"]
            dk[0][j], dk[1][j] = np.where(on, g, 0.0), np.where(on, e, 0.0)
            dm[j] = np.where(on, wtmass * rho, 0.0)
            wide = on & ((f1 > shear_panel.EFFECTIVE_WIDTH) | (f2 > shear_panel.EFFECTIVE_WIDTH))
            if wide.any():
                kfac[2] = np.where(wide, 0.0, kfac[2])
                width_terms.append((np.where(wide, e, 0.0), Term(None, ((j, 2.0),), 1.0)))
        if card == "MAT1" and "E" in slots:
            j = slots["E"]
            mat = bdf.materials[cid]
            if "NU" in getattr(mat, "blank", ()) and "G" not in mat.blank:
                raise InputError(f"MAT1 {cid} field E: not a parameter of a shear panel's "
                                 f"material with NU blank (NASTRAN's NU = E / (2 G) - 1 "
                                 f"follows E, and the panel's K is not linear in it)")
            if rows[int(np.flatnonzero(on)[0])][6]:  # G = E / (2 (1 + NU)) follows E
                dk[0][j] = np.where(on, g * t / mat.e, 0.0)
            dk[1][j], dk[2][j] = np.where(on, t, 0.0), np.where(on, t * t, 0.0)
        if card == "MAT1" and "RHO" in slots:
            dm[slots["RHO"]] = np.where(on, wtmass * t, 0.0)
    kfac = [fixed(k, d, values) for k, d in zip(kfac, dk, strict=True)]
    mfac = fixed(mfac, dm, values)
    xyz_e = xyz[nodes]
    rods = bool(np.any(f1) or np.any(f2))

    def blocks(s: slice) -> list:
        units = [shear_panel.shear_stiffness(xyz_e[s], nu[s], labels[s])]
        units += list(shear_panel.edge_rod_stiffness(xyz_e[s], f1[s], f2[s])) if rods else []
        m = shear_panel.shear_mass(xyz_e[s])  # a node's m I: the same in any axes
        parts = [scaled(ku, m, s, kf, d, mfac, dm)
                 for ku, kf, d in zip(units, kfac, dk, strict=False)]
        out = [_sum(p[i] for p in parts) for i in range(1 + n)] + parts[0][1 + n:]
        out += [None if not np.any(c[s]) else c[s, None, None] * units[2]
                for c, _ in width_terms]
        return [None if b is None else _to_cd(b, frames, nodes[s], 3)
                if i < 1 + n or i >= 2 + n + len(mj) else b for i, b in enumerate(out)]

    mats = assemble_many(nodes, blocks, 2 + n + len(mj) + len(width_terms), len(xyz), 3)
    for i, (_, term) in enumerate(width_terms):
        trip = type(k0)()
        _add(trip, mats[2 + n + len(mj) + i], 3)
        extra.append(("k", trip, term))
    _add_all(mats, k0, kj, m0, mj, 3)


def _sum(blocks):
    """Sum of the blocks that are not None (None if all are)."""
    out = None
    for b in blocks:
        if b is not None:
            out = b if out is None else out + b
    return out


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
