"""Scalar springs and masses (CELAS1-4, CMASS1-4), CONM1, CONM2 and CBUSH of a deck."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse import csgraph

from eigenupdate.errors import InputError
from eigenupdate.io.nastran_fields import FIELDS, in_range, pbush_k
from eigenupdate.io.numbers import eigenvalues_with_slack, printed_half_unit
from eigenupdate.model import frame3d, point_elements


def assemble_scalars(bdf, point, wtmass, pindex, values, k0, m0, kj, mj) -> None:
    """CELAS1-4 and CMASS1-4: a scalar between two components or scalar points (or to
    ground)."""
    def put(trip, dofs, value):
        if len(dofs) == 1:
            trip.add(dofs, dofs, [value])
        else:
            a, b = dofs
            trip.add([a, a, b, b], [a, b, a, b], [value, -value, -value, value])

    def dofs_of(e, label):
        out = []
        for n, c in zip(e.nodes, (getattr(e, "c1", None), getattr(e, "c2", None)),
                        strict=True):
            if n in (None, 0):
                continue
            out.append(point(n, label, c))
        if not out or (len(out) == 2 and out[0] == out[1]):
            raise InputError(f"{label}: needs one or two different grid components")
        return out

    # (cards, with a property, property card, direct card, field, K or M, unit scale)
    masses: list = []  # (rows, value, scale, label) of every scalar mass
    kinds = ((bdf.elements, ("CELAS1", "CELAS3"), bdf.properties, "PELAS", ("CELAS2", "CELAS4"),
              "K", k0, kj, 1.0),
             (bdf.masses, ("CMASS1", "CMASS3"), bdf.properties_mass, "PMASS",
              ("CMASS2", "CMASS4"), "M", m0, mj, wtmass))
    for cards, with_prop, props, prop_card, direct, fld, dest0, dests, scale in kinds:
        for eid, e in sorted(cards.items()):
            label = f"{e.type} {eid}"
            if e.type in with_prop:
                p = props.get(e.pid)
                if p is None or p.type != prop_card:
                    raise InputError(f"{label}: property {prop_card} {e.pid} is not defined")
                value = getattr(p, FIELDS[prop_card][fld])
                j = pindex.get((prop_card, p.pid), {}).get(fld)
            elif e.type in direct:
                value = getattr(e, FIELDS[e.type][fld])
                j = pindex.get((e.type, eid), {}).get(fld)
            else:
                continue
            value = in_range(value, f"{label}: {fld}")
            dofs = dofs_of(e, label)
            if fld == "M":
                if value < 0 and len(dofs) == 1:
                    raise InputError(f"{label}: negative mass {value:g}")
                masses.append((dofs, value, scale, label))
            if j is None:
                put(dest0, dofs, scale * value)
            else:
                put(dests[j], dofs, scale)
    _check_coupling_masses(masses)


def _check_coupling_masses(masses: list) -> None:
    """A negative scalar mass between two coordinates (NASTRAN's M is any real number: a
    pair of grounded masses and a negative coupling one write a lumped mass matrix with an
    off-diagonal term) is accepted where the scalar masses on the coordinates it joins stay
    positive semi-definite, to within the rounding of their printed values; the other
    elements' masses are semi-definite and can only add to them."""
    if not any(value < 0 for _, value, _, _ in masses):
        return
    rows = sorted({d for dofs, *_ in masses for d in dofs})
    at = {r: i for i, r in enumerate(rows)}
    pairs = np.array([[at[d[0]], at[d[-1]]] for d, *_ in masses]).T
    graph = sp.coo_array((np.ones(pairs.shape[1]), (pairs[0], pairs[1])),
                         shape=(len(rows), len(rows)))
    _, part = csgraph.connected_components(graph, directed=False)
    for group in {int(part[at[d[0]]]) for d, value, *_ in masses if value < 0}:
        mine = [x for x in masses if part[at[x[0][0]]] == group]
        first = next(label for _, value, _, label in mine if value < 0)
        local = {r: i for i, r in enumerate(sorted({d for dofs, *_ in mine for d in dofs}))}
        if len(local) > 2000:
            raise InputError(f"{first}: a negative coupling mass among {len(local)} coordinates "
                             f"joined by scalar masses, too many to check it leaves their mass "
                             f"positive semi-definite")
        m, half = np.zeros((len(local),) * 2), np.zeros((len(local),) * 2)
        for dofs, value, scale, _ in mine:
            idx = [local[d] for d in dofs]
            sign = np.array([[1.0, -1.0], [-1.0, 1.0]])[:len(idx), :len(idx)]
            m[np.ix_(idx, idx)] += scale * value * sign
            half[np.ix_(idx, idx)] += scale * printed_half_unit(value)
        lam, slack = eigenvalues_with_slack(m, half)
        if lam[0] < -slack:
            raise InputError(f"{first}: negative mass between two coordinates makes the scalar "
                             f"masses on them indefinite (smallest eigenvalue {lam[0]:.4g})")


def _rect_axes(bdf, cid, label: str) -> np.ndarray:
    """Rows: the axes of rectangular system ``cid`` in basic (0: basic)."""
    if not cid:
        return np.eye(3)
    if cid not in bdf.coords:
        raise InputError(f"{label}: coordinate system {cid} is not defined")
    if bdf.coords[cid].Type != "R":
        raise InputError(f"{label}: CID {cid} must be rectangular")
    return bdf.coords[cid].beta()


