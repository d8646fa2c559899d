"""Assembling a NASTRAN deck's K and M, linear in named card fields.

:func:`read_nastran` reads the deck (:mod:`eigenupdate.io.nastran_deck`) and assembles a
:class:`ParametricModel` whose parameters are named card fields (``MAT1 1 E``); the
element matrices are :mod:`eigenupdate.model.frame3d`'s, the Guyan reduction of
ASET/OMIT decks :mod:`eigenupdate.model.reduction`'s. :mod:`eigenupdate.io.nastran_write`
writes the deck back. pyNastran is an optional extra (``pip install eigenupdate[nastran]``).

Coordinates: the displacement ``component`` (1-6) of ``grid`` is coordinate
``10 * grid + component`` of the model, in the grid's displacement frame (CD).
"""

from __future__ import annotations

import math
import re
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import scipy.sparse as sp

from eigenupdate.errors import EigenupdateWarning, InputError
from eigenupdate.io.nastran_deck import Deck, load_deck
from eigenupdate.model import constraints, frame3d, reduction, sections
from eigenupdate.model.coordinates import Coordinate, CoordinateTable
from eigenupdate.model.parameters import Parameter
from eigenupdate.model.parametric import ParametricModel

# card -> field -> (pyNastran attribute, what it scales); the rest are refused with a reason
FIELDS = {
    "MAT1": {"E": "e", "RHO": "rho"},
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
}
NOT_LINEAR = {
    ("MAT1", "NU"): "G = E / (2 (1 + NU)) is not linear in NU",
    ("MAT1", "G"): "give E (G follows it when the card leaves G blank)",
}
# PBARL shapes read: pyNastran's A, I1, I2, J as they are (ROD, TUBE), or with NASTRAN's
# torsion constant (BAR, BOX), or all from model/sections.py (I, T, CHAN)
PBARL_SHAPES = ("ROD", "TUBE", "BAR", "BOX", *sections.THIN_WALLED)


def dof_number(grid: int, component: int) -> int:
    """Model coordinate of a GRID's displacement component (1-6).

    >>> dof_number(1203, 2)
    12032
    """
    return 10 * int(grid) + int(component)


@dataclass(frozen=True)
class CardField:
    """A parameter's place in the bulk data: card type, card id and field name."""

    card: str
    id: int
    field: str


@dataclass
class NastranModel:
    """A BDF read and assembled: the parametric model and what write-back needs."""

    path: Path
    model: ParametricModel
    fields: tuple[CardField, ...]
    consistent_mass: bool
    spc_set: int | None
    restrained: frozenset  # coordinates held by the SPC set or GRID PS
    bdf: Any  # pyNastran BDF, kept to write the file back
    skipped: str = ""  # cards skipped because they change neither K nor M
    dependent: dict = field(default_factory=dict)  # coordinate -> rigid element / MPC
    text: list = field(default_factory=list)  # the deck's lines, INCLUDEs expanded

    def grid_dof(self, grid: int, component: int) -> int:
        """Coordinate of (grid, component); InputError if unknown or restrained."""
        if grid in self.bdf.spoints and grid not in self.bdf.nodes:
            if component not in (0, 1):
                raise InputError(f"scalar point {grid} has component 0 (or 1) only")
            component = 1  # a scalar point's one coordinate is 10 * id + 1
        elif component not in range(1, 7):
            raise InputError(f"component {component} must be 1-6")
        elif grid not in self.bdf.nodes:
            raise InputError(f"GRID {grid} is not defined in {self.path}")
        c = dof_number(grid, component)
        if c in self.dependent:
            raise InputError(f"GRID {grid} component {component} is dependent on "
                             f"{self.dependent[c]} (a rigid element or MPC eliminates it): "
                             f"put the perturbation on an independent grid")
        if c not in self.model.coordinates:
            why = (f"SPC set {self.spc_set} or GRID PS" if c in self.restrained
                   else "it carries neither stiffness nor mass")
            raise InputError(f"GRID {grid} component {component} is restrained ({why})")
        return c


def read_nastran(path: str | Path, parameters: Sequence[tuple[Parameter, CardField]] = ()
                 ) -> NastranModel:
    """Read a BDF and assemble K = K0 + sum s_j K_j, M = M0 + sum s_j M_j.

    Parameters
    ----------
    path : the bulk data file.
    parameters : (parameter, card field) pairs; each parameter's value is taken from its
        card field (``Parameter.value`` is ignored), its name, std and update flag are kept.

    Returns
    -------
    NastranModel
    """
    path = Path(path)
    src = str(path)
    deck = None
    try:
        deck = load_deck(path)
        nm = _assemble(path, deck.bdf, parameters)
    except InputError as exc:
        if exc.source:
            raise
        raise InputError(_located(str(exc), deck), source=src, field=exc.field) from None
    except OverflowError:
        raise InputError("a number in the deck overflows K or M (a value near 1e300?)",
                         source=src) from None
    if deck.skipped:
        warnings.warn(f"{path.name}: skipped (they change neither K nor M): {deck.skipped}",
                      EigenupdateWarning, stacklevel=2)
    nm.skipped = deck.skipped
    nm.text = deck.text
    return nm


_LABEL = re.compile(r"^([A-Z][A-Z0-9]*) (\d+)(:| field)")


def _located(message: str, deck: Deck | None) -> str:
    """Prefix ``file:line:`` of the card a message starts with (``CBAR 1043: ...``)."""
    m = _LABEL.match(message)
    if deck is None or m is None:
        return message
    hit = deck.lines.get((m.group(1), int(m.group(2))))
    if not hit:
        return message
    name, line = hit.rsplit(":", 1)
    return f"{'line ' + line if name == deck.path.name else hit}: {message}"


def _param(bdf, name: str, default):
    p = bdf.params.get(name)
    if p is None:
        return default
    v = p.values[0]
    return v if isinstance(default, str) else float(v)


