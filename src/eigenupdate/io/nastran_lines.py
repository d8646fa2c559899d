"""CBAR, CBEAM, CROD and CONROD of a deck: sections, materials, shear factors, and the
assembly of their (parameter) stiffness and mass, vectorised over elements with
:mod:`eigenupdate.model.frame3d`."""

from __future__ import annotations

import math
import re
import warnings

import numpy as np

from eigenupdate.errors import EigenupdateWarning, InputError
from eigenupdate.io import nastran_tapered
from eigenupdate.io.nastran_fields import in_range, tied_shear_modulus, undefined_material
from eigenupdate.model import frame3d, sections
from eigenupdate.model import sections_library as library
from eigenupdate.model.parametric import FunctionTerm
from eigenupdate.model.sections import PARTS, SectionPart

# PBARL shapes read (A, I1, I2, I12, J from model/sections.py and sections_library.py)
PBARL_SHAPES = sections.SHAPES


def assemble_lines(bdf, where, grid, xyz, frames, consistent, wtmass, pindex, values,
           k0, m0, kj, mj, extra) -> None:
    """CBAR, CROD and CONROD, vectorised over elements. Parameters that enter an
    element's K or M nonlinearly (a PBARL/PBEAML dimension, or two parameters in one
    quantity: MAT1 E and PBAR A) make one :class:`FunctionTerm` per material, section
    and part, appended to ``extra`` as ("k" or "m", triplets of its matrix, term)."""
    sections: dict = {}  # validated once per property (or CONROD)

    def section(key, make, where_):
        if key not in sections:
            A, i1, i2, j, nsm, mid, pkey, *shear = make()
            for name, x in (("A", A), ("I1", i1), ("I2", i2), ("J", j), ("NSM", nsm)):
                owner = pkey[0] + " " + str(pkey[1]) if pkey else where_
                if x is None or in_range(x, f"{owner}: {name}") < 0:
                    raise InputError(f"{owner}: {name} = {x} must be >= 0")
            mat, rho, g, tied = _material(bdf, mid, where_)
            k1, k2, nsi, *rest = shear
            i12 = float(rest[0]) if rest else 0.0
            if (k1 or k2) and not g > 0:
                raise InputError(f"{where_}: shear factors K1, K2 need MAT1 {mid} G > 0")
            sections[key] = (mat.e, g, tied, rho, float(A), float(i1), float(i2),
                             float(j or 0.0), float(nsm or 0.0), mid, pkey, k1, k2,
                             in_range(nsi, f"{where_}: NSI"), i12)
        return sections[key]

    label, rod, ga, gb, g0, xv, wa, wb, sec = [], [], [], [], [], [], [], [], []
    basic_v, offt_o = [], []  # X in basic; offsets at A, B in the offset system
    tapers: dict = {}  # per property: its nastran_tapered.Taper, None if constant
    taper_of: list = []  # per element
    pins = []
    zero = np.zeros(3)
    for eid, e in sorted(bdf.elements.items()):
        lab = f"{e.type} {eid}"
        if e.type in ("CBAR", "CBEAM"):
            ptype = "PBAR" if e.type == "CBAR" else "PBEAM"
            prop = bdf.properties.get(e.pid)
            if prop is None or prop.type not in {"PBAR": ("PBAR", "PBARL"),
                                                 "PBEAM": ("PBEAM", "PBEAML")}[ptype]:
                raise InputError(f"{lab}: property {ptype} {e.pid} is not defined")
            offt = "GGG" if str(e.offt) == "1" else str(e.offt)  # NASTRAN-95's F = 1
            if e.offt is None and getattr(e, "bit", None) is not None:  # a real in field 9
                raise InputError(f"{lab}: field 9 = {e.bit:g} is BIT (built-in twist, QRG "
                                 f"CBEAM: beam p-elements), not an OFFT code: not supported")
            if not re.fullmatch("[GB][GO][GO]", offt):
                raise InputError(f"{lab}: OFFT {e.offt} is not one of GGG, BGG, GGO, BGO, "
                                 f"GOG, BOG, GOO, BOO (QRG CBAR)")
            pin = np.zeros(12, bool)
            for end, flags in ((0, e.pa), (6, e.pb)):
                pin[[end + int(c) - 1 for c in str(flags or "") if c != "0"]] = True
            if pin.any() and consistent:
                raise InputError(f"{lab}: pin flags PA/PB with coupled mass are not supported")
            if getattr(e, "sa", 0) or getattr(e, "sb", 0):
                raise InputError(f"{lab}: scalar points SA/SB (warping) are not supported")
            a, b = grid(e.nodes[0], lab), grid(e.nodes[1], lab)
            g0.append(-1 if e.g0 is None else grid(e.g0, lab))
            xv.append(zero if e.g0 is not None else e.x)
            basic_v.append(offt[0] == "B")  # X in basic, not in GA's system
            offt_o.append((offt[1] == "O", offt[2] == "O"))
            # lumped mass too: the end masses sit at the offset ends, carried rigidly to
            # the grids (NASTRAN-95 mis/bard.f; tests/io/test_nastran_bar_offset_mass.py)
            wa.append(e.wa)
            wb.append(e.wb)
            if (prop.type, e.pid) not in tapers:
                tapers[(prop.type, e.pid)] = _taper(prop)
            taper = tapers[(prop.type, e.pid)]
            if taper is not None and pin.any():
                raise InputError(f"{lab}: pin flags on a tapered beam ({taper.where}) are "
                                 f"not supported")
            sec.append(section((prop.type, e.pid), lambda p=prop, tp=taper: _section_of(
                p, tp), lab))
            taper_of.append(taper)
        elif e.type in ("CROD", "CONROD", "CTUBE"):
            if e.type == "CTUBE":
                prop = bdf.properties.get(e.pid)
                if prop is None or prop.type != "PTUBE":
                    raise InputError(f"{lab}: property PTUBE {e.pid} is not defined")
                sec.append(section(("PTUBE", e.pid), lambda p=prop: _tube(p), lab))
            elif e.type == "CROD":
                prop = bdf.properties.get(e.pid)
                if prop is None or prop.type != "PROD":
                    raise InputError(f"{lab}: property PROD {e.pid} is not defined")
                sec.append(section(("PROD", e.pid), lambda p=prop: (
                    p.A, 0.0, 0.0, p.j, p.nsm, p.mid, ("PROD", p.pid), 0.0, 0.0, 0.0), lab))
            else:
                sec.append(section(("CONROD", eid), lambda e=e: (
                    e.A, 0.0, 0.0, e.j, e.nsm, e.mid, None, 0.0, 0.0, 0.0), lab))
            a, b = grid(e.nodes[0], lab), grid(e.nodes[1], lab)
            g0.append(-1)
            xv.append(zero)
            basic_v.append(False)
            offt_o.append((False, False))
            taper_of.append(None)
            wa.append(zero)
            wb.append(zero)
        else:
            continue
        pins.append(pin if e.type in ("CBAR", "CBEAM") else np.zeros(12, bool))
        label.append(lab)
        rod.append(e.type in ("CROD", "CONROD", "CTUBE"))
        ga.append(a)
        gb.append(b)
    if not label:
        return
    rod, ga, gb, g0 = np.array(rod), np.array(ga), np.array(gb), np.array(g0)
    # orientation vector and offsets are given in GA's (GB's) displacement system
    to_basic = np.transpose(frames, (0, 2, 1))
    v = np.einsum("nij,nj->ni", to_basic[ga], np.array(xv, float))
    basic_v = np.array(basic_v, bool)
    v[basic_v] = np.array(xv, float)[basic_v]
    by_g0 = g0 >= 0
    v[by_g0] = xyz[g0[by_g0]] - xyz[ga[by_g0]]
    v[rod] = frame3d.any_normal((xyz[gb] - xyz[ga])[rod])
    wa_raw, wb_raw = np.array(wa, float).reshape(-1, 3), np.array(wb, float).reshape(-1, 3)
    wa = np.einsum("nij,nj->ni", to_basic[ga], wa_raw)
    wb = np.einsum("nij,nj->ni", to_basic[gb], wb_raw)
    offt_o = np.array(offt_o, bool).reshape(-1, 2)
    if offt_o.any():  # OFFT ?O? / ??O: in the offset system, x from GA to GB and y from v
        sel = offt_o.any(axis=1)
        _, r = frame3d.local_axes(xyz[ga][sel], xyz[gb][sel], v[sel],
                                  [label[i] for i in np.flatnonzero(sel)])
        for end, w, raw in ((0, wa, wa_raw), (1, wb, wb_raw)):
            on = offt_o[sel, end]
            w[np.flatnonzero(sel)[on]] = np.einsum("nji,nj->ni", r[on], raw[sel][on])
    xa, xb = xyz[ga] + wa, xyz[gb] + wb
    rows = sec  # per element: E, G, tied, rho, A, I1, I2, J, nsm, mid, pkey, K1, K2, NSI, I12
    L, R = frame3d.local_axes(xa, xb, v, label)
    T = frame3d.element_transform(R, wa, wb, frames[ga], frames[gb])
    E, G, rho = (np.array([r[k] for r in rows], float) for k in (0, 1, 3))
    tied = np.array([r[2] for r in rows])
    A, I1, I2, J, nsm = (np.array([r[k] for r in rows], float) for k in range(4, 9))
    K1, K2, nsi, I12 = (np.array([r[k] for r in rows], float) for k in (11, 12, 13, 14))
    coupled = I12 != 0
    if np.any(coupled & np.array(pins).any(1)):
        e = int(np.flatnonzero(coupled & np.array(pins).any(1))[0])
        raise InputError(f"{label[e]}: pin flags with I12 != 0 are not supported")
    beam = np.array([lab.startswith("CBEAM") for lab in label])
    # Timoshenko shear parameters; K = 0 (or PBAR's blank) is a shear-rigid section
    with np.errstate(divide="ignore", invalid="ignore"):
        phi1 = np.where(K1 > 0, 12 * E * I1 / (K1 * A * G * L**2), 0.0)
        phi2 = np.where(K2 > 0, 12 * E * I2 / (K2 * A * G * L**2), 0.0)
    bad = np.flatnonzero(~(np.isfinite(phi1) & np.isfinite(phi2)))
    if bad.size:
        raise InputError(f"{label[bad[0]]}: shear factors K1/K2 need A > 0 and G > 0")
    tap = np.array([t is not None for t in taper_of])
    phi1[tap] = phi2[tap] = 0.0  # the tapered parts hold their shear flexibility
    with np.errstate(over="ignore", invalid="ignore"):
        big = ~np.isfinite(E * np.maximum(A, np.maximum(I1, I2)) / L**3 * 12)
    if big.any():
        e = int(np.flatnonzero(big)[0])
        raise InputError(f"{label[e]}: stiffness overflows (MAT1 {rows[e][9]} E = "
                         f"{E[e]:g} on a {L[e]:g} long element)")
    kp = frame3d.stiffness_parts(L, phi1, phi2)
    frame3d.release(kp, np.array(pins))
    mp = frame3d.mass_parts(L, consistent)
    mp["translation"][rod] = frame3d.rod_mass_part(L[rod], consistent)
    mp["torsion"][~beam] = 0.0  # NASTRAN's CBAR and CROD carry no torsional inertia
    parts = {**{f"k_{k}": x for k, x in kp.items()}, **{f"m_{k}": x for k, x in mp.items()}}
    if coupled.any():  # unsymmetric sections (PBAR/PBEAM I12)
        parts["k_bend12"] = frame3d.bending_coupling_part(L)
    if tap.any():
        te = np.flatnonzero(tap)
        for name, arr in nastran_tapered.element_parts(
                [taper_of[e] for e in te], L[te], E[te], G[te], rho[te], K1[te], K2[te],
                consistent).items():
            parts[name][te] = arr
    dofs = (6 * np.stack([ga, gb], 1)[:, :, None] + np.arange(6)[None, None, :]).reshape(-1, 12)
    r_idx = np.repeat(dofs, 12, axis=1)
    c_idx = np.tile(dofs, (1, 12))
    # section quantities and the parameters that scale each (one at most per element)
    total = {"k_axial": E * A, "k_torsion": G * J, "k_bend1": E * I1, "k_bend2": E * I2,
             "m_translation": wtmass * (rho * A + nsm),
             "m_torsion": np.where(beam, wtmass * (rho * (I1 + I2) + nsi), 0.0)}
    if coupled.any():
        total["k_bend12"] = E * I12
    n = len(rows)
    deriv: list[dict[str, np.ndarray]] = [{} for _ in kj]

    def d(j, part, coef, mask):
        arr = deriv[j].setdefault(part, np.zeros(n))
        arr[mask] += coef[mask] if np.ndim(coef) else coef

    mids = np.array([r[9] for r in rows])
    pkeys = [r[10] for r in rows]
    shear = (phi1 != 0) | (phi2 != 0)

    # a parameter in phi = 12 E I / (K A G L^2) makes a shear-flexible element's K not
    # linear in it: that element goes to function terms (E with G blank and RHO stay linear)
    in_phi = np.zeros(n, bool)

    for (card, cid), slots in pindex.items():
        if card == "MAT1":
            mask = mids == cid
            if "E" in slots:
                in_phi |= mask & shear & ~tied
                j = slots["E"]
                for part, c in (("k_axial", A), ("k_bend1", I1), ("k_bend2", I2)):
                    d(j, part, c, mask)
                if coupled.any():
                    d(j, "k_bend12", I12, mask)
                d(j, "k_torsion", np.where(tied, G * J / E, 0.0), mask)
            if "RHO" in slots:
                j = slots["RHO"]
                d(j, "m_translation", wtmass * A, mask)
                d(j, "m_torsion", np.where(beam, wtmass * (I1 + I2), 0.0), mask)
        elif card in ("PBAR", "PBEAM", "PROD"):
            mask = np.array([k == (card, cid) for k in pkeys])
            tors = np.where(beam, wtmass * rho, 0.0)
            for fld, parts_ in (("A", (("k_axial", E), ("m_translation", wtmass * rho))),
                                ("I1", (("k_bend1", E), ("m_torsion", tors))),
                                ("I2", (("k_bend2", E), ("m_torsion", tors))),
                                ("J", (("k_torsion", G),))):
                if fld in slots:
                    planes = {"A": shear, "I1": phi1 != 0, "I2": phi2 != 0, "J": np.zeros(n, bool)}
                    in_phi |= mask & planes[fld]
                    for part, c in parts_:
                        d(slots[fld], part, c, mask)
    if tap.any():
        nastran_tapered.refuse_parameters(pindex, mids, pkeys, taper_of, K1, K2, tied)
    nonlin = _nonlinear_elements(deriv, pindex, pkeys, label, shear & np.array(pins).any(1),
                                 in_phi)
    if np.any(nonlin & coupled):
        e = int(np.flatnonzero(nonlin & coupled)[0])
        raise InputError(f"{label[e]}: I12 != 0 with parameters that enter the element "
                         f"nonlinearly (a section dimension, or two in one quantity) is not "
                         f"supported")
    for dj in deriv:  # those elements' parts all go to their function terms
        for arr in dj.values():
            arr[nonlin] = 0.0
    base = {part: tot - sum((values[j] * dj[part] for j, dj in enumerate(deriv) if part in dj),
                            np.zeros(n)) for part, tot in total.items()}
    for part in base:
        base[part][nonlin] = 0.0

    def put(dest, coefs: dict[str, np.ndarray]) -> None:
        # sum the local parts first: one transformation and one COO block per element
        sel = np.flatnonzero(np.any([c != 0 for c in coefs.values()], axis=0))
        if sel.size:
            local = sum(c[sel, None, None] * parts[p][sel] for p, c in coefs.items())
            dest.add(r_idx[sel], c_idx[sel], frame3d.to_global(local, T[sel]))

    for key in sorted({(int(mids[e]), pkeys[e]) for e in np.flatnonzero(nonlin)}):
        grp = nonlin & (mids == key[0]) & np.array([k == key[1] for k in pkeys])
        e = int(np.flatnonzero(grp)[0])
        r = rows[e]
        prop = bdf.properties[key[1][1]]
        shape = prop.Type if key[1][0] in ("PBARL", "PBEAML") else None
        fixed = {"E": r[0], "G": r[1], "RHO": r[3], "A": r[4], "I1": r[5], "I2": r[6],
                 "J": r[7], "NSM": r[8], "NSI": r[13]}
        if shape is not None:
            dims = np.atleast_2d(np.asarray(prop.dim, float))[0]
            fixed.update({f"DIM{k + 1}": float(x) for k, x in enumerate(dims)})
        slots = {**pindex.get(("MAT1", key[0]), {}), **pindex.get(key[1], {})}
        for part in PARTS:
            k_shear = {"k_bend1": r[11], "k_bend2": r[12]}.get(part, 0.0)
            # phi = 12 E I / (K A G L^2) holds A too
            deps = [f for f in slots if _enters(part, f, r[2], bool(beam[e]))
                    or (k_shear and f != "RHO")]
            if not deps:  # this part does not depend on the parameters
                base[part][grp] = total[part][grp]
                continue
            idx = tuple(slots[f] for f in deps)
            if not k_shear:
                fn = SectionPart(part, tuple(deps), tuple(fixed.items()), shape, r[2],
                                 bool(beam[e]), float(wtmass))
                dest = type(k0)()
                put(dest, {part: grp.astype(float)})
                extra.append((part[0], dest, FunctionTerm(None, idx, fn)))
                continue
            # Timoshenko: EI (U0 + phi U1) / (1 + phi) per unit EI, phi = c / L^2 differs
            # with the length: two terms per distinct length
            for length in np.unique(L[grp]):
                sel = np.flatnonzero(grp & (L == length))
                u0 = frame3d.stiffness_parts(L[sel])[part[2:]]
                u1 = 2 * frame3d.stiffness_parts(L[sel], np.ones(sel.size),
                                                 np.ones(sel.size))[part[2:]] - u0
                for which, local in ((0, u0), (1, u1)):
                    fn = SectionPart(part, tuple(deps), tuple(fixed.items()), shape, r[2],
                                     bool(beam[e]), float(wtmass), float(k_shear),
                                     float(length), which)
                    dest = type(k0)()
                    dest.add(r_idx[sel], c_idx[sel], frame3d.to_global(local, T[sel]))
                    extra.append(("k", dest, FunctionTerm(None, idx, fn)))

    for kind, dest0, dests in (("k", k0, kj), ("m", m0, mj)):
        put(dest0, {p: c for p, c in base.items() if p[0] == kind})
        for j, dj in enumerate(deriv):
            if any(p[0] == kind for p in dj):
                put(dests[j], {p: c for p, c in dj.items() if p[0] == kind})


