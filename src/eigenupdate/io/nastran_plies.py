"""Shell thicknesses as parameters: PSHELL T (:func:`thickness_terms`) and PCOMP ply
thicknesses (``PCOMP pid Tk``, k the card's ply; :func:`ply_terms`), and the plies'
MAT8 moduli E1, E2, NU12, G12, G1Z, G2Z and RHO (:func:`ply_terms`).

A shell's stiffness is linear in the laminate's A, D and H in element axes, and those
are the laminate's own A0(t), D0(t), H0(t) turned by the element's material angle phi:
A = T(phi)^T A0 T(phi) (:func:`eigenupdate.model.laminate.rotate_plane`, congruent in
each entry of A0). So K = sum_ij A0_ij(t) K^A_ij + D0_ij(t) K^D_ij + H0_ij(t) K^H_ij with
fixed matrices assembled from unit moduli turned per element, and coefficient functions
of the ply thicknesses (:class:`~eigenupdate.model.laminate.PlyStackEntry`; a blank Z0
is -T/2 and moves with T; a Z0 given on the card stays, which a thickness change turns
into membrane-bending coupling: refused). The drilling penalty follows A's in-plane
shear entry, so it rides with the membrane basis; the CQUAD4, CTRIA3, CTRIA6 shear
factor T^2 / (T^2 + alpha h^2) is a term per element size, as for a PSHELL's T.
The mass per area WTMASS (sum RHO_k t_k + NSM) is linear in each t_k. A CQUAD4's
membrane condenses Wilson's modes, which is not linear in A: where the plies' plane
moduli are equal (A0 = T q) it is T times one part; else the modes are condensed as under
the deck's A0 (:func:`eigenupdate.model.shells.local_parts` ``condense_with``), linear in
A, exact at the deck's thicknesses and a Ritz approximation (stiffer by the square of
the change of A's shape) at others.

A MAT8 modulus enters A0, D0, H0 through the plies' Q (and a rigid ply's shear, a
multiple of its reference shear modulus) on the same basis: the coefficient functions
take the plies' moduli from x too (:class:`eigenupdate.model.ply_moduli.PlyModuli`), so
thickness and modulus parameters of one PCOMP share them; one MAT8 parameter moves every
ply of that MID. The same A0 shape then moves with the moduli, so a CQUAD4 always
condenses as under the deck's A0 (exact too when every modulus scales by one factor).
The mass is WTMASS sum RHO_k t_k: one term per (RHO, thickness) pair. A MAT8's RHO alone
(no modulus or thickness of that PCOMP a parameter) stays a linear parameter
(:mod:`eigenupdate.io.nastran_continuum`), its plies' mass at their height.
"""

from __future__ import annotations

import warnings

import numpy as np

from eigenupdate.errors import EigenupdateWarning, InputError
from eigenupdate.io.nastran_materials import RIGID_SHEAR
from eigenupdate.model import laminate, ply_moduli, shells
from eigenupdate.model.parametric import FunctionTerm, Term
from eigenupdate.model.shells_quadratic import stabilisation_ratio

_SYM3 = ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))
_SYM2 = ((0, 0), (0, 1), (1, 1))
PARTS = (("membrane", "drilling"), ("bending",), ("shear",))


def _unit(i: int, j: int, r: int) -> np.ndarray:
    e = np.zeros((r, r))
    e[i, j] = e[j, i] = 1.0
    return e


def clear_linear(deriv_k, deriv_m, on: np.ndarray) -> None:
    """Drop the linear derivatives of the elements ``on``: their parameter enters through
    function terms instead."""
    for d in deriv_k:
        for c in d.values():
            c[on] = 0.0
    for j, d in enumerate(deriv_m):
        if d is not None:
            deriv_m[j] = np.where(on, 0.0, d)


