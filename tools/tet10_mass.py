"""What MSC Nastran 2005's lumped CTETRA10 mass of pyn_tet10 must be (issue 20): a diagnostic.

Fits a diagonal mass, the same in x, y, z at a grid, zero at the corner grids, free at the
six unconstrained mid-edge grids, to MSC's ten frequencies (ref.json) with our stiffness
(5-point rule: MSC's static displacements within 1e-5, tests/io/test_shell_decks.py), and
prints what the fit fixes and what it cannot:

* the six masses (10 data, 6 unknowns; max residual about 2e-7);
* their sum against rho (V1 + V2 / 2), V the isoparametric (curved) volumes: element 1's
  whole mass is on its mid-edge grids and element 2 puts half of its on the three free ones;
* the split of the three grids shared by both elements is not identifiable (a 2-parameter
  family): element 1's fractions implied by a hypothesis for element 2's;
* the largest frequency error of a few candidate rules computed on both elements.

Not a rule and not used by the package. Usage (NASTRAN environment, shared data present):
``PYTHONPATH=src python tools/tet10_mass.py``.
"""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import scipy.linalg as sl
import scipy.optimize as so
from pyNastran.bdf.bdf import BDF

from eigenupdate.io.nastran import read_nastran
from eigenupdate.model import solids

FOLDER = Path(__file__).resolve().parents[1] / "../shared/data/nastran/pyn_tet10"
PAIRS = [0, 1, 2, 1, 2, 0]  # G5..G10 -> opposite-edge pair (1-2/3-4, 2-3/1-4, 3-1/2-4)


def _setup():
    deck = FOLDER / "Simple_Example.bdf"
    ref = np.array(json.loads((FOLDER / "ref.json").read_text())["elastic_hz"])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = read_nastran(deck).model
        bdf = BDF(debug=None)
        bdf.read_bdf(str(deck))
    xyz = {g: n.get_position() for g, n in bdf.nodes.items()}
    elems = {e: [xyz[g] for g in el.node_ids] for e, el in bdf.elements.items()}
    nodes = {e: el.node_ids for e, el in bdf.elements.items()}
    rho = bdf.materials[1].rho
    return model, ref, {e: np.array(x) for e, x in elems.items()}, nodes, rho


def main() -> None:
    model, ref, X, nodes, rho = _setup()
    K = model.stiffness().toarray()
    free = list(nodes[1][4:])

    def rows(g):
        return [model.index(10 * g + c + 1) for c in range(3)]

    def freqs(m: dict) -> np.ndarray:
        d = np.zeros(model.n)
        for g, v in m.items():
            if g in free:
                d[rows(g)] += v
        a, z = np.flatnonzero(d > 0), np.flatnonzero(d <= 0)
        kc = K[np.ix_(a, a)] - K[np.ix_(a, z)] @ np.linalg.solve(K[np.ix_(z, z)], K[np.ix_(z, a)])
        return np.sqrt(sl.eigh(kc, np.diag(d[a]), eigvals_only=True)[:ref.size]) / (2 * np.pi)

    fit = None
    for start in np.random.default_rng(0).uniform(0.3, 3, (10, 6)):
        r = so.least_squares(lambda p: freqs(dict(zip(free, np.exp(p), strict=True))) / ref - 1,
                             np.log(start * 5e-8), bounds=(np.log(1e-10), np.log(1e-5)),
                             xtol=1e-15, ftol=1e-15, gtol=1e-15)
        fit = r if fit is None or r.cost < fit.cost else fit
    m = dict(zip(free, np.exp(fit.x), strict=True))
    print("fitted masses", {g: f"{v:.5e}" for g, v in m.items()},
          f"max residual {np.abs(fit.fun).max():.1e}")
    V = {e: solids.solid_mass(X[e][None], False)[0][0::3, 0::3].sum() for e in X}
    print(f"sum / rho (V1 + V2/2) - 1 = {sum(m.values()) / (rho * (V[1] + V[2] / 2)) - 1:.1e}")

    def inv_sin(P):  # 1 / sin(angle between opposite edges), per mid-edge node
        E = solids._TET_EDGES
        w = []
        for k in range(3):
            u = P[E[k, 1]] - P[E[k, 0]]
            o = (5, 3, 4)[k]
            v = P[E[o, 1]] - P[E[o, 0]]
            w.append(np.linalg.norm(u) * np.linalg.norm(v) / np.linalg.norm(np.cross(u, v)))
        w = np.array(w)[PAIRS]
        return w / w.sum()

    for name, f2 in (("sixths", np.full(6, 1 / 6)), ("1/sin", inv_sin(X[2][:4]))):
        f1 = [(m[g] - (rho * V[2] * f2[nodes[2][4:].index(g)] if g in nodes[2] else 0))
              / (rho * V[1]) for g in nodes[1][4:]]
        print(f"element 2 {name} {np.round(f2, 5)} -> element 1 {np.round(f1, 5)}")

    def mids_only(rule):
        out = {}
        for e in X:
            w = rule(X[e])
            for k, g in enumerate(nodes[e][4:]):
                out[g] = out.get(g, 0) + rho * V[e] * w[k] / w.sum()
        return np.abs(freqs(out) / ref - 1).max()

    def hrz(x):
        return np.diagonal(solids.solid_mass(x[None], False)[0][0::3, 0::3])[4:]

    def row(x):
        return solids.solid_mass(x[None], False)[0][0::3, 0::3].sum(axis=1)[4:]

    def length(x):
        return np.linalg.norm(x[solids._TET_EDGES[:, 1]] - x[solids._TET_EDGES[:, 0]], axis=1)

    for name, rule in (("equal sixths", lambda x: np.ones(6)), ("HRZ diagonal, mids", hrz),
                       ("row sums, mids", row), ("edge length", length),
                       ("sqrt edge length", lambda x: np.sqrt(length(x))),
                       ("1/sin opposite edges", lambda x: inv_sin(x[:4]))):
        print(f"{name:22s} max frequency error {mids_only(rule):.4f}")


if __name__ == "__main__":
    main()
