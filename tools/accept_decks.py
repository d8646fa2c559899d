"""Acceptance decks for shells and solids (issue 20): fresh NASTRAN decks as a pre-processor
writes them, each with an independent reference, written into a folder and optionally run.

Usage (in the NASTRAN venv, from the repository root)::

    PYTHONPATH=src python tools/accept_decks.py OUTDIR [--run] [-k SUBSTRING]

Writes OUTDIR/NAME.bdf and NAME.toml (a study of the deck alone) for every deck, and for the
CalculiX references OUTDIR/ccx/NAME.inp (the same nodes and elements). With ``--run`` it runs
``eigenupdate frequencies`` on each deck (and ``ccx`` where its reference is CalculiX and
``ccx`` is on the path) and prints, per deck, each compared mode's relative difference
from its reference (for a pair, the largest difference between the two decks). References:

* ``closed``: closed forms - Leissa's clamped square plate (lambda = omega a^2 sqrt(rho h /
  D): 35.9852, 73.3938, 73.3938, 108.2165, 131.5808, 132.2048), the clamped circular plate
  (10.2158, 21.2604 (2), 34.8770 (2), 39.7711), the Mindlin and FSDT (cross-ply laminate)
  Navier solutions of simply supported plates without rotary inertia (NASTRAN's shells
  have none), shear factor 5/6. Two meshes per case: the error must fall with the mesh.
* ``ccx``: CalculiX on the same mesh (C3D8I, C3D20, C3D10, C3D6, C3D15 with consistent
  mass, so the decks set COUPMASS; S8R shells): the difference is the formulations' and
  falls with the mesh.
* ``same``: two decks that must agree to round-off (offsets WA/WB and ZOFFS against
  explicit offset grids tied by RBE2; RBE2 and RBE3 against hand-written MPC equations).

OUTDIR must lie outside the repository.
"""

from __future__ import annotations

import argparse
import itertools
import shutil
import sys
from pathlib import Path

import numpy as np
from accept_cards import (
    CCX_TYPE,
    STEEL,
    Case,
    Nodes,
    bar_mesh,
    ccx_input,
    deck,
    free,
    large,
    run_ccx,
    run_ours,
    small,
    spc1,
)

LEISSA = [35.9852, 73.3938, 73.3938, 108.2165, 131.5808, 132.2048]
CIRCLE = [10.2158, 21.2604, 21.2604, 34.8770, 34.8770, 39.7711]

# ---- plates against closed forms -------------------------------------------------------

def _hz(lam: float, a: float, h: float, E=STEEL[0], nu=STEEL[1], rho=STEEL[2]) -> float:
    D = E * h**3 / (12 * (1 - nu**2))
    return lam / a**2 * np.sqrt(D / (rho * h)) / (2 * np.pi)


def clamped_square(n: int, skew: bool, a=1.0, h=0.005) -> str:
    """CQUAD4, clamped edges; ``skew``: interior grids moved (random and a sine shear)
    and written large-field."""
    g = np.linspace(0, a, n + 1)
    X, Y = (v.ravel() for v in np.meshgrid(g, g, indexing="ij"))
    inner = (X > 0) & (X < a) & (Y > 0) & (Y < a)
    if skew:
        d = (np.random.default_rng(7).random((X.size, 2)) - 0.5) * 0.4 * a / n
        shear = 0.12 * a * np.sin(np.pi * X / a) * np.sin(np.pi * Y / a)
        X = X + np.where(inner, d[:, 0] + shear, 0)
        Y = Y + np.where(inner, d[:, 1], 0)
    card = large if skew else small
    nid = np.arange(X.size).reshape(n + 1, n + 1) + 1
    cards = [card("GRID", i + 1, "", float(x), float(y), 0.0)
             for i, (x, y) in enumerate(zip(X, Y, strict=True))]
    cards += [small("CQUAD4", k + 1, 1, nid[i, j], nid[i + 1, j], nid[i + 1, j + 1], nid[i, j + 1])
              for k, (i, j) in enumerate(itertools.product(range(n), range(n)))]
    cards += [small("PSHELL", 1, 1, h, 1, "", 1), small("MAT1", 1, STEEL[0], "", *STEEL[1:])]
    return deck(cards + spc1(1, 123456, nid[~inner.reshape(n + 1, n + 1)]))