def _taper(prop) -> nastran_tapered.Taper | None:
    """The taper of a CBEAM's property (None: a constant section)."""
    if prop.type == "PBEAM":
        return nastran_tapered.pbeam_taper(prop)
    if prop.type != "PBEAML":
        return None
    _check_shape(prop)
    return nastran_tapered.pbeaml_taper(prop, lambda d: pbarl_values(prop, d),
                                        lambda d, a: _shear_factors(prop.Type, d, a))


def _section_of(prop, taper) -> tuple:
    """A property's section tuple; a tapered one's A, I1, I2, J, NSM, NSI its means."""
    row = list(pbarl_section(prop) if prop.type in ("PBARL", "PBEAML")
               else bar_section(prop, taper is not None))
    if taper is not None:
        A, i1, i2, j, nsm, nsi = taper.means()
        row[:5] = A, i1, i2, j, nsm
        row[9] = nsi
    return tuple(row)


def bar_section(prop, tapered: bool = False) -> tuple:
    """(A, I1, I2, J, NSM, MID, (card, id), K1, K2) of a PBAR or a constant-section
    PBEAM (``tapered``: end A's values of a PBEAM that nastran_tapered reads); K = 0
    means no shear flexibility (PBAR's blank, PBEAM's 0.0)."""
    where = f"{prop.type} {prop.pid}"
    k1, k2 = prop.k1 or 0.0, prop.k2 or 0.0
    if prop.type == "PBAR" and k1 >= 1e8:  # pyNastran's stand-in for a blank K1
        k1 = 0.0
    if prop.type == "PBAR" and k2 >= 1e8:
        k2 = 0.0
    if k1 < 0 or k2 < 0:
        raise InputError(f"{where}: shear factors K1 = {k1:g}, K2 = {k2:g} must be >= 0")
    if prop.type == "PBEAM":
        for name in ("A", "i1", "i2", "i12", "j", "nsm") if not tapered else ():
            v = np.asarray(getattr(prop, name), float)
            # one value written twice to different digits (.0052083, .005208) is constant
            if np.ptp(v) > nastran_tapered.ROUNDING * np.abs(v).max():
                raise InputError(f"{where}: {name.upper()} varies along the beam; only a "
                                 f"constant section is supported")
        # S1, S2 (shear relief of a taper) do nothing on a constant section
        extra = [n for n in ("cwa", "cwb", "m1a", "m2a", "m1b", "m2b", "n1a", "n2a", "n1b",
                             "n2b") if getattr(prop, n)]
        if extra:
            raise InputError(f"{where}: {', '.join(x.upper() for x in extra)} (warping, "
                             f"offsets of the mass or neutral axis) are not supported")
        nsia = prop.nsia or 0.0
        nsib = nsia if prop.nsib is None else prop.nsib
        if nsia != nsib and not tapered:
            raise InputError(f"{where}: NSI varies along the beam ({nsia:g}, {nsib:g})")
    first = [float(np.ravel(getattr(prop, n))[0]) for n in ("A", "i1", "i2", "i12", "j", "nsm")]
    A, i1, i2, i12, j, nsm = first
    if i12:
        in_range(i12, f"{where}: I12")
        if not i1 * i2 > i12**2:
            raise InputError(f"{where}: I12 = {i12:g} needs I1 I2 > I12^2 (I1 = {i1:g}, "
                             f"I2 = {i2:g})")
        if prop.type == "PBEAM" and (k1 or k2):  # PBAR's rule is not stated for PBEAM
            raise InputError(f"{where}: I12 = {i12:g} with shear factors K1 = {k1:g}, K2 = "
                             f"{k2:g} (PBEAM's default 1.0) is not supported; with K1 = K2 = "
                             f"0.0 (shear-rigid) it is")
        k1 = k2 = 0.0  # NASTRAN ignores K1, K2 when I12 != 0 (QRG PBAR, NASTRAN-95 KBAR)
    nsi = nsia if prop.type == "PBEAM" else 0.0
    return A, i1, i2, j, nsm, prop.mid, (prop.type, prop.pid), k1, k2, nsi, i12


