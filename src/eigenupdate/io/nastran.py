"""Assembling a NASTRAN deck's K and M as functions of named card fields (linear in most;
PBARL/PBEAML dimensions and products such as MAT1 E with PBAR A through their formulas).

:func:`read_nastran` reads the deck (:mod:`eigenupdate.io.nastran_deck`) and assembles a
:class:`ParametricModel` whose parameters are named card fields (``MAT1 1 E``, see
:mod:`eigenupdate.io.nastran_fields`): line elements in :mod:`eigenupdate.io.nastran_lines`
(matrices of :mod:`eigenupdate.model.frame3d`), scalar elements, CONM1/2 and CBUSH in
:mod:`eigenupdate.io.nastran_points`, GENEL in :mod:`eigenupdate.io.nastran_genel`, rigid
elements and MPCs in :mod:`eigenupdate.io.nastran_constraints` (eliminated by
:mod:`eigenupdate.model.constraints`), ASET/OMIT/QSET by :mod:`eigenupdate.io.nastran_sets`.
:mod:`eigenupdate.io.nastran_write` writes the deck back. pyNastran is an optional extra
(``pip install eigenupdate[nastran]``).

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

from eigenupdate.errors import EigenupdateWarning, InputError, shorten
from eigenupdate.io import nastran_offsets as offsets
from eigenupdate.io import nastran_sets
from eigenupdate.io.nastran_constraints import constraint_equations
from eigenupdate.io.nastran_continuum import assemble_continuum
from eigenupdate.io.nastran_deck import Deck, case_value, load_deck, modal_subcases, place
from eigenupdate.io.nastran_deck import param as _param
from eigenupdate.io.nastran_dmig import assemble_dmig, idle_note
from eigenupdate.io.nastran_fields import (
    FIELDS,
    NOT_LINEAR,
    field_unit,
    get_field,
    set_field,
    stores,
)
from eigenupdate.io.nastran_genel import assemble_genel
from eigenupdate.io.nastran_lines import assemble_lines
from eigenupdate.io.nastran_plates95 import read_plates
from eigenupdate.io.nastran_points import (
    assemble_cbush,
    assemble_conm1,
    assemble_conm2,
    assemble_scalars,
)
from eigenupdate.io.nastran_shear import assemble_shear
from eigenupdate.model import constraints, shells
from eigenupdate.model.coordinates import CoordinateTable
from eigenupdate.model.parameters import Parameter
from eigenupdate.model.parametric import ParametricModel, Term

__all__ = ["FIELDS", "CardField", "NastranModel", "get_field", "read_nastran", "set_field"]


MAX_ID = 2**31 - 1
"""NASTRAN's largest id (a 32-bit integer)."""


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
    included: list = field(default_factory=list)  # the files its INCLUDEs read
    omitted: frozenset = frozenset()  # coordinates reduced out by ASET/OMIT
    modal: frozenset = frozenset()  # q-set SPOINTs: fixed-interface mode amplitudes
    fixed_hz: tuple = ()  # the frequencies of those modes (NASTRAN's first table)

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
        if c in self.omitted:
            raise InputError(f"GRID {grid} component {component} is omitted by ASET/OMIT "
                             f"(reduced out): put the perturbation on a kept coordinate")
        if c in self.modal:
            raise InputError(f"SPOINT {grid} is a q-set coordinate (the amplitude of a "
                             f"fixed-interface mode, QSET): put the perturbation on a "
                             f"physical a-set coordinate")
        if c not in self.model.coordinates:
            why = (f"SPC set {self.spc_set} or GRID PS" if c in self.restrained
                   else "it carries neither stiffness nor mass")
            raise InputError(f"GRID {grid} component {component} is restrained ({why})")
        return c