def clamped_circle(nr: int, R=0.5, h=0.005) -> str:
    """CTRIA3 rings (6 i triangles-sides on ring i), free field, lower case."""
    pts, rings = [(0.0, 0.0)], [[0]]
    for i in range(1, nr + 1):
        th = 2 * np.pi * np.arange(6 * i) / (6 * i)
        rings.append(list(range(len(pts), len(pts) + 6 * i)))
        pts += [(R * i / nr * np.cos(t), R * i / nr * np.sin(t)) for t in th]
    tris = []
    for i in range(1, nr + 1):
        inner, outer = rings[i - 1], rings[i]
        for s, j in itertools.product(range(6), range(i)):
            o0, o1 = outer[(s * i + j) % len(outer)], outer[(s * i + j + 1) % len(outer)]
            k = (s * (i - 1) + j) % len(inner)
            tris.append((inner[k], o0, o1))
            if 0 < j + 1 < i:
                tris.append((inner[k], o1, inner[(k + 1) % len(inner)]))
    cards = [free("grid", i + 1, "", float(x), float(y), 0.0) for i, (x, y) in enumerate(pts)]
    cards += [free("ctria3", k + 1, 3, *(v + 1 for v in t)) for k, t in enumerate(tris)]
    cards += [f"pshell,3,7,{h!r},7,,7\t$ tab, then a comment", "mat1,7,2.e11,,0.3,7850."]
    edge = [v + 1 for v in rings[-1]]
    cards += [free("spc1", 1, 123456, *edge[k:k + 7]) for k in range(0, len(edge), 7)]
    return deck(cards, "sol 103\ncend\nspc = 1\nbegin bulk")


def mindlin_navier(a, b, D, kGh, rho_h, nu, modes=8) -> list[float]:
    """Lowest frequencies (Hz) of the hard simply supported Mindlin plate, no rotary
    inertia (the rotations condensed)."""
    out = []
    for m, n in itertools.product(range(1, 8), repeat=2):
        al, be = m * np.pi / a, n * np.pi / b
        K = np.array([[kGh * (al**2 + be**2), kGh * al, kGh * be],
                      [kGh * al, D * (al**2 + (1 - nu) / 2 * be**2) + kGh,
                       D * (1 + nu) / 2 * al * be],
                      [kGh * be, D * (1 + nu) / 2 * al * be,
                       D * (be**2 + (1 - nu) / 2 * al**2) + kGh]])
        k = K[0, 0] - K[0, 1:] @ np.linalg.solve(K[1:, 1:], K[1:, 0])
        out.append(np.sqrt(k / rho_h) / (2 * np.pi))
    return sorted(out)[:modes]


def ss_quadratic(n: int, kind: str, a=1.0, b=0.8, h=0.04) -> str:
    """CQUAD8 (small field) or CTRIA6 (large field) hard simply supported plate; membrane
    and drilling held on every grid (GRID PS 126)."""
    nx, ny = n, max(1, round(n * b / a))
    nid = np.arange((2 * nx + 1) * (2 * ny + 1)).reshape(2 * nx + 1, 2 * ny + 1) + 1
    els = []
    for i, j in itertools.product(range(nx), range(ny)):
        c = nid[2 * i:2 * i + 3, 2 * j:2 * j + 3]
        if kind == "CQUAD8":
            els.append([c[0, 0], c[2, 0], c[2, 2], c[0, 2], c[1, 0], c[2, 1], c[1, 2], c[0, 1]])
        else:
            els += [[c[0, 0], c[2, 0], c[2, 2], c[1, 0], c[2, 1], c[1, 1]],
                    [c[0, 0], c[2, 2], c[0, 2], c[1, 1], c[1, 2], c[0, 1]]]
    used = set(itertools.chain(*els))
    card = small if kind == "CQUAD8" else large
    cards = [card("GRID", int(nid[i, j]), "", a * i / (2 * nx), b * j / (2 * ny), 0.0, "", 126)
             for i, j in itertools.product(range(2 * nx + 1), range(2 * ny + 1))
             if nid[i, j] in used]
    cards += [small(kind, k + 1, 1, *map(int, e)) for k, e in enumerate(els)]
    cards += [small("PSHELL", 1, 1, h, 1, "", 1), small("MAT1", 1, STEEL[0], "", *STEEL[1:])]
    on_x = [g for g in nid[[0, -1], :].ravel() if g in used]
    on_y = [g for g in nid[:, [0, -1]].ravel() if g in used]
    return deck(cards + spc1(1, 34, on_x) + spc1(1, 35, on_y))


