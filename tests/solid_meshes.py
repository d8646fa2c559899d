"""Box meshes of CHEXA8/20, CPENTA6/15, CTETRA4/10, CPYRAM5 elements and of CHEXA8 +
CPYRAM5 + CTETRA4 together, and their frequencies."""

from __future__ import annotations

import itertools

import numpy as np
import scipy.sparse.linalg as spla

from eigenupdate.model import solids
from eigenupdate.model.assembly import node_dofs, scatter

# corner (i, j, k) of a hexahedron -> its CHEXA8 node
_CORNER = {(0, 0, 0): 0, (1, 0, 0): 1, (1, 1, 0): 2, (0, 1, 0): 3,
           (0, 0, 1): 4, (1, 0, 1): 5, (1, 1, 1): 6, (0, 1, 1): 7}


# the six faces of a CHEXA8, each seen from inside (a pyramid's base towards its apex)
_FACES = np.array([[0, 1, 2, 3], [4, 7, 6, 5], [0, 4, 5, 1], [1, 5, 6, 2], [2, 6, 7, 3],
                   [3, 7, 4, 0]])


def box_mesh(size, cells, kind: str, move=None):
    """Nodes (N, 3) and elements of the box [0, size] cut into ``cells`` hexahedra, each
    one CHEXA8, two CPENTA6, six CTETRA4/10 (Kuhn's conforming subdivision) or six
    CPYRAM5/13 (one per face, apex at a node added at the cell's centre); ``move`` maps the
    corner nodes (N, 3) to distorted ones (mid-edge nodes stay mid-edge). ``"MIXED"``
    gives a list of element arrays: CHEXA8 and six-pyramid cells alternating like a
    chequerboard, the pyramids whose bases lie on the box's y = 0 face split into two
    CTETRA4 each (conforming: their triangular faces are kept)."""
    axes = [np.linspace(0, s, c + 1) for s, c in zip(size, cells, strict=True)]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1)
    xyz = grid.reshape(-1, 3)
    if move is not None:
        xyz = move(xyz)
    nid = np.arange(xyz.shape[0]).reshape(grid.shape[:3])
    i, j, k = (a.ravel() for a in np.meshgrid(*[np.arange(c) for c in cells], indexing="ij"))
    hexa = np.column_stack([nid[i + a, j + b, k + c] for (a, b, c) in _CORNER])
    if kind == "CHEXA8":
        return xyz, hexa
    if kind in ("CPYRAM5", "CPYRAM13", "MIXED"):
        centre = xyz.shape[0] + np.arange(hexa.shape[0])
        xyz = np.vstack([xyz, xyz[hexa].mean(axis=1)])
        pyr = np.stack([np.column_stack([hexa[:, f], centre]) for f in _FACES], axis=1)
        if kind == "CPYRAM5":
            return xyz, pyr.reshape(-1, 5)
        if kind == "CPYRAM13":
            return _mid_edges(xyz, pyr.reshape(-1, 5), solids.PYRAM_EDGES)
        odd = (i + j + k) % 2 == 1
        pyr = pyr[odd].reshape(-1, 5)
        base = xyz[pyr[:, :4]]
        split = np.all(np.isclose(base[:, :, 1], 0), axis=1)
        tets = np.vstack([pyr[split][:, [0, 1, 2, 4]], pyr[split][:, [0, 2, 3, 4]]])
        parts = [hexa[~odd], pyr[~split], tets]
        used = np.unique(np.concatenate([q.ravel() for q in parts]))  # hex cells' centres
        new = np.full(xyz.shape[0], -1)
        new[used] = np.arange(used.size)
        return xyz[used], [new[q] for q in parts]
    if kind == "CHEXA20":
        return _mid_edges(xyz, hexa, solids.HEX_EDGES)
    penta = np.vstack([hexa[:, [0, 1, 2, 4, 5, 6]], hexa[:, [0, 2, 3, 4, 6, 7]]])
    if kind == "CPENTA6":
        return xyz, penta
    if kind == "CPENTA15":
        return _mid_edges(xyz, penta, solids.PENTA_EDGES)
    tets = []
    for perm in itertools.permutations(range(3)):
        path, corner = [(0, 0, 0)], [0, 0, 0]
        for axis in perm:
            corner[axis] = 1
            path.append(tuple(corner))
        tets.append(hexa[:, [_CORNER[c] for c in path]])
    tets = np.vstack(tets)
    if kind == "CTETRA4":
        return xyz, tets
    return _mid_edges(xyz, tets, np.array([[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]]))


def _mid_edges(xyz, elements, pairs):
    """Quadratic elements: a node at the middle of each edge (shared between elements),
    in the element's mid-edge order ``pairs``."""
    edges = np.sort(elements[:, pairs], axis=2)
    unique, inverse = np.unique(edges.reshape(-1, 2), axis=0, return_inverse=True)
    mid = xyz[unique].mean(axis=1)
    extra = xyz.shape[0] + inverse.reshape(-1, len(pairs))
    return np.vstack([xyz, mid]), np.hstack([elements, extra])


def solid_matrices(xyz, elements, E, nu, rho, lumped=False):
    """Global K, M (CSR), three translations per node; ``elements`` one array or a list
    of arrays (one per element kind)."""
    if isinstance(elements, list):
        parts = [solid_matrices(xyz, e, E, nu, rho, lumped) for e in elements if len(e)]
        return sum(p[0] for p in parts), sum(p[1] for p in parts)
    C = solids.isotropic_elasticity(E, nu)
    d = node_dofs(elements, 3)
    n = 3 * xyz.shape[0]
    K = scatter(d, solids.solid_stiffness(xyz[elements], C), n)
    M = scatter(d, rho * solids.solid_mass(xyz[elements], lumped), n)
    return K, M


def lowest_frequencies(K, M, fixed_nodes, count):
    """The ``count`` lowest angular frequencies with the given nodes fixed."""
    fixed = node_dofs(np.asarray(fixed_nodes)[:, None], 3).ravel()
    free = np.setdiff1d(np.arange(K.shape[0]), fixed)
    K, M = K[free][:, free], M[free][:, free]
    lam = spla.eigsh(K, count, M, sigma=0, which="LM", return_eigenvectors=False)
    return np.sqrt(np.sort(lam))
