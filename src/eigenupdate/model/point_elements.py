"""Element matrices at points: a rigid point mass on an offset, a mass matrix in another
system, and the deformations of a bushing (six springs at a point rigidly linked to two
grids). Grids' displacements are in their own axes (NASTRAN's CD: ``frame`` rows are the
axes in basic), six components u, theta each.
"""

from __future__ import annotations

import numpy as np

from eigenupdate.model.constraints import rigid_map


def blocks(a: np.ndarray) -> np.ndarray:
    """blockdiag(a, a) of a 3 x 3 rotation: the map of (u, theta)."""
    out = np.zeros((6, 6))
    out[:3, :3] = out[3:, 3:] = a
    return out


def point_mass(offset: np.ndarray, inertia: np.ndarray, frame: np.ndarray
               ) -> tuple[np.ndarray, np.ndarray]:
    """(M per unit mass, M of the inertia) at a grid of a rigid mass whose centre is at
    ``offset`` (basic) from the grid, ``inertia`` (3 x 3, basic) about its centre.

    Examples
    --------
    A unit mass 2 m along x from the grid: rotation about z moves it along y.

    >>> unit, _ = point_mass(np.array([2.0, 0.0, 0.0]), np.zeros((3, 3)), np.eye(3))
    >>> float(unit[1, 5]), float(unit[5, 5])
    (2.0, 4.0)
    """
    a = rigid_map(offset) @ blocks(frame).T  # grid (CD) -> centre (basic)
    unit = np.zeros((6, 6))
    unit[:3, :3] = np.eye(3)
    rot = np.zeros((6, 6))
    rot[3:, 3:] = inertia
    return a.T @ unit @ a, a.T @ rot @ a


def mass_in_system(mass: np.ndarray, axes: np.ndarray, frame: np.ndarray) -> np.ndarray:
    """A 6 x 6 mass matrix given in a rectangular system (``axes`` rows in basic), at a
    grid: T^T M T with T = blockdiag(axes) blockdiag(frame)^T."""
    t = blocks(axes) @ blocks(frame).T
    return t.T @ mass @ t


def bush_deformation(axes: np.ndarray, point: np.ndarray,
                     ends: list[tuple[np.ndarray, np.ndarray, float]]) -> np.ndarray:
    """(6, 6 n) map from the grids' displacements to the bushing's six deformations in
    ``axes`` (rows in basic) at ``point``: each end (position, frame, sign) moves the point
    rigidly, and the deformation is the signed sum (B minus A; one end: grounded)."""
    return np.hstack([sign * blocks(axes) @ rigid_map(point - x) @ blocks(f).T
                      for x, f, sign in ends])