def assemble_conm1(bdf, grid, frames, wtmass, pindex, m0, mj) -> None:
    """CONM1: a 6 x 6 mass matrix (lower triangle given) at a grid, in system CID."""
    for eid, e in sorted(bdf.masses.items()):
        if e.type != "CONM1":
            continue
        label = f"CONM1 {eid}"
        g = grid(e.nid, label)
        low = np.tril(np.asarray(e.mass_matrix, float))
        full = low + np.tril(low, -1).T
        for x in low.ravel():
            in_range(x, f"{label}: mass matrix entry")
        if np.any(np.linalg.eigvalsh(full) < -1e-12 * max(np.abs(full).max(), 1e-300)):
            raise InputError(f"{label}: mass matrix is not positive semi-definite")
        axes = _rect_axes(bdf, e.cid, label)
        dofs = 6 * g + np.arange(6)
        r, c = np.repeat(dofs, 6), np.tile(dofs, 6)
        slots = pindex.get(("CONM1", eid), {})
        base = full.copy()
        for name, j in slots.items():
            i1, i2 = int(name[1]) - 1, int(name[2]) - 1
            unit = np.zeros((6, 6))
            unit[i1, i2] = unit[i2, i1] = 1.0
            base -= full[i1, i2] * unit
            mj[j].add(r, c, wtmass * point_elements.mass_in_system(unit, axes, frames[g]))
        m0.add(r, c, wtmass * point_elements.mass_in_system(base, axes, frames[g]))


def assemble_cbush(bdf, grid, xyz, frames, pindex, k0, kj) -> None:
    """CBUSH + PBUSH: six springs K1-K6 in the element axes at the point a fraction S
    from GA to GB, rigidly linked to both grids (grounded when GB is blank). Axes: the
    CID system, else x from GA to GB and the orientation vector (X or G0) as CBAR."""
    for eid, e in sorted(bdf.elements.items()):
        if e.type != "CBUSH":
            continue
        label = f"CBUSH {eid}"
        p = bdf.properties.get(e.pid)
        if p is None or p.type != "PBUSH":
            raise InputError(f"{label}: property PBUSH {e.pid} is not defined")
        if e.ocid not in (None, -1):
            raise InputError(f"{label}: OCID {e.ocid} (spring offsets) is not supported")
        if getattr(p, "mass", None):
            raise InputError(f"PBUSH {p.pid}: mass M is not supported")
        a = grid(e.nodes[0], label)
        b = None if e.nodes[1] in (None, 0) else grid(e.nodes[1], label)
        xa = xyz[a]
        xb = xa if b is None else xyz[b]
        if e.cid is not None and e.cid >= 0:
            axes = _rect_axes(bdf, e.cid, label)
        else:
            if b is None or np.linalg.norm(xb - xa) <= 1e-12 * max(np.abs(xa).max(), 1.0):
                raise InputError(f"{label}: coincident or grounded grids need a CID")
            v = (xyz[grid(e.g0, label)] - xa if e.g0 is not None
                 else frames[a].T @ np.asarray(e.x, float))
            _, rot = frame3d.local_axes(xa[None], xb[None], v[None], [label])
            axes = rot[0]
        s = 0.5 if e.s is None else float(e.s)
        point = xa + s * (xb - xa)
        cols = [(a, -1.0)] + ([] if b is None else [(b, 1.0)])
        d = point_elements.bush_deformation(axes, point,
                                            [(xyz[g], frames[g], sign) for g, sign in cols])
        dofs = np.concatenate([6 * g + np.arange(6) for g, _ in cols])
        r, c = np.repeat(dofs, dofs.size), np.tile(dofs, dofs.size)
        k = np.array([in_range(x, f"PBUSH {p.pid}: K{i + 1}") for i, x in enumerate(pbush_k(p))])
        if np.any(k < 0):
            raise InputError(f"PBUSH {p.pid}: stiffness K1-K6 must be >= 0")
        slots = pindex.get(("PBUSH", p.pid), {})
        param = {int(name[1]) - 1: j for name, j in slots.items()}
        base = sum(k[i] * np.outer(d[i], d[i]) for i in range(6) if i not in param)
        if np.ndim(base):
            k0.add(r, c, base)
        for i, j in param.items():
            kj[j].add(r, c, np.outer(d[i], d[i]))


def assemble_conm2(bdf, grid, xyz, frames, wtmass, pindex, values, m0, mj) -> None:
    for eid, e in sorted(bdf.masses.items()):
        if e.type != "CONM2":
            continue
        label = f"CONM2 {eid}"
        g = grid(e.nid, label)
        for x in (e.mass, *e.I):
            in_range(x, f"{label}: mass or inertia")
        if e.mass < 0:
            raise InputError(f"{label}: negative mass {e.mass:g}")
        if e.cid == -1:
            offset, rot = np.asarray(e.X, float) - xyz[g], np.eye(3)
        else:
            if e.cid not in bdf.coords:
                raise InputError(f"{label}: coordinate system {e.cid} is not defined")
            rot = bdf.coords[e.cid].beta() if e.cid else np.eye(3)
            if e.cid and bdf.coords[e.cid].Type != "R":
                raise InputError(f"{label}: CID {e.cid} must be rectangular")
            offset = rot.T @ np.asarray(e.X, float)
        i = e.I
        inertia = np.array([[i[0], -i[1], -i[3]], [-i[1], i[2], -i[4]], [-i[3], -i[4], i[5]]])
        if np.any(np.linalg.eigvalsh(inertia) < -1e-12 * max(abs(inertia).max(), 1e-300)):
            raise InputError(f"{label}: inertia matrix is not positive semi-definite")
        unit, rotary = point_elements.point_mass(offset, rot.T @ inertia @ rot, frames[g])
        dofs = 6 * g + np.arange(6)
        r, c = np.repeat(dofs, 6), np.tile(dofs, 6)
        j = pindex.get(("CONM2", eid), {}).get("M")
        trans = wtmass * unit
        m0.add(r, c, wtmass * rotary + (0.0 if j is not None else e.mass * trans))
        if j is not None:
            mj[j].add(r, c, trans)