def ply_slots(pid: int, stack: dict, slots: dict) -> tuple[int, ...]:
    """Parameter index of each ply of the stack (-1: fixed) from ``{"Tk": j}``."""
    n_card = stack["n_card"]
    by_card = [-1] * n_card
    for name, j in slots.items():
        k = int(name[1:])
        if not 1 <= k <= n_card:
            raise InputError(f"PCOMP {pid} field {name}: the card has plies 1-{n_card}")
        by_card[k - 1] = j
    return tuple(by_card[c] for c in stack["card_ply"])


def _stacks(elems, rows, pindex) -> tuple[list[int], dict]:
    """PCOMP(G)s whose ply thicknesses or ply materials' MAT8 moduli are parameters, and
    those moduli's slots {mid: {field: j}}; refuses a MAT8 modulus of a PSHELL's MIDi."""
    moduli = {cid: {f: j for f, j in slots.items() if f != "RHO"}
              for (card, cid), slots in pindex.items() if card == "MAT8"}
    moduli = {cid: s for cid, s in moduli.items() if s}
    pids = set()
    for e, p in zip(elems, rows, strict=True):
        if p["laminate"] is None:
            hit = sorted(moduli.keys() & {p["mid1"], p["mid2"], p["mid3"]})
            if hit:
                raise InputError(f"MAT8 {hit[0]} field {sorted(moduli[hit[0]])[0]}: not a "
                                 f"parameter as PSHELL {e.pid}'s MID1/MID2/MID3 (a MAT8's "
                                 f"moduli are parameters as PCOMP plies only)")
        elif ("PCOMP", e.pid) in pindex or moduli.keys() & p["plies"]:
            pids.add(e.pid)
    return sorted(pids), moduli


def _ply_moduli(st: dict, moduli: dict, rho: dict) -> tuple[list, list, dict]:
    """The plies' (MAT8 slots, RHO slots) per ply and each used slot's deck value."""
    mslots, rslots, x0 = [], [], {}
    for k, mid in enumerate(st["mid"]):
        fields = moduli.get(mid, {})
        vals = st["mat8"].get(mid)
        for name, j in fields.items():
            i = ply_moduli.NAMES.index(name)
            if np.isnan(vals[i]):
                raise InputError(f"MAT8 {mid} field {name}: blank (MSC: a rigid transverse "
                                 f"shear) is not a parameter; give it on the card")
            x0[j] = vals[i]
        mslots.append(tuple(fields.get(n, -1) for n in ply_moduli.NAMES))
        r = rho.get(mid, -1)
        if r >= 0:
            x0[r] = st["rho"][k]
        rslots.append(r)
    return mslots, rslots, x0


