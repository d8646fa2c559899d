"""Grid normals of flat shell facets (CQUAD4, CTRIA3) and the curvature they show.

On a curved surface of flat facets one facet's drilling rotation at a grid is part of
its neighbours' bending rotations. Left to the K6ROT penalty alone, the grid's rotation
about its normal is then a hinge between the facets, and the mesh converges LOW: a
cylinder at R/T = 50 (its n = 2 mode that varies along the axis) -0.66, -1.43, -1.7 % at
32 x 16, 64 x 32, 96 x 48 from CalculiX S8R, moved by 2.7 % between K6ROT 0 and 1e4.
MSC NASTRAN removes the hinge with unique grid normals (PARAM SNORM, 20 degrees by
default since V2001: "What's New in MSC.Nastran 2004", section 12). Their rotation of
each facet's axes to the grid's normal is not exact in rigid motion on flat facets (on
that cylinder it left 4 rigid-body modes and a 29 Hz pair), so here instead the drilling
mismatch (rz - (v,x - u,y)/2)^2, exact in rigid motion, joins the bending part with the
modulus :data:`CURVED_DRILLING` D66 kappa^2, kappa the facet's curvature that the grid
normals show (:func:`facet_curvature`; 0 on a flat mesh, and at a fold beyond SNORM).
The hinge costs about D kappa^2 per unit area, so the term outweighs it by a fixed
factor on any mesh and thickness (thickness power 3, as the bending). Without grid
normals a warped CQUAD4's own corner normals give its kappa (:func:`warped_curvature`):
a twisted mesh hinges far worse than a curved one of flat facets.
"""

from __future__ import annotations

import numpy as np

from eigenupdate.model.rigid_links import warp_heights

CURVED_DRILLING = 1000.0
"""Factor of the curved facets' drilling term over D66 kappa^2. The hinge's remaining
softening falls as its inverse: on the cylinder above (32 x 16) 0.24 % at 100, 0.03 % at
1000, 0 at 1e4 (within 0.01 Hz of the drilling held rigidly); 1000 keeps the term below
the membrane's G T where kappa T < 0.1."""
SNORM = 20.0
"""PARAM SNORM's default (MSC NASTRAN since V2001; V70.7 had none): the largest angle
(degrees) between a facet's normal and its grid's for the grid to count as on a smooth
surface; beyond it, a fold. SNORM <= 0: no grid normals, plain facets."""


def facet_normals(xyz: np.ndarray) -> np.ndarray:
    """Unit normals (n, 3) of CQUAD4 (xyz (n, 4, 3): the diagonals' cross product) or
    CTRIA3 (n, 3, 3) elements, NASTRAN's (as shells.shell_axes, which checks them); zero
    for a degenerate element."""
    x = np.asarray(xyz, float)
    z = (np.cross(x[:, 2] - x[:, 0], x[:, 3] - x[:, 1]) if x.shape[1] == 4 else
         np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]))
    norm = np.linalg.norm(z, axis=1, keepdims=True)
    return np.divide(z, norm, out=np.zeros_like(z), where=norm > 0)


def grid_normals(facets: list, n_nodes: int, snorm: float = SNORM) -> np.ndarray:
    """Unit normals (N, 3) of grids from their facets, ``facets`` a list of (normals
    (n, 3), nodes (n, k)) (CTRIA3 and CQUAD4 apart): the principal axis of the sum of
    n n^T over the facets at a grid, so that neither the facets' orientation (G1-G2-G3
    order) nor a fold's side matters; then again over the facets within ``snorm``
    degrees of it, so that at a fold between equal sides (whose principal axis is any in
    their plane) the normal is one side's or none. Zero at a grid of no such facet.

    >>> nrm = np.array([[0., 0, 1], [0, 0, -1]])
    >>> grid_normals([(nrm, np.array([[0, 1], [1, 2]]))], 3)[:, 2].round(6).tolist()
    [1.0, 1.0, 1.0]
    """
    first = _principal(facets, n_nodes)
    return _principal(facets, n_nodes, first, np.cos(np.radians(snorm)))


