"""Rigid elements (RBE1, RBE2, RBAR, RROD, RBE3, NASTRAN-95's CRIGD1/2/3/R) and MPCs of a
deck as constraint equations for :mod:`eigenupdate.model.constraints`."""

from __future__ import annotations

import numpy as np

from eigenupdate.errors import InputError
from eigenupdate.io.nastran_deck import case_value, modal_subcases
from eigenupdate.io.nastran_rejected import card_fields, card_name
from eigenupdate.model import constraints


def _ints(fields: list[str], label: str) -> list[int]:
    try:
        return [int(x) for x in fields]
    except ValueError:
        raise InputError(f"{label}: only integer grid ids and components are read "
                         f"(no THRU), got {' '.join(fields)}") from None


def constraint_equations(bdf, grid, point, xyz, frames) -> list:
    """(dependent row, [(row, coefficient)], card label) of every rigid element and the
    MPC set case control selects; ``point(id, label, component)`` is the row of a GRID's
    component or of a scalar point (component 0 or blank), which an MPC may name."""
    eqs = []

    def rigid(label, indep, dep):
        gi = [(grid(n, label), int(c)) for n, c in indep]
        gd = [(grid(n, label), int(c)) for n, c in dep]
        both = sorted(set(indep) & set(dep))
        if both:
            raise InputError(f"{label}: GRID {both[0][0]} component {both[0][1]} is both "
                             f"independent and dependent")
        for (g, c), terms in constraints.rigid_equations(xyz, frames, gi, gd, label):
            eqs.append((6 * g + c - 1, [(6 * a + b - 1, v) for (a, b), v in terms], label))

    def comps(text):
        return [int(x) for x in str(text or "") if x != "0"]

    def rod(label, gi, gd, cd):
        # a rigid rod (CRIGDR, RROD): GD's translation CD keeps the length along the rod
        a, b = grid(gi, label), grid(gd, label)
        axis = xyz[b] - xyz[a]
        if not np.linalg.norm(axis) > 0:
            raise InputError(f"{label}: GRID {gi} and GRID {gd} coincide (the rod has no "
                             f"direction)")
        axis = axis / np.linalg.norm(axis)
        ea, eb = frames[a] @ axis, frames[b] @ axis  # axis in each grid's CD
        if abs(eb[cd - 1]) < 1e-8:
            raise InputError(f"{label}: component {cd} of GRID {gd} is normal to the rod")
        terms = [(6 * a + k, float(ea[k] / eb[cd - 1])) for k in range(3)]
        terms += [(6 * b + k, float(-eb[k] / eb[cd - 1])) for k in range(3) if k != cd - 1]
        eqs.append((6 * b + cd - 1, terms, label))

    for eid, e in sorted(bdf.rigid_elements.items()):
        label = f"{e.type} {eid}"
        if e.type == "RBE2":
            indep = [(e.gn, c) for c in range(1, 7)]
            rigid(label, indep, [(m, c) for m in e.Gmi for c in comps(e.cm)])
        elif e.type == "RBE1":  # MSC's CRIGD3: six independent components on any grids
            rigid(label, [(g, c) for g, cs in zip(e.Gni, e.Cni, strict=True) for c in comps(cs)],
                  [(g, c) for g, cs in zip(e.Gmi, e.Cmi, strict=True) for c in comps(cs)])
        elif e.type == "RROD":  # the one dependent translation at GA (CMA) or GB (CMB)
            ga, gb = e.nodes
            cma, cmb = comps(e.cma), comps(e.cmb)
            if len(cma) + len(cmb) != 1 or max(cma + cmb) > 3:
                raise InputError(f"{label}: CMA, CMB must name one translational component "
                                 f"(1, 2 or 3) at one end, got CMA {e.cma or 'blank'}, CMB "
                                 f"{e.cmb or 'blank'} (the Lagrange-multiplier form with "
                                 f"both blank is not supported)")
            if cma:
                rod(label, gb, ga, cma[0])
            else:
                rod(label, ga, gb, cmb[0])
        elif e.type == "RBAR":
            indep = [(e.ga, c) for c in comps(e.cna)] + [(e.gb, c) for c in comps(e.cnb)]
            dep = [(e.ga, c) for c in comps(e.cma)] + [(e.gb, c) for c in comps(e.cmb)]
            if not dep:  # blank CMA, CMB: the components not independent
                dep = [(g, c) for g in (e.ga, e.gb) for c in range(1, 7)
                       if (g, c) not in indep]
            rigid(label, indep, dep)
        elif e.type == "RBE3":
            if e.Gmi:
                raise InputError(f"{label}: UM (other dependent components) is not supported")
            indep = [(grid(g, label), c, float(w)) for w, cs, gs in
                     zip(e.weights, e.comps, e.Gijs, strict=True) for g in gs
                     for c in comps(cs)]
            for (g, c), terms in constraints.interpolation_equations(
                    xyz, frames, grid(e.refgrid, label), comps(e.refc), indep, label):
                eqs.append((6 * g + c - 1, [(6 * a + b - 1, v) for (a, b), v in terms],
                            label))
        else:
            raise InputError(f"{label}: rigid element {e.type} is not supported")
    for card in getattr(bdf, "reject_lines", []):
        lines = [x for x in card if x.strip() and not x.startswith("$")]
        name = card_name(lines[0])
        f = card_fields(lines)
        label = f"{name} {f[0]}"
        if name in ("CRIGD1", "CRIGD2", "CRIGD3", "CRIGDR"):
            f = [x for x in f[1:] if x]
        if name == "CRIGD1":  # GI, then dependent grids: all six components
            ids = _ints(f, label)
            rigid(label, [(ids[0], c) for c in range(1, 7)],
                  [(g, c) for g in ids[1:] for c in range(1, 7)])
        elif name == "CRIGD2":  # GI, then pairs (GD, CD)
            ids = _ints(f, label)
            rigid(label, [(ids[0], c) for c in range(1, 7)],
                  [(g, c) for g, cd in zip(ids[1::2], ids[2::2], strict=True)
                   for c in comps(cd)])
        elif name == "CRIGD3":  # pairs (GI, CI) up to MSET, then pairs (GD, CD)
            if "MSET" not in [x.upper() for x in f]:
                raise InputError(f"{label}: no MSET field")
            k = [x.upper() for x in f].index("MSET")
            ind, dep = _ints(f[:k], label), _ints(f[k + 1:], label)
            rigid(label, [(g, c) for g, ci in zip(ind[::2], ind[1::2], strict=True)
                          for c in comps(ci)],
                  [(g, c) for g, cd in zip(dep[::2], dep[1::2], strict=True)
                   for c in comps(cd)])
        elif name == "CRIGDR":  # rigid rod: GD's translation CD keeps the length
            gi, gd, cd = _ints(f[:3], label)
            if cd not in (1, 2, 3):
                raise InputError(f"{label}: CD must be 1, 2 or 3, got {cd}")
            rod(label, gi, gd, cd)
    for card in _mpc_cards(bdf):
        label = f"MPC {card.conid}"
        (n0, *nodes), (c0, *cs), (a0, *coefs) = card.nodes, card.components, card.coefficients
        if not a0:
            raise InputError(f"{label}: the dependent term's coefficient is zero")
        dep = point(n0, label, int(c0 or 0))
        eqs.append((dep, [(point(n, label, int(c or 0)), -float(a) / a0)
                          for n, c, a in zip(nodes, cs, coefs, strict=True)], label))
    return eqs


def _mpc_cards(bdf) -> list:
    """MPC cards of the set case control selects (or the only set)."""
    ids = set(bdf.mpcs) | set(bdf.mpcadds)
    if not ids:
        return []
    wanted = {int(v) for sub in modal_subcases(bdf) if (v := case_value(sub, "MPC")) is not None}
    if len(wanted) > 1:
        raise InputError(f"case control selects several MPC sets {sorted(wanted)} (name "
                         f"its subcase: [model] subcase = N in the study)")
    if not wanted:
        inner = {int(s) for add in bdf.mpcadds.values() for a in add for s in a.sets}
        top = sorted(ids - inner)
        if len(top) > 1:
            raise InputError(f"several MPC sets {top} and no case control MPC = to choose one")
        wanted = set(top)
    out, todo = [], list(wanted)
    while todo:
        sid = todo.pop()
        for add in bdf.mpcadds.get(sid, []):
            todo += [int(s) for s in add.sets]
        out += bdf.mpcs.get(sid, [])
    return out