def ply_terms(elems, rows, pindex, phi, size, wtmass, deriv_k, deriv_m, quad4: bool,
              tria6: bool = False) -> list:
    """(pid, part, element mask, term, moduli) of every PCOMP with a ply thickness
    parameter or a ply whose MAT8's moduli are parameters: part "stiffness" with
    ``moduli`` (cm, cb, cs) per element (unit basis turned by ``phi``), the parts they
    make and the membrane moduli CQUAD4 condenses with (None: its own), or "mass".
    Clears those elements' linear derivatives. ``tria6``: ``size`` holds CTRIA6's
    stabilisation ratio at the deck's values
    (:func:`eigenupdate.model.shells_quadratic.stabilisation_ratio`), which a change of
    the plies moves where they differ in material, or a modulus: a note says so."""
    out = []
    pids = np.array([e.pid for e in elems])
    n = len(elems)
    todo, moduli = _stacks(elems, rows, pindex)
    rho = {cid: s["RHO"] for (card, cid), s in pindex.items() if card == "MAT8" and "RHO" in s}
    for pid in todo:
        on = pids == pid
        p = rows[int(np.flatnonzero(on)[0])]
        st = p["stack"]
        slots = pindex.get(("PCOMP", pid), {}) if p["card"] == "PCOMP" else {}
        mine = sorted(moduli.keys() & p["plies"])
        where = (f"PCOMP {pid} field {sorted(slots)[0]}" if slots else
                 f"MAT8 {mine[0]} field {sorted(moduli[mine[0]])[0]} ({p['card']} {pid}'s "
                 f"plies)")
        shared = sorted(m for m in p["plies"] if pindex.get(("MAT1", m)))
        if shared:
            raise InputError(f"{where}: not a parameter together with MAT1 {shared[0]}'s "
                             f"fields (a material of its plies)")
        z0 = p["laminate"][3]
        if st.get("z0_given") and (slots or abs(z0 + p["T"] / 2) > 1e-12 * p["T"]):
            raise InputError(f"{where}: not a parameter with Z0 given on the card (NASTRAN "
                             f"keeps it when the plies change, which makes the stack "
                             f"unsymmetric: B != 0; off the mid-plane, the plies' mass "
                             f"moments are not parametrised); leave Z0 blank (-T/2)")
        sl = ply_slots(pid, st, slots)
        mslots, rslots, x0 = _ply_moduli(st, moduli, rho)
        q0 = laminate.rotate_plane(st["q"], st["theta"])  # laminate axes
        g0 = laminate.rotate_shear(st["g"], st["theta"])
        t0 = st["t"]
        for k, s in enumerate(sl):
            if s >= 0:
                x0[s] = t0[k]
        # the function of x = the used parameters' values, indexed 0..
        used = sorted({s for s in sl if s >= 0} | {j for m in mslots for j in m if j >= 0})
        index = tuple(used)
        local = tuple(used.index(s) if s >= 0 else -1 for s in sl)
        pm = None
        if any(j >= 0 for m in mslots for j in m):
            mats = sorted(set(st["mid"]))
            first = [st["mid"].index(m) for m in mats]
            pm = ply_moduli.PlyModuli(
                np.array([st["mat8"].get(m, np.zeros(6)) for m in mats]),
                tuple(tuple(used.index(j) if j >= 0 else -1 for j in mslots[k]) for k in first),
                st["q"][first], st["g"][first],
                tuple(RIGID_SHEAR / laminate.SHEAR_FACTOR
                      if np.isnan(st["mat8"].get(m, np.zeros(6))[4]) else 0.0 for m in mats),
                tuple(mats.index(m) for m in st["mid"]), st["theta"],
                tuple(f"MAT8 {m}" for m in mats))
        # a generic point near the deck's values (NU12 from 0 too): an entry, a coupling
        # or a moment that is 0 there is 0 structurally, not by the deck's numbers
        xp = np.array([x0[j] * (1 + 0.05 * (i + 1) / len(used)) for i, j in enumerate(used)])
        xp += [0.01 * any(m[2] == j for m in mslots) for j in used]
        qp, gp = pm(xp) if pm is not None else (q0, g0)
        tp = laminate.PlyStackEntry(q0, t0, local, "A", (0, 0)).thicknesses(xp)
        _symmetric(where, sl, t0, q0, tp, qp, st["rho"], rslots)
        if tria6 and not np.isclose(_ratio(tp, qp, gp), _ratio(t0, q0, g0), rtol=1e-9, atol=0):
            held_stabilisation(where, "plies of several materials" if pm is None else
                               "moduli that move")
        clear_linear(deriv_k, deriv_m, on)

        def term(kind, entry, q, c=0.0, index=index, t0=t0, local=local, pm=pm):
            return FunctionTerm(None, index, laminate.PlyStackEntry(q, t0, local, kind, entry,
                                                                    c, pm))

        def some(e, a, b):
            return np.any(a[:, e[0], e[1]]) or np.any(b[:, e[0], e[1]])

        same = pm is None and np.abs(q0 - q0[:1]).max() <= 1e-12 * np.abs(q0).max()
        # CQUAD4 with plies that differ (or moduli that move): its incompatible modes
        # condensed as under the deck's A0 (shells.local_parts), so that the membrane is
        # linear in A (exact at the deck, Ritz elsewhere; exact for A scaled)
        a0 = None
        if not same and quad4:
            a0 = np.broadcast_to(np.eye(3), (n, 3, 3)).copy()
            a0[on] = laminate.rotate_plane(np.einsum("p,pij->ij", t0, q0), phi[on])
        # moduli of basis i: membrane, bending and shear entry i in one local_parts call
        # (shared arrays: the assembly computes each set once); unit membrane moduli off
        # this PCOMP, and A0's own shape when its plies agree (CQUAD4's condensation)
        basis = []
        for i, e in enumerate(_SYM3):
            cm = np.broadcast_to(np.eye(3), (n, 3, 3)).copy()
            cb, cs = np.zeros((n, 3, 3)), np.zeros((n, 2, 2))
            cm[on] = laminate.rotate_plane(q0[0] if same else _unit(*e, 3), phi[on])
            cb[on] = laminate.rotate_plane(_unit(*e, 3), phi[on])
            if i < len(_SYM2):
                cs[on] = laminate.rotate_shear(_unit(*_SYM2[i], 2), phi[on])
            basis.append((cm, cb, cs))
        if same:  # A0 = T q: one membrane term
            out.append((pid, "stiffness", on, term("A", (0, 0), np.ones((len(sl), 1, 1))),
                        (*basis[0], PARTS[0], None)))
        else:
            out += [(pid, "stiffness", on, term("A", e, q0), (*basis[i], PARTS[0], a0))
                    for i, e in enumerate(_SYM3) if some(e, q0, qp)]
        out += [(pid, "stiffness", on, term("D", e, q0), (*basis[i], PARTS[1], a0))
                for i, e in enumerate(_SYM3) if some(e, q0, qp)]
        hs = np.unique(size[on])
        shear = [(i, e) for i, e in enumerate(_SYM2) if some(e, g0, gp)]
        if len(hs) > MAX_SIZES:
            # the stabilisation f(T) = T^2 / (T^2 + alpha h^2) per element as f(T0) +
            # f'(T0) (T - T0), T0 the deck's total: H f(T0) + H (T - T0) f'(T0)
            T0 = float(np.sum(t0))
            c = shells.ALPHA * size**2
            f0 = np.where(on, T0**2 / (T0**2 + c), 0.0)
            f1 = np.where(on, 2 * T0 * c / (T0**2 + c) ** 2, 0.0)
            out += [(pid, "stiffness", w, term(kind, e, g0), (*basis[i], PARTS[2], a0))
                    for w, kind in ((f0, "H"), (f1, "H1")) if np.any(w) for i, e in shear]
            _linearised(f"PCOMP {pid} (its ply thicknesses)", len(hs), T0)
            hs = []
        for h in hs:
            mask = on & (size == h)
            out += [(pid, "stiffness", mask,
                     term("H", e, g0, float(shells.ALPHA * h**2)), (*basis[i], PARTS[2], a0))
                    for i, e in shear]
        out += _mass_terms(pid, on, sl, rslots, st["rho"], t0, wtmass)
        p["fixed_mass"] = sum(st["rho"][i] * t0[i] for i, k in enumerate(sl)
                              if k < 0 and rslots[i] < 0)
    return out


