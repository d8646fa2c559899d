"""Shell offsets (CQUAD4/CTRIA3 ZOFFS; a PCOMP's mass off its reference plane): the
element's reference plane lies z along its normal (element axis z, NASTRAN's sign) from
the plane of its grids, rigidly attached to them.

Stiffness: NASTRAN's rigid offset. NASTRAN-95's QUAD4 and TRIA3 (quad4d.f, tria3d.f)
turn each node's 6 x 6 transformation into one with the offset (TLDRD in tldrs.f):
``u_ref = u + z ry``, ``v_ref = v - z rx`` in element axes, w and the rotations
unchanged, and K_grid = T^T K_ref T. In terms of the grid plane's strains that is the
laminate [[A, B + z A], [B + z A, D + 2 z B + z^2 A]] (eps_ref = eps + z kappa in the
kinematics of :mod:`eigenupdate.model.shells`), with CQUAD4's incompatible modes condensed
on the reference plane's strains, so a plate whose grid plane is free bends exactly as
the same plate without offset (its neutral plane is its reference plane). Each part of
:func:`eigenupdate.model.shells.local_parts` is transformed alone (T is linear), so the
parts keep their factors and parameters:
:func:`eigenupdate.model.rigid_links.offset_parts`. A PCOMP whose stack is
shifted off its reference plane (Z0 != -T/2) is the same stack about its mid-plane
offset by the shift (its B + s A, D + 2 s B + s^2 A): read so, a free plate keeps its
frequencies with CQUAD4 too (B about the grids with the incompatible modes condensed by
the membrane alone made the free 8 x 8 plate's sixth mode 1 % stiff).

Mass: NASTRAN-95's QUAD4 ships a translational mass at the grids and ignores the
offset (quad4d.f, "THERE ARE NO MASS MOMENT OF INERTIA TERMS"); MSC's and NX's treatment
could not be established from their public documentation. Here the mass is moved rigidly
with the reference plane (:func:`offset_mass`): mass components m_i (per area) at
heights h_i along the normal give

    M = m0 M_translation + m1 M_first + m2 M_second,   m0 = sum m_i,
    m1 = sum m_i h_i,  m2 = sum m_i h_i^2

(M_first couples u with ry and v with rx; M_second is rotary inertia on rx, ry), the
consistent mass moving the shape functions' products, the lumped one each node's share as
a point mass at the offset. The plate of the paragraph above then keeps its frequencies
exactly. A PCOMP's components are its materials, each at the centroid of its plies (so a
symmetric stack has m1 = m2 = 0, as NASTRAN's shell has no rotary inertia); NSM lies on
the reference plane.
"""

from __future__ import annotations

import numpy as np

from eigenupdate.model import shells


def offset_mass(xyz: np.ndarray, lumped: bool, labels: list[str] | None = None,
                profile: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """M_first and M_second (each (n, 6k, 6k), global axes) of CTRIA3 or CQUAD4 elements
    per unit first and second mass moment (m1, m2 per area about the grid plane): the
    offset terms of the rigidly moved translational mass of
    :func:`eigenupdate.model.shells.shell_mass` (its ``profile`` too).

    Examples
    --------
    A mass m at height h above a node moves u + h ry: its blocks m h (u, ry), -m h
    (v, rx) and m h^2 (rx, rx), (ry, ry), here for the lumped mass of a unit square.

    >>> xyz = np.array([[[0., 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]])
    >>> m1, m2 = offset_mass(xyz, True)
    >>> float(m1[0, 0, 4]), float(m1[0, 1, 3]), float(m2[0, 3, 3]), float(m2[0, 5, 5])
    (0.25, -0.25, 0.25, 0.0)
    """
    xyz = np.asarray(xyz, float)
    n, k = xyz.shape[:2]
    R, _ = shells.shell_axes(xyz, labels)
    m = shells.shell_mass(xyz, lumped, labels, profile)[:, 0::6, 0::6]  # (n, k, k)
    first = np.zeros((n, 6 * k, 6 * k))
    second = np.zeros((n, 6 * k, 6 * k))
    first[:, 0::6, 4::6] = m
    first[:, 1::6, 3::6] = -m
    first += np.swapaxes(first, 1, 2)
    second[:, 3::6, 3::6] = m
    second[:, 4::6, 4::6] = m
    return shells.rotate(first, R), shells.rotate(second, R)
