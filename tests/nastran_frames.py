"""Small 3-D frames described once, written as NASTRAN bulk data for eigenupdate and
built in OpenSees (openseespy) as the independent reference."""

from __future__ import annotations

import ctypes
import importlib.util
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pytest

REQUIRE = os.environ.get("EIGENUPDATE_REQUIRE_NASTRAN") == "1"


def need(module: str):
    """Import a module of the nastran environment: skip without it in the core environment,
    fail in the nastran one (EIGENUPDATE_REQUIRE_NASTRAN=1), so that run is never empty."""
    if REQUIRE:
        return importlib.import_module(module)
    return pytest.importorskip(module)


def read_quiet(path, parameters=()):
    """``read_nastran`` with its notes (skipped cards, ...) silenced."""
    import warnings

    from eigenupdate.errors import EigenupdateWarning
    from eigenupdate.io.nastran import read_nastran

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EigenupdateWarning)
        return read_nastran(path, parameters)


def opensees():
    """openseespy's module. Its Linux wheel ships BLAS/LAPACK/gfortran beside the
    extension without an rpath to them: load them first, by path."""
    spec = importlib.util.find_spec("openseespylinux")
    if spec is not None and spec.origin:
        lib = Path(spec.origin).parent / "lib"
        for name in ("libquadmath.so.0", "libgfortran.so.4", "libgomp.so.1", "libblas.so.3",
                     "liblapack.so.3"):
            if (lib / name).exists():
                ctypes.CDLL(str(lib / name), mode=ctypes.RTLD_GLOBAL)
    return need("openseespy.opensees")


@dataclass
class Frame:
    nodes: dict[int, np.ndarray]
    bars: list[tuple[int, int, int, np.ndarray, int]]  # eid, ga, gb, orientation v, pid
    sections: dict[int, tuple[float, float, float, float]]  # pid: A, I1, I2, J
    E: float = 2.1e11
    nu: float = 0.3
    rho: float = 7850.0
    fixed: list[int] = field(default_factory=list)
    masses: list[tuple[int, float]] = field(default_factory=list)  # CONM2: grid, mass
    springs: list[tuple[int, int, float]] = field(default_factory=list)  # CELAS2 to ground
    consistent: bool = True
    G: float | None = None  # MAT1 G (None: blank, NASTRAN's E / (2 (1 + nu)))
    shear_factors: dict[int, tuple[float, float]] = field(default_factory=dict)  # PBAR K1, K2

    def bdf(self) -> str:
        out = ["SOL 103", "CEND", "SUBCASE 1", "  SPC = 1", "BEGIN BULK"]
        if self.consistent:
            out.append("PARAM,COUPMASS,1")
        for n, x in sorted(self.nodes.items()):
            out.append(f"GRID*,{n},,{x[0]!r},{x[1]!r}\n*,{x[2]!r}")
        for eid, a, b, v, pid in self.bars:
            out.append(f"CBAR*,{eid},{pid},{a},{b}\n*,{v[0]!r},{v[1]!r},{v[2]!r}")
        for pid, (A, i1, i2, j) in sorted(self.sections.items()):
            k = self.shear_factors.get(pid)
            tail = "" if k is None else f"\n*,,,,\n*,,,,\n*,{k[0]!r},{k[1]!r}"
            out.append(f"PBAR*,{pid},1,{A!r},{i1!r}\n*,{i2!r},{j!r}{',,' if k else ''}{tail}")
        g = "" if self.G is None else repr(self.G)
        out.append(f"MAT1*,1,{self.E!r},{g},{self.nu!r}\n*,{self.rho!r}")
        for n in self.fixed:  # one card each: a free-field line holds 8 data fields
            out.append(f"SPC1,1,123456,{n}")
        for i, (n, m) in enumerate(self.masses):
            out.append(f"CONM2*,{9000 + i},{n},,{m!r}")
        for i, (n, c, k) in enumerate(self.springs):
            out.append(f"CELAS2*,{8000 + i},{k!r},{n},{c}")
        out.append("ENDDATA")
        return "\n".join(out) + "\n"