def _symmetric(where, sl, t0, q0, tp, qp, rho, rslots) -> None:
    """Refuse a stack whose B or first mass moment is not 0 at every parameter value:
    each thickness parameter alone, and all at the generic point (thicknesses ``tp``,
    turned moduli ``qp``); the mass of each RHO parameter's plies on its own."""
    cases = [(np.where(np.array(sl) == s, 1.5 * t0, t0), q0) for s in sorted(set(sl) - {-1})]
    for t, q in cases + [(tp, qp)]:
        z = -t.sum() / 2 + np.concatenate([[0.0], np.cumsum(t)])
        B = np.einsum("p,pij->ij", np.diff(z**2) / 2, q)
        if np.abs(B).max() > 1e-9 * np.abs(q).max() * t.sum() ** 2:
            raise InputError(f"{where}: not a parameter: a change makes the stack "
                             f"unsymmetric (membrane-bending coupling B != 0); use a "
                             f"symmetric stack (LAM=SYM)")
    r = np.asarray(rho, float)
    groups = [r] + [np.where(np.array(rslots) == j, 1.0, 0.0) for j in set(rslots) - {-1}]
    for t in (t0, *(c[0] for c in cases), tp):  # its mass stays on the mid-plane
        zz = -t.sum() / 2 + np.concatenate([[0.0], np.cumsum(t)])
        for w in groups:
            if abs(np.sum(w * np.diff(zz**2) / 2)) > 1e-9 * max(w.max(), 1e-300) * t.sum()**2:
                raise InputError(f"{where}: not a parameter: the plies' mass is not "
                                 f"symmetric about the mid-plane (a first mass moment)")