def _principal(facets: list, n_nodes: int, near: np.ndarray | None = None,
               cos: float = 0.0) -> np.ndarray:
    S = np.zeros((n_nodes, 3, 3))
    for normal, nodes in facets:
        nn = np.repeat(np.einsum("ni,nj->nij", normal, normal), nodes.shape[1], axis=0)
        if near is not None:  # only the facets within the angle of the first estimate
            nn *= (np.abs(np.einsum("mj,mj->m", near[nodes.ravel()],
                                    np.repeat(normal, nodes.shape[1], axis=0))) >= cos
                   )[:, None, None]
        np.add.at(S, nodes.ravel(), nn)
    w, v = np.linalg.eigh(S)
    out = v[:, :, 2]
    out[w[:, 2] <= 0] = 0.0
    return out * np.where(out[:, 2] < 0, -1.0, 1.0)[:, None]


def facet_curvature(xyz: np.ndarray, normals: np.ndarray, snorm: float = SNORM
                    ) -> np.ndarray:
    """Curvature estimate (n,) of flat facets xyz (n, k, 3) from their grids' normals
    (n, k, 3): the largest sin(angle) between the facet's normal and a grid's over the
    grid's in-plane distance from the facet's centre, over the grids within ``snorm``
    degrees (a fold beyond it is not a curvature). 1 / R on a cylinder's facets
    whose grids lie on a circle of radius R, one edge along the axis.

    >>> a = 0.1; xyz = np.array([[[np.cos(-a), np.sin(-a), 0], [np.cos(a), np.sin(a), 0],
    ...                           [np.cos(a), np.sin(a), 1], [np.cos(-a), np.sin(-a), 1]]])
    >>> nrm = xyz * [1, 1, 0]
    >>> round(float(facet_curvature(xyz, nrm)[0] * np.hypot(np.sin(a), 0.5) / np.sin(a)), 6)
    1.0
    """
    xyz = np.asarray(xyz, float)
    z = facet_normals(xyz)
    d = xyz - xyz.mean(axis=1, keepdims=True)
    d -= np.einsum("nkj,nj->nk", d, z)[:, :, None] * z[:, None]
    cos = np.abs(np.einsum("nkj,nj->nk", normals, z))
    sin = np.sqrt(np.clip(1.0 - cos**2, 0.0, None))
    sin = np.where(cos >= np.cos(np.radians(snorm)), sin, 0.0)
    return np.max(sin / np.linalg.norm(d, axis=2), axis=1)


def warped_curvature(xyz: np.ndarray) -> np.ndarray:
    """Curvature (n,) that CQUAD4 elements xyz (n, 4, 3) show by their own warp: the
    :func:`facet_curvature` of the normals of their bilinear surface at the corners (the
    two edges' cross product); 0 for CTRIA3 (k = 3) and for flat quadrilaterals (grids
    within round-off of the mean plane). Without grid normals (no PARAM SNORM) a twisted
    mesh otherwise hinges about its normals: MacNeal and Harder's twisted beam, 12 x 2,
    came out 3.9 times too soft and K6ROT-dependent; with it 0.999 and 1.0006 of their
    reference (tests/io/test_nastran_warped.py)."""
    x = np.asarray(xyz, float)
    if x.shape[1] != 4:
        return np.zeros(x.shape[0])
    warped = np.any(warp_heights(x, facet_normals(x)) != 0, axis=1)
    out = np.zeros(x.shape[0])
    if np.any(warped):
        w = x[warped]
        n = np.cross(np.roll(w, -1, axis=1) - w, np.roll(w, 1, axis=1) - w)
        n /= np.linalg.norm(n, axis=2, keepdims=True)
        out[warped] = facet_curvature(w, n)
    return out
