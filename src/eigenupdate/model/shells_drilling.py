"""CQUADR and CTRIAR: flat shells whose in-plane rotation (drilling, ``rz``) is a true
degree of freedom of the membrane, vectorised over elements.

MSC's documentation (QRG CQUADR/CTRIAR: "isoparametric membrane-bending ... plate element
with vertex rotations"; the rotations normal to the element "are active in the element
formulation"; PARAM K6ROT is ignored for them) does not publish the membrane's
interpolation. "Vertex rotations" is Allman's term (Comput. Struct. 19, 1984: "A
compatible triangular element including vertex rotations for plane elasticity"), so the
best-documented element of that family is built here, without a claim that it is MSC's:

* membrane: Allman's vertex-rotation field (Allman, Comput. Struct. 19, 1984, triangle;
  Ibrahimbegovic, Taylor & Wilson, Int. J. Numer. Meth. Eng. 30, 1990, quadrilateral):
  the bilinear (linear) field plus, on each edge i -> j, a quadratic normal bump whose
  mid-side value is l_ij (w_j - w_i) / 8 along the outward normal (so that the edge's
  normal slope differs by the nodes' rotations), i.e. (w_j - w_i) / 8 (dy, -dx);
  strains integrated 2 x 2 (quadrilateral) and with Strang-Fix's 3 points (triangle,
  exact);
* drilling: Hughes & Brezzi's penalty gamma (w - (v,x - u,y) / 2)^2 with gamma = G
  (MID1's in-plane shear modulus), integrated at the centre (Ibrahimbegovic, Taylor &
  Wilson's choice): it ties the vertex rotations to the membrane's rotation and removes
  the Allman field's spurious mode of equal rotations;
* bending, transverse shear, coupling-free laminates, offsets and mass: those of CQUAD4
  (MITC4 with MacNeal's residual bending flexibility) and CTRIA3 (MITC3, stabilised) of
  :mod:`eigenupdate.model.shells`, as NASTRAN's manuals give QUADR/TRIAR the QUAD4/TRIA3
  properties and card layout. The rotation ``rz`` carries no mass.

Both parts are linear in the membrane moduli (no condensation), so their factors are
those of CQUAD4's membrane and drilling parts (E1 T each): a PSHELL's T, MAT1 E and RHO
stay parameters as for the other shells.
"""

from __future__ import annotations

import numpy as np

from eigenupdate.errors import InputError
from eigenupdate.model import rigid_links, shells

stabilisation_size = shells.stabilisation_size
shell_mass = shells.shell_mass
_COLUMNS = [0, 1, 5]  # u, v, rz of a node
_G = 1.0 / np.sqrt(3.0)
_QUAD_POINTS = [(a * _G, b * _G, 1.0) for b in (-1.0, 1.0) for a in (-1.0, 1.0)]
_TRIA_POINTS = [(1 / 6, 1 / 6, 1 / 6), (2 / 3, 1 / 6, 1 / 6), (1 / 6, 2 / 3, 1 / 6)]


def _quad(xi: float, eta: float):
    """Corner functions N (4,), their natural gradients (2, 4) and the edges' bump
    functions' natural gradients (2, 4) (edges 1-2, 2-3, 3-4, 4-1)."""
    N, dn = shells._quad_shape(xi, eta)
    dm = np.array([[-xi * (1 - eta), 0.5 * (1 - eta**2), -xi * (1 + eta), -0.5 * (1 - eta**2)],
                   [-0.5 * (1 - xi**2), -eta * (1 + xi), 0.5 * (1 - xi**2), -eta * (1 - xi)]])
    return N, dn, dm


def _tria(r: float, s: float):
    """As :func:`_quad` for the triangle: bumps 4 L_i L_j on edges 1-2, 2-3, 3-1."""
    N, dn = shells._tria_shape(r, s)
    dm = np.array([[4 * (dn[a, i] * N[j] + N[i] * dn[a, j]) for i, j in ((0, 1), (1, 2), (2, 0))]
                   for a in (0, 1)])
    return N, dn, dm


