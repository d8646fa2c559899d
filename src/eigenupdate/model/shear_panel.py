"""The shear panel (NASTRAN's CSHEAR with PSHEAR), vectorised; PSHEAR F1/F2's edge rods
(MSC's and NX's, absent from NASTRAN-95) in :func:`edge_rod_stiffness`.

Formulation: NASTRAN-95's (mis/sheard.f, the EMG stiffness; mis/kpanel.f is the same
with another branch threshold), after Garvey's theory of tapered shear panels. The panel
carries one generalized stress, the shear flow, and no direct stress of its own: its
corner forces act along the diagonals (f_i = A_i q e_i, e_1 = e_3 along G1-G3, e_2 =
e_4 along G2-G4, A_1 = -A_3, A_2 = -A_4 from the geometry), so

    K = a a^T / (2 Z),    a = (A_1 e_1, A_2 e_2, A_3 e_3, A_4 e_4) on the translations,

of rank one, Z the panel's flexibility (its strain energy is Z q'^2). For a
parallelogram of area S, skew d (cot of the angle between its sides)
Z = S / (2 G t) (1 + 2 d^2 / (1 + nu)): the shear strain energy and, since uniform
shear flow on inclined edges needs a direct stress sigma = 2 d tau, the direct stress's
E = 2 G (1 + nu) term; a trapezoid and a general quadrilateral take Garvey's forms (the
flows vary as the sides converge). A rectangle a x b is G t a / b in shear: the hand
formula. Geometry as NASTRAN: the mean plane normal to G1-G3 x G2-G4, x along G1-G2
projected; a warped panel is projected (beyond :data:`eigenupdate.model.shells.WARN_WARP`
refused: it has no rotations to link its grids to the plane), a concave one or one
numbered out of order is refused. The rotations of the grids carry nothing.

Mass: NASTRAN-95's (mis/emadtq.f, type 6, used whatever COUPMASS says): each grid gets
translational mass (rho t + NSM) (S_i + S) / 6, S_i the area of the triangle of the grid
and its two neighbours (a quarter of the total on a parallelogram).
"""

from __future__ import annotations

import numpy as np

from eigenupdate.errors import InputError
from eigenupdate.model import rigid_links, shells

BRANCH = 0.01
"""NASTRAN-95's EMG threshold (sheard.f, EP): two opposite sides whose directions differ
by less than this (relative) are parallel, and the trapezoid or parallelogram form of Z
is used."""


def panel_geometry(xyz: np.ndarray, labels: list[str] | None = None):
    """NASTRAN's panel axes (n, 3, 3; rows x, y, z) and in-plane coordinates X2, X3, Y3,
    X4, Y4 (each (n,); G1 at the origin, G2 on x), the area (n,) of the projected
    panel (half |G1G3 x G2G4|). Zero area, warp and non-convex panels: InputError."""
    xyz = np.asarray(xyz, float)
    Rs, _ = shells.shell_axes(xyz, labels)  # zero area, convex and in order
    # no rotations to link a warped panel's grids to its mean plane: refused beyond
    # NASTRAN's warning level
    warp = rigid_links.warp(xyz, Rs[:, 2])
    bad = np.flatnonzero(warp > shells.WARN_WARP)
    if bad.size:
        raise InputError(f"{labels[bad[0]] if labels else f'panel {bad[0]}'}: warped by "
                         f"{warp[bad[0]]:.3g} (nodes' distance from the mean plane / "
                         f"sqrt(area); at most {shells.WARN_WARP} for a shear panel)")
    d1, d2 = xyz[:, 2] - xyz[:, 0], xyz[:, 3] - xyz[:, 1]
    k = np.cross(d1, d2)
    area = np.linalg.norm(k, axis=1) / 2
    k /= 2 * area[:, None]
    v12 = xyz[:, 1] - xyz[:, 0]
    x = v12 - np.sum(v12 * k, axis=1)[:, None] * k
    x2 = np.linalg.norm(x, axis=1)
    x /= x2[:, None]
    y = np.cross(k, x)
    R = np.stack([x, y, k], axis=1)
    v14 = xyz[:, 3] - xyz[:, 0]
    c = [np.sum(d1 * x, axis=1), np.sum(d1 * y, axis=1), np.sum(v14 * x, axis=1),
         np.sum(v14 * y, axis=1)]
    return R, (x2, *c), area