def _mass_terms(pid, on, sl, rslots, rho, t0, wtmass) -> list:
    """WTMASS sum RHO_k t_k of the plies with a parametric thickness or density, one
    term per (RHO, thickness) pair of slots."""
    groups: dict = {}
    for k, (s, r) in enumerate(zip(sl, rslots, strict=True)):
        if s >= 0 or r >= 0:
            # (r, s) both parameters: x_r x_s; one: the other's deck value as coefficient
            groups[(r, s)] = groups.get((r, s), 0.0) + (1.0 if r >= 0 else rho[k]) * (
                1.0 if s >= 0 else t0[k])
    return [(pid, "mass", on, Term(None, tuple((j, 1.0) for j in key if j >= 0),
                                   wtmass * c), None)
            for key, c in sorted(groups.items()) if c]


def _ratio(t: np.ndarray, q: np.ndarray, g: np.ndarray) -> float:
    """CTRIA6's stabilisation ratio of a stack of turned moduli q, g at thicknesses t:
    its bending per T^3 and shear per T, as the assembly passes them
    (:mod:`eigenupdate.io.nastran_continuum`), so a one-material stack's is its
    material's at any thickness."""
    T = float(np.sum(t))
    _, _, D, H = laminate.abd(q, g, t, -T / 2, np.zeros((1, len(t))))
    return float(stabilisation_ratio(D[0] / T**3, H[0] / T)[()])


def held_stabilisation(where: str, why: str) -> None:
    """Note that CTRIA6's stabilisation ratio is held at the deck's values (``why``: what
    moves it)."""
    warnings.warn(f"{where}: {why}: CTRIA6's shear stabilisation is held at the deck's "
                  f"section (second order in the change: update again from the written "
                  f"BDF)", EigenupdateWarning, stacklevel=3)


MAX_SIZES = 64
"""Most distinct CQUAD4, CTRIA3, CTRIA6 sizes of one PSHELL whose T (or PCOMP whose ply
thicknesses) are parameters for which each size's shear part (T^3 / (T^2 + alpha h^2))
is a term of its own; beyond it the shear part is linearised about the deck's T
(:func:`thickness_terms`, :func:`ply_terms`)."""


def _linearised(what: str, sizes: int, T0: float) -> None:
    warnings.warn(f"{what}: the transverse shear of its {sizes} element sizes is "
                  f"linearised about the deck's T = {T0:g} (exact there, second order in "
                  f"the change elsewhere); after a large change, update again from the "
                  f"written BDF", EigenupdateWarning, stacklevel=3)