def _tube(prop) -> tuple:
    """The section of a constant PTUBE: outer diameter OD, wall T (blank: a solid rod);
    A = pi (OD^2 - ID^2) / 4, J = pi (OD^4 - ID^4) / 32 (NASTRAN's PTUBE)."""
    where = f"PTUBE {prop.pid}"
    od = in_range(prop.OD1, f"{where}: OD")
    if prop.OD2 is not None and prop.OD2 != prop.OD1:
        raise InputError(f"{where}: a tapered tube (OD2 = {prop.OD2:g}) is not supported")
    t = od / 2 if prop.t is None else in_range(prop.t, f"{where}: T")
    if not 0 < t <= od / 2:
        raise InputError(f"{where}: wall T = {t:g} must be > 0 and at most OD / 2 = {od / 2:g}")
    inner = od - 2 * t
    area = math.pi * (od**2 - inner**2) / 4
    j = math.pi * (od**4 - inner**4) / 32
    return area, 0.0, 0.0, j, prop.nsm or 0.0, prop.mid, ("PTUBE", prop.pid), 0.0, 0.0, 0.0


def _check_shape(prop) -> None:
    """InputError unless a PBARL/PBEAML is a supported standard section."""
    where, shape = f"{prop.type} {prop.pid}", prop.Type
    if prop.group.strip() != "MSCBML0":
        raise InputError(f"{where}: GROUP {prop.group} (a user section library) is not "
                         f"supported; only the standard sections of MSCBML0")
    if shape not in PBARL_SHAPES:
        # L: MSC's axes for it (I12's sign) are only in its figure, which only pyNastran
        # reads (its I1, I2 are wrong); HAT1 and DBOX are closed cells with open parts
        why = {"L": " (its section axes, which give I12's sign, are not established)",
               "HAT1": " (a closed cell with open flanges: its J is not modelled)",
               "DBOX": " (a two-cell box: its J is not modelled)",
               }.get(shape, "")
        raise InputError(f"{where}: section type {shape}{why} is not supported (supported: "
                         f"{', '.join(PBARL_SHAPES)})")