def _rows(N, dn, dm, xy):
    """Membrane strain rows (n, 3, 3k) and the drilling mismatch row (n, 1, 3k) on the
    columns u, v, rz of each node, and det J, at one point."""
    n, k = xy.shape[:2]
    _, det, inv, g = shells._jacobian(dn, xy)
    gm = inv @ dm  # bumps' gradients (n, 2, k)
    e = np.roll(xy, -1, axis=1) - xy  # edge i -> i+1: (dx, dy)
    diff = (np.roll(np.eye(k), 1, axis=1) - np.eye(k)) / 8.0  # (w_j - w_i) / 8
    # displacement of node m's rotation: u = sum_e bump_e dy_e D[e, m], v with -dx_e
    gu = np.einsum("nae,ne,em->nam", gm, e[:, :, 1], diff)
    gv = -np.einsum("nae,ne,em->nam", gm, e[:, :, 0], diff)
    b = np.zeros((n, 3, 3 * k))
    b[:, 0, 0::3], b[:, 0, 2::3] = g[:, 0], gu[:, 0]
    b[:, 1, 1::3], b[:, 1, 2::3] = g[:, 1], gv[:, 1]
    b[:, 2, 0::3], b[:, 2, 1::3] = g[:, 1], g[:, 0]
    b[:, 2, 2::3] = gu[:, 1] + gv[:, 0]
    d = np.zeros((n, 1, 3 * k))
    d[:, 0, 2::3] = N - 0.5 * (gv[:, 0] - gu[:, 1])
    d[:, 0, 0::3], d[:, 0, 1::3] = 0.5 * g[:, 1], -0.5 * g[:, 0]
    return b, d, det


def membrane_drilling(xy: np.ndarray, membrane: np.ndarray, profile: np.ndarray | None = None
                      ) -> tuple[np.ndarray, np.ndarray]:
    """Membrane and drilling blocks (n, 3k, 3k) on ``[u, v, rz]`` of each node, element
    axes, of elements whose nodes lie at ``xy`` (n, k, 2) (counter-clockwise), per unit
    thickness, with plane moduli ``membrane`` (n, 3, 3); gamma = its shear term.
    ``profile`` (n, k): the corners' thickness relative to the unit, interpolated to
    each integration point (:func:`eigenupdate.model.shells.local_parts`)."""
    n, k = xy.shape[:2]
    cm = np.broadcast_to(np.asarray(membrane, float), (n, 3, 3))
    shape, points, centre, area = ((_quad, _QUAD_POINTS, (0.0, 0.0), 4.0) if k == 4 else
                                   (_tria, _TRIA_POINTS, (1 / 3, 1 / 3), 0.5))

    def at(N):  # thickness (n,) at a point with corner functions N
        return 1.0 if profile is None else np.asarray(profile, float) @ N

    km = np.zeros((n, 3 * k, 3 * k))
    for p, q, weight in points:
        f = shape(p, q)
        b, _, det = _rows(*f, xy)
        km += np.einsum("nai,nab,nbj->nij", b, cm, b) * (weight * det * at(f[0]))[:, None, None]
    f = shape(*centre)
    _, d, det = _rows(*f, xy)
    kd = np.einsum("nai,naj->nij", d, d) * (area * det * cm[:, 2, 2] * at(f[0]))[:, None, None]
    return km, kd


def local_parts(xyz: np.ndarray, membrane: np.ndarray, bending: np.ndarray,
                shear: np.ndarray, k6rot: float = shells.K6ROT, labels: list[str] | None = None,
                condense_with: np.ndarray | None = None, coupling: np.ndarray | None = None,
                curvature: np.ndarray | None = None, profile: np.ndarray | None = None):
    """:func:`eigenupdate.model.shells.local_parts` for CQUADR (xyz (n, 4, 3)) and CTRIAR
    (n, 3, 3): the same bending and shear, the membrane and drilling parts of
    :func:`membrane_drilling` on u, v, rz (all with the corner thickness ``profile``).
    ``k6rot`` is not used (as NASTRAN ignores K6ROT for them); ``condense_with``
    neither (nothing is condensed, so a laminate's membrane is the sum of its moduli's
    parts exactly); ``curvature`` neither (the drilling rotation is tied to the
    membrane's anyway). An unsymmetric laminate's ``coupling`` is refused."""
    if coupling is not None and np.any(coupling):
        raise InputError(f"{labels[0] if labels else 'element'}: membrane-bending coupling "
                         f"(an unsymmetric laminate) is not supported on CQUADR/CTRIAR")
    xyz = np.asarray(xyz, float)
    k = xyz.shape[1]
    # CQUAD4's membrane is formed and replaced (any positive moduli: its condensation)
    R, parts = shells.local_parts(xyz, np.eye(3), bending, shear, 0.0, labels,
                                  profile=profile)
    _, xy = shells.shell_axes(xyz, labels)
    km, kd = membrane_drilling(xy, membrane, profile)
    cols = (6 * np.arange(k)[:, None] + np.array(_COLUMNS)).ravel()
    mine = {"membrane": (cols, km), "drilling": (cols, kd)}
    parts.update(rigid_links.warp_links(mine, xyz, R) if k == 4 else mine)
    return R, parts