PLY = dict(E1=140e9, E2=10e9, NU12=0.3, G12=5e9, G13=5e9, G23=3.5e9, RHO=1600.0)


def fsdt_navier(angles, t, a, b, modes=6) -> list[float]:
    """Cross-ply laminate (0/90 plies of PLY), SS-1, FSDT with 5/6 sum G t, no rotary
    inertia: the lowest root of each (m, n)."""
    p = PLY
    d = 1 - p["NU12"] ** 2 * p["E2"] / p["E1"]
    Q0 = np.array([[p["E1"], p["NU12"] * p["E2"], 0], [p["NU12"] * p["E2"], p["E2"], 0],
                   [0, 0, p["G12"] * d]]) / d
    z = np.linspace(-len(angles) * t / 2, len(angles) * t / 2, len(angles) + 1)
    A, B, D, H = np.zeros((3, 3)), np.zeros((3, 3)), np.zeros((3, 3)), np.zeros(2)
    for k, ang in enumerate(angles):
        Q = Q0 if ang == 0 else Q0[[1, 0, 2]][:, [1, 0, 2]]
        A, B, D = (A + Q * (z[k + 1] - z[k]), B + Q * (z[k + 1] ** 2 - z[k] ** 2) / 2,
                   D + Q * (z[k + 1] ** 3 - z[k] ** 3) / 3)
        g13 = np.array([p["G13"], p["G23"]])
        H = H + 5 / 6 * t * (g13 if ang == 0 else g13[::-1])
    out = []
    for m, n in itertools.product(range(1, 7), repeat=2):
        al, be = m * np.pi / a, n * np.pi / b
        e = np.array([[-al, 0, 0, 0, 0], [0, -be, 0, 0, 0], [be, al, 0, 0, 0]])
        k = np.array([[0, 0, 0, -al, 0], [0, 0, 0, 0, -be], [0, 0, 0, be, al]])
        s = np.array([[0, 0, al, 1, 0], [0, 0, be, 0, 1]])
        K = e.T @ A @ e + e.T @ B @ k + k.T @ B @ e + k.T @ D @ k + s.T @ np.diag(H) @ s
        Kc = K[:3, :3] - K[:3, 3:] @ np.linalg.solve(K[3:, 3:], K[3:, :3])
        out.append(np.sqrt(np.linalg.eigvalsh(Kc)[0] / (p["RHO"] * len(angles) * t)) / (2 * np.pi))
    return sorted(out)[:modes]


def laminate(n: int, angles, t: float, tri: bool, a=0.5, b=0.4) -> str:
    """PCOMP of MAT8 plies, SS-1 (x edges: v, w, rx held; y edges: u, w, ry); CTRIA3
    ordered with G1-G2 along +-x (NASTRAN's ply axes: the G1-G2 side)."""
    nx, ny = n, round(n * b / a)
    nid = np.arange((nx + 1) * (ny + 1)).reshape(nx + 1, ny + 1) + 1
    cards = [free("GRID", int(nid[i, j]), "", a * i / nx, b * j / ny, 0.0)
             for i, j in itertools.product(range(nx + 1), range(ny + 1))]
    for i, j in itertools.product(range(nx), range(ny)):
        q = [int(v) for v in (nid[i, j], nid[i + 1, j], nid[i + 1, j + 1], nid[i, j + 1])]
        if tri:
            cards += [small("CTRIA3", len(cards), 5, *q[:3]),
                      small("CTRIA3", len(cards) + 1, 5, q[2], q[3], q[0])]
        else:
            cards.append(small("CQUAD4", len(cards), 5, *q))
    plies = itertools.chain(*[(8, t, float(g), "") for g in angles])
    cards.append(small("PCOMP", 5, "", "", "", "", "", "", "", *plies))
    cards.append(small("MAT8", 8, *(PLY[k] for k in ("E1", "E2", "NU12", "G12", "G13", "G23",
                                                     "RHO"))))
    return deck(cards + spc1(1, 234, nid[[0, -1], :].ravel())
                + spc1(1, 135, nid[1:-1, [0, -1]].ravel()))