def pbarl_section(prop) -> tuple:
    """(A, I1, I2, J, NSM, MID, (card, id), K1, K2) of a standard PBARL or a constant
    PBEAML section: the equivalent PBAR's (PBEAM's) values (the shear centre is taken
    at the centroid)."""
    _check_shape(prop)
    where, shape = f"{prop.type} {prop.pid}", prop.Type
    dim, nsm = prop.dim, prop.nsm
    if prop.type == "PBEAML":  # one row of dimensions per station: end A's (a taper's
        rows = np.atleast_2d(np.asarray(dim, float))  # are read by nastran_tapered)
        dim, nsm = rows[0], float(np.ravel(nsm)[0])
    A, i1, i2, i12, j = _values(prop, dim)
    if shape not in sections.SHEAR_SHAPES:
        warnings.warn(f"{where}: NASTRAN gives section {shape} shear flexibility with factors "
                      f"not modelled here (Euler-Bernoulli); stubby members will differ",
                      EigenupdateWarning, stacklevel=2)
    if shape in library.CAVEATS:
        warnings.warn(f"{where}: section {shape}: {library.CAVEATS[shape]}",
                      EigenupdateWarning, stacklevel=2)
    offset = sections.shear_centre_offset(shape, dim)
    if prop.type == "PBEAML" and offset is None:
        warnings.warn(f"{where}: section {shape}'s shear centre is not computed here; NASTRAN "
                      f"puts it on the CBEAM's axis, this element the centroid: the member "
                      f"may sit elsewhere", EigenupdateWarning, stacklevel=2)
    dy, dz = offset or (0.0, 0.0)
    if prop.type == "PBEAML" and math.hypot(dy, dz) > 1e-6 * math.sqrt(A):
        # MSC's PBEAML figures put the shear centre at the element axis and offset the
        # neutral axis from it; a member's effective offset then differs by (dy, dz)
        warnings.warn(f"{where}: section {shape}'s shear centre is ({dy:.4g}, {dz:.4g}) (y, z) "
                      f"from its centroid; NASTRAN puts the shear centre on the CBEAM's axis, "
                      f"this element the centroid: the member sits that much elsewhere",
                      EigenupdateWarning, stacklevel=2)
    k1, k2 = _shear_factors(shape, dim, A)
    return A, i1, i2, j, nsm, prop.mid, (prop.type, prop.pid), k1, k2, 0.0, i12


