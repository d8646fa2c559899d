"""Curved quadratic shells CQUAD8 (8-node serendipity) and CTRIA6 (6-node), vectorised.

Formulation: the degenerated (continuum-based) shell of Ahmad, Irons & Zienkiewicz
(Int. J. Numer. Meth. Eng. 2, 1970) linearised in the thickness coordinate z, so that
it splits into the same *parts* as :mod:`eigenupdate.model.shells` (membrane T,
drilling T, bending T^3, shear s(T)). The mid-surface x(xi, eta) and the displacement
u are interpolated from the nodes; each node carries a unit director V_i (the element
surface's normal at the node) and the rotation theta_i (three components, global
axes), the fibre turning by beta = sum N_i theta_i x V_i. At each integration point,
in the local Cartesian axes e_x, e_y (tangent), e_z (normal):

* membrane strains  sym(e_a . u,b);
* curvatures        sym(e_a . beta,b + V,a . u,b)  (the second term is the reference
  surface's curvature: without it a curved element misses the coupling of rotations
  with the changing director and converges to a wrong cylinder);
* transverse shear  e_a . beta + V . u,a;
* drilling          :mod:`~eigenupdate.model.shells`' penalty on
  e_z . theta - (e_y . u,x - e_x . u,y) / 2 (PARAM K6ROT).

Every term vanishes for a rigid motion u = t + theta x x, theta_i = theta, on any
curved element. CQUAD8 is curved: per-point frames on its true surface (NASTRAN
defines its element axes per point too). CTRIA6 is flat: its nodes are projected on
the plane of its corners, with rigid links from the grids so rigid motions stay
rigid, and a mid-side node off that plane by more than :data:`MAX_OFFSET` sqrt(area)
is refused here. Measured (tests/model): the curved 6-node triangle membrane-locks (a
free cylinder's n = 2 ring mode, R/h = 1000, 48 x 8 x 2 elements: 50 % high), the flat
one converges as the mesh size squared (0.26 % there). A deck's curved CTRIA6 (off by
more than :data:`FACET_OFFSET`) are read as four flat CTRIA3 on their six grids
(:data:`FACETS`, :mod:`eigenupdate.io.nastran_continuum`).

Element axes (NASTRAN's, per point): CQUAD8's x bisects, with y, the angle between the
tangents of the lines of constant eta and xi ("double bisection"); CTRIA6's x is the
tangent of the G1-G2 parameter line. Material angles (THETA/MCID of a PCOMP) are taken
at the element centre (:func:`material_axes`) and held over the element.

Integration and locking. CQUAD8: bending, drilling and shear 3 x 3 Gauss points,
membrane 2 x 2 (reduced membrane: without it the curved element membrane-locks, a free
cylinder's ring mode 65 % high at 24 x 4 elements; a single flat element then has one
spurious membrane mode, which an assembled mesh does not: six zero eigenvalues).
CQUAD8's transverse shear is an MITC8-type assumed covariant strain (after Bucalem &
Bathe, Int. J. Numer. Meth. Eng. 36, 1993; this tying was chosen and checked by the
tests, not taken from the paper): e_rt = a_r . beta + V . u,r is replaced by the field
in 1, r, s, rs, s^2 that takes its values at r = +-1/sqrt(3) on the edges s = +-1 and
its mean over the element (e_st likewise, r and s swapped), then turned to the element
axes. It needs no factor, so the shear part stays linear in T. Measured (tests/model):
a simply supported plate's error falls as the mesh size to the fourth (+0.33, +0.021,
+0.0013 % at 4, 8, 16 per side against Mindlin's plate, the same at a/h = 100 to
10000); the Lyly-Stenberg factor it replaced gave the square (-0.33, -0.11, -0.027 %),
plain 2 x 2 shear locked (22 % high at a/h = 1e4, 8 x 8), MITC9's six tying points
(r = +-1/sqrt(3), s = 0, +-sqrt(3/5)) lock on this element (178 %: too many
constraints for its nodes), and the centre value instead of the mean is too soft
(-0.13 % at 16 per side, as the square). CTRIA6: Dunavant's 6-point rule (degree 4),
shear and membrane on the 3-point rule, with the Lyly-Stenberg factor of CTRIA3 on its
shear moduli, :func:`eigenupdate.model.shells.shear_thickness`, h_e half the longest
edge (the node spacing): its error is independent of the thickness and falls as the
mesh size squared (0.69, 0.15 % at 8, 16 per side on that plate); alpha h_e^2 is
scaled by the section's shear over bending stiffness (:func:`stabilisation_ratio`, 1 for
an isotropic PSHELL), without which a shear-soft laminate was stabilised ten times too
much (-1.94 % at 8 per side, tests/model/test_shells_quadratic_laminate.py). MITC6-type
tying (rotated Raviart-Thomas of degree one, edge Gauss points and the mean) without MITC7's
bubble locks mildly (0.19 % at 16 per side, a/h = 1e4, against 0.0025 % at a/h = 100),
so CTRIA6 keeps the factor.

Offsets (NASTRAN's ZOFFS, :func:`offset_geometry`): the element is integrated on its
reference surface, its nodes moved along their directors (CQUAD8's normals vary over a
curved element, so its reference surface is the parallel surface; CTRIA6's is the
corners' plane moved along its normal), rigidly linked to the grids (u + z theta x V_i,
the link of the CTRIA6 projection above), its mass with it: a free offset element keeps
its rigid modes and frequencies exactly. The directors are per element, so on a curved
mesh two elements' offset nodes at a shared grid may differ by the angle between their
normals there times z (zero on a flat mesh; 0.028 rad between neighbours on a cylinder
of eight CQUAD8 round, 45 degrees each, falling as the cube of the element's angle).

Blank mid-side nodes (NaN coordinates): the transition elements of
:mod:`~eigenupdate.model.shells_transition`, whose shear tying replaces the above.

Laminates: the membrane-bending coupling (N = A eps + B kappa, M = B eps + D kappa) is
integrated on the membrane's points (CQUAD8 2 x 2, CTRIA6 3), so a membrane strain state
of no energy there (a flat CQUAD8's spurious mode) does no coupling work, and the bending
is split so that the energy stays positive: D - B A^-1 B on the bending's points and
B A^-1 B with the coupling on the membrane's, where the laminate's energy is then
(eps + A^-1 B kappa) A (eps + A^-1 B kappa) + kappa (D - B A^-1 B) kappa. Both rules
integrate constant strains exactly (the patch test holds); B = 0 is the plain element.
A mass off the reference surface (a stack's first moment): :mod:`~eigenupdate.model.
shells_quadratic_mass`.

Corner thicknesses (NASTRAN's T1-T4): a ``profile`` of nodal thicknesses
(:func:`nodal_profile`, a mid-side node the mean of its edge's corners) interpolated to
every integration point, each part taking it to its power and the mass to the first; a
laminate's coupling with it is not formed.

Mass: translational (no rotary inertia, as :mod:`~eigenupdate.model.shells`),
consistent ``sum w N_i N_j`` or lumped by the HRZ diagonal scaling (Hinton, Rock &
Zienkiewicz, Earthq. Eng. Struct. Dyn. 4, 1976: positive nodal masses; the row sums of
a quadratic element's consistent mass are negative at its corners).
"""

