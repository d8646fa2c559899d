"""Card writers, CalculiX inputs and runners of tools/accept_decks.py (issue 20's
acceptance decks): NASTRAN small, large and free field as a pre-processor writes them."""

from __future__ import annotations

import itertools
import json
import os
import re
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

STEEL = (2.0e11, 0.3, 7850.0)


def _real(x: float, width: int) -> str:
    """The shortest real of at most ``width`` characters with a decimal point."""
    if x == 0:
        return "0."
    for p in range(width, 0, -1):
        s = f"{x:.{p}g}"
        if "e" in s:
            m, e = s.split("e")
            s = (m if "." in m else m + ".") + "E" + str(int(e))
        elif "." not in s:
            s += "."
        if len(s) <= width:
            return s
    raise ValueError(f"{x} does not fit {width} characters")


def _text(v, width: int) -> str:
    return "" if v is None or v == "" else _real(v, width) if isinstance(v, float) else str(v)


def small(name: str, *fields) -> str:
    """Small-field card: 8-column fields, 8 to a line."""
    vals = [f"{_text(v, 8):<8s}" for v in fields]
    rows = [vals[i:i + 8] for i in range(0, len(vals), 8)] or [[]]
    return "\n".join((f"{name:<8s}" if i == 0 else " " * 8) + "".join(r)
                     for i, r in enumerate(rows)).rstrip()


def large(name: str, *fields) -> str:
    """Large-field card: NAME*, 16-column fields, 4 to a line, '*' continuations."""
    vals = [f"{_text(v, 16):<16s}" for v in fields]
    rows = [vals[i:i + 4] for i in range(0, len(vals), 4)] or [[]]
    return "\n".join((f"{name + '*':<8s}" if i == 0 else f"{'*':<8s}") + "".join(r)
                     for i, r in enumerate(rows)).rstrip()


def free(name: str, *fields) -> str:
    """Free-field card (commas), 8 fields a line, continued by a leading comma."""
    vals = [_text(v, 16) for v in fields]
    rows = [vals[i:i + 8] for i in range(0, len(vals), 8)] or [[]]
    return "\n".join((name if i == 0 else "") + "," + ",".join(r) for i, r in enumerate(rows))


def spc1(sid: int, comps: int, grids) -> list[str]:
    grids = [int(g) for g in grids]
    return [small("SPC1", sid, comps, *grids[k:k + 6]) for k in range(0, len(grids), 6)]


def deck(cards: list[str], head: str = "SOL 103\nCEND\nSPC = 1\nBEGIN BULK") -> str:
    return "\n".join([head, *cards, "ENDDATA"]) + "\n"


@dataclass
class Case:
    """Decks (name -> text) compared with one reference over ``modes`` modes."""

    what: str
    decks: dict[str, str]
    kind: str  # "closed", "ccx" or "same"
    modes: int = 6
    hz: list[float] = field(default_factory=list)  # closed
    ccx: dict[str, str] = field(default_factory=dict)  # deck name -> CalculiX input


HEX = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
# mid-edge nodes: NASTRAN's order and CalculiX's (corner pairs)
EDGES = {"CHEXA20": ([(0, 1), (1, 2), (2, 3), (3, 0), (0, 4), (1, 5), (2, 6), (3, 7), (4, 5),
                      (5, 6), (6, 7), (7, 4)],
                     [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4), (0, 4),
                      (1, 5), (2, 6), (3, 7)]),
         "CPENTA15": ([(0, 1), (1, 2), (2, 0), (0, 3), (1, 4), (2, 5), (3, 4), (4, 5), (5, 3)],
                      [(0, 1), (1, 2), (2, 0), (3, 4), (4, 5), (5, 3), (0, 3), (1, 4), (2, 5)]),
         "CTETRA10": ([(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)],) * 2}
CCX_TYPE = {"CHEXA8": "C3D8I", "CHEXA20": "C3D20", "CTETRA10": "C3D10", "CPENTA6": "C3D6",
            "CPENTA15": "C3D15", "CQUAD4": "S4", "CQUAD8": "S8R"}


class Nodes:
    """Grid ids of points, merged by position."""

    def __init__(self):
        self.xyz: dict[int, np.ndarray] = {}
        self._ids: dict[tuple, int] = {}

    def at(self, p) -> int:
        key = tuple(np.round(np.asarray(p, float), 10))
        if key not in self._ids:
            self._ids[key] = len(self._ids) + 1
            self.xyz[self._ids[key]] = np.asarray(p, float)
        return self._ids[key]

    def mid(self, a: int, b: int) -> int:
        return self.at((self.xyz[a] + self.xyz[b]) / 2)


