"""Flat-plate meshes and their lowest frequencies, for the shell element tests."""

from __future__ import annotations

import numpy as np
import scipy.sparse.linalg as spla

from eigenupdate.model import shells
from eigenupdate.model.assembly import node_dofs, scatter

E, NU, RHO = 200e9, 0.3, 7850.0


# two PSHELL regions of one MAT1, their thicknesses and the material as parameters (the
# NASTRAN shell-deck tests)
INIT = {"t1": 0.004, "t2": 0.006, "E": E, "rho": RHO}
FIELDS = [("t1", "PSHELL", 1, "T"), ("t2", "PSHELL", 2, "T"), ("E", "MAT1", 1, "E"),
          ("rho", "MAT1", 1, "RHO")]


def read_deck(path, specs=()):
    """``read_nastran(path, specs)`` with its warnings silenced (needs pyNastran)."""
    import warnings

    from eigenupdate.errors import EigenupdateWarning
    from eigenupdate.io.nastran import read_nastran

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EigenupdateWarning)
        return read_nastran(path, specs)


def card_specs(fields=FIELDS):
    """(Parameter, CardField) pairs of (name, card, id, field) rows, values from the deck."""
    from eigenupdate.io.nastran import CardField
    from eigenupdate.model.parameters import Parameter

    return [(Parameter(n, 0.0), CardField(c, i, f)) for n, c, i, f in fields]


def square_mesh(nx: int, a: float, triangles: bool) -> tuple[np.ndarray, np.ndarray]:
    """Nodes (N, 3) and elements (n, 4) (or (2n, 3)) of an a x a square in z = 0."""
    x, y = np.meshgrid(np.linspace(0, a, nx + 1), np.linspace(0, a, nx + 1), indexing="ij")
    xyz = np.column_stack([x.ravel(), y.ravel(), np.zeros(x.size)])
    nid = np.arange(x.size).reshape(nx + 1, nx + 1)
    quads = np.column_stack([nid[:-1, :-1].ravel(), nid[1:, :-1].ravel(),
                             nid[1:, 1:].ravel(), nid[:-1, 1:].ravel()])
    if triangles:
        return xyz, np.vstack([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    return xyz, quads


def plate_matrices(xyz, elements, h, lumped=False):
    """Global K, M (CSR) of a PSHELL plate of thickness h, steel."""
    moduli = shells.pshell_moduli(E, NU)
    m = shells.pshell_matrices(xyz[elements], h, *moduli, rho=RHO, lumped=lumped)
    d = node_dofs(elements, 6)
    n = 6 * xyz.shape[0]
    return scatter(d, m["K"], n), scatter(d, m["M"], n)


def plate_frequency(nx: int, a: float, h: float, edge: str, triangles: bool) -> float:
    """Lowest angular frequency of a square plate, edges simply supported ("ss": w and
    the rotation about the edge's normal fixed, the hard support) or clamped."""
    xyz, el = square_mesh(nx, a, triangles)
    K, M = plate_matrices(xyz, el, h)
    free = np.flatnonzero(~plate_fixed(xyz, a, edge).ravel())
    K, M = K[free][:, free], M[free][:, free]
    # M is singular (rotations carry no mass): the largest 1/lambda of M x = (1/lambda) K x
    mu = spla.eigsh(M, 1, K, which="LA", return_eigenvectors=False)
    return float(np.sqrt(1.0 / mu[0]))


def navier(a: float, h: float, m: int = 1, n: int = 1) -> float:
    """Navier's omega_mn = pi^2 (m^2 + n^2) / a^2 sqrt(D / (rho h)) of a simply supported
    square Kirchhoff plate."""
    D = E * h**3 / (12 * (1 - NU**2))
    return np.pi**2 * (m**2 + n**2) / a**2 * np.sqrt(D / (RHO * h))


def plate_fixed(xyz: np.ndarray, a: float, edge: str) -> np.ndarray:
    """(N, 6) mask of the held coordinates of an a x a plate in z = 0: in-plane motion
    and drilling everywhere (uncoupled from bending), w on the edges, and the rotation
    about each edge's normal ("ss": hard simple support) or both rotations ("clamped")."""
    x, y = xyz[:, 0], xyz[:, 1]
    on_x = np.isclose(x, 0) | np.isclose(x, a)
    on_y = np.isclose(y, 0) | np.isclose(y, a)
    fixed = np.zeros((xyz.shape[0], 6), bool)
    fixed[:, [0, 1, 5]] = True
    fixed[on_x | on_y, 2] = True
    if edge == "clamped":
        fixed[on_x | on_y, 3:5] = True
    else:
        fixed[on_x, 3] = True
        fixed[on_y, 4] = True
    return fixed


def constant_strain_state(xy: np.ndarray, which: str) -> np.ndarray:
    """Exact nodal values (n, 6) in element axes of a constant-strain state: membrane
    (u, v linear, rz their rotation) or Kirchhoff bending (w quadratic, rx = w,y,
    ry = -w,x: constant curvature, no transverse shear)."""
    x, y = xy[:, 0], xy[:, 1]
    out = np.zeros((xy.shape[0], 6))
    if which == "membrane":
        out[:, 0] = 1e-3 * (1.0 + 2.0 * x + 0.5 * y)
        out[:, 1] = 1e-3 * (-0.5 + 1.0 * x + 3.0 * y)
        out[:, 5] = 0.5 * 1e-3 * (1.0 - 0.5)
    else:
        out[:, 2] = 1e-3 * (0.1 + x + 2 * x**2 + 1.5 * x * y + y**2)
        out[:, 3] = 1e-3 * (1.5 * x + 2 * y)
        out[:, 4] = -1e-3 * (1 + 4 * x + 1.5 * y)
    return out


def two_region_deck(path, v=INIT, nx=8, a=1.0, card="CQUAD4", nsm=0.5, held="126"):
    """An a x a plate of ``card`` elements (CQUAD4, CTRIA3, CQUADR, CTRIAR), w held on its
    edges and the components ``held`` everywhere, PSHELL 1 (thickness t1) on x < a/2 and
    PSHELL 2 (t2, NSM) beyond, both MAT1 1, coupled mass; written with the values ``v``
    in the cards' text (repr: every digit)."""
    xyz, el = square_mesh(nx, a, card in ("CTRIA3", "CTRIAR"))
    lines = [f"GRID,{i + 1},,{x!r},{y!r},0." for i, (x, y, _) in enumerate(xyz)]
    for k, e in enumerate(el):
        pid = 1 if xyz[e, 0].mean() < a / 2 else 2
        lines.append(f"{card},{k + 1},{pid}," + ",".join(str(n + 1) for n in e))
    edge = [i + 1 for i, (x, y, _) in enumerate(xyz)
            if min(x, y) < 1e-12 * a or max(x, y) > a * (1 - 1e-12)]
    lines += [f"SPC1,1,{held},1,THRU,{len(xyz)}"] + [f"SPC1,1,3,{n}" for n in edge]
    path.write_text(
        "BEGIN BULK\nPARAM,COUPMASS,1\n"
        f"PSHELL,1,1,{v['t1']!r},1,,1\nPSHELL,2,1,{v['t2']!r},1,,1,,{nsm!r}\n"
        f"MAT1,1,{v['E']!r},,{NU!r},{v['rho']!r}\n" + "\n".join(lines) + "\nENDDATA\n")
    return path