def plate_cases() -> dict[str, Case]:
    out = {}
    out["clamped_cquad4"] = Case("CQUAD4 clamped square, small field (Leissa)",
                                 {f"cc_q4_{n}": clamped_square(n, False) for n in (12, 24)},
                                 "closed", hz=[_hz(x, 1.0, 0.005) for x in LEISSA])
    out["skewed_cquad4"] = Case("CQUAD4 irregular clamped square, GRID* (Leissa)",
                                {f"cc_skew_{n}": clamped_square(n, True) for n in (12, 24)},
                                "closed", hz=[_hz(x, 1.0, 0.005) for x in LEISSA])
    out["circle_ctria3"] = Case("CTRIA3 clamped circle, free field, lower case (Bessel)",
                                {f"circ_t3_{n}": clamped_circle(n) for n in (6, 12)},
                                "closed", hz=[_hz(x, 0.5, 0.005) for x in CIRCLE])
    E, nu, rho = STEEL
    ref = mindlin_navier(1.0, 0.8, E * 0.04**3 / (12 * (1 - nu**2)),
                         5 / 6 * E / (2 * (1 + nu)) * 0.04,
                         rho * 0.04, nu)
    for kind in ("CQUAD8", "CTRIA6"):
        decks = {f"ss_{kind.lower()}_{n}": ss_quadratic(n, kind) for n in (4, 8)}
        out[f"ss_{kind.lower()}"] = Case(f"{kind} simply supported, a/h 25 (Mindlin-Navier)",
                                         decks, "closed", modes=5, hz=ref)
    for angles, tag in (([0, 90, 90, 0], "0_90_90_0"), ([0, 90], "0_90")):
        for tri in (False, True):
            el = "ctria3" if tri else "cquad4"
            decks = {f"pcomp_{tag}_{el}_{n}": laminate(n, angles, 0.001, tri) for n in (10, 20)}
            out[f"pcomp_{tag}_{el}"] = Case(f"PCOMP [{tag}] {el.upper()} (FSDT Navier)", decks,
                                            "closed", hz=fsdt_navier(angles, 0.001, 0.5, 0.4))
    return out



def solid_cases() -> dict[str, Case]:
    out = {}
    meshes = {"CHEXA8": [(20, 2, 2), (40, 4, 4)], "CHEXA20": [(10, 1, 1), (20, 2, 2)],
              "CTETRA10": [(10, 1, 1), (20, 2, 2)], "CPENTA6": [(20, 2, 2), (40, 4, 4)],
              "CPENTA15": [(10, 1, 1), (20, 2, 2)]}
    for kind, sizes in meshes.items():
        case = Case(f"{kind} cantilever bar, COUPMASS 1 (CalculiX {CCX_TYPE[kind]})", {},
                    "ccx", modes=8)
        card = small if kind in ("CHEXA8", "CPENTA6") else large
        for cells in sizes:
            nodes, nas, ccx = bar_mesh(kind, cells)
            root = [g for g, p in nodes.xyz.items() if p[0] == 0]
            cards = ["PARAM,COUPMASS,1"] + [card("GRID", g, "", *map(float, p))
                                            for g, p in nodes.xyz.items()]
            cards += [small(kind.rstrip("0123456789"), k + 1, 1, *e) for k, e in enumerate(nas)]
            cards += [small("PSOLID", 1, 1), small("MAT1", 1, STEEL[0], "", *STEEL[1:])]
            name = f"bar_{kind.lower()}_{cells[0]}"
            case.decks[name] = deck(cards + spc1(1, 123, root))
            case.ccx[name] = ccx_input(nodes, [("EALL", CCX_TYPE[kind], dict(enumerate(ccx, 1)))],
                                       {"STEEL": STEEL},
                                       ["*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL"],
                                       {g: "1, 3" for g in root}, 8)
        out[kind.lower()] = case
    out["cylinder_cquad8"] = _cylinder()
    out["hexa_quad4_skin"] = _mixed()
    return out