from __future__ import annotations

import numpy as np

from eigenupdate.errors import InputError
from eigenupdate.model import shells
from eigenupdate.model import shells_quadratic_stabilisation as stabilisation
from eigenupdate.model import shells_transition as transition

STIFFNESS_PARTS = shells.STIFFNESS_PARTS
K6ROT = shells.K6ROT
NODES = {"CQUAD8": 8, "CTRIA6": 6}
MAX_OFFSET = 0.05
"""Largest distance of a CTRIA6's mid-side node from its corners' plane, over
sqrt(area), that the flat projection accepts (as :data:`eigenupdate.model.shells.MAX_WARP`
for CQUAD4)."""
stabilisation_size = stabilisation.stabilisation_size  # CTRIA6's shear, its own module
stabilisation_ratio = stabilisation.stabilisation_ratio

_QXI = np.array([-1.0, 1.0, 1.0, -1.0, 0.0, 1.0, 0.0, -1.0])
_QETA = np.array([-1.0, -1.0, 1.0, 1.0, -1.0, 0.0, 1.0, 0.0])
_TR = np.array([0.0, 1.0, 0.0, 0.5, 0.5, 0.0])
_TS = np.array([0.0, 0.0, 1.0, 0.0, 0.5, 0.5])


def _gauss(n: int) -> list[tuple[float, float, float]]:
    x, w = np.polynomial.legendre.leggauss(n)
    return [(float(x[i]), float(x[j]), float(w[i] * w[j])) for j in range(n) for i in range(n)]


def _dunavant4() -> list[tuple[float, float, float]]:
    """Dunavant's degree-4 rule, 6 points, weights summing to the area 1/2."""
    out = []
    for a, w in ((0.445948490915965, 0.223381589678011), (0.091576213509771,
                                                           0.109951743655322)):
        for r, s in ((a, a), (1 - 2 * a, a), (a, 1 - 2 * a)):
            out.append((r, s, w / 2))
    return out


