"""CQUAD8 and CTRIA6 meshes of rectangles and cylinders, for the quadratic shell tests."""

from __future__ import annotations

import numpy as np
import scipy.sparse.linalg as spla
from plates import plate_fixed

from eigenupdate.model import shells
from eigenupdate.model import shells_quadratic as sq
from eigenupdate.model import shells_transition as st
from eigenupdate.model.assembly import node_dofs, scatter

E, NU, RHO = 200e9, 0.3, 7850.0


def grid_mesh(nx: int, ny: int, triangles: bool):
    """Parameters (N, 2) in [0, 1]^2 of the nodes and elements (n, 8) (CQUAD8) or
    (2n, 6) (CTRIA6) of an nx x ny grid, NASTRAN's node order."""
    ix, iy = np.meshgrid(np.arange(2 * nx + 1), np.arange(2 * ny + 1), indexing="ij")
    keep = np.ones(ix.shape, bool) if triangles else ~((ix % 2 == 1) & (iy % 2 == 1))
    idx = -np.ones(ix.shape, int)
    idx[keep] = np.arange(keep.sum())
    uv = np.column_stack([ix[keep] / (2 * nx), iy[keep] / (2 * ny)])
    el = []
    for i in range(0, 2 * nx, 2):
        for j in range(0, 2 * ny, 2):
            c = idx[i:i + 3, j:j + 3]
            if triangles:
                el.append([c[0, 0], c[2, 0], c[2, 2], c[1, 0], c[2, 1], c[1, 1]])
                el.append([c[0, 0], c[2, 2], c[0, 2], c[1, 1], c[1, 2], c[0, 1]])
            else:
                el.append([c[0, 0], c[2, 0], c[2, 2], c[0, 2], c[1, 0], c[2, 1], c[1, 2],
                           c[0, 1]])
    return uv, np.array(el)


def plate_mesh(nx: int, a: float, b: float, triangles: bool):
    """Nodes (N, 3) in z = 0 and elements of an a x b rectangle."""
    uv, el = grid_mesh(nx, nx, triangles)
    return np.column_stack([uv[:, 0] * a, uv[:, 1] * b, np.zeros(len(uv))]), el


def cylinder_mesh(nc: int, nl: int, radius: float, length: float, triangles: bool):
    """Nodes and elements of a closed cylinder round z (nc elements round, nl along),
    the seam's nodes merged."""
    uv, el = grid_mesh(nc, nl, triangles)
    ang = 2 * np.pi * uv[:, 0]
    xyz = np.column_stack([radius * np.cos(ang), radius * np.sin(ang), length * uv[:, 1]])
    seam = np.flatnonzero(np.isclose(uv[:, 0], 1.0))
    start = np.flatnonzero(np.isclose(uv[:, 0], 0.0))
    ren = np.arange(len(uv))
    ren[seam[np.argsort(uv[seam, 1])]] = start[np.argsort(uv[start, 1])]
    keep = np.setdiff1d(np.arange(len(uv)), seam)
    new = -np.ones(len(uv), int)
    new[keep] = np.arange(keep.size)
    return xyz[keep], new[ren[el]]


def plate_frequency(nx: int, a: float, h: float, edge: str, triangles: bool) -> float:
    """Lowest angular frequency of a steel PSHELL square plate of nx x nx CQUAD8 (or
    2 nx x nx CTRIA6), edges as :func:`plate_fixed`."""
    xyz, el = plate_mesh(nx, a, a, triangles)
    m = sq.pshell_matrices(xyz[el], h, *shells.pshell_moduli(E, NU), rho=RHO)
    d, n = node_dofs(el, 6), 6 * xyz.shape[0]
    K, M = scatter(d, m["K"], n), scatter(d, m["M"], n)
    free = np.flatnonzero(~plate_fixed(xyz, a, edge).ravel())
    K, M = K[free][:, free], M[free][:, free]
    # M is singular (rotations carry no mass): the largest 1/lambda of M x = (1/lambda) K x
    mu = spla.eigsh(M, 1, K, which="LA", return_eigenvectors=False)
    return float(np.sqrt(1.0 / mu[0]))


def drop_mid_sides(xyz, el, which: str, seed: int = 0):
    """Element nodes (n, k, 3) with the mid-side nodes of ``which`` blank (NaN), shared
    by the neighbours: "half" those with x > 1/2 (a full region, a linear one and a
    column of transition elements between), "random" each with probability 1/2, "all",
    "none"; and the blank nodes' indices."""
    k = el.shape[1]
    mids = np.unique(el[:, k - len(st.EDGES[k]):])
    gone = {"half": mids[xyz[mids, 0] > 0.5 + 1e-9], "all": mids, "none": mids[:0],
            "random": mids[np.random.default_rng(seed).random(mids.size) < 0.5]}[which]
    x = xyz[el].copy()
    x[np.isin(el, gone)] = np.nan
    return x, gone


def transition_plate_frequency(nx, h, triangles, which, seed=0):
    """Lowest angular frequency of a simply supported unit plate (as
    quadratic_meshes.plate_frequency) with the mid-side nodes ``which`` blank."""
    xyz, el = plate_mesh(nx, 1.0, 1.0, triangles)
    x, gone = drop_mid_sides(xyz, el, which, seed)
    m = sq.pshell_matrices(x, h, *shells.pshell_moduli(E, NU), rho=RHO)
    d, n = node_dofs(el, 6), 6 * xyz.shape[0]
    K, M = scatter(d, m["K"], n), scatter(d, m["M"], n)
    fixed = plate_fixed(xyz, 1.0, "ss")
    fixed[gone] = True  # no grid there
    free = np.flatnonzero(~fixed.ravel())
    mu = spla.eigsh(M[free][:, free], 1, K[free][:, free], which="LA",
                    return_eigenvectors=False)
    return float(np.sqrt(1 / mu[0]))


def skewed_plate():
    """The bending patch tests' parallelograms: a 3 x 3 CQUAD8 grid of unequal columns and
    rows (piecewise linear, so mid-side nodes stay in the middle), then one skew. Returns
    the mesh's unit-square nodes (N, 3), its elements, the skewed in-plane coordinates
    (N, 2) and which nodes lie on the boundary."""
    xyz, el = plate_mesh(3, 1.0, 1.0, False)
    xy = xyz[:, :2].copy()
    xy[:, 0] = np.interp(xy[:, 0], [0, 1 / 3, 2 / 3, 1], [0, 0.2, 0.65, 1.0])
    xy[:, 1] = np.interp(xy[:, 1], [0, 1 / 3, 2 / 3, 1], [0, 0.4, 0.55, 0.7])
    xy[:, 0] += 0.3 * xy[:, 1]
    on = (np.isclose(xyz[:, 0], 0) | np.isclose(xyz[:, 0], 1) | np.isclose(xyz[:, 1], 0)
          | np.isclose(xyz[:, 1], 1))
    return xyz, el, xy, on