def thickness_terms(elems, rows, pindex, size, wtmass, deriv_k, deriv_m,
                     fixed_shear: np.ndarray, own: np.ndarray | None = None) -> list:
    """(pid, part, element weights, term) of every PSHELL whose T is a parameter:
    membrane and drilling E1 T, bending E2 T^3 (12I/T^3 in the moduli), shear G3 s(T) (T
    on a CQUAD8, per size on a CQUAD4, CTRIA3, CTRIA6), mass WTMASS RHO1 T (NSM stays
    fixed); a MAT1 E or RHO that is a parameter too multiplies in. Clears those elements'
    linear derivatives.

    An auto-meshed region has as many sizes as elements. Beyond MAX_SIZES the shear part
    is s(T0) + s'(T0) (T - T0) per element, T0 the deck's T: exact value and derivative
    at the deck, second order in T - T0 elsewhere (a note says so; an update from the
    written BDF removes it). Its part without T is added to ``fixed_shear`` (G3 times it,
    per element) where E is not a parameter too. Elements ``own`` (n,) keep their own
    thickness (T1-T4 given, TFLAG 0: :mod:`eigenupdate.io.nastran_corners`): no terms."""
    out = []
    pids = np.array([e.pid for e in elems])
    for (card, pid), slots in sorted(pindex.items()):
        on = (pids == pid) & (True if own is None else ~own)
        if card not in ("PSHELL", "PQUAD2", "PTRIA2") or "T" not in slots:
            continue
        if (kept := int(np.sum(pids == pid)) - int(on.sum())) > 0:  # NASTRAN's meaning
            warnings.warn(f"{card} {pid}: T is a parameter but {kept} of its "
                          f"{int(np.sum(pids == pid))} elements give their own corner "
                          f"thicknesses T1-T4 (TFLAG 0) and do not follow it",
                          EigenupdateWarning, stacklevel=2)
        if not on.any():
            continue
        p = rows[int(np.flatnonzero(on)[0])]
        t = slots["T"]
        clear_linear(deriv_k, deriv_m, on)

        def times(mid, value, tied=True):
            """(powers, coefficient) of a material's modulus: its E a parameter or not."""
            e = pindex.get(("MAT1", mid), {}).get("E")
            return ((((e, 1.0),), 1.0) if e is not None and tied else ((), value))

        for part, mid, value, power in (("membrane", p["mid1"], p["E1"], 1.0),
                                        ("drilling", p["mid1"], p["E1"], 1.0),
                                        ("bending", p["mid2"], p["E2"], 3.0)):
            if value:
                pw, c = times(mid, value)
                out.append((pid, part, on, Term(None, ((t, power),) + pw, c)))
        if p["G3"]:
            pw, c = times(p["mid3"], p["G3"], p["tied3"])
            c = c if not pw else p["G3"] / p["E3"]
            sizes = np.unique(size[on])
            if sizes.size > MAX_SIZES:
                # s(T) = a + b T per element (CQUAD8: h = 0, s = T: a = 0, b = 1 exactly)
                T0 = float(p["T"])
                b = np.where(on, shells.shear_thickness_derivative(T0, size), 0.0)
                a = np.where(on, shells.shear_thickness(T0, size), 0.0) - b * T0
                out.append((pid, "shear", b, Term(None, ((t, 1.0),) + pw, c)))
                if pw:
                    out.append((pid, "shear", a, Term(None, pw, c)))
                else:
                    fixed_shear += c * a
                _linearised(f"{card} {pid} field T", sizes.size, T0)
            for h in sizes if sizes.size <= MAX_SIZES else ():
                mask = on & (size == h)
                if h == 0:  # CQUAD8: s(T) = T
                    out.append((pid, "shear", mask, Term(None, ((t, 1.0),) + pw, c)))
                    continue
                out.append((pid, "shear", mask, FunctionTerm(
                    None, (t, *(j for j, _ in pw)),
                    shells.ShearThickness(float(shells.ALPHA * h**2), float(c), bool(pw)))))
        rho = [(mid, r) for mid, (r, _) in p["mass"].items()]
        for mid, r in rho:
            j = (pindex.get(("MAT1", mid)) or pindex.get(("MAT8", mid)) or {}).get("RHO")
            pw, c = ((((j, 1.0),), wtmass) if j is not None else ((), wtmass * r))
            if pw or r:
                out.append((pid, "mass", on, Term(None, ((t, 1.0),) + pw, c)))
    return out