_RULES = {8: {"full": _gauss(3), "shear": _gauss(2)},
          6: {"full": _dunavant4(), "shear": shells._TRIA_POINTS}}
# CQUAD8's shear is tied (MITC, below) and integrated on the full rule
RULE_PARTS = {8: (("full", ("bending", "drilling", "shear")), ("shear", ("membrane",))),
              6: (("full", ("bending", "drilling")), ("shear", ("shear", "membrane")))}

def shape(k: int, p: float, q: float) -> tuple[np.ndarray, np.ndarray]:
    """Shape functions N (k,) and natural gradients (2, k) of CQUAD8 (k = 8, at xi, eta
    in [-1, 1]) or CTRIA6 (k = 6, at r, s of the unit triangle), NASTRAN's node order.

    >>> bool(np.isclose(shape(8, 0.3, -0.2)[0].sum(), 1.0))
    True
    >>> [abs(float(v)) for v in shape(6, 0.5, 0.0)[0]]
    [0.0, 0.0, 0.0, 1.0, 0.0, 0.0]
    """
    if k == 8:
        xi, eta = _QXI, _QETA
        N, d = np.empty(8), np.empty((2, 8))
        c = slice(0, 4)
        N[c] = 0.25 * (1 + xi[c] * p) * (1 + eta[c] * q) * (xi[c] * p + eta[c] * q - 1)
        d[0, c] = 0.25 * xi[c] * (1 + eta[c] * q) * (2 * xi[c] * p + eta[c] * q)
        d[1, c] = 0.25 * eta[c] * (1 + xi[c] * p) * (xi[c] * p + 2 * eta[c] * q)
        for i in (4, 6):  # xi_i = 0
            N[i] = 0.5 * (1 - p * p) * (1 + eta[i] * q)
            d[0, i], d[1, i] = -p * (1 + eta[i] * q), 0.5 * eta[i] * (1 - p * p)
        for i in (5, 7):  # eta_i = 0
            N[i] = 0.5 * (1 + xi[i] * p) * (1 - q * q)
            d[0, i], d[1, i] = 0.5 * xi[i] * (1 - q * q), -q * (1 + xi[i] * p)
        return N, d
    if k == 6:
        L = np.array([1 - p - q, p, q])
        dL = np.array([[-1.0, 1.0, 0.0], [-1.0, 0.0, 1.0]])
        N = np.concatenate([L * (2 * L - 1), 4 * L * np.roll(L, -1)])
        d = np.concatenate([(4 * L - 1) * dL,
                            4 * (dL * np.roll(L, -1) + L * np.roll(dL, -1, axis=1))], axis=1)
        return N, d
    raise ValueError(f"{k} nodes: a quadratic shell has 6 or 8")


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _frame(a: np.ndarray, k: int) -> np.ndarray:
    """Local axes (n, 3, 3) (rows x, y, z) from the natural tangents a (n, 2, 3)."""
    z = _unit(np.cross(a[:, 0], a[:, 1]))
    if k == 8:  # double bisection of the xi and eta lines
        e1, e2 = _unit(a[:, 0]), _unit(a[:, 1])
        b, c = _unit(e1 + e2), _unit(e2 - e1)
        x = _unit(b - c)
    else:
        x = _unit(a[:, 0])
    return np.stack([x, np.cross(z, x), z], axis=1)


def _name(labels, i: int) -> str:
    return labels[i] if labels else f"element {i}"


def geometry(xyz: np.ndarray, labels: list[str] | None = None
             ) -> tuple[np.ndarray, np.ndarray]:
    """The nodes (n, k, 3) the element is integrated on and their unit directors
    (n, k, 3): CQUAD8's own nodes and its surface's normals at them; CTRIA6's nodes
    projected on the plane of its corners and that plane's normal (a mid-side node
    further than :data:`MAX_OFFSET` from it is an :class:`InputError`)."""
    xyz = transition.fill(xyz)[0]
    if xyz.shape[1] != 6:
        return xyz, directors(xyz, labels)
    off, z, rel = _plane_offsets(xyz, labels)
    bad = np.flatnonzero(rel > MAX_OFFSET)
    if bad.size:
        raise InputError(f"{_name(labels, bad[0])}: curved (a mid-side node {rel[bad[0]]:.3g} "
                         f"sqrt(area) off the corners' plane; at most {MAX_OFFSET}): curved "
                         f"CTRIA6 are not supported (use CQUAD8 or more elements)")
    flat = xyz - off[:, :, None] * z[:, None]
    directors(flat, labels)  # the Jacobian checks
    return flat, np.broadcast_to(z[:, None], flat.shape)


