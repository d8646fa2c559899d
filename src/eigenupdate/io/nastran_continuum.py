"""CQUAD4, CTRIA3, CQUAD8 and CTRIA6 (PSHELL, PCOMP) and CHEXA (8, 20 nodes), CPENTA
(6, 15), CTETRA (4, 10), CPYRAM (5, 13) (PSOLID) of a deck:
properties, materials and the assembly of their (parameter) stiffness and mass with
:mod:`eigenupdate.model.shells`, :mod:`~eigenupdate.model.shells_quadratic`,
:mod:`eigenupdate.model.solids` and
:mod:`eigenupdate.model.laminate`, a chunk of elements at a time
(:func:`eigenupdate.model.assembly.assemble_many`).

MAT1 as NASTRAN uses it (MSC/NX MAT1 remarks): shells take E and NU for membrane and
bending (so in-plane shear is E / (2 (1 + NU)) even when G is given) and G for transverse
shear; solids take E and NU, never G. A PSHELL's stiffness is therefore, part by part,
E1 T K_membrane + E1 T K_drilling + E2 T^3 K_bending + G3 s(T) K_shear (MIDi's moduli),
linear in each material's E (G3 too when MAT1 leaves G blank) and the mass
WTMASS (RHO1 T + NSM) M linear in RHO: ``MAT1 E`` and ``RHO`` are parameters.
THETA/MCID (material axes) do not matter for an isotropic MAT1 and are ignored there;
they orient the plies of a PCOMP and a PSHELL's MAT8 (:mod:`eigenupdate.io.nastran_materials`).
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from eigenupdate.errors import InputError
from eigenupdate.io import nastran_corners as corners
from eigenupdate.io import nastran_offsets as offsets
from eigenupdate.io import nastran_plates95 as plates95
from eigenupdate.io.nastran_fields import in_range, mat9, tied_shear_modulus
from eigenupdate.io.nastran_materials import mat1 as _mat1
from eigenupdate.io.nastran_materials import mat8_values, ply, pshell, rigid_plies
from eigenupdate.io.nastran_plies import held_stabilisation, ply_terms, thickness_terms
from eigenupdate.model import laminate, shells, shells_drilling, solids
from eigenupdate.model import shells_quadratic as quadratic
from eigenupdate.model import shells_transition as transition
from eigenupdate.model.assembly import assemble_many

SHELLS = {"CQUAD4": 4, "CTRIA3": 3, "CQUAD8": 8, "CTRIA6": 6,
          **{name: k for name, (_, k, _) in plates95.ELEMENTS.items()}}  # NASTRAN-95's
DRILLING = {"CQUADR": 4, "CTRIAR": 3}  # model/shells_drilling.py
SOLIDS = {("CHEXA", 8): "CHEXA8", ("CHEXA", 20): "CHEXA20", ("CPENTA", 6): "CPENTA6",
          ("CPENTA", 15): "CPENTA15", ("CTETRA", 4): "CTETRA4", ("CTETRA", 10): "CTETRA10",
          ("CPYRAM", 5): "CPYRAM5", ("CPYRAM", 13): "CPYRAM13"}
SHELL_EDGES = {8: np.array([[0, 1], [1, 2], [2, 3], [3, 0]]),
               6: np.array([[0, 1], [1, 2], [2, 0]])}  # CQUAD8 G5-G8, CTRIA6 G4-G6
PARTS = shells.STIFFNESS_PARTS
MAX_ANGLE = 360.0
"""Largest |THETA| (degrees) of a ply or an element's material axis: one turn either
way; beyond, an angle is a typing error (and far beyond, cos/sin of it lose all
digits: 1e300 degrees has no defined direction)."""
def assemble_continuum(bdf, grid, xyz, frames, n_nodes, consistent, wtmass, k6rot, pindex,
                       values, k0, m0, kj, mj, extra, curvature=None) -> None:
    """Add the shells' and solids' K and M (and each parameter's K_j, M_j) to the
    triplets of :mod:`eigenupdate.io.nastran`; a PSHELL's T as a parameter adds its
    terms to ``extra`` (:func:`~eigenupdate.io.nastran_plies.thickness_terms`)."""
    groups: dict = {}
    for eid, e in sorted(bdf.elements.items()):
        if e.type in SHELLS | DRILLING or e.type in ("CHEXA", "CPENTA", "CTETRA", "CPYRAM"):
            given = [g for g in e.node_ids if g]
            twice = sorted({g for g in given if given.count(g) > 1})
            if twice:
                raise InputError(f"{e.type} {eid}: GRID {twice[0]} appears twice among its "
                                 f"nodes (a collapsed element is not supported)")
        if e.type in SHELLS:
            groups.setdefault(("shell", SHELLS[e.type]), []).append(e)
        elif e.type in DRILLING:
            groups.setdefault(("shellr", DRILLING[e.type]), []).append(e)
        elif e.type in ("CHEXA", "CPENTA", "CTETRA", "CPYRAM"):
            n = sum(1 for g in e.node_ids if g)
            kind = SOLIDS.get((e.type, n))
            if kind is None or any(not g for g in e.node_ids[:n]):
                raise InputError(f"{e.type} {eid}: {n} nodes: only CHEXA 8 or 20, CPENTA 6 "
                                 f"or 15, CTETRA 4 or 10 (every mid-edge node or none) and "
                                 f"CPYRAM 5 or 13 are supported")
            groups.setdefault(("solid", kind), []).append(e)
    tria6 = groups.get(("shell", 6), [])
    if tria6:  # a transition CTRIA6 (blank grids) is projected flat, never facetted
        labels = [f"CTRIA6 {e.eid}" for e in tria6]
        curved = quadratic.curved_tria6(_element_xyz(tria6, labels, grid, xyz)[1], labels)
        curved &= np.array([all(e.node_ids) for e in tria6])
        if curved.any():
            groups[("shell", 6)] = [e for e, c in zip(tria6, curved, strict=True) if not c]
            groups.setdefault(("shell", 3), []).extend(
                _Facet(e, f) for e, c in zip(tria6, curved, strict=True) if c
                for f in quadratic.FACETS)
            if not groups[("shell", 6)]:
                del groups[("shell", 6)]
    for (family, k), elems in sorted(groups.items()):
        if family in ("shell", "shellr"):
            _shells(bdf, elems, k, grid, xyz, frames, n_nodes, consistent, wtmass, k6rot,
                    pindex, values, k0, m0, kj, mj, extra, curvature, family == "shellr")
        else:
            _solids(bdf, elems, k, grid, xyz, frames, n_nodes, consistent, wtmass, pindex,
                    values, k0, m0, kj, mj)


def _element_xyz(elems, labels, grid, xyz) -> tuple[np.ndarray, np.ndarray]:
    """The elements' grid indices (n, k) and nodes (n, k, 3); a blank mid-side grid of a
    CQUAD8/CTRIA6 (a transition element, model/shells_transition.py) is NaN there and
    indexed as its element's first grid (its blocks are zero)."""
    nodes = np.array([[grid(g, lab) if g else -1 for g in e.node_ids]
                      for e, lab in zip(elems, labels, strict=True)])
    blank = nodes < 0
    k = nodes.shape[1]
    if blank[:, :k - len(SHELL_EDGES.get(k, ()))].any():
        i = int(np.argwhere(blank)[0, 0])
        raise InputError(f"{labels[i]}: a corner grid is blank")
    out = xyz[np.where(blank, nodes[:, :1], nodes)]
    out[blank] = np.nan
    return np.where(blank, nodes[:, :1], nodes), out


class _Facet:
    """One of the four flat CTRIA3 a curved CTRIA6 is modelled by
    (:data:`eigenupdate.model.shells_quadratic.FACETS`): the CTRIA6's card (its id and
    type name errors) on three of its grids."""

    def __init__(self, e, facet: tuple[int, int, int]):
        self.type, self.eid, self.pid = e.type, e.eid, e.pid
        self.node_ids = [e.node_ids[i] for i in facet]
        self.zoffset, self.tflag, self.theta_mcid = e.zoffset, e.tflag, e.theta_mcid
        # the CTRIA6's corner thicknesses: nastran_corners takes its field at ``facet``
        self.T1, self.T2, self.T3, self.facet = e.T1, e.T2, e.T3, facet


def _linear_in_e(mat, slots) -> None:
    """Refuse E as a parameter of a MAT1 with NU blank and G given: NASTRAN's NU =
    E / (2 G) - 1 then follows E, and a shell's or solid's K is not linear in E."""
    if "E" in slots and "NU" in getattr(mat, "blank", ()) and "G" not in mat.blank:
        raise InputError(f"MAT1 {mat.mid} field E: not a parameter of a shell or solid "
                         f"material with NU blank (NASTRAN's NU = E / (2 G) - 1 follows E, "
                         f"so K is not linear in E); give NU on the card, or leave G blank")


def _pcomp(bdf, prop) -> dict:
    """A PCOMP, or a PCOMPG (the same laminate, its plies named by global ids: MSC QRG)."""
    where = f"{prop.type} {prop.pid}"
    lam = (prop.lam or "").strip().upper()
    if lam not in (("", "SYM") if prop.type == "PCOMP" else ("",)):
        raise InputError(f"{where}: LAM = {lam} is not supported (blank"
                         f"{' or SYM' if prop.type == 'PCOMP' else ''})")
    t = np.asarray(prop.get_thicknesses(), float)
    if not (t.size and np.all(t > 0)):  # a PCOMPG without plies reads as no ply
        raise InputError(f"{where}: needs plies, every thickness T > 0, got {t.tolist()}")
    angles = np.asarray(prop.get_thetas(), float)
    if not np.all(np.abs(angles) <= MAX_ANGLE):
        raise InputError(f"{where}: ply angles THETA {angles.tolist()} must be within "
                         f"-{MAX_ANGLE:g} to {MAX_ANGLE:g} degrees")
    mids = prop.get_material_ids()
    plies = rigid_plies([ply(bdf, int(m), f"{where} ply {i + 1}") for i, m in enumerate(mids)],
                        mids, where)
    T = float(t.sum())
    z0 = -T / 2 if prop.z0 is None else in_range(prop.z0, f"{where}: Z0")
    mass: dict = {}
    for m, p, ti in zip(mids, plies, t, strict=True):
        mass[int(m)] = (p[2], mass.get(int(m), (0.0, 0.0))[1] + ti)
    nsm = in_range(prop.nsm or 0.0, f"{where}: NSM")
    if sum(r * ti for r, ti in mass.values()) + nsm < 0:
        raise InputError(f"{where}: NSM = {nsm:g} makes the mass per area negative")
    out = {"T": T, "E1": 1.0, "E2": 1.0, "G3": 1.0, "E3": 1.0, "mid1": 0, "mid2": 0,
           "mid3": 0, "tied3": False, "mass": mass, "nsm": nsm, "plies": set(mass),
           "card": prop.type, "heights": offsets.ply_heights(t, z0, mids),
           "laminate": (np.stack([p[0] for p in plies]), np.stack([p[1] for p in plies]),
                        t, z0, np.radians(angles)),
           "stack": {"q": np.stack([p[0] for p in plies]), "g": np.stack([p[1] for p in plies]),
                     "t": t, "theta": np.radians(angles), "rho": [p[2] for p in plies],
                     "n_card": len(prop.thicknesses), "mid": [int(m) for m in mids],
                     "mat8": {int(m): mat8_values(bdf.materials[int(m)]) for m in set(mids)
                              if bdf.materials[int(m)].type == "MAT8"},
                     # Z0 on the card stays when a ply changes; blank, it is -T/2 (moves)
                     "z0_given": "Z0" not in getattr(prop, "blank", {"Z0"}),
                     "card_ply": [prop._adjust_ply_id(i) for i in range(len(t))]}}
    one = bdf.materials[int(mids[0])]
    if len(mass) == 1 and one.type == "MAT1":
        # one isotropic material: A, D ~ E and H ~ G, so its E is a linear parameter
        # as a PSHELL's (the laminate's moduli are divided by them below)
        out.update(E1=one.e, E2=one.e, G3=one.g or 1.0, E3=one.e, mid1=one.mid, mid2=one.mid,
                   mid3=one.mid, tied3=tied_shear_modulus(one))
    return out


def _material_angle(bdf, elems, xyz_e: np.ndarray, labels: list[str]) -> np.ndarray:
    """Angle (n,) of each element's material x axis from its element x axis: THETA from
    the G1-G2 side (CQUAD8, CTRIA6: the xi line at the centre), or MCID's x axis
    projected on the element (rectangular MCID)."""
    if xyz_e.shape[1] in (6, 8):
        R, out = quadratic.material_axes(xyz_e, labels)
    else:
        R, local = shells.shell_axes(xyz_e, labels)
        side = local[:, 1] - local[:, 0]
        out = np.arctan2(side[:, 1], side[:, 0])
    for i, e in enumerate(elems):
        tm = e.theta_mcid
        if isinstance(tm, int):
            c = bdf.coords.get(tm)
            if c is None or c.Type != "R":
                raise InputError(f"{labels[i]}: MCID {tm} must be a defined rectangular system")
            x = R[i] @ c.beta()[0]
            if math.hypot(x[0], x[1]) < 1e-8:
                raise InputError(f"{labels[i]}: MCID {tm}'s x axis is normal to the element")
            out[i] = math.atan2(x[1], x[0])
        elif not abs(float(tm or 0.0)) <= MAX_ANGLE:
            raise InputError(f"{labels[i]}: THETA = {float(tm):g} must be within "
                             f"-{MAX_ANGLE:g} to {MAX_ANGLE:g} degrees")
        else:
            out[i] += math.radians(float(tm or 0.0))
    return out


def _shells(bdf, elems, k, grid, xyz, frames, n_nodes, consistent, wtmass, k6rot, pindex,
            values, k0, m0, kj, mj, extra, curvature=None, drilling=False) -> None:
    props: dict = {}
    labels = [f"{e.type} {e.eid}" for e in elems]
    elem = quadratic if k in (6, 8) else shells_drilling if drilling else shells
    nodes, xyz_e = _element_xyz(elems, labels, grid, xyz)
    if k in SHELL_EDGES:
        solids.check_mid_edges(transition.fill(xyz_e)[0], SHELL_EDGES[k], labels)
    rows = []
    for e, lab in zip(elems, labels, strict=True):
        prop = bdf.properties.get(e.pid)
        kind = None if prop is None else plates95.READ_AS.get(prop.type, prop.type)
        # a NASTRAN-95 plate's own property (nastran_plates95 checked it) or a PSHELL/PCOMP
        if kind not in ("PSHELL", "PCOMP", "PCOMPG") or (kind != prop.type) != (
                e.type in plates95.ELEMENTS):
            have = f" (property {e.pid} is a {prop.type})" if prop is not None else ""
            raise InputError(f"{lab}: property PSHELL, PCOMP or PCOMPG {e.pid} is not "
                             f"defined{have}")
        if e.pid not in props:
            props[e.pid] = pshell(bdf, prop) if kind == "PSHELL" else _pcomp(bdf, prop)
        rows.append(props[e.pid])
    n = len(elems)
    # T1-T4: each corner's thickness over the property's T (nastran_corners)
    profile, tapered, own = corners.profiles(elems, rows, labels, pindex, k)
    zo = offsets.element_offsets(elems, labels, rows)
    zk = zo.copy()  # the stiffness's offset: ZOFFS and a PCOMP stack's shift (Z0)
    T = np.array([p["T"] for p in rows])
    E1, E2, G3, E3 = (np.array([p[q] for p in rows]) for q in ("E1", "E2", "G3", "E3"))
    cm, cb, cs, cc = (np.zeros((n, 3, 3)), np.zeros((n, 3, 3)), np.zeros((n, 2, 2)),
                      np.zeros((n, 3, 3)))
    flat = np.array([p["laminate"] is None for p in rows])
    for i, p in enumerate(rows):
        if flat[i]:
            cm[i], cb[i], cs[i] = p["cm"], p["cb"], p["cs"]
    phi = np.zeros(n)
    turn = np.flatnonzero([p.get("oriented", False) for p in rows])
    if turn.size:  # a PSHELL's MAT8 in its material axes (THETA/MCID), as a ply's
        phi[turn] = _material_angle(bdf, [elems[i] for i in turn], xyz_e[turn],
                                    [labels[i] for i in turn])
        cm[turn], cb[turn] = (laminate.rotate_plane(c[turn], phi[turn]) for c in (cm, cb))
        cs[turn] = laminate.rotate_shear(cs[turn], phi[turn])
    if not flat.all():
        lam = np.flatnonzero(~flat)
        angle = _material_angle(bdf, [elems[i] for i in lam], xyz_e[lam],
                                [labels[i] for i in lam])
        phi[lam] = angle
        for pid in sorted({elems[i].pid for i in lam}):
            sel = lam[[elems[i].pid == pid for i in lam]]
            q, g, t, z0, theta = props[pid]["laminate"]
            Tp = props[pid]["T"]
            # about the stack's mid-plane; Z0 != -T/2 shifts it rigidly (the laminate's
            # B + s A, D + 2 s B + s^2 A about the reference plane, with CQUAD4's
            # incompatible modes on the mid-plane: see model/shell_offsets.py)
            A, B, D, H = laminate.abd(q, g, t, -Tp / 2, angle[np.searchsorted(lam, sel)][
                :, None] + theta[None, :])
            shift, card = z0 + Tp / 2, props[pid]["card"]
            if abs(shift) > 1e-12 * Tp:
                zk[sel] += shift
            big = np.abs(B).max(axis=(1, 2)) > 1e-9 * np.abs(A).max(axis=(1, 2)) * Tp
            why = ("on CQUADR/CTRIAR" if drilling else "with a ply thickness "
                   "parameter" if ("PCOMP", pid) in pindex else "")
            if big.any() and why:
                raise InputError(f"{card} {pid}: membrane-bending coupling (an unsymmetric "
                                 f"laminate) is not supported {why}")
            p = props[pid]  # moduli per unit E1, E2, G3 (1 unless one MAT1)
            cm[sel], cb[sel] = A / (Tp * p["E1"]), D / (Tp**3 * p["E2"])
            cc[sel] = np.where(big[:, None, None], B / (Tp**2 * p["E1"]), 0.0)
            cs[sel] = H / (Tp * p["G3"])
    size = elem.stabilisation_size(xyz_e)
    if profile is not None:  # the shear's stabilisation at the mean thickness T g
        size = size / profile.mean(axis=1)
    if k == 6:  # the stabilisation relative to the section's bending (at the deck's values)
        e1 = E1[:, None, None]
        size = size * np.sqrt(quadratic.stabilisation_ratio(
            cb * E2[:, None, None], cs * G3[:, None, None], cm * e1, cc * e1))
    total = {"membrane": E1 * T, "drilling": E1 * T, "bending": E2 * T**3,
             "shear": G3 * shells.shear_thickness(T, size),
             shells.COUPLING: np.where(np.abs(cc).max(axis=(1, 2)) > 0, E1 * T**2, 0.0)}
    mass = offsets.mass_moments(rows, zo, wtmass)  # (3, n): m0, m1, m2
    nsm = np.array([p["nsm"] for p in rows])
    # a tapered element's NSM is per area, its rho t follows the profile: apart
    area = offsets.at_height(wtmass * np.where(tapered, nsm, 0.0), zo)
    off = offsets.off_surface(rows, labels, xyz_e)
    deriv_k: list[dict] = [{} for _ in kj]
    deriv_m: list = [None for _ in mj]
    mids = {q: np.array([p[q] for p in rows]) for q in ("mid1", "mid2", "mid3")}
    tied3 = np.array([p["tied3"] for p in rows])
    for (card, cid), slots in pindex.items():
        if card not in ("MAT1", "MAT8"):  # a MAT8's moduli: nastran_plies.ply_terms
            continue
        if card == "MAT1" and any(np.any(m == cid) for m in mids.values()):
            _linear_in_e(bdf.materials[cid], slots)
        mixed = sorted({e.pid for e, p in zip(elems, rows, strict=True)
                        if cid in p.get("plies", ()) and p["mid1"] != cid})
        if mixed and "E" in slots:
            raise InputError(f"MAT1 {cid} field E: not a parameter of "
                             f"{bdf.properties[mixed[0]].type} {mixed[0]}, whose "
                             f"plies use several materials (its condensed membrane is not "
                             f"linear in one of them)")
        if "E" in slots and k == 6 and np.any((mids["mid2"] == cid)
                                              != ((mids["mid3"] == cid) & tied3)):
            held_stabilisation(f"MAT1 {cid} field E", "its bending and shear apart")
        if "E" in slots:
            d = deriv_k[slots["E"]]
            sh = shells.shear_thickness(T, size)
            for part, mask, f in (("membrane", mids["mid1"] == cid, T),
                                  ("drilling", mids["mid1"] == cid, T),
                                  ("bending", mids["mid2"] == cid, T**3),
                                  ("shear", (mids["mid3"] == cid) & tied3, sh * G3 / E3),
                                  (shells.COUPLING, (mids["mid1"] == cid) & (total[
                                      shells.COUPLING] != 0), T**2)):
                if mask.any():
                    d[part] = np.where(mask, f, 0.0)
        if "RHO" in slots:
            d = offsets.rho_moments(rows, zo, wtmass, cid)
            if d.any():
                deriv_m[slots["RHO"]] = d
    fixed_shear = np.zeros(n)
    thick = [(*t, None) for t in thickness_terms(elems, rows, pindex, size, wtmass,
                                                   deriv_k, deriv_m, fixed_shear, own)]
    thick += ply_terms(elems, rows, pindex, phi, size, wtmass, deriv_k, deriv_m,
                       k == 4 and not drilling, k == 6)
    base = {part: tot - sum((values[j] * d[part] for j, d in enumerate(deriv_k) if part in d),
                            np.zeros(n)) for part, tot in total.items()}
    mbase = mass - area - sum((values[j] * d for j, d in enumerate(deriv_m)
                               if d is not None), np.zeros((3, n)))
    if thick:  # those elements' parts are all in their terms, but NSM (and T1-T4 their own)
        on = np.isin([e.pid for e in elems], list({t[0] for t in thick})) & ~own
        for c in base.values():
            c[on] = 0.0
        base["shear"] += fixed_shear
        mbase[:, on] = offsets.at_height(wtmass * np.array(
            [p.get("fixed_mass", 0.0) for p in rows]) + wtmass * np.where(
                tapered, 0.0, nsm), zo)[:, on]
    lumped = not consistent

    def blocks(s: slice) -> list:
        cpl = {"coupling": cc[s]} if np.any(total[shells.COUPLING][s]) else {}
        kap = {"curvature": curvature(nodes[s])} if curvature and elem is shells else {}
        tap = {"profile": profile[s]} if tapered[s].any() else {}
        R, parts = offsets.stiffness_parts(elem, xyz_e[s], cm[s], cb[s], cs[s], k6rot,
                                           labels[s], zk[s], **cpl | kap | tap)
        hit = {p: c[s] for p, c in base.items() if np.any(c[s])}
        out = [_to_cd(shells.combine(R, parts, hit), frames, nodes[s], 6) if hit else None]
        for d in deriv_k:
            hit = {p: c[s] for p, c in d.items() if np.any(c[s])}
            out.append(_to_cd(shells.combine(R, parts, hit), frames, nodes[s], 6)
                       if hit else None)
        # a node's lumped block m I is the same in any axes, but the coupled mass's
        # blocks between grids with different CD axes (cylindrical) are not
        def units(**t):  # the masses per unit m0, m1, m2
            return [_to_cd(x, frames, nodes[s], 6) for x in offsets.unit_masses(
                elem, xyz_e[s], lumped, labels[s], zo[s], mass[:, s], bool(off[s].any()), **t)]

        m = units()  # per area (a tapered element's NSM)
        mt = units(**tap) if tap else m  # per unit thickness T: the corners' profile

        def moved(c, m=mt):  # sum of c[i] (n,) times the mass of moment i
            return sum(c[i][s, None, None] * m[i] for i in range(len(m)))

        out.append(None if not np.any(mbase[:, s]) and not np.any(area[:, s]) else
                   moved(mbase) + moved(area, m))
        out += [None if d is None or not np.any(d[:, s]) else moved(d) for d in deriv_m]
        cache: dict = {}  # a PCOMP's basis moduli: their parts, once a chunk
        for _, part, mask, _, moduli in thick:
            if not mask[s].any():
                out.append(None)
            elif part == "mass":  # on the reference plane, ZOFFS from the grids
                out.append(moved(offsets.at_height(np.asarray(mask, float), zo)))
            elif moduli is not None:  # a PCOMP's unit basis
                key = tuple(id(c) for c in (*moduli[:3], moduli[4]))
                if key not in cache:
                    cond = {} if moduli[4] is None else {"condense_with": moduli[4][s]}
                    cache[key] = offsets.stiffness_parts(
                        elem, xyz_e[s], *(c[s] for c in moduli[:3]), k6rot, labels[s],
                        zk[s], **cond, **kap)
                Rb, pb = cache[key]
                out.append(_to_cd(shells.combine(Rb, pb, {q: mask[s].astype(float)
                                                          for q in moduli[3]}),
                                  frames, nodes[s], 6))
            else:
                out.append(_to_cd(shells.combine(R, parts, {part: mask[s].astype(float)}),
                                  frames, nodes[s], 6))
        return out

    mats = assemble_many(nodes, blocks, 2 + len(kj) + len(mj) + len(thick), n_nodes, 6)
    for i, (_, part, _, term, _) in enumerate(thick):
        trip = type(k0)()
        _add(trip, mats[2 + len(kj) + len(mj) + i], 6)
        extra.append(("m" if part == "mass" else "k", trip, term))
    _add_all(mats, k0, kj, m0, mj, 6)


def _solids(bdf, elems, kind, grid, xyz, frames, n_nodes, consistent, wtmass, pindex,
            values, k0, m0, kj, mj) -> None:
    k = solids.NODES[kind]
    labels = [f"{e.type} {e.eid}" for e in elems]
    nodes = np.array([[grid(g, lab) for g in e.node_ids[:k]]
                      for e, lab in zip(elems, labels, strict=True)])
    if kind in solids.MID_EDGES:
        solids.check_mid_edges(xyz[nodes], solids.MID_EDGES[kind], labels)
    mats: dict = {}
    aniso: dict = {}  # element index -> MAT9 moduli in basic
    mid = np.zeros(len(elems), int)
    for i, (e, lab) in enumerate(zip(elems, labels, strict=True)):
        prop = bdf.properties.get(e.pid)
        if prop is None or prop.type != "PSOLID":
            raise InputError(f"{lab}: property PSOLID {e.pid} is not defined")
        where = f"PSOLID {e.pid}"
        for name, default in (("isop", None), ("integ", None), ("fctn", "SMECH")):
            v = getattr(prop, name, default)
            if v not in (default, "", None) and str(v).strip().upper() not in (default, ""):
                raise InputError(f"{where}: {name.upper().replace('INTEG', 'IN')} = {v} is "
                                 f"not supported (blank: NASTRAN's default element)")
        cordm = getattr(prop, "cordm", 0)
        if cordm not in (0, -1, None) and cordm not in bdf.coords:
            raise InputError(f"{where}: CORDM {cordm} is not a defined coordinate system")
        mat = bdf.materials.get(prop.mid)
        if mat is not None and mat.type == "MAT9":
            aniso[i] = mat9(bdf, mat, cordm, where)
            mats.setdefault(prop.mid, mat)
        elif prop.mid not in mats:
            mats[prop.mid] = _mat1(bdf, prop.mid, where, solid=True)
        mid[i] = prop.mid
    iso = [mats[m].type == "MAT1" for m in mid]
    E = np.array([mats[m].e if o else 1.0 for m, o in zip(mid, iso, strict=True)])
    nu = np.array([mats[m].nu if o else 0.0 for m, o in zip(mid, iso, strict=True)])
    rho = np.array([mats[m].rho or 0.0 for m in mid])
    unit = solids.isotropic_elasticity(np.ones(len(elems)), nu)
    for i, c in aniso.items():
        unit[i] = c
    kfac, mfac = E.copy(), wtmass * rho
    dk = [None for _ in kj]
    dm = [None for _ in mj]
    for (card, cid), slots in pindex.items():
        if card == "MAT1" and cid in mats and mats[cid].type == "MAT1":
            _linear_in_e(mats[cid], slots)
            if "E" in slots:
                dk[slots["E"]] = np.where(mid == cid, 1.0, 0.0)
            if "RHO" in slots:
                dm[slots["RHO"]] = np.where(mid == cid, wtmass, 0.0)
    kfac, mfac = fixed(kfac, dk, values), fixed(mfac, dm, values)
    lumped = not consistent
    if lumped and kind == "CTETRA10":
        _warn_tet10_lumping(labels)
    xyz_e = xyz[nodes]

    def blocks(s: slice) -> list:
        ku = _to_cd(solids.solid_stiffness(xyz_e[s], unit[s], labels[s]), frames, nodes[s], 3)
        m = _to_cd(solids.solid_mass(xyz_e[s], lumped, labels[s]), frames, nodes[s], 3)
        return scaled(ku, m, s, kfac, dk, mfac, dm)

    _add_all(assemble_many(nodes, blocks, 2 + len(kj) + len(mj), n_nodes, 3),
             k0, kj, m0, mj, 3)


def _warn_tet10_lumping(labels: list[str]) -> None:
    """Say that a lumped CTETRA10 mass is HRZ's, not MSC's (tools/tet10_mass.py)."""
    warnings.warn(
        f"{len(labels)} CTETRA10 (the first {labels[0]}): lumped mass (PARAM,COUPMASS "
        "absent or <= 0) is the coupled mass's diagonal scaled to the element's mass (HRZ, "
        "as Autodesk Nastran's QRG states); MSC Nastran puts a 10-node tetrahedron's lumped "
        "mass on its mid-edge grids by an unpublished rule (pyn_tet10, 2 elements: ours 7-23 "
        "% below MSC's frequencies); the two lumpings converge as h^2 (equal shares on the "
        "mid-edge grids are within 0.6 % of HRZ on a bar of 16 x 4 x 4 cells); "
        "PARAM,COUPMASS,1 gives the coupled mass every NASTRAN shares", stacklevel=2)


def fixed(total: np.ndarray, terms: list, values) -> np.ndarray:
    """The per-element factor left fixed once each parameter's share (``values[j]``
    times ``terms[j]``, None where it has none) is taken out of ``total``."""
    return total - sum(values[j] * d for j, d in enumerate(terms) if d is not None)


def scaled(ku, m, s: slice, kfac, dk, mfac, dm) -> list:
    """Element blocks K, each K_j, M, each M_j of elements ``s`` from their unit stiffness
    ``ku`` and mass ``m`` and the per-element factors (None where zero)."""
    return ([kfac[s, None, None] * ku if np.any(kfac[s]) else None]
            + [None if d is None or not np.any(d[s]) else d[s, None, None] * ku for d in dk]
            + [mfac[s, None, None] * m if np.any(mfac[s]) else None]
            + [None if d is None or not np.any(d[s]) else d[s, None, None] * m for d in dm])


def _to_cd(blocks: np.ndarray, frames: np.ndarray, nodes: np.ndarray, per_node: int
           ) -> np.ndarray:
    """Element blocks (n, m, m) in basic axes turned to each grid's displacement axes
    (CD; ``frames`` rows): F K F^T node block by node block."""
    F = frames[nodes]  # (n, k, 3, 3)
    if np.all(F == np.eye(3)):
        return blocks
    n, k = nodes.shape
    T = np.zeros((n, k * per_node, k * per_node))
    for a in range(k):
        for b in range(0, per_node, 3):
            r = a * per_node + b
            T[:, r:r + 3, r:r + 3] = F[:, a]
    return T @ blocks @ np.swapaxes(T, 1, 2)


def _add(trip, mat, per_node: int) -> None:
    """Add a matrix assembled ``per_node`` coordinates a node to the 6-a-node triplets."""
    if mat.nnz == 0:
        return
    if per_node == 6:  # already numbered as the model
        trip.add_matrix(mat)
        return
    coo = mat.tocoo()
    r, c = coo.row.astype(np.int64), coo.col.astype(np.int64)
    trip.add(6 * (r // per_node) + r % per_node, 6 * (c // per_node) + c % per_node, coo.data)


def _add_all(mats, k0, kj, m0, mj, per_node: int) -> None:
    """Add assembled [K0, K_1.., M0, M_1..] (``assemble_many``'s order) to their triplets."""
    for trip, mat in zip([k0, *kj, m0, *mj], mats, strict=False):  # then the caller's own
        _add(trip, mat, per_node)