def _cylinder(R=0.2, L=0.6, h=0.004) -> Case:
    """A free-free CQUAD8 cylinder on grids given in a CORD2C (CP) whose axis is basic x,
    origin moved; displacements in it (CD)."""
    o, ex, ez = np.array([1.0, 2.0, 3.0]), np.array([0.0, 1.0, 0.0]), np.array([1.0, 0.0, 0.0])
    case = Case("CQUAD8 free cylinder, CP = CD = CORD2C (CalculiX S8R)", {}, "ccx", modes=10)
    for nth, nz in ((16, 6), (32, 12)):
        nodes, pos, els = Nodes(), {}, []
        for j, i in itertools.product(range(2 * nz + 1), range(2 * nth)):
            if i % 2 and j % 2:
                continue
            th = 2 * np.pi * i / (2 * nth)
            radial = np.cos(th) * ex + np.sin(th) * np.cross(ez, ex)
            g = nodes.at(o + R * radial + L * j / (2 * nz) * ez)
            pos[(i, j)] = (g, 360.0 * i / (2 * nth), L * j / (2 * nz))
        for i, j in itertools.product(range(nth), range(nz)):
            c = [pos[((2 * i + di) % (2 * nth), 2 * j + dj)][0]
                 for di, dj in ((0, 0), (2, 0), (2, 2), (0, 2), (1, 0), (2, 1), (1, 2), (0, 1))]
            els.append(c)
        cards = [large("CORD2C", 10, 0, *map(float, o), *map(float, o + ez), *map(float, o + ex))]
        cards += [small("GRID", g, 10, R, th, z, 10) for g, th, z in pos.values()]
        cards += [small("CQUAD8", k + 1, 1, *e) for k, e in enumerate(els)]
        cards += [small("PSHELL", 1, 1, h, 1, "", 1), small("MAT1", 1, STEEL[0], "", *STEEL[1:])]
        name = f"cyl_cquad8_{nth}"
        case.decks[name] = deck(cards, "SOL 103\nCEND\nBEGIN BULK")
        case.ccx[name] = ccx_input(nodes, [("EALL", "S8R", dict(enumerate(els, 1)))],
                                   {"STEEL": STEEL},
                                   ["*SHELL SECTION, ELSET=EALL, MATERIAL=STEEL", f"{h}"], {}, 16)
    return case


def _mixed() -> Case:
    """An aluminium CHEXA8 cantilever with steel CQUAD4 skins (1 mm) on its top and bottom
    faces, sharing the faces' grids."""
    al, st = (7.0e10, 0.33, 2700.0), STEEL
    case = Case("CHEXA8 core + CQUAD4 skins on shared grids (CalculiX C3D8I + S4)", {}, "ccx",
                modes=8)
    for cells in ((20, 2, 2), (40, 4, 4)):
        nodes, nas, _ = bar_mesh("CHEXA8", cells)
        top = [e[4:] for e in nas if np.allclose([nodes.xyz[g][2] for g in e[4:]], 0.04)]
        bottom = [[e[0], e[3], e[2], e[1]] for e in nas
                  if np.allclose([nodes.xyz[g][2] for g in e[:4]], 0)]
        skins = top + bottom
        root = [g for g, p in nodes.xyz.items() if p[0] == 0]
        cards = ["PARAM,COUPMASS,1"] + [small("GRID", g, "", *map(float, p))
                                        for g, p in nodes.xyz.items()]
        cards += [small("CHEXA", k + 1, 1, *e) for k, e in enumerate(nas)]
        cards += [small("CQUAD4", 100000 + k, 2, *e) for k, e in enumerate(skins)]
        cards += [small("PSOLID", 1, 1), small("PSHELL", 2, 2, 0.001, 2, "", 2),
                  small("MAT1", 1, al[0], "", *al[1:]), small("MAT1", 2, st[0], "", *st[1:])]
        name = f"mixed_{cells[0]}"
        case.decks[name] = deck(cards + spc1(1, 123456, root))
        case.ccx[name] = ccx_input(
            nodes, [("CORE", "C3D8I", dict(enumerate(nas, 1))),
                    ("SKIN", "S4", {100000 + k: e for k, e in enumerate(skins)})],
            {"AL": al, "ST": st}, ["*SOLID SECTION, ELSET=CORE, MATERIAL=AL",
                                   "*SHELL SECTION, ELSET=SKIN, MATERIAL=ST", "0.001"],
            {g: "1, 6" for g in root}, 8)
    return case


# ---- pairs that must agree to round-off -------------------------------------------------