def _plane_offsets(xyz: np.ndarray, labels: list[str] | None = None
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """CTRIA6 nodes' distances (n, 6) from their corners' plane, its unit normal (n, 3)
    and the largest distance over sqrt(area) (n,); a zero area is an InputError."""
    xyz = transition.fill(xyz)[0]
    c = xyz[:, :3]
    z = np.cross(c[:, 1] - c[:, 0], c[:, 2] - c[:, 0])
    area2 = np.linalg.norm(z, axis=1)
    size2 = np.max(np.sum((c - c.mean(axis=1, keepdims=True)) ** 2, axis=2), axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        bad = np.flatnonzero(~(area2 > 1e-10 * size2))
        z = z / area2[:, None]
    if bad.size:
        raise InputError(f"{_name(labels, bad[0])}: zero area (corners coincide or lie on a "
                         f"line)")
    off = np.einsum("nkj,nj->nk", xyz - c[:, :1], z)
    return off, z, np.max(np.abs(off), axis=1) / np.sqrt(area2 / 2)


def curved_tria6(xyz: np.ndarray, labels: list[str] | None = None) -> np.ndarray:
    """Which CTRIA6 (xyz (n, 6, 3)) are curved: a mid-side node more than
    :data:`FACET_OFFSET` sqrt(area) off the corners' plane."""
    return _plane_offsets(np.asarray(xyz, float), labels)[2] > FACET_OFFSET


FACET_OFFSET = 1e-3
"""A CTRIA6 whose mid-side node lies further than this times sqrt(area) off its corners'
plane is read as four flat facets (:data:`FACETS`) rather than projected flat: on a free
cylinder (R/h 100, ring mode n = 2, tests/io/test_nastran_quadratic_shells.py) the
projection was +1.35 % and +0.33 % off at 24 x 4 and 48 x 8 x 2 elements where the facets
were +0.71 % and +0.17 %; below 1e-3 the projection moves a node by less than the
coordinates' usual rounding matters."""
FACETS = ((0, 3, 5), (3, 1, 4), (5, 4, 2), (4, 5, 3))
"""A curved CTRIA6 as four flat CTRIA3 on its six grids (G1 G4 G6, G4 G2 G5, G6 G5 G3,
G5 G6 G4): each facet's G1-G2 side is parallel to the CTRIA6's (the last reversed, which
turns no ply: a ply is the same at theta and theta + 180 degrees), so THETA keeps its
meaning; the facets' normals point as the CTRIA6's."""


def _offset_links(real: np.ndarray, used: np.ndarray) -> np.ndarray | None:
    """T (n, 6k, 6k) with u_used = T u_real: rigid links from the grids to the projected
    nodes (u + theta x d, d = used - real), so that rigid motions stay rigid; None
    when no node moved."""
    d = used - real
    if not np.any(d):
        return None
    n, k = d.shape[:2]
    T = np.broadcast_to(np.eye(6 * k), (n, 6 * k, 6 * k)).copy()
    for i in range(k):
        r = 6 * i
        x, y, z = d[:, i, 0], d[:, i, 1], d[:, i, 2]
        # theta x d = -[d]x theta
        T[:, r, r + 4], T[:, r, r + 5] = z, -y
        T[:, r + 1, r + 3], T[:, r + 1, r + 5] = -z, x
        T[:, r + 2, r + 3], T[:, r + 2, r + 4] = y, -x
    return T


def _linked(blocks: np.ndarray, T: np.ndarray | None) -> np.ndarray:
    return blocks if T is None else np.swapaxes(T, 1, 2) @ blocks @ T


def directors(xyz: np.ndarray, labels: list[str] | None = None) -> np.ndarray:
    """Unit normals (n, k, 3) of the elements' surfaces at their nodes. A zero or
    reversed Jacobian at a node or an integration point (nodes out of order, a
    mid-side node outside the middle half of its edge, a zero area) is an
    :class:`InputError` naming the element."""
    xyz = transition.fill(xyz)[0]
    n, k = xyz.shape[:2]
    if k == 8:
        nat = list(zip(_QXI, _QETA, strict=True))
        centre = (0.0, 0.0)
    else:
        nat = list(zip(_TR, _TS, strict=True))
        centre = (1 / 3, 1 / 3)
    size2 = np.max(np.sum((xyz - xyz.mean(axis=1, keepdims=True)) ** 2, axis=2), axis=1)
    n0 = np.cross(*np.einsum("ak,nkb->nab", shape(k, *centre)[1], xyz).transpose(1, 0, 2))
    with np.errstate(invalid="ignore", divide="ignore"):
        n0 = n0 / np.linalg.norm(n0, axis=1, keepdims=True)
    out = np.empty((n, k, 3))
    checks = [(p, q) for p, q, _ in _RULES[k]["full"]] + nat
    for j, (p, q) in enumerate(checks):
        a = np.einsum("ak,nkb->nab", shape(k, p, q)[1], xyz)
        c = np.cross(a[:, 0], a[:, 1])
        with np.errstate(invalid="ignore"):
            bad = np.flatnonzero(~(np.sum(c * n0, axis=1) > 1e-8 * size2))
        if bad.size:
            raise InputError(f"{_name(labels, bad[0])}: zero or negative Jacobian (zero "
                             f"area, nodes not in order round it, or a mid-side node out "
                             f"of place)")
        if j >= len(checks) - k:
            out[:, j - len(checks) + k] = _unit(c)
    return out


def _point(xyz, V, k, p, q, C=None):
    """At one natural point: N (n, k), the local axes (n, 3, 3), the local gradients
    G (n, 2, k), det J (n,), the interpolated director and its gradients; with ``C``
    (:func:`~eigenupdate.model.shells_transition.tie`), the transition element's."""
    N, dn = shape(k, p, q)
    n = xyz.shape[0]
    if C is None:
        N, dn = np.broadcast_to(N, (n, k)), np.broadcast_to(dn, (n, 2, k))
    else:
        N, dn = N @ C, np.einsum("ak,nkj->naj", dn, C)
    a = np.einsum("nak,nkb->nab", dn, xyz)
    R = _frame(a, k)
    J = np.einsum("nab,ncb->nac", a, R[:, :2])  # J[a, b] = a_a . e_b
    det = J[:, 0, 0] * J[:, 1, 1] - J[:, 0, 1] * J[:, 1, 0]
    G = np.linalg.solve(J, dn)
    return N, R, G, det, np.einsum("nk,nkb->nb", N, V), np.einsum("nak,nkb->nab", G, V), J


def _tied_shear(xyz, V, k, mean, C=None):
    """CQUAD8's covariant transverse shear strains (n, 7, 6k): e_rt at the edge points
    of :data:`~eigenupdate.model.shells_transition.POINTS` and its ``mean`` (n, 2, 6k:
    e_rt, e_st) over the natural square, then e_st's (r, s swapped)."""
    out = []
    for row in (0, 1):
        rows = []
        for r, s in transition.POINTS:
            if C is None and r == 0:  # MITC4's points: only where a mid-side node is blank
                rows.append(np.zeros_like(mean[:, row]))
                continue
            N, R, G, _, Vp, dV, J = _point(xyz, V, k, *((r, s) if row == 0 else (s, r)), C)
            # covariant = J Cartesian: a_r . beta + V . u,r with the tangent a_r
            rows.append((J @ _b_matrices(N, R, G, Vp, dV, V)["shear"])[:, row])
        out.append(np.stack(rows + [mean[:, row]], axis=1))
    return out


def _b_matrices(N, R, G, Vp, dV, V):
    """B (n, rows, 6k) of membrane, bending, shear, drilling in global coordinates."""
    n, _, k = G.shape
    ex, ey, ez = R[:, 0], R[:, 1], R[:, 2]
    gx, gy = G[:, 0, :, None], G[:, 1, :, None]  # (n, k, 1)
    vx, vy = np.cross(V, ex[:, None]), np.cross(V, ey[:, None])  # (n, k, 3)
    bm, bb = np.zeros((n, 3, k, 6)), np.zeros((n, 3, k, 6))
    bs, bd = np.zeros((n, 2, k, 6)), np.zeros((n, 1, k, 6))
    bm[:, 0, :, :3] = gx * ex[:, None]
    bm[:, 1, :, :3] = gy * ey[:, None]
    bm[:, 2, :, :3] = gy * ex[:, None] + gx * ey[:, None]
    bb[:, 0, :, 3:], bb[:, 0, :, :3] = gx * vx, gx * dV[:, None, 0]
    bb[:, 1, :, 3:], bb[:, 1, :, :3] = gy * vy, gy * dV[:, None, 1]
    bb[:, 2, :, 3:] = gy * vx + gx * vy
    bb[:, 2, :, :3] = gy * dV[:, None, 0] + gx * dV[:, None, 1]
    bs[:, 0, :, 3:], bs[:, 0, :, :3] = N[:, :, None] * vx, gx * Vp[:, None]
    bs[:, 1, :, 3:], bs[:, 1, :, :3] = N[:, :, None] * vy, gy * Vp[:, None]
    bd[:, 0, :, 3:] = N[:, :, None] * ez[:, None]
    bd[:, 0, :, :3] = -0.5 * (gx * ey[:, None] - gy * ex[:, None])
    return {name: b.reshape(n, b.shape[1], 6 * k) for name, b in
            (("membrane", bm), ("bending", bb), ("shear", bs), ("drilling", bd))}


def offset_geometry(xyz: np.ndarray, offset: np.ndarray | None = None,
                    labels: list[str] | None = None) -> tuple[np.ndarray, np.ndarray]:
    """:func:`geometry`'s nodes moved ``offset`` (n,) along their directors (the
    reference surface of a ZOFFS: CQUAD8's nodes along its surface's normal at each,
    so a curved element's reference surface is the parallel one; CTRIA6's along its
    corners' normal) and the directors, unchanged (the fibres through the grids).
    A reference surface folded over (an offset beyond a curved element's radius) is
    an :class:`InputError`, as a zero or reversed Jacobian on it."""
    present = transition.fill(xyz)[1]
    xyz, V = geometry(xyz, labels)
    if offset is None or not np.any(offset):
        return xyz, V
    # a blank mid-side node stays at its (moved) edge's middle: a straight edge
    xyz = transition.refill(xyz + np.asarray(offset, float)[:, None, None] * V, present)
    turned = np.flatnonzero(np.min(np.sum(directors(xyz, labels) * V, axis=2), axis=1) <= 0)
    if turned.size:
        raise InputError(f"{_name(labels, turned[0])}: ZOFFS = {offset[turned[0]]:g} turns "
                         f"its reference surface inside out (an offset beyond its radius "
                         f"of curvature)")
    return xyz, V


def nodal_profile(corners: np.ndarray) -> np.ndarray:
    """Thickness (n, k) at every node of CQUAD8 (k = 8) or CTRIA6 (6) from its corners'
    (n, 4) or (n, 3) (T1-T4, NASTRAN's corner thicknesses): a mid-side node the mean of
    its edge's corners. The shape functions then interpolate the corners' bilinear
    (CQUAD8) or linear (CTRIA6) field exactly: the serendipity and quadratic bases
    contain it, and its values at the mid-sides are those means.

    >>> nodal_profile(np.array([[1.0, 0.5, 0.5, 1.0]])).tolist()
    [[1.0, 0.5, 0.5, 1.0, 0.75, 0.5, 0.75, 1.0]]
    """
    corners = np.asarray(corners, float)
    k = {4: 8, 3: 6}[corners.shape[1]]
    return np.concatenate([corners, corners[:, transition.EDGES[k]].mean(axis=2)], axis=1)


def local_parts(xyz: np.ndarray, membrane: np.ndarray, bending: np.ndarray,
                shear: np.ndarray, k6rot: float = K6ROT, labels: list[str] | None = None,
                offset: np.ndarray | None = None, coupling: np.ndarray | None = None,
                profile: np.ndarray | None = None):
    """As :func:`eigenupdate.model.shells.local_parts` for CQUAD8 (xyz (n, 8, 3)) or
    CTRIA6 (n, 6, 3): axes R and ``{part: (columns, (n, 6k, 6k) block)}`` per unit
    thickness power. The blocks are already in global axes (R is the identity: the
    element axes change from point to point), so :func:`eigenupdate.model.shells.combine`
    applies unchanged. The moduli are in the element axes of :func:`material_axes`.
    ``offset`` (n,): NASTRAN's ZOFFS, the element on :func:`offset_geometry`'s
    reference surface rigidly linked to the grids (u + z theta x V_i, rotations
    unchanged: on a flat element u + z ry, v - z rx in its axes, as CQUAD4's).
    ``coupling`` (n, 3, 3): a laminate's B / T^2 per unit of the membrane's factor: the
    part ``coupling`` (T^2) on the membrane's points, and the bending split (module
    docstring, "Laminates"), B A^-1 B from ``membrane`` and ``coupling``: per unit of
    the bending's factor when that equals the membrane's, as a PCOMP's (E1 = E2).
    ``profile`` (n, k): the thickness at each node over the one the factors take
    (:func:`nodal_profile`), interpolated by the shape functions to each integration
    point, where each part takes it to its power (membrane, drilling, shear 1, bending
    3, as :func:`eigenupdate.model.shells.local_parts`); None: uniform."""
    real, present = transition.fill(xyz)
    n, k = real.shape[:2]
    if coupling is not None and profile is not None:
        raise ValueError("coupling with a profile is not formed")
    C = None if present is None else transition.tie(present)
    xyz, V = offset_geometry(real, offset, labels)
    T = _offset_links(real, xyz)
    cm, cb, cs = (np.broadcast_to(np.asarray(c, float), (n,) + np.shape(c)[-2:])
                  for c in (membrane, bending, shear))
    gd = (1e-6 * k6rot * cm[:, 2, 2]).reshape(n, 1, 1)
    moduli = {"membrane": cm, "bending": cb, "shear": cs, "drilling": gd}
    rows: dict = {name: ([], []) for name in STIFFNESS_PARTS}  # B, w D B of every point
    points, thick = [], []  # thick: the thickness (n, 1, 1) at each point over the unit
    for rule, names in RULE_PARTS[k]:
        for p, q, weight in _RULES[k][rule]:
            N, R, G, det, Vp, dV, J = _point(xyz, V, k, p, q, C)
            points.append((names, p, q, weight * det, _b_matrices(N, R, G, Vp, dV, V), J))
            thick.append(None if profile is None else
                         np.einsum("nk,nk->n", N, profile)[:, None, None])
    if k == 8:  # MITC: the tied covariant strains, turned to the element axes
        full = _RULES[8]["full"]  # the first points: their mean over the square (area 4)
        mean = sum(w * (J @ b["shear"]) for (*_, b, J), (_, _, w)
                   in zip(points[:len(full)], full, strict=True)) / 4.0
        tied = _tied_shear(xyz, V, k, mean, C)
        for names, p, q, _, b, J in points:
            if "shear" in names:
                w = transition.tying_weights(present, p, q)
                sub = "t,ntj->nj" if present is None else "nt,ntj->nj"
                w = w[0] if present is None else w
                cov = np.stack([np.einsum(sub, w[..., 0, :], tied[0]),
                                np.einsum(sub, w[..., 1, :], tied[1])], axis=1)
                b["shear"] = np.linalg.solve(J, cov)
    if k == 6 and present is not None:  # transition CTRIA6: tied shear, MITC3-like
        tr = ~present.all(axis=1)[:, None, None]
        t = transition.tangents()
        tied = []
        for i, (_, (r, s)) in enumerate(transition.TRIA_POINTS):
            N, R, G, _, Vp, dV, J = _point(xyz, V, k, r, s, C)
            tied.append(t[i] @ (J @ _b_matrices(N, R, G, Vp, dV, V)["shear"]))
        tied = np.stack(tied, axis=1)  # (n, 9, 6k)
        for names, p, q, _, b, J in points:
            if "shear" in names:
                cov = np.einsum("nat,ntj->naj", transition.tria_tying_weights(present, p, q),
                                tied)
                b["shear"] = np.where(tr, np.linalg.solve(J, cov), b["shear"])
    if coupling is not None:
        cc = np.broadcast_to(np.asarray(coupling, float), (n, 3, 3))
        split = cc @ np.linalg.solve(cm, cc)  # B A^-1 B per unit T^3, as cb
        moduli["bending"] = cb - split
        rows[shells.COUPLING] = ([], [])
    for (names, _, _, w, b, _), t in zip(points, thick, strict=True):
        for name in names:
            rows[name][0].append(b[name])
            db = (moduli[name] @ b[name]) * w[:, None, None]
            rows[name][1].append(db if t is None else db * t ** shells.THICKNESS_POWER[name])
        if coupling is not None and "membrane" in names:
            rows["bending"][0].append(b["bending"])
            rows["bending"][1].append((split @ b["bending"]) * w[:, None, None])
            rows[shells.COUPLING][0].append(b["membrane"])
            rows[shells.COUPLING][1].append((cc @ b["bending"]) * w[:, None, None])
    # one batched product per part over all its points (as shells.py)
    out = {name: np.swapaxes(np.concatenate(bs, 1), 1, 2) @ np.concatenate(dbs, 1)
           for name, (bs, dbs) in rows.items()}
    if coupling is not None:
        out[shells.COUPLING] = out[shells.COUPLING] + np.swapaxes(out[shells.COUPLING], 1, 2)
    cols = np.arange(6 * k)
    return np.broadcast_to(np.eye(3), (n, 3, 3)), {q: (cols, _linked(out[q], T))
                                                   for q in out}


def material_axes(xyz: np.ndarray, labels: list[str] | None = None
                  ) -> tuple[np.ndarray, np.ndarray]:
    """Element axes at the centre (n, 3, 3; rows x, y, z) and the angle (n,) from x to
    the line THETA is measured from (the xi line: constant eta; CTRIA6's G1-G2 line)."""
    xyz = np.asarray(xyz, float)
    k = xyz.shape[1]
    xyz = geometry(xyz, labels)[0]
    centre = (0.0, 0.0) if k == 8 else (1 / 3, 1 / 3)
    a = np.einsum("ak,nkb->nab", shape(k, *centre)[1], xyz)
    R = _frame(a, k)
    t = np.einsum("nij,nj->ni", R, a[:, 0])
    return R, np.arctan2(t[:, 1], t[:, 0])


def shell_mass(xyz: np.ndarray, lumped: bool, labels: list[str] | None = None,
               offset: np.ndarray | None = None, profile: np.ndarray | None = None
               ) -> np.ndarray:
    """Translational mass (n, 6k, 6k) per unit mass per area: consistent or HRZ-lumped;
    with ``offset`` (ZOFFS, n,), on the reference surface of :func:`offset_geometry`
    rigidly linked to the grids (so moved with it, as the stiffness). ``profile`` (n, k):
    the mass per area at the nodes over the unit (:func:`local_parts`), interpolated to
    the integration points (HRZ then scales the diagonal to the element's tapered mass).

    Examples
    --------
    Both keep a 2 x 1 rectangle's area; HRZ gives CQUAD8 corners 3/76 of it each:

    >>> x = np.array([[[0., 0, 0], [2, 0, 0], [2, 1, 0], [0, 1, 0], [1, 0, 0], [2, .5, 0],
    ...                [1, 1, 0], [0, .5, 0]]])
    >>> [round(float(shell_mass(x, c)[0, 0::6, 0::6].sum()), 12) for c in (False, True)]
    [2.0, 2.0]
    >>> round(float(shell_mass(x, True)[0, 0, 0] * 76 / 2), 12)
    3.0
    """
    real, present = transition.fill(xyz)
    n, k = real.shape[:2]
    C = None if present is None else transition.tie(present)
    xyz, V = offset_geometry(real, offset, labels)
    m = np.zeros((n, k, k))
    for p, q, weight in _RULES[k]["full"]:
        N, _, _, det, _, _, _ = _point(xyz, V, k, p, q, C)
        w = weight * det if profile is None else weight * det * np.einsum("nk,nk->n", N,
                                                                          profile)
        m += w[:, None, None] * N[:, :, None] * N[:, None, :]
    if lumped:
        d = np.einsum("nii->ni", m)
        d = d * (m.sum(axis=(1, 2)) / d.sum(axis=1))[:, None]
        m = np.einsum("ni,ij->nij", d, np.eye(k))
    out = np.zeros((n, 6 * k, 6 * k))
    for c in range(3):
        out[:, c::6, c::6] = m
    if offset is None or not np.any(offset):
        return out  # at the grids: a CTRIA6's projection changes only its stiffness
    return _linked(out, _offset_links(real, xyz))


def pshell_matrices(xyz: np.ndarray, T: np.ndarray, membrane: np.ndarray,
                    bending: np.ndarray, shear: np.ndarray, rho: np.ndarray,
                    nsm: np.ndarray = 0.0, lumped: bool = False, k6rot: float = K6ROT,
                    labels: list[str] | None = None) -> dict[str, np.ndarray]:
    """K, M, dK/dT, dM/dT (n, 6k, 6k), global axes, as
    :func:`eigenupdate.model.shells.pshell_matrices`, for CQUAD8 and CTRIA6."""
    xyz = np.asarray(xyz, float)
    n = xyz.shape[0]
    T = np.broadcast_to(np.asarray(T, float), (n,))
    size = stabilisation_size(xyz) * np.sqrt(stabilisation_ratio(bending, shear))
    R, p = local_parts(xyz, membrane, bending, shear, k6rot, labels)
    k = {"membrane": T, "drilling": T, "bending": T**3,
         "shear": shells.shear_thickness(T, size)}
    dk = {"membrane": np.ones(n), "drilling": np.ones(n), "bending": 3 * T**2,
          "shear": shells.shear_thickness_derivative(T, size)}
    m = shell_mass(xyz, lumped, labels)
    rho = np.broadcast_to(np.asarray(rho, float), (n,))[:, None, None]
    nsm = np.broadcast_to(np.asarray(nsm, float), (n,))[:, None, None]
    return {"K": shells.combine(R, p, k), "dK": shells.combine(R, p, dk),
            "M": (rho * T[:, None, None] + nsm) * m, "dM": rho * m}
