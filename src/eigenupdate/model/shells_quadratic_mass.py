"""A CQUAD8's or CTRIA6's mass off its reference surface (a PCOMP whose materials'
plies are not centred on it: an unsymmetric stack, or Z0 != -T/2), as three unit
masses per unit first and second moment, the form of
:func:`eigenupdate.model.shell_offsets.offset_mass` for CQUAD4/CTRIA3.

A mass m per area at height h above the reference surface is attached to it rigidly,
node by node along the nodes' directors V_i (u_h = u + h theta x V_i, the link of
ZOFFS in :mod:`eigenupdate.model.shells_quadratic`): with T_h = I + h L,

    M(h) = M_r + h (L^T M_r + M_r L) + h^2 L^T M_r L,

M_r the translational mass on the reference surface, exactly quadratic in h, so the
components' mass m_i at heights h_i enter as sum m_i, sum m_i h_i, sum m_i h_i^2 and
each material's RHO stays linear. On a flat element this is the mass moved to height h;
on a curved one it is the reference surface's mass carried out along the directors
(the parallel surface's area change, of relative order h / R, is left out).
The deck's moments are about the grids (heights H = ZOFFS + h): :func:`unit_masses`
turns them to the reference surface's.
"""

from __future__ import annotations

import numpy as np

from eigenupdate.model import shells_quadratic as quadratic


def unit_masses(xyz: np.ndarray, lumped: bool, labels: list[str] | None = None,
                offset: np.ndarray | None = None) -> list[np.ndarray]:
    """M_0, M_1, M_2 (each (n, 6k, 6k), global axes): the mass of CQUAD8 or CTRIA6
    elements whose components have moments m0, m1, m2 (per area, about the grids, heights
    along the directors) is m0 M_0 + m1 M_1 + m2 M_2; ``offset`` (n,) is ZOFFS.

    Examples
    --------
    A flat element with all its mass on its reference surface (m1 = m2 = 0 about it,
    ZOFFS 0) has the plain mass; one at height h the plain mass moved: its translation
    the same, its rotary inertia m h^2 on rx, ry.

    >>> x = np.array([[[0., 0, 0], [2, 0, 0], [2, 1, 0], [0, 1, 0], [1, 0, 0], [2, .5, 0],
    ...                [1, 1, 0], [0, .5, 0]]])
    >>> m0, m1, m2 = unit_masses(x, True)
    >>> bool(np.array_equal(m0, quadratic.shell_mass(x, True)))
    True
    >>> m = m0 + 0.1 * m1 + 0.01 * m2  # h = 0.1
    >>> round(float(m[0, 3::6, 3::6].trace() / m[0, 0::6, 0::6].trace()), 12)
    0.01
    """
    real = np.asarray(xyz, float)
    zo = np.zeros(real.shape[0]) if offset is None else np.asarray(offset, float)
    moved = bool(np.any(zo))
    ref, V = quadratic.offset_geometry(real, zo if moved else None, labels)
    r0 = quadratic.shell_mass(ref, lumped, labels)  # on the reference surface's nodes
    L = quadratic._offset_links(ref, ref + V) - np.eye(r0.shape[1])  # h theta x V_i
    r1 = np.swapaxes(L, 1, 2) @ r0 + r0 @ L
    r2 = np.swapaxes(L, 1, 2) @ r0 @ L
    z = zo[:, None, None]  # moments about the grids (H = ZOFFS + h) to the reference's
    out = [r0 - z * r1 + z * z * r2, r1 - 2 * z * r2, r2]
    # linked to the grids as shell_mass links its offset mass (a CTRIA6's projection
    # alone, without ZOFFS, is not linked there either)
    return [quadratic._linked(m, quadratic._offset_links(real, ref) if moved else None)
            for m in out]