def opensees_frequencies(path: Path | str, n_modes: int) -> np.ndarray:
    """Lowest n_modes natural frequencies (Hz) by OpenSees of a BDF holding CBAR/PBAR/MAT1,
    CONM2 (point masses without offset or inertia), grounded CELAS2 and SPC1 (one set):
    pyNastran reads the cards, OpenSees' elastic beam-columns with the same mass
    formulation (``-cMass`` when PARAM COUPMASS > 0) and its full generalized LAPACK
    eigen-solver do the rest."""
    bdf = need("pyNastran.bdf.bdf").BDF(debug=None)
    bdf.read_bdf(str(path), xref=False)
    ops = opensees()
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    for n, g in bdf.nodes.items():
        ops.node(n, *map(float, g.xyz))
    fix = {}
    for cards in bdf.spcs.values():
        for c in cards:
            for n in c.nodes:
                fix.setdefault(n, set()).update(int(x) for x in c.components)
    for n, comps in fix.items():
        ops.fix(n, *[int(d in comps) for d in range(1, 7)])
    coup = bdf.params.get("COUPMASS")
    consistent = coup is not None and coup.values[0] > 0
    k = 0
    for eid, e in bdf.elements.items():
        if e.type == "CBAR":
            p = bdf.properties[e.pid]
            m = bdf.materials[p.mid]
            xa, xb = bdf.nodes[e.ga].xyz, bdf.nodes[e.gb].xyz
            vecxz = np.cross(xb - xa, e.x)  # local z of NASTRAN's CBAR
            ops.geomTransf("Linear", eid, *map(float, vecxz))
            extra = ["-cMass"] if consistent else []
            # OpenSees: Iy bends in the local x-z plane (NASTRAN I2), Iz in x-y (I1)
            # OpenSees gives a bar the torsional inertia (mass per length) J / A, NASTRAN's
            # CBAR none: J 1e-12 times smaller and G 1e12 times larger keep GJ and drop it
            ops.element("elasticBeamColumn", eid, e.ga, e.gb, p.A, m.e, m.g * 1e12,
                        p.j * 1e-12, p.i2, p.i1, eid, "-mass", m.rho * p.A, *extra)
        elif e.type == "CELAS2":
            k += 1
            n = e.nodes[0]
            ops.node(900000 + k, *map(float, bdf.nodes[n].xyz))
            ops.fix(900000 + k, 1, 1, 1, 1, 1, 1)
            ops.uniaxialMaterial("Elastic", k, e.k)
            ops.element("zeroLength", 9000000 + k, 900000 + k, n, "-mat", k, "-dir", e.c1)
    for e in bdf.masses.values():
        ops.mass(e.nid, e.mass, e.mass, e.mass, 0.0, 0.0, 0.0)
    lam = np.array(ops.eigen("-fullGenLapack", n_modes))
    ops.wipe()
    return np.sqrt(lam) / (2 * np.pi)


def random_frame(rng: np.random.Generator, consistent: bool = True) -> Frame:
    """A random portal-like frame: columns on fixed bases, beams between their tops,
    random sections, orientation vectors, CONM2 masses and one grounded spring."""
    bays_x, bays_y = rng.integers(1, 3), rng.integers(1, 3)
    storeys = int(rng.integers(1, 3))
    h, ax, ay = rng.uniform(2.5, 4.0), rng.uniform(3.0, 6.0), rng.uniform(3.0, 6.0)
    nodes, bars = {}, []
    per = 3  # elements per member
    nid = [0]

    def node(x):
        nid[0] += 1
        nodes[nid[0]] = np.asarray(x, float)
        return nid[0]

    corner = {}
    fixed = []
    for i in range(bays_x + 1):
        for j in range(bays_y + 1):
            for s in range(storeys + 1):
                corner[i, j, s] = node([i * ax, j * ay, s * h])
                if s == 0:
                    fixed.append(corner[i, j, s])

    def member(a, b, pid):
        xa, xb = nodes[a], nodes[b]
        chain = [a] + [node(xa + (xb - xa) * t / per) for t in range(1, per)] + [b]
        axis = (xb - xa) / np.linalg.norm(xb - xa)
        for p, q in zip(chain[:-1], chain[1:], strict=True):
            while True:
                v = rng.normal(size=3)
                if np.linalg.norm(np.cross(axis, v)) > 0.3 * np.linalg.norm(v):
                    break
            bars.append((len(bars) + 1, p, q, v, pid))

    for (i, j, s), n in list(corner.items()):
        if s < storeys:
            member(n, corner[i, j, s + 1], 1)
        if s > 0 and i < bays_x:
            member(n, corner[i + 1, j, s], 2)
        if s > 0 and j < bays_y:
            member(n, corner[i, j + 1, s], 2)
    sections = {1: (rng.uniform(4e-3, 8e-3), rng.uniform(2e-5, 6e-5), rng.uniform(1e-5, 3e-5),
                    rng.uniform(1e-7, 1e-6)),
                2: (rng.uniform(3e-3, 6e-3), rng.uniform(1e-5, 4e-5), rng.uniform(5e-6, 2e-5),
                    rng.uniform(1e-7, 1e-6))}
    tops = [n for (i, j, s), n in corner.items() if s == storeys]
    masses = [(n, float(rng.uniform(50, 500))) for n in tops[:3]]
    springs = [(tops[-1], int(rng.integers(1, 4)), float(rng.uniform(1e5, 1e6)))]
    return Frame(nodes, bars, sections, fixed=fixed, masses=masses, springs=springs,
                 consistent=consistent)


def assert_hand_edited_deck(model, deck: Path, old: str, pattern: str, read) -> None:
    """Source: the deck with its parameter's value changed in its text (``old`` replaced
    by ``pattern.format(new)``, the model's one value times 1.3) and read again by
    ``read``: its K and M equal the model's at the new value (1e-12 of the largest entry)."""
    new = [1.3 * v for v in model.values]
    text = deck.read_text()
    assert old in text
    edited = deck.with_name("edited_" + deck.name)
    edited.write_text(text.replace(old, pattern.format(new[0])))
    ref = read(edited).model
    for a, b in ((model.stiffness(new), ref.stiffness()), (model.mass(new), ref.mass())):
        assert abs(a - b).max() <= 1e-12 * abs(b).max()