def _plate_cards(nx=24, ny=16, a=0.6, b=0.4, h=0.003, zoffs=None, explicit=None):
    """A pinned aluminium CQUAD4 plate; ``zoffs`` on the card, or ``explicit`` offset
    grids tied to the plate's by RBE2."""
    nid = np.arange((nx + 1) * (ny + 1)).reshape(nx + 1, ny + 1) + 1
    cards = [small("GRID", int(nid[i, j]), "", a * i / nx, b * j / ny, 0.0)
             for i, j in itertools.product(range(nx + 1), range(ny + 1))]
    shift = 100000 if explicit else 0
    for k, (i, j) in enumerate(itertools.product(range(nx), range(ny))):
        q = [int(v) + shift for v in (nid[i, j], nid[i + 1, j], nid[i + 1, j + 1], nid[i, j + 1])]
        cards.append(small("CQUAD4", k + 1, 1, *q, "", zoffs or ""))
    if explicit:
        for i, j in itertools.product(range(nx + 1), range(ny + 1)):
            g = int(nid[i, j])
            cards += [small("GRID", g + shift, "", a * i / nx, b * j / ny, explicit),
                      small("RBE2", 200000 + g, g, 123456, g + shift)]
    cards += [small("PSHELL", 1, 1, h, 1, "", 1), small("MAT1", 1, 7.0e10, "", 0.33, 2700.0)]
    edge = nid[[0, -1], :].ravel().tolist() + nid[1:-1, [0, -1]].ravel().tolist()
    return nid, cards + spc1(1, 123, edge)


def _stiffened(offsets: bool, coupled: bool, w=-0.02, z=0.0015) -> str:
    """The plate with ZOFFS and a CBAR stiffener on offsets WA/WB down the middle, or
    the same with explicit offset grids and RBE2s."""
    nid, cards = _plate_cards(zoffs=z if offsets else None, explicit=None if offsets else z)
    line = nid[:, nid.shape[1] // 2]
    for i in range(len(line) - 1):
        ga, gb = int(line[i]), int(line[i + 1])
        if offsets:
            cards.append(small("CBAR", 5000 + i, 2, ga, gb, 0.0, 0.0, 1.0, "", "", "", 0.0,
                               0.0, w, 0.0, 0.0, w))
        else:
            cards.append(small("CBAR", 5000 + i, 2, ga + 300000, gb + 300000, 0.0, 0.0, 1.0))
    if not offsets:
        cards += [small("GRID", int(g) + 300000, "", *_xy(cards, int(g)), w) for g in line]
        cards += [small("RBE2", 400000 + int(g), int(g), 123456, int(g) + 300000) for g in line]
    cards.append(small("PBAR", 2, 1, 1.8e-4, 1.35e-8, 5.4e-10, 1.89e-9))
    return deck((["PARAM,COUPMASS,1"] if coupled else []) + cards)


def _xy(cards: list[str], g: int) -> tuple[float, float]:
    """x, y of small-field GRID g among ``cards``."""
    line = next(c for c in cards if c.startswith("GRID") and int(c[8:16]) == g)
    return float(line[24:32]), float(line[32:40])


def _mpc(terms) -> str:
    """Free-field MPC (set 1): [(grid, component, coefficient)], the dependent first."""
    txt = [f"{g},{c},{a!r}" for g, c, a in terms]
    return "\n".join(("MPC,1," if k == 0 else ",,") + ",".join(txt[k:k + 2])
                     for k in range(0, len(txt), 2))


def _points(rigid: bool) -> str:
    """The plate with an RBE2 from a grid above it to four plate grids (CONM2 with offset
    and inertia, CELAS2 to ground) and an RBE3 (REFC 123, weights 1, 2, 1, 3) whose
    reference above a cell carries a CONM2; or the same written as MPC equations: the
    rigid body's, and the weighted least-squares rigid motion at the reference."""
    nid, cards = _plate_cards()
    xyz = {int(nid[i, j]): np.array([0.6 * i / 24, 0.4 * j / 16, 0.0])
           for i, j in itertools.product(range(25), range(17))}
    dep = [int(nid[16, 7]), int(nid[17, 8]), int(nid[16, 9]), int(nid[15, 8])]
    ind = [int(nid[5, 3]), int(nid[6, 3]), int(nid[6, 4]), int(nid[5, 4])]
    wts = [1.0, 2.0, 1.0, 3.0]
    xn, xr = np.array([0.4, 0.2, 0.05]), np.array([0.1375, 0.0875, 0.03])
    cards += [small("GRID", 9001, "", *map(float, xn)),
              small("CONM2", 9002, 9001, "", 0.5, 0.01, 0.0, -0.02, "", 2e-4, 0.0, 3e-4, 0.0,
                    0.0, 1e-4),
              small("CELAS2", 9003, 2.0e4, 9001, 3),
              small("GRID", 9101, "", *map(float, xr), "", 456),
              small("CONM2", 9102, 9101, "", 0.3)]
    if rigid:
        cards += [small("RBE2", 9004, 9001, 123456, *dep),
                  small("RBE3", 9104, "", 9101, 123,
                        *itertools.chain(*[(w, 123, g) for w, g in zip(wts, ind, strict=True)]))]
        return deck(cards)
    for g in dep:
        d = xyz[g] - xn
        cards += [_mpc([(g, 1, -1.0), (9001, 1, 1.0), (9001, 5, d[2]), (9001, 6, -d[1])]),
                  _mpc([(g, 2, -1.0), (9001, 2, 1.0), (9001, 6, d[0]), (9001, 4, -d[2])]),
                  _mpc([(g, 3, -1.0), (9001, 3, 1.0), (9001, 4, d[1]), (9001, 5, -d[0])])]
        cards += [_mpc([(g, c, -1.0), (9001, c, 1.0)]) for c in (4, 5, 6)]
    rows = []
    for g in ind:  # u_i = u0 + theta x r_i
        r = xyz[g] - xr
        skew = np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])
        rows.append(np.hstack([np.eye(3), -skew]))
    A, W = np.vstack(rows), np.diag(np.repeat(wts, 3))
    C = np.linalg.solve(A.T @ W @ A, A.T @ W)[:3]
    for c in range(3):
        cards.append(_mpc([(9101, c + 1, -1.0)] + [(g, cc + 1, float(C[c, 3 * k + cc]))
                                                   for k, g in enumerate(ind) for cc in range(3)
                                                   if abs(C[c, 3 * k + cc]) > 1e-14]))
    return deck(cards, "SOL 103\nCEND\nSPC = 1\nMPC = 1\nBEGIN BULK")