def read_nastran(path: str | Path, parameters: Sequence[tuple[Parameter, CardField]] = (),
                 subcase: int | None = None) -> NastranModel:
    """Read a BDF and assemble K = K0 + sum s_j K_j, M = M0 + sum s_j M_j.

    Parameters
    ----------
    path : the bulk data file.
    parameters : (parameter, card field) pairs; each parameter's value is taken from its
        card field (``Parameter.value`` is ignored), its name, std and update flag are kept.
    subcase : the case control subcase whose SPC, MPC, K2GG and M2GG make the model
        (default: those of the modes subcases, which must agree).

    Returns
    -------
    NastranModel
    """
    path = Path(path)
    src = str(path)
    deck = None
    try:
        deck = load_deck(path)
        read_plates(deck)  # NASTRAN-95's CQUAD1.. PTRIA2 as CQUAD4/CTRIA3 + PSHELL
        deck.bdf.eigenupdate_subcase = subcase
        nm = _assemble(path, deck.bdf, parameters)
        deck.skipped = ", ".join(x for x in (deck.skipped, idle_note(deck.bdf)) if x)
    except InputError as exc:
        if exc.source:
            raise
        raise InputError(_located(exc.message, deck), source=src, field=exc.field) from None
    except OverflowError:
        raise InputError("a number in the deck overflows K or M (a value near 1e300?)",
                         source=src) from None
    if deck.skipped:
        warnings.warn(f"{path.name}: skipped (they change neither K nor M): {deck.skipped}",
                      EigenupdateWarning, stacklevel=2)
    nm.skipped = deck.skipped
    nm.text = deck.text
    nm.included = deck.included
    return nm


_LABEL = re.compile(r"^([A-Z][A-Z0-9]*) ([A-Z0-9_]+)(:| field)")


def _located(message: str, deck: Deck | None) -> str:
    """Prefix ``file:line:`` of the card a message starts with (``CBAR 1043: ...``)."""
    m = _LABEL.match(message)
    if deck is None or m is None:
        return message
    key = m.group(2)
    hit = deck.lines.get((m.group(1), int(key) if key.isdigit() else key))
    return f"{place(hit, deck.path.name)}: {message}" if hit else message


class _Triplets:
    """COO pieces of one sparse matrix."""

    def __init__(self):
        self.r, self.c, self.v = [], [], []
        self.whole: list = []  # assembled (n, n) matrices (shells, solids)

    def add(self, rows, cols, vals):
        self.r.append(np.ravel(rows))
        self.c.append(np.ravel(cols))
        self.v.append(np.ravel(vals))

    def add_matrix(self, m) -> None:
        """Add an already assembled sparse matrix of the model's size."""
        self.whole.append(m)

    def matrix(self, n: int, keep: np.ndarray | None = None) -> sp.csr_array:
        if not self.v:
            m = sp.csr_array((n, n))
        else:
            m = sp.csr_array((np.concatenate(self.v), (np.concatenate(self.r),
                                                      np.concatenate(self.c))), shape=(n, n))
        for w in self.whole:
            m = m + w if m.nnz else sp.csr_array(w)
        m.sum_duplicates()
        return m if keep is None else sp.csr_array(m[keep][:, keep])


def _coordinate_error(exc: BaseException) -> str:
    """The coordinate system pyNastran failed on (the innermost card in the traceback)
    and why, in NASTRAN's terms."""
    tb, card = exc.__traceback__, ""
    while tb is not None:
        c = tb.tb_frame.f_locals.get("self")
        if str(getattr(c, "type", "")).startswith("CORD") and isinstance(
                getattr(c, "cid", None), int):
            card = f"{c.type} {c.cid}: "
        tb = tb.tb_next
    if isinstance(exc, RecursionError):
        return (f"{card}coordinate systems defined through one another in a loop (a CORD1's "
                f"grid given in that system, or CORD2 RIDs that return)")
    if "norm" in str(exc):
        return f"{card}its defining points coincide or are collinear: the axes are undefined"
    return f"{card}coordinate systems: {shorten(str(exc), 120)}"


