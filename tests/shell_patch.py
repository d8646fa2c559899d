"""MacNeal & Harder's distorted patch (Finite Elem. Anal. Des. 1, 1985, fig. 2) for the
shell patch tests: a 0.24 x 0.12 rectangle cut into five distorted quadrilaterals (or
ten triangles) by four inner nodes."""

from __future__ import annotations

import numpy as np
from bounds import solve_floor

from eigenupdate.model.assembly import node_dofs

PATCH_XY = np.array([[0.0, 0.0], [0.24, 0.0], [0.24, 0.12], [0.0, 0.12],
                     [0.04, 0.02], [0.18, 0.03], [0.16, 0.08], [0.08, 0.08]])
PATCH_QUADS = np.array([[0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7], [4, 5, 6, 7]])
PATCH_TRIAS = np.vstack([PATCH_QUADS[:, [0, 1, 2]], PATCH_QUADS[:, [0, 2, 3]]])
INNER = np.arange(4, 8)


def assert_inner_nodes_follow(K: np.ndarray, u: np.ndarray) -> None:
    """The inner nodes, free, take the state ``u`` imposed on the outer ones (the patch
    test), within 10 times the solve's rounding floor (tests/bounds.py)."""
    inner = node_dofs(INNER[:, None], 6).ravel()
    outer = np.setdiff1d(np.arange(u.size), inner)
    Kii = K[np.ix_(inner, inner)]
    got = np.linalg.solve(Kii, -K[np.ix_(inner, outer)] @ u[outer])
    err = np.linalg.norm(got - u[inner]) / np.linalg.norm(u[inner])
    assert err <= solve_floor(Kii) * 10, err


def rigid_motions(xyz: np.ndarray) -> np.ndarray:
    """The six rigid motions (6 N, 6) of grids xyz (N, 3), six coordinates each:
    u = t + theta x r, the rotations theta."""
    out = np.zeros((6 * len(xyz), 6))
    for i, p in enumerate(xyz):
        out[6 * i:6 * i + 3, :3] = np.eye(3)
        out[6 * i:6 * i + 3, 3:] = -np.array([[0, -p[2], p[1]], [p[2], 0, -p[0]],
                                              [-p[1], p[0], 0]])
        out[6 * i + 3:6 * i + 6, 3:] = np.eye(3)
    return out