def _flexibility(x2, x3, y3, x4, y4, area, nu) -> np.ndarray:
    """Z G t (n,): sheard.f's four forms, each on the panels it applies to."""
    nuc = 1.0 / (1.0 + nu)
    c23 = 2.0 / 3.0
    temp = x3 - x2
    p12 = np.abs(y3 - y4) < BRANCH * np.abs(x3 - x4)  # G1-G2 parallel to G3-G4
    p23 = np.abs(y4 * temp - y3 * x4) < BRANCH * np.abs(x4 * temp + y4 * y3)
    out = np.empty(x2.shape)
    s = p12 & p23  # parallelogram
    d = -0.5 * (x4[s] / y4[s] + (x3[s] - x2[s]) / y3[s] + (y3[s] - y4[s]) / (x3[s] - x4[s]))
    out[s] = area[s] / 2 * (1 + 2 * d * d * nuc[s])
    s = p12 & ~p23  # trapezoid: sides 2-3 and 4-1 meet at P
    if s.any():
        X2, X3, Y3, X4, Y4 = (v[s] for v in (x2, x3, y3, x4, y4))
        t = Y3 * X4 - Y4 * (X3 - X2)
        yp, xp = X2 * Y3 * Y4 / t, X2 * Y3 * X4 / t
        sa, c = (X2 - xp) / yp, -xp / yp
        out[s] = (yp * yp * area[s] / ((yp - Y3) * (yp - Y4) * 2)
                  * (1 + c23 * nuc[s] * (sa * sa + sa * c + c * c)))
    s = ~p12 & p23  # trapezoid: sides 1-2 and 3-4 meet at Q
    if s.any():
        X2, X3, Y3, X4, Y4 = (v[s] for v in (x2, x3, y3, x4, y4))
        d = -0.5 * (X4 / Y4 + (X3 - X2) / Y3)
        xq = X4 - Y4 * (X3 - X4) / (Y3 - Y4)
        r = 1 / np.sqrt(1 + d * d)
        p = [(xq - X1 - d * Y1) * r for X1, Y1 in ((0.0, 0.0), (X2, 0.0), (X3, Y3), (X4, Y4))]
        b = ((xq - X4) * d + Y4) / ((xq - X4) - Y4 * d)
        out[s] = (p[0] * p[1] * area[s] / (p[2] * p[3] * 2)
                  * (1 + c23 * nuc[s] * (b * b + b * d + d * d)))
    s = ~p12 & ~p23  # general
    if s.any():
        X2, X3, Y3, X4, Y4 = (v[s] for v in (x2, x3, y3, x4, y4))
        xq = X4 - (X3 - X4) / (Y3 - Y4) * Y4
        t = Y3 * X4 - Y4 * (X3 - X2)
        xp, yp = X2 * Y3 * X4 / t, X2 * Y3 * Y4 / t
        xl = np.sqrt((xq - xp) ** 2 + yp * yp)
        d = (xq - xp) / yp
        r = yp / xl
        p = [r * (xq - X1 - d * Y1) for X1, Y1 in ((0.0, 0.0), (X2, 0.0), (X3, Y3), (X4, Y4))]
        c = xl / p[0] - d
        b = xl / p[3] - c
        a = xl / p[1] - d

        def g(u, v):
            return (u + v + c23 * (u**3 + v**3) + 0.2 * (u**5 + v**5)) * np.log(np.abs(u + v))

        f = 0.5 * p[0] * p[1] * p[2] * p[3] / xl**2 * (
            g(a, b) + g(c, d) - g(b, c) - g(d, a)
            + 0.1 * ((a * a - c * c) * (b**3 - d**3) + (b * b - d * d) * (a**3 - c**3))
            - 0.2 * ((a - c) * (b**4 - d**4) + (b - d) * (a**4 - c**4)))
        out[s] = p[0] * p[1] / (p[2] * p[3] * 2) * (area[s] + 4 * nuc[s] * (f - c23 * area[s]))
    return out


def shear_stiffness(xyz: np.ndarray, nu: np.ndarray, labels: list[str] | None = None
                    ) -> np.ndarray:
    """K per unit G t (n, 12, 12) on the corners' translations (basic axes) of shear
    panels xyz (n, 4, 3) of Poisson's ratio ``nu`` (n,).

    Examples
    --------
    A 2 x 1 rectangle sheared u = gamma y stores G t S gamma^2 / 2 (S = 2):

    >>> x = np.array([[[0., 0, 0], [2, 0, 0], [2, 1, 0], [0, 1, 0]]])
    >>> u = np.zeros(12); u[6] = u[9] = 0.1  # the top side moves 0.1 along x
    >>> round(float(u @ shear_stiffness(x, np.array([0.3]))[0] @ u / 2), 12)
    0.01
    """
    xyz = np.asarray(xyz, float)
    R, (x2, x3, y3, x4, y4), area = panel_geometry(xyz, labels)
    nu = np.broadcast_to(np.asarray(nu, float), x2.shape)
    z = _flexibility(x2, x3, y3, x4, y4, area, nu)
    l13 = np.hypot(x3, y3)
    l24 = np.hypot(x4 - x2, y4)
    e13 = (x3 / l13)[:, None] * R[:, 0] + (y3 / l13)[:, None] * R[:, 1]
    e24 = ((x4 - x2) / l24)[:, None] * R[:, 0] + (y4 / l24)[:, None] * R[:, 1]
    t = x4 * y3 - x3 * y4
    a1 = -0.5 * x2 * y4 * l13 / t
    a2 = 0.5 * x2 * y3 * l24 / (t - x2 * (y3 - y4))
    a = np.concatenate([a1[:, None] * e13, a2[:, None] * e24, -a1[:, None] * e13,
                        -a2[:, None] * e24], axis=1)
    return a[:, :, None] * a[:, None, :] / (2 * z)[:, None, None]