def _shear_factors(shape: str, dim, area: float) -> tuple[float, float]:
    """NASTRAN's K1, K2 of a PBARL/PBEAML section; (0, 0): none modelled."""
    if shape not in sections.SHEAR_SHAPES:
        return 0.0, 0.0
    return tuple(float(k) for k in sections.shear_factors(shape, np.asarray(dim, float), area))


def pbarl_values(prop, dim) -> tuple[float, float, float, float]:
    """A, I1, I2, J of a PBARL/PBEAML shape at dimensions ``dim`` (InputError naming the
    card if they make no section, or if it has an I12: a taper's stations)."""
    A, i1, i2, i12, j = _values(prop, dim)
    if i12 != 0:
        raise InputError(f"{prop.type} {prop.pid}: a tapered section with I12 != 0 (section "
                         f"{prop.Type}) is not supported")
    return A, i1, i2, j


def _values(prop, dim) -> tuple[float, ...]:
    """A, I1, I2, I12, J (InputError naming the card if the dimensions make no section)."""
    try:
        return sections.section_values(prop.Type, dim)
    except InputError as exc:
        raise InputError(f"{prop.type} {prop.pid}: {exc}") from None


def _nonlinear_elements(deriv, pindex, pkeys, label, shear, in_phi) -> np.ndarray:
    """Mask of the elements whose K or M is not linear in the parameters: a section
    dimension is one, two parameters scale one of their quantities (E A), or one is in a
    shear-flexible element's phi (``in_phi``). ``shear``: the shear-flexible elements
    with pin flags (condensed with phi: refused)."""
    dims = {k for k in pindex if k[0] in ("PBARL", "PBEAML")}
    out = np.array([k in dims for k in pkeys], dtype=bool) | in_phi
    for part in {p for dj in deriv for p in dj}:
        count = sum((dj[part] != 0).astype(int) for dj in deriv if part in dj)
        out |= count > 1
    hit = np.flatnonzero(out & shear)
    if hit.size:
        raise InputError(f"{label[hit[0]]}: its parameters enter K nonlinearly (a section "
                         f"dimension, a product such as MAT1 E with PBAR A, or a quantity in "
                         f"the shear parameter phi), which is not supported with pin flags "
                         f"on a shear-flexible section")
    return out