def bar_mesh(kind: str, cells, size=(0.5, 0.05, 0.04)):
    """A box cut into hexahedra, each one element, two wedges or six (Kuhn) tetrahedra:
    (nodes, NASTRAN connectivity, CalculiX connectivity)."""
    nodes, nas, ccx = Nodes(), [], []
    step = np.array(size) / cells
    for ijk in itertools.product(*map(range, cells)):
        c = [nodes.at((np.array(ijk) + o) * step) for o in HEX]
        if kind.startswith("CHEXA"):
            cells_ = [c]
        elif kind.startswith("CPENTA"):
            cells_ = [[c[i] for i in (0, 1, 2, 4, 5, 6)], [c[i] for i in (0, 2, 3, 4, 6, 7)]]
        else:
            cells_ = []
            for perm in itertools.permutations(range(3)):
                corner, path = [0, 0, 0], [(0, 0, 0)]
                for ax in perm:
                    corner[ax] = 1
                    path.append(tuple(corner))
                t = [c[HEX.index(p)] for p in path]
                if np.linalg.det([nodes.xyz[t[q]] - nodes.xyz[t[0]] for q in (1, 2, 3)]) < 0:
                    t = [t[0], t[2], t[1], t[3]]
                cells_.append(t)
        for e in cells_:
            en, ec = EDGES.get(kind, ([], []))
            nas.append(e + [nodes.mid(e[a], e[b]) for a, b in en])
            ccx.append(e + [nodes.mid(e[a], e[b]) for a, b in ec])
    return nodes, nas, ccx


def ccx_input(nodes: Nodes, elsets, materials, sections, fixed, modes: int) -> str:
    """A CalculiX *FREQUENCY input: elsets [(name, type, {eid: nodes})]."""
    out = ["*NODE, NSET=NALL"] + [f"{i}, {x:.12g}, {y:.12g}, {z:.12g}"
                                  for i, (x, y, z) in nodes.xyz.items()]
    for name, typ, els in elsets:
        out.append(f"*ELEMENT, TYPE={typ}, ELSET={name}")
        for e, c in els.items():
            flat = [e, *c]
            out += [", ".join(map(str, flat[i:i + 15])) + ("," if i + 15 < len(flat) else "")
                    for i in range(0, len(flat), 15)]
    for name, (E, nu, rho) in materials.items():
        out += [f"*MATERIAL, NAME={name}", "*ELASTIC", f"{E:.12g}, {nu:.12g}", "*DENSITY",
                f"{rho:.12g}"]
    out += sections + ["*BOUNDARY"] + [f"{g}, {dofs}" for g, dofs in fixed.items()]
    return "\n".join(out + ["*STEP", "*FREQUENCY", str(modes), "*END STEP"]) + "\n"


def run_ours(path: Path, modes: int) -> list[float]:
    """``eigenupdate frequencies`` of a study (this checkout's package), its base modes."""
    env = dict(os.environ, PYTHONPATH=str(Path(__file__).resolve().parents[1] / "src"))
    r = subprocess.run([sys.executable, "-m", "eigenupdate", "frequencies", str(path), "--modes",
                        str(modes), "--json"], capture_output=True, text=True, env=env)
    if r.returncode:
        raise RuntimeError(r.stderr.strip().splitlines()[-1] if r.stderr.strip()
                           else f"exit status {r.returncode}")
    return json.loads(r.stdout)["configurations"][0]["frequencies_hz"]


def run_ccx(folder: Path, name: str, floor_hz=5.0) -> list[float]:
    """CalculiX's frequencies (Hz) of ``folder/name.inp`` above ``floor_hz`` (rigid modes
    out): the cycles/time column of its eigenvalue table (mode, eigenvalue, rad/time,
    cycles/time, imaginary part)."""
    subprocess.run(["ccx", "-i", name], cwd=folder, capture_output=True, text=True,
                   env=dict(os.environ, OMP_NUM_THREADS="1"))
    dat = folder / f"{name}.dat"
    text = dat.read_text() if dat.exists() else ""
    if "E I G E N V A L U E   O U T P U T" not in text:
        raise RuntimeError(f"ccx {name}: no eigenvalues")
    block = text.split("E I G E N V A L U E   O U T P U T")[1].split("P A R T I C I P A T I O N")[0]
    rows = (re.match(r"\s*\d+\s+\S+\s+\S+\s+(\S+)\s+\S+\s*$", ln) for ln in block.splitlines())
    return [f for f in (float(m.group(1)) for m in rows if m) if f > floor_hz]