class _Triplets:
    """COO pieces of one sparse matrix."""

    def __init__(self):
        self.r, self.c, self.v = [], [], []

    def add(self, rows, cols, vals):
        self.r.append(np.ravel(rows))
        self.c.append(np.ravel(cols))
        self.v.append(np.ravel(vals))

    def matrix(self, n: int, keep: np.ndarray | None = None) -> sp.csr_array:
        if not self.v:
            m = sp.csr_array((n, n))
        else:
            m = sp.csr_array((np.concatenate(self.v), (np.concatenate(self.r),
                                                      np.concatenate(self.c))), shape=(n, n))
        m.sum_duplicates()
        return m if keep is None else sp.csr_array(m[keep][:, keep])


def _assemble(path: Path, bdf, specs) -> NastranModel:
    consistent = _param(bdf, "COUPMASS", -1.0) > 0
    wtmass = _param(bdf, "WTMASS", 1.0)
    if not wtmass > 0:
        raise InputError(f"PARAM WTMASS {wtmass} must be > 0")
    if not bdf.nodes and not bdf.spoints:
        raise InputError("no GRID or SPOINT cards")
    try:
        bdf._cross_reference_coordinates()
    except Exception as exc:
        raise InputError(f"coordinate systems: {exc}") from None
    # scalar points take six rows like a grid, of which only the first is used
    grids = np.array(sorted(bdf.nodes), dtype=int)
    spoints = np.array(sorted(set(bdf.spoints) - set(bdf.nodes)), dtype=int)
    clash = sorted(set(bdf.spoints) & set(bdf.nodes))
    if clash:
        raise InputError(f"SPOINT {clash[0]}: is also a GRID")
    nids = np.concatenate([grids, spoints])
    where = {int(n): i for i, n in enumerate(nids)}
    xyz = np.concatenate([_positions(bdf, grids), np.zeros((spoints.size, 3))])
    frames = np.concatenate([_frames(bdf, grids, xyz[:grids.size]),
                             np.tile(np.eye(3), (spoints.size, 1, 1))])
    ndof = 6 * nids.size

    specs = list(specs)
    fields = [f for _, f in specs]
    pindex = _check_fields(bdf, fields)
    k0, m0 = _Triplets(), _Triplets()
    kj = [_Triplets() for _ in specs]
    mj = [_Triplets() for _ in specs]
    values = [_field_value(bdf, f) for f in fields]

    def grid(n, card):
        if n not in where or where[n] >= grids.size:
            what = "a scalar point, not a GRID" if n in where else "referenced but not defined"
            raise InputError(f"{card}: GRID {n} is {what}")
        return where[n]

    def point(n, card, c):
        """Row of a GRID's component c (1-6) or of a scalar point (c 0 or blank)."""
        if n in where and where[n] >= grids.size:
            if c not in (None, 0, 1):
                raise InputError(f"{card}: component {c} of scalar point {n} must be 0 or "
                                 f"blank")
            return 6 * where[n]
        if c not in range(1, 7):
            raise InputError(f"{card}: component {c} must be 1-6 on a GRID")
        return 6 * grid(n, card) + int(c) - 1

    _lines(bdf, where, grid, xyz, frames, consistent, wtmass, pindex, values, k0, m0, kj, mj)
    _scalars(bdf, point, wtmass, pindex, values, k0, m0, kj, mj)
    _conm2(bdf, grid, xyz, frames, wtmass, pindex, values, m0, mj)
    _conm1(bdf, grid, frames, wtmass, pindex, m0, mj)
    _cbush(bdf, grid, xyz, frames, pindex, k0, kj)

    restrained, spc_set = _spc(bdf, where)
    K0, M0 = k0.matrix(ndof), m0.matrix(ndof)
    kt = [t.matrix(ndof) for t in kj]
    mt = [t.matrix(ndof) for t in mj]
    # rigid elements and MPCs: u = T u_i, every matrix reduced to the independent rows
    eqs = _constraint_equations(bdf, grid, xyz, frames)
    labels = np.array(["" for _ in range(ndof)], dtype=object)
    rows_ind = np.arange(ndof)
    if eqs:
        dep = np.array([e[0] for e in eqs])
        er = np.concatenate([np.full(len(e[1]), k) for k, e in enumerate(eqs)])
        ec = np.concatenate([[t[0] for t in e[1]] for e in eqs]).astype(int)
        ev = np.concatenate([[t[1] for t in e[1]] for e in eqs]).astype(float)
        T, rows_ind = constraints.constraint_transform(ndof, dep, er, ec, ev,
                                                       [e[2] for e in eqs])
        labels[dep] = [e[2] for e in eqs]
        held_dep = np.intersect1d(dep, restrained)
        if held_dep.size:
            r = int(held_dep[0])
            raise InputError(f"{labels[r]}: GRID {nids[r // 6]} component {r % 6 + 1} is "
                             f"dependent and also restrained by SPC or PS")
        K0, M0 = T.T @ K0 @ T, T.T @ M0 @ T
        kt = [sp.csr_array(T.T @ a @ T) for a in kt]
        mt = [sp.csr_array(T.T @ a @ T) for a in mt]
        restrained = np.flatnonzero(np.isin(rows_ind, restrained))
    nfree = rows_ind.size
    K, M = sp.csr_array(K0), sp.csr_array(M0)
    for s, a, b in zip(values, kt, mt, strict=True):
        K, M = K + s * a, M + s * b
    # coordinates with neither stiffness nor mass (rod rotations) carry nothing; with
    # PARAM AUTOSPC YES (MSC's and NX's default in normal modes) NASTRAN also constrains
    # those with mass and no stiffness (unconnected grids, rotations of rod-only grids)
    stiff, heavy = np.zeros(nfree, bool), np.zeros(nfree, bool)
    for mat, hit in [(K, stiff), (M, heavy)] + [(t, stiff) for t in kt] + [(t, heavy)
                                                                           for t in mt]:
        coo = mat.tocoo()
        hit[coo.row[coo.data != 0]] = True
    autospc = str(_param(bdf, "AUTOSPC", "YES")).upper() not in ("NO", "N")
    free = stiff if autospc else stiff | heavy
    free[restrained] = False
    keep = np.flatnonzero(free)
    if keep.size == 0:
        raise InputError("every coordinate is restrained or carries neither stiffness nor mass")
    k0m, m0m = (sp.csr_array(sp.csr_array(a)[keep][:, keep]) for a in (K0, M0))
    analysis = _analysis_set(bdf, where, ndof)
    if analysis is not None:
        analysis = analysis[rows_ind]
        if specs:
            raise InputError("ASET/OMIT (Guyan reduction): K and M of the reduced model are "
                             "not linear in the parameters; remove the ASET/OMIT cards to "
                             "update the full model")
        k0m, m0m = reduction.guyan(k0m, m0m, np.flatnonzero(analysis[keep]))
        keep = keep[analysis[keep]]
    coords = (10 * np.repeat(nids, 6) + np.tile(np.arange(1, 7), nids.size))[rows_ind[keep]]
    params = []
    for (p, _), v in zip(specs, values, strict=True):
        params.append(Parameter(p.name, v, p.std, p.update))
    pm = ParametricModel(
        k0m, m0m, tuple(params),
        tuple(None if t.nnz == 0 else sp.csr_array(t[keep][:, keep]) for t in kt),
        tuple(None if t.nnz == 0 else sp.csr_array(t[keep][:, keep]) for t in mt),
        coordinates=coords,
        # coordinate 10 * GRID + component: node = GRID, direction = component (UFF codes)
        coordinate_table=CoordinateTable(tuple(Coordinate(int(c), int(c) // 10, int(c) % 10)
                                               for c in coords)))
    for p, f, a, b in zip(params, fields, pm.k_terms, pm.m_terms, strict=True):
        if a is None and b is None:
            raise InputError(f"{f.card} {f.id} field {f.field} (parameter {p.name!r}) acts on "
                             f"no free coordinate")
    held_rows = rows_ind[restrained]
    held = frozenset((10 * nids[held_rows // 6] + held_rows % 6 + 1).tolist())
    dependent = {int(10 * nids[r // 6] + r % 6 + 1): str(labels[r])
                 for r in np.flatnonzero(labels != "")}
    return NastranModel(path, pm, tuple(fields), consistent, spc_set, held, bdf,
                        dependent=dependent)


def _fields(lines: list[str]) -> list[str]:
    """The fields 2.. of a fixed-format card and its continuations (8-character fields;
    free-field commas too), as NASTRAN-95's cards pyNastran does not read arrive."""
    out = []
    for line in lines:
        if "," in line:
            out += [x.strip() for x in line.split(",")[1:]]
            continue
        body = line[8:72].ljust(64)
        out += [body[i:i + 8].strip() for i in range(0, 64, 8)]
    return out


def _ints(fields: list[str], label: str) -> list[int]:
    try:
        return [int(x) for x in fields]
    except ValueError:
        raise InputError(f"{label}: only integer grid ids and components are read "
                         f"(no THRU), got {' '.join(fields)}") from None


def _constraint_equations(bdf, grid, xyz, frames) -> list:
    """(dependent row, [(row, coefficient)], card label) of every rigid element and the
    MPC set case control selects."""
    eqs = []

    def rigid(label, indep, dep):
        gi = [(grid(n, label), int(c)) for n, c in indep]
        gd = [(grid(n, label), int(c)) for n, c in dep]
        for (g, c), terms in constraints.rigid_equations(xyz, frames, gi, gd, label):
            eqs.append((6 * g + c - 1, [(6 * a + b - 1, v) for (a, b), v in terms], label))

    def comps(text):
        return [int(x) for x in str(text or "") if x != "0"]

    for eid, e in sorted(bdf.rigid_elements.items()):
        label = f"{e.type} {eid}"
        if e.type == "RBE2":
            indep = [(e.gn, c) for c in range(1, 7)]
            rigid(label, indep, [(m, c) for m in e.Gmi for c in comps(e.cm)])
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
        lines = [x for x in card if x.strip()]
        name = lines[0][:8].split(",")[0].strip().upper()
        f = _fields(lines)
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
            a, b = grid(gi, label), grid(gd, label)
            axis = xyz[b] - xyz[a]
            axis = axis / np.linalg.norm(axis)
            ea, eb = frames[a] @ axis, frames[b] @ axis  # axis in each grid's CD
            if abs(eb[cd - 1]) < 1e-8:
                raise InputError(f"{label}: component {cd} of GRID {gd} is normal to the rod")
            terms = [(6 * a + k, float(ea[k] / eb[cd - 1])) for k in range(3)]
            terms += [(6 * b + k, float(-eb[k] / eb[cd - 1])) for k in range(3) if k != cd - 1]
            eqs.append((6 * b + cd - 1, terms, label))
    for card in _mpc_cards(bdf):
        label = f"MPC {card.conid}"
        (n0, *nodes), (c0, *cs), (a0, *coefs) = card.nodes, card.components, card.coefficients
        if not a0:
            raise InputError(f"{label}: the dependent term's coefficient is zero")
        dep = 6 * grid(n0, label) + int(c0) - 1
        eqs.append((dep, [(6 * grid(n, label) + int(c) - 1, -float(a) / a0)
                          for n, c, a in zip(nodes, cs, coefs, strict=True)], label))
    return eqs


def _mpc_cards(bdf) -> list:
    """MPC cards of the set case control selects (or the only set)."""
    ids = set(bdf.mpcs) | set(bdf.mpcadds)
    if not ids:
        return []
    wanted = set()
    cc = bdf.case_control_deck
    if cc is not None:
        for sub in cc.subcases.values():
            try:
                wanted.add(int(sub.get_parameter("MPC")[0]))
            except KeyError:
                pass
    if len(wanted) > 1:
        raise InputError(f"case control selects several MPC sets {sorted(wanted)}")
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


def _set_rows(cards, where, label: str) -> list[int]:
    """Rows of ASET/ASET1/OMIT/OMIT1/SUPORT cards (GRID id, components)."""
    rows = []
    for card in cards:
        ids = getattr(card, "ids", None) or getattr(card, "nodes", [])
        comps = getattr(card, "components", None) or getattr(card, "Cs", None)
        comps = [comps] * len(ids) if isinstance(comps, str) else comps
        for n, c in zip(ids, comps, strict=True):
            if n not in where:
                raise InputError(f"{label}: GRID {n} is referenced but not defined")
            rows += [6 * where[n] + int(x) - 1 for x in str(c) if x != "0"]
    return rows


def _analysis_set(bdf, where, ndof: int) -> np.ndarray | None:
    """Mask of NASTRAN's a-set when ASET or OMIT cards ask for a Guyan reduction: the
    ASET coordinates (with the SUPORT ones), or all but the OMIT ones."""
    asets, omits = list(bdf.asets), list(bdf.omits)
    if not asets and not omits:
        return None
    if asets and omits:
        raise InputError("both ASET and OMIT cards: give one of them")
    if asets:
        mask = np.zeros(ndof, bool)
        mask[_set_rows(asets, where, "ASET")] = True
        mask[_set_rows(bdf.suport, where, "SUPORT")] = True
    else:
        mask = np.ones(ndof, bool)
        mask[_set_rows(omits, where, "OMIT")] = False
    return mask


def _positions(bdf, nids: np.ndarray) -> np.ndarray:
    out = np.empty((nids.size, 3))
    for i, n in enumerate(nids):
        g = bdf.nodes[int(n)]
        if g.cp == 0:
            out[i] = g.xyz
        else:
            if g.cp not in bdf.coords:
                raise InputError(f"GRID {n}: coordinate system CP {g.cp} is not defined")
            out[i] = bdf.coords[g.cp].transform_node_to_global(np.asarray(g.xyz, float))
        if not np.all(np.isfinite(out[i])) or np.abs(out[i]).max() > 1e100:
            raise InputError(f"GRID {n}: coordinates {list(map(float, g.xyz))} are not finite "
                             f"numbers (of magnitude below 1e100)")
    return out


def _frames(bdf, nids: np.ndarray, xyz: np.ndarray) -> np.ndarray:
    """Rows = displacement axes (CD) of each grid in basic; in a cylindrical (spherical)
    system they are the local r, theta, z (R, theta, phi) directions at the grid."""
    out = np.tile(np.eye(3), (nids.size, 1, 1))
    for i, n in enumerate(nids):
        g = bdf.nodes[int(n)]
        if g.cd in (0, None):
            continue
        if g.cd not in bdf.coords:
            raise InputError(f"GRID {n}: coordinate system CD {g.cd} is not defined")
        c = bdf.coords[g.cd]
        beta = c.beta()
        if c.Type == "R":
            out[i] = beta
            continue
        x, y, z = (xyz[i] - np.asarray(c.origin, float)) @ beta.T  # in the system's axes
        r = math.hypot(x, y)
        if r <= 1e-12 * max(abs(z), 1.0):
            raise InputError(f"GRID {n}: lies on the axis of displacement system CD {g.cd} "
                             f"({c.type}), where its directions are undefined")
        cp, sp_ = x / r, y / r
        if c.Type == "C":
            axes = np.array([[cp, sp_, 0.0], [-sp_, cp, 0.0], [0.0, 0.0, 1.0]])
        else:  # spherical: R, theta from the z axis, phi about it
            rho = math.hypot(r, z)
            st, ct = r / rho, z / rho
            axes = np.array([[st * cp, st * sp_, ct], [ct * cp, ct * sp_, -st],
                             [-sp_, cp, 0.0]])
        out[i] = axes @ beta
    return out


def _check_fields(bdf, fields: list[CardField]) -> dict:
    """{(card, id): {field: parameter index}} after validating every field."""
    out: dict = {}
    stores = _stores(bdf)
    for j, f in enumerate(fields):
        if (f.card, f.field) in NOT_LINEAR:
            raise InputError(f"{f.card} {f.id} field {f.field}: not a parameter: "
                             f"{NOT_LINEAR[(f.card, f.field)]}")
        if f.card in ("PBARL", "PBEAML") and f.field.startswith("DIM"):
            raise InputError(f"{f.card} {f.id} field {f.field}: not a parameter: A, I and J are "
                             f"not linear in the section's dimensions (MAT1 E and RHO are)")
        if f.card not in FIELDS:
            have = ", ".join(f"{c} {'/'.join(v)}" for c, v in FIELDS.items())
            raise InputError(f"card {f.card} has no parameter fields (supported: {have})")
        if f.field not in FIELDS[f.card]:
            raise InputError(f"{f.card} {f.id}: field {f.field!r} is not a parameter; K and M "
                             f"are linear in {sorted(FIELDS[f.card])} only")
        card = stores[f.card].get(f.id)
        if card is None or card.type != f.card:
            raise InputError(f"{f.card} {f.id} is not in the file")
        slot = out.setdefault((f.card, f.id), {})
        if f.field in slot:
            raise InputError(f"{f.card} {f.id} field {f.field} is named by two parameters")
        slot[f.field] = j
    return out


def _stores(bdf) -> dict:
    return {"MAT1": bdf.materials, "PBAR": bdf.properties, "PBEAM": bdf.properties,
            "PROD": bdf.properties,
            "PELAS": bdf.properties, "CELAS2": bdf.elements, "CELAS4": bdf.elements,
            "CMASS4": bdf.masses, "CONM2": bdf.masses, "CONM1": bdf.masses,
            "PBUSH": bdf.properties,
            "CMASS2": bdf.masses, "PMASS": bdf.properties_mass}


def _field_value(bdf, f: CardField) -> float:
    card = _stores(bdf)[f.card][f.id]
    v = get_field(card, FIELDS[f.card][f.field])
    if not v >= 0:
        raise InputError(f"{f.card} {f.id} field {f.field} = {v:g} is negative (a parameter "
                         f"must be >= 0)")
    return v


def get_field(card, spec) -> float:
    """A card's field value: ``spec`` is pyNastran's attribute, or (attribute, index)."""
    if isinstance(spec, str):
        return float(np.ravel(getattr(card, spec))[0])
    attr, index = spec
    if attr == "_k":
        return float(_pbush_k(card)[index])
    return float(np.asarray(getattr(card, attr))[index])


def set_field(card, spec, value: float) -> None:
    """Put ``value`` in a card's field (:func:`get_field`'s ``spec``)."""
    if isinstance(spec, str):
        old = getattr(card, spec)
        setattr(card, spec, np.full_like(old, value) if isinstance(old, np.ndarray) else value)
    elif spec[0] == "_k":
        ki = list(card.Ki) + [None] * (6 - len(card.Ki))
        ki[spec[1]] = value
        card.Ki = ki
    else:
        getattr(card, spec[0])[spec[1]] = value


def _pbush_k(card) -> np.ndarray:
    """PBUSH K1-K6 (blank = 0)."""
    k = np.zeros(6)
    for i, v in enumerate(getattr(card, "Ki", None) or []):
        k[i] = v or 0.0
    return k


def _material(bdf, mid: int, where: str):
    mat = bdf.materials.get(mid)
    if mat is None or mat.type != "MAT1":
        raise InputError(f"{where}: material MAT1 {mid} is not defined")
    rho = mat.rho or 0.0
    if rho < 0:
        raise InputError(f"MAT1 {mid}: negative density RHO = {rho:g}")
    if not (mat.e and mat.e > 0):
        raise InputError(f"MAT1 {mid}: E must be > 0 for a bar or rod, got {mat.e}")
    g = mat.g if mat.g is not None else 0.0
    return mat, rho, g, _tied(mat)


def _tied(mat) -> bool:
    """True when MAT1's G was left blank: pyNastran filled in E / (2 (1 + NU)), so G
    follows E."""
    g = mat.g or 0.0
    return mat.nu is not None and g > 0 and math.isclose(g, mat.e / (2 * (1 + mat.nu)),
                                                         rel_tol=1e-12)


def _lines(bdf, where, grid, xyz, frames, consistent, wtmass, pindex, values,
           k0, m0, kj, mj) -> None:
    """CBAR, CROD and CONROD, vectorised over elements."""
    sections: dict = {}  # validated once per property (or CONROD)

    def section(key, make, where_):
        if key not in sections:
            A, i1, i2, j, nsm, mid, pkey, *shear = make()
            for name, x in (("A", A), ("I1", i1), ("I2", i2), ("J", j), ("NSM", nsm)):
                if x is None or not math.isfinite(x) or x < 0:
                    raise InputError(f"{pkey[0] + ' ' + str(pkey[1]) if pkey else where_}: "
                                     f"{name} = {x} must be >= 0")
            mat, rho, g, tied = _material(bdf, mid, where_)
            k1, k2 = shear or (0.0, 0.0)
            if (k1 or k2) and not g > 0:
                raise InputError(f"{where_}: shear factors K1, K2 need MAT1 {mid} G > 0")
            sections[key] = (mat.e, g, tied, rho, float(A), float(i1), float(i2),
                             float(j or 0.0), float(nsm or 0.0), mid, pkey, k1, k2)
        return sections[key]

    label, rod, ga, gb, g0, xv, wa, wb, sec = [], [], [], [], [], [], [], [], []
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
            if str(e.offt) not in ("GGG", "1"):  # NASTRAN-95's F = 1: X is a vector, as GGG
                raise InputError(f"{lab}: OFFT {e.offt} is not supported (only GGG)")
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
            if not consistent and (np.any(e.wa) or np.any(e.wb)):
                # lumped end masses on rigid offsets give a singular, non-diagonal M
                raise InputError(f"{lab}: offsets WA/WB need consistent mass "
                                 f"(PARAM,COUPMASS,1) here")
            wa.append(e.wa)
            wb.append(e.wb)
            sec.append(section((prop.type, e.pid), lambda p=prop: (
                _pbarl_section(p) if p.type in ("PBARL", "PBEAML") else _bar_section(p)),
                lab))
        elif e.type in ("CROD", "CONROD"):
            if e.type == "CROD":
                prop = bdf.properties.get(e.pid)
                if prop is None or prop.type != "PROD":
                    raise InputError(f"{lab}: property PROD {e.pid} is not defined")
                sec.append(section(("PROD", e.pid), lambda p=prop: (
                    p.A, 0.0, 0.0, p.j, p.nsm, p.mid, ("PROD", p.pid), 0.0, 0.0), lab))
            else:
                sec.append(section(("CONROD", eid), lambda e=e: (
                    e.A, 0.0, 0.0, e.j, e.nsm, e.mid, None, 0.0, 0.0), lab))
            a, b = grid(e.nodes[0], lab), grid(e.nodes[1], lab)
            g0.append(-1)
            xv.append(zero)
            wa.append(zero)
            wb.append(zero)
        else:
            continue
        pins.append(pin if e.type in ("CBAR", "CBEAM") else np.zeros(12, bool))
        label.append(lab)
        rod.append(e.type in ("CROD", "CONROD"))
        ga.append(a)
        gb.append(b)
    if not label:
        return
    rod, ga, gb, g0 = np.array(rod), np.array(ga), np.array(gb), np.array(g0)
    # orientation vector and offsets are given in GA's (GB's) displacement system
    to_basic = np.transpose(frames, (0, 2, 1))
    wa = np.einsum("nij,nj->ni", to_basic[ga], np.array(wa, float))
    wb = np.einsum("nij,nj->ni", to_basic[gb], np.array(wb, float))
    xa, xb = xyz[ga] + wa, xyz[gb] + wb
    v = np.einsum("nij,nj->ni", to_basic[ga], np.array(xv, float))
    by_g0 = g0 >= 0
    v[by_g0] = xyz[g0[by_g0]] - xyz[ga[by_g0]]
    v[rod] = frame3d.any_normal((xb - xa)[rod])
    rows = sec  # per element: E, G, tied, rho, A, I1, I2, J, nsm, mid, pkey, K1, K2
    L, R = frame3d.local_axes(xa, xb, v, label)
    T = frame3d.element_transform(R, wa, wb, frames[ga], frames[gb])
    E, G, rho = (np.array([r[k] for r in rows], float) for k in (0, 1, 3))
    tied = np.array([r[2] for r in rows])
    A, I1, I2, J, nsm = (np.array([r[k] for r in rows], float) for k in range(4, 9))
    K1, K2 = (np.array([r[k] for r in rows], float) for k in (11, 12))
    beam = np.array([lab.startswith("CBEAM") for lab in label])
    # Timoshenko shear parameters; K = 0 (or PBAR's blank) is a shear-rigid section
    with np.errstate(divide="ignore", invalid="ignore"):
        phi1 = np.where(K1 > 0, 12 * E * I1 / (K1 * A * G * L**2), 0.0)
        phi2 = np.where(K2 > 0, 12 * E * I2 / (K2 * A * G * L**2), 0.0)
    bad = np.flatnonzero(~(np.isfinite(phi1) & np.isfinite(phi2)))
    if bad.size:
        raise InputError(f"{label[bad[0]]}: shear factors K1/K2 need A > 0 and G > 0")
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
    dofs = (6 * np.stack([ga, gb], 1)[:, :, None] + np.arange(6)[None, None, :]).reshape(-1, 12)
    r_idx = np.repeat(dofs, 12, axis=1)
    c_idx = np.tile(dofs, (1, 12))
    # section quantities and the parameters that scale each (one at most per element)
    total = {"k_axial": E * A, "k_torsion": G * J, "k_bend1": E * I1, "k_bend2": E * I2,
             "m_translation": wtmass * (rho * A + nsm),
             "m_torsion": np.where(beam, wtmass * rho * (I1 + I2), 0.0)}
    n = len(rows)
    deriv: list[dict[str, np.ndarray]] = [{} for _ in kj]

    def d(j, part, coef, mask):
        arr = deriv[j].setdefault(part, np.zeros(n))
        arr[mask] += coef[mask] if np.ndim(coef) else coef

    mids = np.array([r[9] for r in rows])
    pkeys = [r[10] for r in rows]
    shear = (phi1 != 0) | (phi2 != 0)

    def linear_only(mask, fld, card, cid, planes):
        hit = np.flatnonzero(mask & planes)
        if hit.size:
            raise InputError(f"{card} {cid} field {fld}: not a parameter of the shear-flexible "
                             f"{label[hit[0]]} (K1/K2 make K not linear in it; E with G "
                             f"blank and RHO are)")

    for (card, cid), slots in pindex.items():
        if card == "MAT1":
            mask = mids == cid
            if "E" in slots:
                linear_only(mask, "E", card, cid, shear & ~tied)
                j = slots["E"]
                for part, c in (("k_axial", A), ("k_bend1", I1), ("k_bend2", I2)):
                    d(j, part, c, mask)
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
                    linear_only(mask, fld, card, cid, planes[fld])
                    for part, c in parts_:
                        d(slots[fld], part, c, mask)
    _one_parameter_per_quantity(deriv, label, kj)
    base = {part: tot - sum((values[j] * dj[part] for j, dj in enumerate(deriv) if part in dj),
                            np.zeros(n)) for part, tot in total.items()}

    def put(dest, coefs: dict[str, np.ndarray]) -> None:
        # sum the local parts first: one transformation and one COO block per element
        sel = np.flatnonzero(np.any([c != 0 for c in coefs.values()], axis=0))
        if sel.size:
            local = sum(c[sel, None, None] * parts[p][sel] for p, c in coefs.items())
            dest.add(r_idx[sel], c_idx[sel], frame3d.to_global(local, T[sel]))

    for kind, dest0, dests in (("k", k0, kj), ("m", m0, mj)):
        put(dest0, {p: c for p, c in base.items() if p[0] == kind})
        for j, dj in enumerate(deriv):
            if any(p[0] == kind for p in dj):
                put(dests[j], {p: c for p, c in dj.items() if p[0] == kind})


def _bar_section(prop) -> tuple:
    """(A, I1, I2, J, NSM, MID, (card, id), K1, K2) of a PBAR or a constant-section
    PBEAM; K = 0 means no shear flexibility (PBAR's blank, PBEAM's 0.0)."""
    where = f"{prop.type} {prop.pid}"
    k1, k2 = prop.k1 or 0.0, prop.k2 or 0.0
    if prop.type == "PBAR" and k1 >= 1e8:  # pyNastran's stand-in for a blank K1
        k1 = 0.0
    if prop.type == "PBAR" and k2 >= 1e8:
        k2 = 0.0
    if k1 < 0 or k2 < 0:
        raise InputError(f"{where}: shear factors K1 = {k1:g}, K2 = {k2:g} must be >= 0")
    if prop.type == "PBEAM":
        for name in ("A", "i1", "i2", "i12", "j", "nsm"):
            if np.ptp(np.asarray(getattr(prop, name), float)) != 0:
                raise InputError(f"{where}: {name.upper()} varies along the beam; only a "
                                 f"constant section is supported")
        extra = [n for n in ("s1", "s2", "nsia", "nsib", "cwa", "cwb", "m1a", "m2a", "m1b",
                             "m2b", "n1a", "n2a", "n1b", "n2b") if getattr(prop, n)]
        if extra:
            raise InputError(f"{where}: {', '.join(x.upper() for x in extra)} (warping, "
                             f"offsets of the mass or neutral axis) are not supported")
    first = [float(np.ravel(getattr(prop, n))[0]) for n in ("A", "i1", "i2", "i12", "j", "nsm")]
    A, i1, i2, i12, j, nsm = first
    if i12:
        raise InputError(f"{where}: I12 = {i12:g} is not supported")
    return A, i1, i2, j, nsm, prop.mid, (prop.type, prop.pid), k1, k2


# shear factors NASTRAN gives the PBARL/PBEAML sections: circle 0.9 (NASTRAN's
# documentation; Simcenter's frequencies of the shared pyn_beam_modes deck agree to 1e-7,
# NASTRAN_CoFE's 0.85716 would be 0.96 % off), solid rectangle 5/6 (NASTRAN_CoFE's PBEAML)
SHEAR_FACTORS = {"BAR": (5.0 / 6.0, 5.0 / 6.0), "ROD": (0.9, 0.9)}


def _pbarl_section(prop) -> tuple:
    """(A, I1, I2, J, NSM, MID, (card, id), K1, K2) of a standard PBARL or a constant
    PBEAML section: the equivalent PBAR's (PBEAM's) values (the shear centre is taken
    at the centroid)."""
    where = f"{prop.type} {prop.pid}"
    shape = prop.Type
    if prop.group.strip() != "MSCBML0":
        raise InputError(f"{where}: GROUP {prop.group} (a user section library) is not "
                         f"supported; only the standard sections of MSCBML0")
    if shape not in PBARL_SHAPES:
        why = " (unsymmetric: I12 != 0, as PBAR I12)" if shape == "L" else ""
        raise InputError(f"{where}: section type {shape}{why} is not supported (supported: "
                         f"{', '.join(PBARL_SHAPES)})")
    dim, nsm = prop.dim, prop.nsm
    if prop.type == "PBEAML":  # one row of dimensions per station: constant sections only
        rows = np.atleast_2d(np.asarray(dim, float))
        if np.ptp(rows, axis=0).any() or np.ptp(np.ravel(nsm)) != 0:
            raise InputError(f"{where}: the section varies along the beam; only a constant "
                             f"section is supported")
        dim, nsm = rows[0], float(np.ravel(nsm)[0])
    try:
        if shape in sections.THIN_WALLED:
            A, i1, i2, _ = sections.thin_walled_section(shape, dim)
        else:
            A, i1, i2 = sections.solid_section(shape, dim)
        j = sections.torsion_constant(shape, dim)
    except InputError as exc:
        raise InputError(f"{where}: {exc}") from None
    if shape not in SHEAR_FACTORS:
        warnings.warn(f"{where}: NASTRAN gives section {shape} shear flexibility with factors "
                      f"not modelled here (Euler-Bernoulli); stubby members will differ",
                      EigenupdateWarning, stacklevel=2)
    k1, k2 = SHEAR_FACTORS.get(shape, (0.0, 0.0))
    return A, i1, i2, j, nsm, prop.mid, (prop.type, prop.pid), k1, k2


def _one_parameter_per_quantity(deriv, label, kj) -> None:
    parts = {p for dj in deriv for p in dj}
    for part in parts:
        owner = np.full(len(label), -1)
        for j, dj in enumerate(deriv):
            if part not in dj:
                continue
            hit = np.flatnonzero(dj[part])
            clash = hit[owner[hit] >= 0]
            if clash.size:
                e = clash[0]
                raise InputError(f"{label[e]}: parameters {owner[e] + 1} and {j + 1} both scale "
                                 f"its {part[2:]} {'stiffness' if part[0] == 'k' else 'mass'}"
                                 f": K or M would hold their product (not linear)")
            owner[hit] = j


def _scalars(bdf, point, wtmass, pindex, values, k0, m0, kj, mj) -> None:
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
            if fld == "M" and value < 0:
                raise InputError(f"{label}: negative mass {value:g}")
            dofs = dofs_of(e, label)
            if j is None:
                put(dest0, dofs, scale * value)
            else:
                put(dests[j], dofs, scale)


def _rect_axes(bdf, cid, label: str) -> np.ndarray:
    """Rows: the axes of rectangular system ``cid`` in basic (0: basic)."""
    if not cid:
        return np.eye(3)
    if cid not in bdf.coords:
        raise InputError(f"{label}: coordinate system {cid} is not defined")
    if bdf.coords[cid].Type != "R":
        raise InputError(f"{label}: CID {cid} must be rectangular")
    return bdf.coords[cid].beta()


def _blocks(a: np.ndarray) -> np.ndarray:
    out = np.zeros((6, 6))
    out[:3, :3] = out[3:, 3:] = a
    return out


def _conm1(bdf, grid, frames, wtmass, pindex, m0, mj) -> None:
    """CONM1: a 6 x 6 mass matrix (lower triangle given) at a grid, in system CID."""
    for eid, e in sorted(bdf.masses.items()):
        if e.type != "CONM1":
            continue
        label = f"CONM1 {eid}"
        g = grid(e.nid, label)
        low = np.tril(np.asarray(e.mass_matrix, float))
        full = low + np.tril(low, -1).T
        if np.any(np.linalg.eigvalsh(full) < -1e-12 * max(np.abs(full).max(), 1e-300)):
            raise InputError(f"{label}: mass matrix is not positive semi-definite")
        # u_cid = B F^T u_cd: B the CID axes, F the grid's displacement axes (rows)
        t = _blocks(_rect_axes(bdf, e.cid, label)) @ _blocks(frames[g]).T
        dofs = 6 * g + np.arange(6)
        r, c = np.repeat(dofs, 6), np.tile(dofs, 6)
        slots = pindex.get(("CONM1", eid), {})
        base = full.copy()
        for name, j in slots.items():
            i1, i2 = int(name[1]) - 1, int(name[2]) - 1
            unit = np.zeros((6, 6))
            unit[i1, i2] = unit[i2, i1] = 1.0
            base -= full[i1, i2] * unit
            mj[j].add(r, c, wtmass * (t.T @ unit @ t))
        m0.add(r, c, wtmass * (t.T @ base @ t))


def _cbush(bdf, grid, xyz, frames, pindex, k0, kj) -> None:
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
        # element deformations d = E [-R_A F_A^T, R_B F_B^T] u: R the rigid map to the point
        cols = [(a, -1.0)] + ([] if b is None else [(b, 1.0)])
        d = np.hstack([sign * _blocks(axes) @ constraints.rigid_map(point - xyz[g])
                       @ _blocks(frames[g]).T for g, sign in cols])
        dofs = np.concatenate([6 * g + np.arange(6) for g, _ in cols])
        r, c = np.repeat(dofs, dofs.size), np.tile(dofs, dofs.size)
        k = _pbush_k(p)
        if np.any(k < 0):
            raise InputError(f"PBUSH {p.pid}: stiffness K1-K6 must be >= 0")
        slots = pindex.get(("PBUSH", p.pid), {})
        param = {int(name[1]) - 1: j for name, j in slots.items()}
        base = sum(k[i] * np.outer(d[i], d[i]) for i in range(6) if i not in param)
        if np.ndim(base):
            k0.add(r, c, base)
        for i, j in param.items():
            kj[j].add(r, c, np.outer(d[i], d[i]))


def _conm2(bdf, grid, xyz, frames, wtmass, pindex, values, m0, mj) -> None:
    for eid, e in sorted(bdf.masses.items()):
        if e.type != "CONM2":
            continue
        label = f"CONM2 {eid}"
        g = grid(e.nid, label)
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
        # rigid offset: u_cg = u_grid + theta x offset, all in basic, then to the grid's CD
        a = np.zeros((6, 6))
        a[:3, :3] = np.eye(3)
        a[:3, 3:] = -frame3d.skew(offset[None])[0]
        a[3:, 3:] = np.eye(3)
        cd = np.zeros((6, 6))
        cd[:3, :3] = cd[3:, 3:] = frames[g].T
        a = a @ cd
        unit = np.zeros((6, 6))
        unit[:3, :3] = np.eye(3)
        rot_in = np.zeros((6, 6))
        rot_in[3:, 3:] = rot.T @ inertia @ rot
        dofs = 6 * g + np.arange(6)
        r, c = np.repeat(dofs, 6), np.tile(dofs, 6)
        j = pindex.get(("CONM2", eid), {}).get("M")
        trans = wtmass * (a.T @ unit @ a)
        m0.add(r, c, wtmass * (a.T @ rot_in @ a) + (0.0 if j is not None else e.mass * trans))
        if j is not None:
            mj[j].add(r, c, trans)


def _spc(bdf, where) -> tuple[np.ndarray, int | None]:
    """Restrained rows: GRID PS fields and the SPC set chosen by case control (or the
    only set in the file)."""
    rows = []
    gs = bdf.grdset
    if gs is not None and (gs.cp or gs.cd):
        raise InputError(f"GRDSET: CP {gs.cp} / CD {gs.cd} defaults are not supported "
                         f"(give them on the GRID cards)")
    default_ps = str(gs.ps or "") if gs is not None else ""
    for n, g in bdf.nodes.items():
        for c in str(g.ps or default_ps):
            if c != "0":
                rows.append(6 * where[n] + int(c) - 1)
    ids = set(bdf.spcs) | set(bdf.spcadds)
    chosen = None
    cc = bdf.case_control_deck
    if cc is not None:
        wanted = set()
        for sub in cc.subcases.values():
            try:
                wanted.add(int(sub.get_parameter("SPC")[0]))
            except KeyError:  # this subcase restrains nothing
                pass
        if len(wanted) > 1:
            raise InputError(f"case control selects several SPC sets {sorted(wanted)}; "
                             f"one is needed for one model")
        chosen = int(wanted.pop()) if wanted else None
    if chosen is None:
        inner = {int(s) for add in bdf.spcadds.values() for a in add for s in a.sets}
        top = sorted(ids - inner)
        if len(top) > 1:
            raise InputError(f"several SPC sets {top} and no case control SPC = to choose one")
        chosen = top[0] if top else None
    if chosen is not None:
        rows += _spc_rows(bdf, where, chosen, set())
    return np.array(sorted(set(rows)), dtype=int), chosen


def _spc_rows(bdf, where, sid: int, seen: set) -> list[int]:
    if sid in seen:
        raise InputError(f"SPCADD {sid} includes itself")
    seen.add(sid)
    if sid not in bdf.spcs and sid not in bdf.spcadds:
        raise InputError(f"SPC set {sid} is not defined")
    rows = []
    for add in bdf.spcadds.get(sid, []):
        for s in add.sets:
            rows += _spc_rows(bdf, where, int(s), seen)
    for card in bdf.spcs.get(sid, []):
        pairs = ([(n, card.components) for n in card.nodes] if card.type == "SPC1"
                 else list(zip(card.nodes, card.components, strict=True)))
        for n, comps in pairs:
            if n not in where:
                raise InputError(f"{card.type} {sid}: GRID {n} is referenced but not defined")
            rows += [6 * where[n] + int(c) - 1 for c in str(comps) if c != "0"]
    return rows