def _enters(part: str, field: str, tied: bool, beam: bool) -> bool:
    """True when a parameter field enters one part coefficient of an element."""
    if part == "m_torsion" and not beam:
        return False
    if field.startswith("DIM"):
        return True
    return {"E": part[0] == "k" and (part != "k_torsion" or tied), "RHO": part[0] == "m",
            "A": part in ("k_axial", "m_translation"), "I1": part in ("k_bend1", "m_torsion"),
            "I2": part in ("k_bend2", "m_torsion"), "J": part == "k_torsion"}[field]


def _material(bdf, mid: int, where: str):
    mat = bdf.materials.get(mid)
    if mat is None:
        raise InputError(f"{where}: {undefined_material(bdf, mid)}")
    if mat.type != "MAT1":  # MAT8 or MAT9 (shells', solids')
        raise InputError(f"{where}: material {mat.type} {mid} is not supported here (MAT1 only)")
    for name in ("e", "g", "rho"):
        if getattr(mat, name) is not None:
            in_range(getattr(mat, name), f"MAT1 {mid}: {name.upper()}")
    rho = mat.rho or 0.0
    if rho < 0:
        raise InputError(f"MAT1 {mid}: negative density RHO = {rho:g}")
    if not (mat.e and mat.e > 0):
        raise InputError(f"MAT1 {mid}: E must be > 0 for a bar or rod, got {mat.e}")
    g = mat.g if mat.g is not None else 0.0
    return mat, rho, g, tied_shear_modulus(mat)