def pair_cases() -> dict[str, Case]:
    out = {}
    for coupled in (False, True):
        tag = "coupled" if coupled else "lumped"
        out[f"offsets_{tag}"] = Case(f"CBAR WA/WB + CQUAD4 ZOFFS vs explicit grids + RBE2 "
                                     f"({tag} mass)",
                                     {f"stiff_offset_{tag}": _stiffened(True, coupled),
                                      f"stiff_explicit_{tag}": _stiffened(False, coupled)},
                                     "same", modes=10)
    out["rbe2_rbe3"] = Case("RBE2 + CONM2 + CELAS2, RBE3 vs hand-written MPCs",
                            {"points_rbe": _points(True), "points_mpc": _points(False)},
                            "same", modes=10)
    return out


# ---- running --------------------------------------------------------------------------

def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("outdir", type=Path)
    ap.add_argument("--run", action="store_true", help="run eigenupdate (and ccx) and compare")
    ap.add_argument("-k", default="", help="only cases whose name holds this")
    args = ap.parse_args(argv)
    repo = Path(__file__).resolve().parents[1]
    if args.outdir.resolve().is_relative_to(repo):
        ap.error(f"{args.outdir} is inside the repository: give a folder outside it")
    cases = {**plate_cases(), **solid_cases(), **pair_cases()}
    (args.outdir / "ccx").mkdir(parents=True, exist_ok=True)
    for key, case in cases.items():
        if args.k not in key:
            continue
        print(f"{key}: {case.what}")
        got = {}
        for name, text in case.decks.items():
            (args.outdir / f"{name}.bdf").write_text(text)
            (args.outdir / f"{name}.toml").write_text(
                f'[model]\ntype = "nastran"\nbdf = "{name}.bdf"\n')
            if name in case.ccx:
                (args.outdir / "ccx" / f"{name}.inp").write_text(case.ccx[name])
            if not args.run:
                continue
            try:
                got[name] = run_ours(args.outdir / f"{name}.toml", case.modes)
                if case.kind == "closed":
                    ref = case.hz
                elif case.kind == "ccx" and shutil.which("ccx"):
                    ref = run_ccx(args.outdir / "ccx", name)
                else:
                    continue
            except RuntimeError as exc:
                print(f"  {name}: {exc}")
                continue
            if not ref:
                print(f"  {name}: no reference frequencies")
                continue
            diff = [f / r - 1 for f, r in zip(got[name], ref, strict=False)]
            print(f"  {name}: modes 1-{len(diff)} relative to the reference "
                  + " ".join(f"{d:+.2e}" for d in diff))
        if args.run and case.kind == "same" and len(got) == 2:
            a, b = got.values()
            worst = max(abs(x / y - 1) for x, y in zip(a, b, strict=True))
            print(f"  largest relative difference of the pair {worst:.1e}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