def shear_mass(xyz: np.ndarray) -> np.ndarray:
    """NASTRAN-95's lumped mass (n, 12, 12) per unit mass per area on the corners'
    translations: (S_i + S) / 6 at grid i (emadtq.f).

    >>> x = np.array([[[0., 0, 0], [2, 0, 0], [2, 1, 0], [0, 1, 0]]])
    >>> np.diag(shear_mass(x)[0])[::3].tolist()
    [0.5, 0.5, 0.5, 0.5]
    """
    xyz = np.asarray(xyz, float)
    whole = np.linalg.norm(np.cross(xyz[:, 2] - xyz[:, 0], xyz[:, 3] - xyz[:, 1]), axis=1) / 2
    m = np.zeros((xyz.shape[0], 12, 12))
    for i in range(4):
        a, b = xyz[:, (i + 1) % 4] - xyz[:, i], xyz[:, (i - 1) % 4] - xyz[:, i]
        tri = np.linalg.norm(np.cross(a, b), axis=1) / 2
        for c in range(3):
            m[:, 3 * i + c, 3 * i + c] = (tri + whole) / 6
    return m


EFFECTIVE_WIDTH = 1.01
"""MSC's PSHEAR remark: F <= 1.01 is an effectiveness factor (edge rods of area
F T PA / (L12 + L34)), F > 1.01 an effective width in thicknesses (area F T^2 / 2)."""

EDGES = ((0, 1), (1, 2), (2, 3), (3, 0))  # 1-2, 2-3, 3-4, 4-1: F1, F2, F1, F2


def edge_rod_stiffness(xyz: np.ndarray, f1: np.ndarray, f2: np.ndarray
                       ) -> tuple[np.ndarray, np.ndarray]:
    """The extensional stiffness of PSHEAR F1/F2 (MSC's and NX's convention, QRG PSHEAR
    remark: rods on the panel's edges, Poisson coupling ignored, no mass of their own) on
    the corners' translations (basic axes): (per unit E T, per unit E T^2), each
    (n, 12, 12). An edge of effectiveness factor F <= 1.01 on edges 1-2 and 3-4 (F1; F2
    on 2-3 and 4-1) is a rod of area F T PA / (L12 + L34), PA the panel's area (half
    |G1G3 x G2G4|): F1 = 1 on a rectangle a x b (a along 1-2) is two rods of T b / 2,
    the whole section E T b / a in extension along 1-2. F > 1.01 is an effective width:
    area F T^2 / 2. The rods run between the grids (as CRODs would).

    >>> x = np.array([[[0., 0, 0], [2, 0, 0], [2, 1, 0], [0, 1, 0]]])
    >>> lin, quad = edge_rod_stiffness(x, np.array([1.0]), np.array([0.0]))
    >>> u = np.zeros(12); u[3] = u[6] = 0.1  # grids 2 and 3 move 0.1 along x
    >>> round(float(u @ lin[0] @ u), 12), float(np.abs(quad).max())  # (T b / a) 0.1^2
    (0.005, 0.0)
    """
    xyz = np.asarray(xyz, float)
    n = xyz.shape[0]
    pa = np.linalg.norm(np.cross(xyz[:, 2] - xyz[:, 0], xyz[:, 3] - xyz[:, 1]), axis=1) / 2
    vec = [xyz[:, b] - xyz[:, a] for a, b in EDGES]
    length = np.stack([np.linalg.norm(v, axis=1) for v in vec], axis=1)
    lin, quad = np.zeros((n, 12, 12)), np.zeros((n, 12, 12))
    for k, (a, b) in enumerate(EDGES):
        f = np.broadcast_to(np.asarray(f1 if k % 2 == 0 else f2, float), (n,))
        factor = f <= EFFECTIVE_WIDTH
        per_t = np.where(factor, f * pa / (length[:, k] + length[:, (k + 2) % 4]), 0.0)
        per_t2 = np.where(factor, 0.0, 0.5 * f)
        e = vec[k] / length[:, k, None]
        ee = e[:, :, None] * e[:, None, :] / length[:, k, None, None]
        for out, area in ((lin, per_t), (quad, per_t2)):
            block = area[:, None, None] * ee
            for i, j, sign in ((a, a, 1), (b, b, 1), (a, b, -1), (b, a, -1)):
                out[:, 3 * i:3 * i + 3, 3 * j:3 * j + 3] += sign * block
    return lin, quad