def _assemble(path: Path, bdf, specs) -> NastranModel:
    consistent = _param(bdf, "COUPMASS", -1.0) > 0
    wtmass = _param(bdf, "WTMASS", 1.0)
    if not wtmass > 0:
        raise InputError(f"PARAM WTMASS {wtmass} must be > 0")
    if not bdf.nodes and not bdf.spoints:
        raise InputError("no GRID or SPOINT cards")
    _link_cord1_grids(bdf)
    try:
        bdf._cross_reference_coordinates()
    except Exception as exc:  # pyNastran's words, e.g. "v=[0. 0. 0.] norm(v)=0.0"
        raise InputError(_coordinate_error(exc)) from None
    # scalar points take six rows like a grid, of which only the first is used
    big = [n for n in (*bdf.nodes, *bdf.spoints) if not 0 < n <= MAX_ID]
    if big:  # coordinate 10 id + component must stay an exact integer
        what = "GRID" if big[0] in bdf.nodes else "SPOINT"
        raise InputError(f"{what} {big[0]}: id outside NASTRAN's 1 to {MAX_ID}")
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
    pindex = _check_fields(bdf, fields, [p.name for p, _ in specs])
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
        row = 6 * grid(n, card)  # first: an id that is no point at all is named so
        if c not in range(1, 7):
            raise InputError(f"{card}: component {c} must be 1-6 on a GRID")
        return row + int(c) - 1

    extra: list = []  # nonlinear parts: ("k" or "m", triplets, FunctionTerm)
    assemble_lines(bdf, where, grid, xyz, frames, consistent, wtmass, pindex, values,
                   k0, m0, kj, mj, extra)
    assemble_continuum(bdf, grid, xyz, frames, nids.size, consistent, wtmass,
                       _param(bdf, "K6ROT", shells.K6ROT), pindex, values, k0, m0, kj, mj,
                       extra, offsets.curvature(bdf, grid, xyz, nids.size,
                                                  _param(bdf, "SNORM", offsets.SNORM)))
    assemble_shear(bdf, grid, xyz, frames, wtmass, pindex, values, k0, m0, kj, mj, extra)
    assemble_scalars(bdf, point, wtmass, pindex, values, k0, m0, kj, mj)
    assemble_conm2(bdf, grid, xyz, frames, wtmass, pindex, values, m0, mj)
    assemble_conm1(bdf, grid, frames, wtmass, pindex, m0, mj)
    assemble_cbush(bdf, grid, xyz, frames, pindex, k0, kj)
    assemble_genel(bdf, grid, point, xyz, frames, k0)
    assemble_dmig(bdf, point, lambda name, default: _param(bdf, name, default), k0, m0)

    restrained, spc_set = _spc(bdf, where)
    K0, M0 = k0.matrix(ndof), m0.matrix(ndof)
    kt = [t.matrix(ndof) for t in kj]
    mt = [t.matrix(ndof) for t in mj]
    xt = [(kind, t.matrix(ndof), term) for kind, t, term in extra]
    # rigid elements and MPCs: u = T u_i, every matrix reduced to the independent rows
    eqs = constraint_equations(bdf, grid, point, xyz, frames)
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
        xt = [(kind, sp.csr_array(T.T @ a @ T), term) for kind, a, term in xt]
        restrained = np.flatnonzero(np.isin(rows_ind, restrained))
    nfree = rows_ind.size
    K, M = sp.csr_array(K0), sp.csr_array(M0)
    for s, a, b in zip(values, kt, mt, strict=True):
        K, M = K + s * a, M + s * b
    for kind, a, term in xt:
        if kind == "k":
            K = K + term.value(np.asarray(values)) * a
        else:
            M = M + term.value(np.asarray(values)) * a
    # coordinates with neither stiffness nor mass (rod rotations) carry nothing; with
    # PARAM AUTOSPC YES (MSC's and NX's default in normal modes) NASTRAN also constrains
    # those with mass and no stiffness (unconnected grids, rotations of rod-only grids)
    stiff, heavy = np.zeros(nfree, bool), np.zeros(nfree, bool)
    for mat, hit in ([(K, stiff), (M, heavy)] + [(t, stiff) for t in kt]
                     + [(t, heavy) for t in mt]
                     + [(a, stiff if kind == "k" else heavy) for kind, a, _ in xt]):
        coo = mat.tocoo()
        hit[coo.row[coo.data != 0]] = True
    autospc = str(_param(bdf, "AUTOSPC", "YES")).upper() not in ("NO", "N")
    free = stiff if autospc else stiff | heavy
    free[restrained] = False
    keep = np.flatnonzero(free)
    if keep.size == 0:
        raise InputError("every coordinate is restrained or carries neither stiffness nor mass")
    k0m, m0m = (_kept(a, keep) for a in (K0, M0))
    red = nastran_sets.reduce(bdf, where, grids.size, ndof, k0m, m0m, keep, rows_ind,
                              restrained, nids, bool(specs))
    k0m, m0m, keep = red.k, red.m, red.keep
    coords = np.concatenate([(10 * np.repeat(nids, 6) + np.tile(np.arange(1, 7), nids.size))
                             [rows_ind[keep]], red.modal])
    params = []
    for (p, where), v in zip(specs, values, strict=True):
        params.append(Parameter(p.name, v, p.std, p.update, p.unit).with_unit(
            field_unit(where.card, where.field)))
    parts: dict[str, list] = {"k": [], "m": []}
    for kind, ts in (("k", kt), ("m", mt)):
        parts[kind] += [Term(_kept(t, keep), ((j, 1.0),)) for j, t in enumerate(ts) if t.nnz]
    for kind, a, term in xt:
        if a.nnz:
            parts[kind].append(term.replaced(_kept(a, keep)))
    pm = ParametricModel.from_parts(
        k0m, m0m, tuple(params), parts["k"], parts["m"],
        coordinates=coords,
        # coordinate 10 * GRID + component: node = GRID, direction = component (UFF codes)
        coordinate_table=CoordinateTable.from_arrays(coords, coords // 10, coords % 10))
    for p, f, a, b in zip(params, fields, pm.k_terms, pm.m_terms, strict=True):
        if a is None and b is None:
            raise InputError(f"{f.card} {f.id} field {f.field} (parameter {p.name!r}) acts on "
                             f"no free coordinate")
    held_rows = rows_ind[restrained]
    held = frozenset((10 * nids[held_rows // 6] + held_rows % 6 + 1).tolist())
    dependent = {int(10 * nids[r // 6] + r % 6 + 1): str(labels[r])
                 for r in np.flatnonzero(labels != "")}
    gone = red.gone
    omitted = frozenset((10 * nids[gone // 6] + gone % 6 + 1).tolist())
    return NastranModel(path, pm, tuple(fields), consistent, spc_set, held, bdf,
                        dependent=dependent, omitted=omitted,
                        modal=frozenset(red.modal.tolist()), fixed_hz=red.fixed_hz)


def _kept(a, keep: np.ndarray) -> sp.csr_array:
    """Rows and columns ``keep`` of a square matrix (no copy when all are kept)."""
    a = sp.csr_array(a)
    if keep.size == a.shape[0]:
        return a
    return sp.csr_array(a[keep][:, keep])


def _link_cord1_grids(bdf) -> None:
    """Give the grids that define a CORD1R/C/S their CP system: pyNastran's setup of
    those systems reads the grids' positions through it (unset, every deck with a CORD1
    card was refused with "'NoneType' object has no attribute 'setup'")."""
    for c in bdf.coords.values():
        if not c.type.startswith("CORD1"):
            continue
        for n in (c.g1, c.g2, c.g3):
            g = bdf.nodes.get(n)
            if g is None:
                raise InputError(f"{c.type} {c.cid}: GRID {n} is referenced but not defined")
            if g.cp not in bdf.coords:
                raise InputError(f"GRID {n}: coordinate system CP {g.cp} is not defined")
            g.cp_ref = bdf.coords[g.cp]


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


def _check_fields(bdf, fields: list[CardField], names: list[str]) -> dict:
    """{(card, id): {field: parameter index}} after validating every field."""
    out: dict = {}
    cards = stores(bdf)
    for j, f in enumerate(fields):
        if (f.card, f.field) in NOT_LINEAR:
            raise InputError(f"{f.card} {f.id} field {f.field}: not a parameter: "
                             f"{NOT_LINEAR[(f.card, f.field)]}")
        if f.card not in FIELDS:
            raise InputError(f"{f.card} {f.id} field {f.field}: card {f.card} has no "
                             f"parameter fields (cards with some: {', '.join(FIELDS)})")
        if f.field not in FIELDS[f.card]:
            have = ", ".join(_series(FIELDS[f.card]))
            raise InputError(f"{f.card} {f.id}: field {f.field!r} is not a parameter; the "
                             f"parameter fields of {f.card} are {have}")
        card = cards[f.card].get(f.id)
        if card is None or card.type != f.card:
            raise InputError(f"{f.card} {f.id} is not in the file (parameter {j + 1}, "
                             f"{names[j]!r})")
        if f.card in ("PBARL", "PBEAML"):
            n = np.atleast_2d(np.asarray(card.dim, float)).shape[1]
            if int(f.field[3:]) > n:
                raise InputError(f"{f.card} {f.id}: section {card.Type} has DIM1-DIM{n}, "
                                 f"not {f.field}")
        slot = out.setdefault((f.card, f.id), {})
        if f.field in slot:
            raise InputError(f"{f.card} {f.id} field {f.field} is named by two parameters")
        slot[f.field] = j
    return out


def _field_value(bdf, f: CardField) -> float:
    card = stores(bdf)[f.card][f.id]
    try:
        v = get_field(card, FIELDS[f.card][f.field])
    except TypeError:  # pyNastran keeps a blank field as None
        raise InputError(f"{f.card} {f.id} field {f.field} is blank: a parameter starts "
                         f"from the card's value; give one") from None
    if not v >= 0:
        raise InputError(f"{f.card} {f.id} field {f.field} = {v:g} is negative (a parameter "
                         f"must be >= 0)")
    return v


def _spc(bdf, where) -> tuple[np.ndarray, int | None]:
    """Restrained rows: GRID PS fields and the SPC set chosen by case control (or the
    only set in the file)."""
    rows = []
    gs = bdf.grdset  # its CP and CD are in the GRIDs already (nastran_deck)
    default_ps = str(gs.ps or "") if gs is not None else ""
    for n, g in bdf.nodes.items():
        for c in str(g.ps or default_ps):
            if c != "0":
                rows.append(6 * where[n] + int(c) - 1)
    ids = set(bdf.spcs) | set(bdf.spcadds)
    wanted = {int(v) for sub in modal_subcases(bdf)
              if (v := case_value(sub, "SPC")) is not None}  # else it restrains nothing
    if len(wanted) > 1:
        raise InputError(f"case control selects several SPC sets {sorted(wanted)}; "
                         f"one is needed for one model (name its subcase: [model] "
                         f"subcase = N in the study)")
    chosen = wanted.pop() if wanted else None
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
            if str(comps or "").strip() in ("", "0"):
                if n not in bdf.nodes:
                    rows.append(6 * where[n])  # a scalar point's component is 0 or blank
                else:  # QRG SPC/SPC1: a grid's components are 1-6
                    warnings.warn(f"{card.type} {sid}: GRID {n} with component 0 or blank "
                                  f"restrains nothing", EigenupdateWarning, stacklevel=2)
    return rows


def _series(names) -> list[str]:
    """Field names with numbered runs shortened: T1, T2, ..., T99 -> T1-T99.

    >>> _series(["A", "I1", "I2", "DIM1", "DIM2", "DIM3"])
    ['A', 'I1-I2', 'DIM1-DIM3']
    """
    out: list[list] = []  # [prefix, first, last] or [name]
    for n in names:
        m = re.fullmatch(r"([A-Z]+)(\d+)", n)
        if m and out and len(out[-1]) == 3 and out[-1][0] == m[1] and out[-1][2] + 1 == int(m[2]):
            out[-1][2] += 1
        else:
            out.append([m[1], int(m[2]), int(m[2])] if m else [n])
    return [f"{o[0]}{o[1]}" + (f"-{o[0]}{o[2]}" if o[2] > o[1] else "") if len(o) == 3
            else o[0] for o in out]
