"""Flat shell elements CQUAD4 (MITC4) and CTRIA3 (MITC3), vectorised over elements.

Reissner-Mindlin kinematics in element axes x, y (in the element's plane) and z (its
normal): displacements ``u + z ry``, ``v - z rx``, ``w``, so that

* membrane strains ``u,x``, ``v,y``, ``u,y + v,x``;
* curvatures ``ry,x``, ``-rx,y``, ``ry,y - rx,x``;
* transverse shear strains ``w,x + ry`` and ``w,y - rx``, interpolated as MITC4 (Bathe &
  Dvorkin, Int. J. Numer. Meth. Eng. 21, 1985: covariant strains tied at the edge
  mid-points) and MITC3 (Lee & Bathe, Comput. Struct. 82, 2004). MITC4 does not lock
  (one bilinear element bends with constant curvature only, so CQUAD4 adds MacNeal's
  residual bending flexibility to its shear, :data:`RBF_ALPHA`, as NASTRAN's QUAD4);
  MITC3 alone does (5.7 % on a thin plate's first mode with 32 x 32 x 2 elements, a/h =
  1000), so the triangle's shear moduli are scaled by T^2 / (T^2 + alpha h_e^2) (Lyly,
  Stenberg & Vihinen, Comput. Mech. 13, 1993; alpha = 0.1, h_e its longest edge), which
  tends to 1 as the mesh is refined and makes the error independent of the thickness;
* membrane of CQUAD4: bilinear plus Wilson's incompatible modes (Taylor's QM6,
  condensed per element), free of the bilinear element's parasitic shear in in-plane
  bending (MacNeal's QUAD4 avoids it too, by other means);
* drilling rotation: MSC/NX NASTRAN's penalty ``1e-6 K6ROT G T (rz - (v,x - u,y)/2)^2``
  (PARAM K6ROT, default 100), whose only job is to keep ``rz`` from being singular; on a
  curved surface (``curvature`` given) also a term of the bending part that ties ``rz``
  to the membrane rotation (:mod:`eigenupdate.model.shell_normals`).

Element axes are NASTRAN's: CQUAD4's normal is the cross product of the diagonals
G1-G3 and G2-G4, its x axis bisects the angle between them (the mean plane's nodes are
projected onto it, as NASTRAN's flat QUAD4 does); CTRIA3's x axis runs from G1 to G2.
Element matrices come back in global axes, 6 coordinates per node
``[u, v, w, rx, ry, rz]``, nodes in the card's order.

PSHELL's fields enter as *parts* of fixed matrices times a power of the thickness T:

    K(T) = T K_membrane + T K_drilling + T^3 K_bending + s(T) K_shear
    M(T) = (rho T + NSM) M_translation

where s(T) = T^3 / (T^2 + alpha h_e^2) (:func:`shear_thickness`, derivative
:func:`shear_thickness_derivative`): CTRIA3's stabilisation, and CQUAD4's residual
bending flexibility (:data:`RBF_ALPHA`), both vanishing as the mesh is refined
with the moduli of :func:`pshell_moduli` (MID1 plane-stress matrix; MID2's times
(12 I / T^3) / 12; MID3's transverse shear moduli times TS/T), so a thickness parameter
has the exact derivative dK/dT = K_membrane + K_drilling + 3 T^2 K_bending + s'(T) K_shear
(:func:`pshell_matrices` forms both).
An unsymmetric laminate (PCOMP, :mod:`eigenupdate.model.laminate`) adds the part
``coupling``, T^2 times the integral of Bm^T Bc Bb + Bb^T Bc Bm (Bc its coupling moduli
B / T^2; the resultants are N = A eps + B kappa, M = B eps + D kappa, the strain at z
being eps + z kappa in the convention above). CQUAD4's incompatible modes are condensed
by the membrane part alone; the coupling takes the membrane strain with the modes'
amplitudes that condensation sets (-k_ii^-1 k_ic u), so that the energy stays the laminate's
positive [eps, kappa] [[A, B], [B, D]] [eps, kappa] at each point (compatible strains
alone against the softer condensed membrane made a [0/90] element indefinite: one
negative eigenvalue), and the patch test holds (the modes are zero in constant strain
states and do no work on a constant curvature). Where B = 0 the part is not formed.
The mass has no rotary inertia (as NASTRAN's CQUAD4/CTRIA3 with MID4 blank): the
consistent mass couples the translations with the bilinear (linear) shape functions,
the lumped one puts the integral of each shape function at its node.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from eigenupdate.errors import InputError
from eigenupdate.model import rigid_links
from eigenupdate.model.shell_normals import CURVED_DRILLING

STIFFNESS_PARTS = ("membrane", "drilling", "bending", "shear")
COUPLING = "coupling"
"""The membrane-bending coupling part (only where given: not in STIFFNESS_PARTS)."""
THICKNESS_POWER = {"membrane": 1, "drilling": 1, "bending": 3, "shear": 1, COUPLING: 2}
"""Thickness power of each part (CTRIA3's shear: :func:`shear_thickness` instead)."""
ALPHA = 0.1
"""Shear stabilisation of CTRIA3 (Lyly, Stenberg & Vihinen's alpha)."""
RBF_ALPHA = 5 / 6 * (1 - 0.3) / 2
"""CQUAD4's residual bending flexibility (MacNeal, Comput. Struct. 8, 1978, the QUAD4 of
MSC NASTRAN: "augmentation of transverse shear flexibility to account for a deficiency
in the bending strain energy"): a bilinear element bends with constant curvature only,
so one element across a span held at both ends is shear-dominated (a strip's end
rotation stiffness D/L + kappa G T L/4 instead of 4 D/L: 22 times too stiff on the skin
of NX's nx_sine deck). Adding the compliance h^2 / (12 D) to the shear's, h the
element's size, makes that case exact: kappa G T h^2 / (12 D) = alpha h^2 / T^2 with
alpha = kappa (1 - NU) / 2, here at kappa = 5/6, NU = 0.3 (h: the shortest edge).
Measured against NASTRAN's printed frequencies: the dakota cylinder's n = 2 modes from
+2.55 and +2.22 % to -0.36 and -0.56 %, nx_sine's modes 1-8 within 0.23 % (its mode 7
was 122 % high), pyn_solid_shell_bar 0.24, 0.10, 0.61 % (was 0.30, 0.18, 0.81 %)."""
_PART_COLUMNS = {"membrane": [0, 1], "drilling": [0, 1, 5], "bending": [3, 4],
                 "shear": [2, 3, 4], COUPLING: [0, 1, 3, 4]}  # a part's columns of a node
K6ROT = 100.0
"""MSC/NX NASTRAN's default PARAM K6ROT."""
MAX_WARP = 0.2
"""Largest warp (distance of a CQUAD4 node from the mean plane over sqrt(area)) accepted:
the element is computed on its mean plane and rigidly linked to its grids
(:func:`eigenupdate.model.rigid_links.warp_links`), which keeps rigid motions exact, but
a flat element cannot follow a surface twisted further. NASTRAN warns from 0.05
(GEOMCHECK Q4_WARP): :data:`WARN_WARP`."""
WARN_WARP = 0.05

MIN_AREA = 1e-6
"""Smallest twice-area over the squared largest centre-to-node distance: a strip L x w
has about 8 w / L, so aspect ratios beyond about 1e7 are refused (their membrane
stiffness spans (L / w)^2, beyond what the eigen-solver resolves: a 1 x 1e-9 CQUAD4
left massless mechanisms that named no element)."""

_G = 1.0 / np.sqrt(3.0)
_QUAD_XI = np.array([-1.0, 1.0, 1.0, -1.0])
_QUAD_ETA = np.array([-1.0, -1.0, 1.0, 1.0])
_QUAD_POINTS = [(a * _G, b * _G, 1.0) for b in (-1.0, 1.0) for a in (-1.0, 1.0)]
# Strang-Fix 3-point rule, exact for quadratics on the reference triangle (area 1/2)
_TRIA_POINTS = [(1 / 6, 1 / 6, 1 / 6), (2 / 3, 1 / 6, 1 / 6), (1 / 6, 2 / 3, 1 / 6)]


def plane_stress(E: np.ndarray, nu: np.ndarray) -> np.ndarray:
    """Isotropic plane-stress matrices (n, 3, 3) for strains ``[exx, eyy, gxy]``.

    Examples
    --------
    >>> plane_stress(np.array([2.0]), np.array([0.0]))[0].tolist()
    [[2.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 1.0]]
    """
    E, nu = np.broadcast_arrays(np.atleast_1d(np.asarray(E, float)),
                                np.atleast_1d(np.asarray(nu, float)))
    c = np.zeros((E.size, 3, 3))
    f = E / (1.0 - nu**2)
    c[:, 0, 0] = c[:, 1, 1] = f
    c[:, 0, 1] = c[:, 1, 0] = f * nu
    c[:, 2, 2] = E / (2.0 * (1.0 + nu))
    return c


def pshell_moduli(E1: np.ndarray, nu1: np.ndarray, E2: np.ndarray | None = None,
                  nu2: np.ndarray | None = None, G3: np.ndarray | None = None,
                  bending_ratio: np.ndarray | float = 1.0,
                  shear_ratio: np.ndarray | float = 5.0 / 6.0
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Moduli per unit thickness power of PSHELL with MAT1 materials.

    Returns ``membrane`` (n, 3, 3) (MID1), ``bending`` (n, 3, 3) = MID2's plane-stress
    matrix times ``bending_ratio`` (PSHELL 12I/T^3) / 12, and ``shear`` (n, 2, 2) = MID3's
    G times ``shear_ratio`` (PSHELL TS/T, NASTRAN's default 5/6) on ``[gxz, gyz]``.
    MID2 and MID3 default to MID1 (``G3`` to E1 / (2 (1 + nu1))); pass zeros for a
    membrane-only shell.
    """
    membrane = plane_stress(E1, nu1)
    bending = plane_stress(E1 if E2 is None else E2, nu1 if nu2 is None else nu2)
    bending = bending * (np.asarray(bending_ratio, float) / 12.0).reshape(-1, 1, 1)
    g = membrane[:, 2, 2] if G3 is None else np.broadcast_to(np.asarray(G3, float),
                                                            (membrane.shape[0],))
    shear = np.zeros((membrane.shape[0], 2, 2))
    shear[:, 0, 0] = shear[:, 1, 1] = g * np.asarray(shear_ratio, float)
    return membrane, bending, shear


def shell_axes(xyz: np.ndarray, labels: list[str] | None = None
               ) -> tuple[np.ndarray, np.ndarray]:
    """NASTRAN element axes (rows x, y, z; (n, 3, 3)) and the nodes' in-plane element
    coordinates (n, k, 2) of CTRIA3 (k = 3) or CQUAD4 (k = 4) elements.

    A zero area, a warped quadrilateral (:data:`MAX_WARP`), and a quadrilateral that is
    not convex (or whose nodes are not in order round it) are :class:`InputError`
    naming the element (``labels``).

    Examples
    --------
    >>> R, xy = shell_axes(np.array([[[0., 0, 0], [2, 0, 0], [2, 1, 0], [0, 1, 0]]]))
    >>> bool(np.allclose(R[0], np.eye(3))), bool(np.allclose(xy[0, 2], [1.0, 0.5]))
    (True, True)
    """
    xyz = np.asarray(xyz, float)
    n, k = xyz.shape[:2]

    def name(i: int) -> str:
        return labels[i] if labels else f"element {i}"

    if k == 4:
        d13, d24 = xyz[:, 2] - xyz[:, 0], xyz[:, 3] - xyz[:, 1]
        z = np.cross(d13, d24)
        x = (d13 / np.linalg.norm(d13, axis=1, keepdims=True)
             - d24 / np.linalg.norm(d24, axis=1, keepdims=True))
    elif k == 3:
        x = xyz[:, 1] - xyz[:, 0]
        z = np.cross(x, xyz[:, 2] - xyz[:, 0])
    else:
        raise ValueError(f"{k} nodes: a shell element has 3 or 4")
    area2 = np.linalg.norm(z, axis=1)  # twice the (projected) area
    size2 = np.max(np.sum((xyz - xyz.mean(axis=1, keepdims=True)) ** 2, axis=2), axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        bad = np.flatnonzero(~(area2 > MIN_AREA * size2))
    if bad.size:
        raise InputError(f"{name(bad[0])}: zero area (nodes coincide or lie on a line, or "
                         f"it is narrower than 1e-6 of its length)")
    z = z / area2[:, None]
    x = x - np.sum(x * z, axis=1)[:, None] * z
    x /= np.linalg.norm(x, axis=1, keepdims=True)
    R = np.stack([x, np.cross(z, x), z], axis=1)
    local = np.einsum("nij,nkj->nki", R, xyz - xyz.mean(axis=1, keepdims=True))
    if k == 4:
        warp = rigid_links.warp(xyz, z)
        bad = np.flatnonzero(warp > MAX_WARP)
        if bad.size:
            raise InputError(f"{name(bad[0])}: warped by {warp[bad[0]]:.3g} (nodes' distance "
                             f"from the mean plane / sqrt(area); at most {MAX_WARP})")
        # every corner turns left: convex and numbered round the element
        xy = local[:, :, :2]
        e = np.roll(xy, -1, axis=1) - xy
        prev = np.roll(e, 1, axis=1)
        turn = e[:, :, 0] * prev[:, :, 1] - e[:, :, 1] * prev[:, :, 0]
        bad = np.flatnonzero(~np.all(turn < 0, axis=1))
        if bad.size:
            raise InputError(f"{name(bad[0])}: not convex, or its nodes are not in order round "
                             "it (negative Jacobian)")
    return R, local[:, :, :2]


def _jacobian(dn: np.ndarray, xy: np.ndarray):
    """J[a, b] = d x_b / d xi_a (n, 2, 2), det J, J^-1, and the shape functions'
    gradients (n, 2, k) at one point whose natural gradients are ``dn`` (2, k)."""
    J = np.einsum("ak,nkb->nab", dn, xy)
    det = J[:, 0, 0] * J[:, 1, 1] - J[:, 0, 1] * J[:, 1, 0]
    inv = np.empty_like(J)
    inv[:, 0, 0], inv[:, 1, 1] = J[:, 1, 1], J[:, 0, 0]
    inv[:, 0, 1], inv[:, 1, 0] = -J[:, 0, 1], -J[:, 1, 0]
    inv /= det[:, None, None]
    return J, det, inv, inv @ dn


def _b_membrane(g: np.ndarray) -> np.ndarray:
    n, _, k = g.shape
    b = np.zeros((n, 3, 6 * k))
    b[:, 0, 0::6] = g[:, 0]
    b[:, 1, 1::6] = g[:, 1]
    b[:, 2, 0::6] = g[:, 1]
    b[:, 2, 1::6] = g[:, 0]
    return b


def _b_bending(g: np.ndarray) -> np.ndarray:
    n, _, k = g.shape
    b = np.zeros((n, 3, 6 * k))
    b[:, 0, 4::6] = g[:, 0]
    b[:, 1, 3::6] = -g[:, 1]
    b[:, 2, 4::6] = g[:, 1]
    b[:, 2, 3::6] = -g[:, 0]
    return b


def _b_drilling(N: np.ndarray, g: np.ndarray) -> np.ndarray:
    n, _, k = g.shape
    b = np.zeros((n, 1, 6 * k))
    b[:, 0, 5::6] = N
    b[:, 0, 1::6] = -0.5 * g[:, 0]
    b[:, 0, 0::6] = 0.5 * g[:, 1]
    return b


def _covariant_shear(N: np.ndarray, dn: np.ndarray, J: np.ndarray, a: int) -> np.ndarray:
    """Row (n, 6k) of the covariant shear strain w,a + x,a ry - y,a rx along natural
    direction ``a`` at a point with shape functions N (k,), gradients dn (2, k)."""
    k = N.size
    row = np.zeros((J.shape[0], 6 * k))
    row[:, 2::6] = dn[a]
    row[:, 4::6] = J[:, a, 0:1] * N
    row[:, 3::6] = -J[:, a, 1:2] * N
    return row


def _quad_shape(xi: float, eta: float) -> tuple[np.ndarray, np.ndarray]:
    N = 0.25 * (1 + _QUAD_XI * xi) * (1 + _QUAD_ETA * eta)
    dn = 0.25 * np.array([_QUAD_XI * (1 + _QUAD_ETA * eta), _QUAD_ETA * (1 + _QUAD_XI * xi)])
    return N, dn


def _tria_shape(r: float, s: float) -> tuple[np.ndarray, np.ndarray]:
    return np.array([1 - r - s, r, s]), np.array([[-1.0, 1.0, 0.0], [-1.0, 0.0, 1.0]])


def _quad_shear(xi: float, eta: float, xy: np.ndarray, inv: np.ndarray) -> np.ndarray:
    """MITC4: gxi tied at (0, +-1), geta at (+-1, 0), interpolated linearly between."""
    def cov(p, q, a):
        N, dn = _quad_shape(p, q)
        return _covariant_shear(N, dn, np.einsum("ak,nkb->nab", dn, xy), a)
    gxi = 0.5 * (1 + eta) * cov(0.0, 1.0, 0) + 0.5 * (1 - eta) * cov(0.0, -1.0, 0)
    geta = 0.5 * (1 + xi) * cov(1.0, 0.0, 1) + 0.5 * (1 - xi) * cov(-1.0, 0.0, 1)
    return inv @ np.stack([gxi, geta], axis=1)


def _tria_shear(r: float, s: float, xy: np.ndarray, inv: np.ndarray) -> np.ndarray:
    """MITC3: e_r tied at (1/2, 0), e_s at (0, 1/2), both at (1/2, 1/2)."""
    def cov(p, q, a):
        N, dn = _tria_shape(p, q)
        return _covariant_shear(N, dn, np.einsum("ak,nkb->nab", dn, xy), a)
    er1, es2 = cov(0.5, 0.0, 0), cov(0.0, 0.5, 1)
    c = es2 - er1 - cov(0.5, 0.5, 1) + cov(0.5, 0.5, 0)
    return inv @ np.stack([er1 + c * s, es2 - c * r], axis=1)


def rotate(local: np.ndarray, R: np.ndarray) -> np.ndarray:
    """T^T k T for symmetric blocks (n, m, m) whose every 3 coordinates are in the axes
    whose rows are R (n, 3, 3) (T = diag(R, R, ...)): the blocks in global axes."""
    n, m = local.shape[:2]
    y = (local.reshape(n, m * m // 3, 3) @ R).reshape(n, m // 3, 3, m)  # k T
    return (np.swapaxes(R, 1, 2)[:, None] @ y).reshape(n, m, m)


def _expand(terms, n: int, m: int) -> np.ndarray:
    """Sum (n, m, m) of compact parts ``(columns, (n, c, c) block, factor (n, 1, 1))``."""
    out = np.zeros((n, m, m))
    for cols, block, factor in terms:
        out[:, cols[:, None], cols[None, :]] += block * factor
    return out


def _local_parts(xyz: np.ndarray, membrane: np.ndarray, bending: np.ndarray,
                 shear: np.ndarray, k6rot: float, labels: list[str] | None,
                 condense_with: np.ndarray | None = None, coupling: np.ndarray | None = None,
                 curvature: np.ndarray | None = None, profile: np.ndarray | None = None):
    """Element axes R and the stiffness parts in element axes, each as its columns and
    its block on them (membrane: u, v; drilling: u, v, rz; bending: rx, ry; shear: w,
    rx, ry; coupling, when ``coupling`` moduli are given: u, v, rx, ry), all integration
    points in one product. ``condense_with`` (CQUAD4), ``profile``: see
    :func:`local_parts`."""
    xyz = np.asarray(xyz, float)
    n, k = xyz.shape[:2]
    R, xy = shell_axes(xyz, labels)
    cm, cb, cs = (np.broadcast_to(np.asarray(c, float), (n,) + np.shape(c)[-2:])
                  for c in (membrane, bending, shear))
    gd = np.broadcast_to((1e-6 * k6rot * cm[:, 2, 2]).reshape(n, 1, 1), (n, 1, 1))
    cols = {name: (6 * np.arange(k)[:, None] + np.array(c)).ravel()
            for name, c in _PART_COLUMNS.items()}
    b_all = {name: [] for name in STIFFNESS_PARTS}
    db_all = {name: [] for name in STIFFNESS_PARTS}
    c0 = None if condense_with is None or k != 4 else \
        np.broadcast_to(np.asarray(condense_with, float), (n, 3, 3))
    db0 = []  # the membrane with the moduli whose incompatible modes are kept
    cc = None if coupling is None else \
        np.broadcast_to(np.asarray(coupling, float), (n, 3, 3))
    kc = 0.0
    if cc is not None and (c0 is not None or profile is not None):
        raise ValueError("coupling with condense_with or a profile is not formed")
    rotations = cols["bending"]  # rx, ry: the coupling's bending columns
    curved = None
    if curvature is not None:
        gb = (CURVED_DRILLING * cb[:, 2, 2] * np.asarray(curvature, float) ** 2
              ).reshape(n, 1, 1)
        if np.any(gb):
            curved = np.zeros((n, 4, 4))
            curved[:, :3, :3], curved[:, 3:, 3:] = cb, gb
            cols["bending"] = (6 * np.arange(k)[:, None] + np.array([0, 1, 3, 4, 5])).ravel()
    if k == 4:
        points, shape, shear_b = _QUAD_POINTS, _quad_shape, _quad_shear
        _, det0, inv0, _ = _jacobian(_quad_shape(0.0, 0.0)[1], xy)
    else:
        points, shape, shear_b = _TRIA_POINTS, _tria_shape, _tria_shear
    for p, q, weight in points:
        N, dn = shape(p, q)
        _, det, inv, g = _jacobian(dn, xy)
        w = (weight * det)[:, None, None]
        t = 1.0 if profile is None else (np.asarray(profile, float) @ N)[:, None, None]
        bm = _b_membrane(g)[:, :, cols["membrane"]]
        if k == 4:
            # Wilson's modes 1 - xi^2, 1 - eta^2 in u and v, with Taylor's centre
            # Jacobian (det J0 / det J) so that constant strains stay exact
            ga = inv0 @ np.diag([-2.0 * p, -2.0 * q]) * (det0 / det)[:, None, None]
            bm = np.concatenate([bm, _b_membrane(ga)[:, :, [0, 1, 6, 7]]], axis=2)
        bb, cbb = _b_bending(g), cb
        if curved is not None:  # the drilling mismatch on a curved surface (shell_normals)
            bb, cbb = np.concatenate([bb, _b_drilling(N, g)], axis=1), curved
        for name, b, d in (("membrane", bm, cm), ("drilling", _b_drilling(N, g), gd),
                           ("bending", bb, cbb),
                           ("shear", shear_b(p, q, xy, inv), cs)):
            if name != "membrane":
                b = b[:, :, cols[name]]
            b_all[name].append(b)
            db_all[name].append(np.einsum("nab,nbj->naj", d, b) * (
                w * t ** THICKNESS_POWER[name]))
        if cc is not None:  # membrane (with Wilson's modes) x curvature: (n, 2k(+4), 2k)
            kc = kc + np.einsum("nai,nab,nbj->nij", bm * w, cc,
                                _b_bending(g)[:, :, rotations])
        if c0 is not None:
            db0.append(np.einsum("nab,nbj->naj", c0, bm) * (w * t))
    out = {name: (cols[name], np.einsum("nai,naj->nij", np.concatenate(b_all[name], 1),
                                        np.concatenate(db_all[name], 1)))
           for name in STIFFNESS_PARTS}
    if k == 4 and c0 is None:  # condense the incompatible modes element by element
        c, km = out["membrane"]
        out["membrane"] = (c, km[:, :8, :8] - km[:, :8, 8:] @ np.linalg.solve(
            km[:, 8:, 8:], km[:, 8:, :8]))
        if cc is not None:  # the modes' amplitudes as the membrane condensation sets them
            kc = kc[:, :8] - np.swapaxes(np.linalg.solve(km[:, 8:, 8:], km[:, 8:, :8]), 1,
                                         2) @ kc[:, 8:]
    elif k == 4:  # T^T k T, T = [I; -k0_ii^-1 k0_ic] from the moduli condense_with
        c, km = out["membrane"]
        k0 = np.einsum("nai,naj->nij", np.concatenate(b_all["membrane"], 1),
                       np.concatenate(db0, 1))
        t = -np.linalg.solve(k0[:, 8:, 8:], k0[:, 8:, :8])
        tt = np.swapaxes(t, 1, 2)
        out["membrane"] = (c, km[:, :8, :8] + km[:, :8, 8:] @ t + tt @ km[:, 8:, :8]
                           + tt @ km[:, 8:, 8:] @ t)
    if cc is not None:
        block = np.zeros((n, 4 * k, 4 * k))
        im, ib = np.arange(4 * k).reshape(k, 2, 2).transpose(1, 0, 2).reshape(2, 2 * k)
        block[:, im[:, None], ib[None, :]] = kc
        out[COUPLING] = (cols[COUPLING], block + np.swapaxes(block, 1, 2))
    return R, rigid_links.warp_links(out, xyz, R) if k == 4 else out


def local_parts(xyz: np.ndarray, membrane: np.ndarray, bending: np.ndarray,
                shear: np.ndarray, k6rot: float = K6ROT, labels: list[str] | None = None,
                condense_with: np.ndarray | None = None, coupling: np.ndarray | None = None,
                curvature: np.ndarray | None = None, profile: np.ndarray | None = None):
    """Element axes R (n, 3, 3) and the stiffness parts per unit thickness power in
    element axes, compact: ``{part: (columns, (n, c, c) block)}``; :func:`combine` sums
    them with per-element factors and turns the sum to global axes (one rotation for
    any number of factor sets, which is what a deck's parameters need).

    CQUAD4's membrane condenses its incompatible modes, which is not linear in the
    moduli. With ``condense_with`` (membrane moduli A0, (n, 3, 3) or (3, 3)) the modes
    are condensed as they are under A0 (T^T k T, T = [I; -k0_ii^-1 k0_ic]): linear in
    ``membrane``, so a laminate's membrane is the sum of its moduli's parts, equal to the
    exact condensation where membrane = A0 and stiffer by the square of the change of
    A's shape elsewhere (a Ritz approximation with A0's incompatible modes).

    ``coupling`` (n, 3, 3) or (3, 3): a laminate's B / T^2 in element axes; the part
    ``coupling`` (factor T^2, :data:`THICKNESS_POWER`) is formed only when it is given.

    ``curvature`` (n,): the facets' curvature from their grids' normals
    (:func:`eigenupdate.model.shell_normals.facet_curvature`); where it is not zero the
    part ``bending`` gains the drilling mismatch (``shell_normals.CURVED_DRILLING``) and
    the columns u, v, rz.

    ``profile`` (n, k): the thickness at each corner over the one the factors take
    (CQUAD4/CTRIA3 T1-T4): interpolated by the shape functions to each integration
    point, where each part takes it to its power (NASTRAN-95's quad4d.f, THK from the
    grid thicknesses at each Gauss point); None: uniform."""
    return _local_parts(xyz, membrane, bending, shear, k6rot, labels, condense_with,
                        coupling, curvature, profile)


def combine(R: np.ndarray, parts: dict, factors: dict[str, np.ndarray]) -> np.ndarray:
    """Sum (n, 6k, 6k) in global axes of the compact ``parts`` of :func:`local_parts`
    times ``factors`` ({part: (n,)}; a missing part counts 0)."""
    n = R.shape[0]
    m = 6 * (int(max(c.max() for c, _ in parts.values())) // 6 + 1)
    terms = [(*parts[q], np.asarray(f, float).reshape(n, 1, 1)) for q, f in factors.items()]
    return rotate(_expand(terms, n, m), R)


def shell_stiffness_parts(xyz: np.ndarray, membrane: np.ndarray, bending: np.ndarray,
                          shear: np.ndarray, k6rot: float = K6ROT,
                          labels: list[str] | None = None) -> dict[str, np.ndarray]:
    """Stiffness parts (n, 6k, 6k) in global axes of CTRIA3 (xyz (n, 3, 3)) or CQUAD4
    (xyz (n, 4, 3)) elements, per unit thickness power (:data:`THICKNESS_POWER`).

    ``membrane``, ``bending``, ``shear``: the moduli of :func:`pshell_moduli`, (n, 3, 3),
    (n, 3, 3), (n, 2, 2) (or one of each, shared), in element axes. The drilling penalty
    uses the membrane shear modulus (MID1's G) and ``k6rot`` (PARAM K6ROT).
    """
    R, parts = _local_parts(xyz, membrane, bending, shear, k6rot, labels)
    n, m, one = R.shape[0], 6 * np.shape(xyz)[1], np.ones((1, 1, 1))
    return {name: rotate(_expand([(c, b, one)], n, m), R) for name, (c, b) in parts.items()}


def shell_mass(xyz: np.ndarray, lumped: bool, labels: list[str] | None = None,
               profile: np.ndarray | None = None) -> np.ndarray:
    """Translational mass (n, 6k, 6k) per unit mass per area (rho T + NSM) of CTRIA3 or
    CQUAD4 elements: consistent (shape functions' products) or lumped (each shape
    function's integral at its node). Rotations carry no mass. ``profile`` (n, k): the
    mass per area at the corners relative to the unit (:func:`local_parts`), interpolated
    to the integration points.

    Examples
    --------
    Either keeps the element's mass, here a 2 x 1 rectangle:

    >>> xyz = np.array([[[0., 0, 0], [2, 0, 0], [2, 1, 0], [0, 1, 0]]])
    >>> [bool(np.isclose(shell_mass(xyz, c)[0, 0::6, 0::6].sum(), 2.0)) for c in (False, True)]
    [True, True]
    """
    xyz = np.asarray(xyz, float)
    n, k = xyz.shape[:2]
    _, xy = shell_axes(xyz, labels)
    if k == 4:
        points, shape = _QUAD_POINTS, _quad_shape
    else:
        points, shape = _TRIA_POINTS, _tria_shape
    m = np.zeros((n, k, k))
    for p, q, weight in points:
        N, dn = shape(p, q)
        w = weight * _jacobian(dn, xy)[1] * (1.0 if profile is None else profile @ N)
        m += w[:, None, None] * np.outer(N, N)
    if lumped:
        m = np.einsum("nij,ij->nij", np.broadcast_to(m.sum(axis=2)[:, :, None], m.shape),
                      np.eye(k))
    out = np.zeros((n, 6 * k, 6 * k))
    for d in range(3):
        out[:, d::6, d::6] = m
    return out


def stabilisation_size(xyz: np.ndarray) -> np.ndarray:
    """h_e (n,) of :func:`shear_thickness`: a CTRIA3's longest edge; for a CQUAD4 its
    shortest edge times sqrt(RBF_ALPHA / ALPHA), MacNeal's residual bending flexibility
    (see :data:`RBF_ALPHA`)."""
    xyz = np.asarray(xyz, float)
    edges = np.linalg.norm(xyz - np.roll(xyz, 1, axis=1), axis=2)
    if xyz.shape[1] == 4:
        return np.sqrt(RBF_ALPHA / ALPHA) * np.min(edges, axis=1)
    return np.max(edges, axis=1)


def shear_thickness(T: np.ndarray, size: np.ndarray) -> np.ndarray:
    """s(T) = T^3 / (T^2 + alpha h_e^2): the factor of the part ``shear``.

    Examples
    --------
    >>> bool(shear_thickness(0.5, 0.0) == 0.5), bool(shear_thickness(1.0, 3.0) < 1.0)
    (True, True)
    """
    T, h = np.asarray(T, float), np.asarray(size, float)
    return T**3 / (T**2 + ALPHA * h**2)


@dataclass(frozen=True)
class ShearThickness:
    """The shear part's factor of CTRIA3 elements of one size, for a
    :class:`~eigenupdate.model.parametric.FunctionTerm` whose arguments are T (and E
    when ``with_e``): ``coefficient`` (E) T^3 / (T^2 + c), c = alpha h_e^2.

    >>> float(ShearThickness(1.0, 2.0, False)(np.array([1.0])))
    1.0
    """

    c: float
    coefficient: float
    with_e: bool

    def __call__(self, x: np.ndarray):
        t = x[0]
        return self.coefficient * (x[1] if self.with_e else 1.0) * t**3 / (t**2 + self.c)


def shear_thickness_derivative(T: np.ndarray, size: np.ndarray) -> np.ndarray:
    """ds/dT of :func:`shear_thickness`."""
    T, h = np.asarray(T, float), np.asarray(size, float)
    c = ALPHA * h**2
    return T**2 * (T**2 + 3.0 * c) / (T**2 + c) ** 2


def pshell_stiffness(xyz: np.ndarray, T: np.ndarray, membrane: np.ndarray,
                     bending: np.ndarray, shear: np.ndarray, k6rot: float = K6ROT,
                     labels: list[str] | None = None) -> np.ndarray:
    """K (n, 6k, 6k) in global axes of PSHELL elements of thickness T (n,): the ``K`` of
    :func:`pshell_matrices` without its derivative and mass (for assembly)."""
    xyz = np.asarray(xyz, float)
    T = np.broadcast_to(np.asarray(T, float), (xyz.shape[0],))[:, None, None]
    size = stabilisation_size(xyz)[:, None, None]
    R, p = _local_parts(xyz, membrane, bending, shear, k6rot, labels)
    factors = {"membrane": T, "drilling": T, "bending": T**3, "shear": shear_thickness(T, size)}
    return rotate(_expand([(*p[name], factors[name]) for name in STIFFNESS_PARTS],
                          xyz.shape[0], 6 * xyz.shape[1]), R)


def pshell_matrices(xyz: np.ndarray, T: np.ndarray, membrane: np.ndarray,
                    bending: np.ndarray, shear: np.ndarray, rho: np.ndarray,
                    nsm: np.ndarray = 0.0, lumped: bool = False, k6rot: float = K6ROT,
                    labels: list[str] | None = None) -> dict[str, np.ndarray]:
    """K, M and their thickness derivatives dK/dT, dM/dT (each (n, 6k, 6k), global
    axes) of PSHELL elements of thickness T (n,) and mass density ``rho`` (MID1's),
    ``nsm`` per area.

    Examples
    --------
    The derivative is exact: K is a cubic in T.

    >>> xyz = np.array([[[0., 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]])
    >>> m = pshell_moduli(1.0, 0.3)
    >>> a, b = (pshell_matrices(xyz, t, *m, rho=1.0)["K"] for t in (0.1, 0.1 + 1e-6))
    >>> d = pshell_matrices(xyz, 0.1 + 5e-7, *m, rho=1.0)["dK"]
    >>> bool(np.allclose((b - a) / 1e-6, d, rtol=1e-6, atol=1e-9 * abs(d).max()))
    True
    """
    xyz = np.asarray(xyz, float)
    n = xyz.shape[0]
    T = np.broadcast_to(np.asarray(T, float), (n,))[:, None, None]
    size = stabilisation_size(xyz)[:, None, None]
    R, p = _local_parts(xyz, membrane, bending, shear, k6rot, labels)
    m = shell_mass(xyz, lumped, labels)
    rho = np.broadcast_to(np.asarray(rho, float), (n,))[:, None, None]
    nsm = np.broadcast_to(np.asarray(nsm, float), (n,))[:, None, None]
    k = {"membrane": T, "drilling": T, "bending": T**3, "shear": shear_thickness(T, size)}
    dk = {"membrane": 1.0 + 0 * T, "drilling": 1.0 + 0 * T, "bending": 3 * T**2,
          "shear": shear_thickness_derivative(T, size)}
    # rotation is linear: combine in element axes, rotate once
    return {
        "K": rotate(_expand([(*p[q], k[q]) for q in STIFFNESS_PARTS], n, 6 * xyz.shape[1]), R),
        "dK": rotate(_expand([(*p[q], dk[q]) for q in STIFFNESS_PARTS], n, 6 * xyz.shape[1]), R),
        "M": (rho * T + nsm) * m,
        "dM": rho * m,
    }
