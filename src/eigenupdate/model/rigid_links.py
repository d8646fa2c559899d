"""Rigid links along a shell element's normal from its grids to the nodes it is computed
at: ZOFFS (a reference plane off the grid plane) and a warped CQUAD4's grids off its mean
plane. A link of length z from a grid to its node moves the node by the grid's rotation:
``u_node = u + z ry``, ``v_node = v - z rx`` in element axes (NASTRAN-95's TLDRD,
tldrs.f, for ZOFFS), w and the rotations unchanged; K_grid = T^T K_node T. Links along
one normal add, so a ZOFFS and a warp link are one link of their summed length.
"""

from __future__ import annotations

import numpy as np


def offset_parts(parts: dict, z: np.ndarray) -> dict:
    """The compact element-axes parts of :func:`eigenupdate.model.shells.local_parts`
    seen from grids whose nodes lie ``z`` along the normal: (n,) one length per element,
    or (n, k) one per node; T^T k T per part (a part with u (v) gains the node's ry (rx)
    column).

    Examples
    --------
    A membrane block on u of one node: u_node = u + z ry couples u with ry.

    >>> b = offset_parts({"m": (np.array([0]), np.ones((1, 1, 1)))}, np.array([2.0]))["m"]
    >>> b[0].tolist(), b[1][0].tolist()
    ([0, 4], [[1.0, 2.0], [2.0, 4.0]])
    """
    z = np.asarray(z, float)
    n = z.shape[0]
    out = {}
    for name, (cols, block) in parts.items():
        # u brings the node's ry, v its rx
        new = np.union1d(cols, np.concatenate([cols[cols % 6 == 0] + 4,
                                               cols[cols % 6 == 1] + 2]))
        if not np.any(cols % 6 < 2):  # no u, v: unchanged (a coupling part has ry too)
            out[name] = (cols, block)
            continue
        T = np.zeros((n, cols.size, new.size))
        at = {c: i for i, c in enumerate(new)}
        for i, c in enumerate(cols):
            zc = z if z.ndim == 1 else z[:, c // 6]
            T[:, i, at[c]] = 1.0
            if c % 6 == 0:  # u_node = u + z ry
                T[:, i, at[c + 4]] += zc
            elif c % 6 == 1:  # v_node = v - z rx
                T[:, i, at[c + 2]] -= zc
        out[name] = (new, np.swapaxes(T, 1, 2) @ block @ T)
    return out


def warp_heights(xyz: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """Heights (n, k) of elements' grids ``xyz`` (n, k, 3) above their mean plane (unit
    ``normal`` (n, 3), through the grids' centroid); exactly 0 where they lie within
    round-off of it (1e-12 of the element's size), so a flat mesh keeps its parts
    unchanged."""
    xyz = np.asarray(xyz, float)
    rel = xyz - xyz.mean(axis=1, keepdims=True)
    h = np.einsum("nj,nkj->nk", normal, rel)
    size = np.sqrt(np.max(np.sum(rel**2, axis=2), axis=1))
    return np.where(np.abs(h) > 1e-12 * size[:, None], h, 0.0)


def warp(xyz: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """Warp (n,) of quadrilaterals xyz (n, 4, 3): the largest :func:`warp_heights` over
    the square root of the area (half |G1G3 x G2G4|), NASTRAN's geometry."""
    xyz = np.asarray(xyz, float)
    area = np.linalg.norm(np.cross(xyz[:, 2] - xyz[:, 0], xyz[:, 3] - xyz[:, 1]), axis=1) / 2
    return np.max(np.abs(warp_heights(xyz, normal)), axis=1) / np.sqrt(area)


def warp_links(parts: dict, xyz: np.ndarray, R: np.ndarray) -> dict:
    """``parts`` computed on the mean plane of warped quadrilaterals, seen from their
    grids (links of length minus their :func:`warp_heights`); unchanged if none is
    warped. Without them a rigid rotation of the grids strains the projected element
    (a warped CQUAD4 free in space had fewer than six rigid-body modes)."""
    h = warp_heights(xyz, R[:, 2])
    return offset_parts(parts, -h) if np.any(h) else parts
