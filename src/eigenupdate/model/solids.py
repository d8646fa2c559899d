"""Solid elements CTETRA (4, 10 nodes), CPYRAM (5, 13), CPENTA (6, 15) and CHEXA (8, 20),
vectorised over elements.

Isoparametric displacement elements with NASTRAN's node order (corners first, then the
mid-edge nodes of CTETRA10 on edges 1-2, 2-3, 3-1, 1-4, 2-4, 3-4); three translations per
node in the basic system, ``[u, v, w]`` node after node. Strains in Voigt order
``[exx, eyy, ezz, gxy, gyz, gzx]`` (engineering shears).

CHEXA8 adds Wilson's incompatible bubble modes ``1 - xi^2``, ``1 - eta^2``, ``1 - zeta^2``
(Wilson, Taylor, Doherty & Ghaboussi 1973, with Taylor, Beresford & Wilson's 1976
centre-Jacobian gradients so that the patch test is passed on distorted elements),
condensed out element by element: in bending it does not lock in shear as the plain
trilinear brick does, as NASTRAN's CHEXA avoids it by default. CPENTA6 and CTETRA4 are
the plain linear elements (stiff in bending; no bubble functions here); CTETRA10 is
quadratic, its stiffness integrated with the 5-point rule as NASTRAN's (exact on
straight edges; :func:`_tet5_rule`). CPYRAM5 (base G1-G4, apex G5) is Bedrosian's
rational pyramid, linear on its faces (conforming with CHEXA8 and CTETRA4 neighbours),
integrated on the collapsed cube, where its shape functions are polynomials; CPYRAM13
(G6-G9 on the base's edges, G10-G13 on the edges to the apex) is Bedrosian's quadratic
one, conforming with CHEXA20 on its base and CTETRA10 on its sides.

Stiffness is per unit modulus matrix (PSOLID + MAT1: :func:`isotropic_elasticity`), so
dK/dE is K / E; mass is per unit density, consistent (shape functions' products) or
lumped (the consistent matrix's diagonal scaled to the element's mass, Hinton, Rock &
Zienkiewicz 1976: the row sums of a linear element, positive corner masses for CTETRA10).
A zero or changing-sign Jacobian (a flat, inside-out or folded element) is an
:class:`InputError` naming the element; a consistently negative one (nodes numbered the
other way round) gives the same matrices as the positive one.
"""

from __future__ import annotations

import numpy as np

from eigenupdate.errors import InputError

NODES = {"CTETRA4": 4, "CPYRAM5": 5, "CTETRA10": 10, "CPENTA6": 6, "CHEXA8": 8,
         "CHEXA20": 20, "CPENTA15": 15, "CPYRAM13": 13}

_TET_EDGES = np.array([[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]])
_HEX = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                 [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=float)
# NASTRAN's mid-edge order: CHEXA20 G9-G20 and CPENTA15 G7-G15
HEX_EDGES = np.array([[0, 1], [1, 2], [2, 3], [3, 0], [0, 4], [1, 5], [2, 6], [3, 7],
                      [4, 5], [5, 6], [6, 7], [7, 4]])
PENTA_EDGES = np.array([[0, 1], [1, 2], [2, 0], [0, 3], [1, 4], [2, 5], [3, 4], [4, 5],
                        [5, 3]])
_HEX20 = np.vstack([_HEX, (_HEX[HEX_EDGES[:, 0]] + _HEX[HEX_EDGES[:, 1]]) / 2])
# NASTRAN's CPYRAM13 mid-edge order: G6-G9 on the base's edges, G10-G13 up to the apex
PYRAM_EDGES = np.array([[0, 1], [1, 2], [2, 3], [3, 0], [0, 4], [1, 4], [2, 4], [3, 4]])


def _with_mids(corners: np.ndarray, edges: np.ndarray, mids: bool) -> np.ndarray:
    return np.vstack([corners, (corners[edges[:, 0]] + corners[edges[:, 1]]) / 2]
                     if mids else [corners])


_TET_NAT = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
_PENTA_NAT = np.array([[0, 0, -1], [1, 0, -1], [0, 1, -1], [0, 0, 1], [1, 0, 1], [0, 1, 1]],
                      dtype=float)
_PYR_NAT = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], dtype=float)
# natural coordinates of the nodes, where det J is checked besides the integration
# points: a collapsed corner or face (two corners at one point, a corner on the line
# of its neighbours) has det J = 0 there and not at the points. The pyramid's apex is
# left out (det J vanishes there by the collapse); its side edges are checked halfway up.
_NODES = {"CHEXA8": _HEX, "CHEXA20": _with_mids(_HEX, HEX_EDGES, True),
          "CTETRA10": _with_mids(_TET_NAT, _TET_EDGES, True),
          "CPENTA6": _PENTA_NAT, "CPENTA15": _with_mids(_PENTA_NAT, PENTA_EDGES, True),
          "CPYRAM5": _PYR_NAT,
          "CPYRAM13": np.vstack([_with_mids(_PYR_NAT, PYRAM_EDGES[:4], True),
                                 _PYR_NAT * [1, 1, 0] + [0, 0, 0.5]])}


def _pyramid13_span(a, b, c) -> np.ndarray:
    """Bedrosian's 13-node pyramid space, P2 in (x, y, z) = ((1 - c) a, (1 - c) b, c)
    plus x^2 y / (1 - z), x y^2 / (1 - z), x y z / (1 - z): serendipity Q8 on the base,
    P2 on the triangular faces; polynomial in (a, b, c)."""
    x, y, z, r = (1 - c) * a, (1 - c) * b, c, 1 - c
    return np.array([1 + 0 * a, x, y, z, x * x, y * y, z * z, x * y, y * z, z * x,
                     r * r * a * a * b, r * r * a * b * b, r * a * b * c])


def _pyramid13_coefficients() -> np.ndarray:
    corners = np.vstack([np.column_stack([_HEX[:4, :2], np.zeros(4)]), [[0.5, 0.5, 1.0]]])
    corners[4] = [0.0, 0.0, 1.0]
    nodes = np.vstack([corners, (corners[PYRAM_EDGES[:, 0]] + corners[PYRAM_EDGES[:, 1]]) / 2])
    # natural (a, b, c) of each node (the apex: any a, b)
    abc = [(x / (1 - z), y / (1 - z), z) if z < 1 else (0.0, 0.0, 1.0) for x, y, z in nodes]
    return np.linalg.inv(np.array([_pyramid13_span(*p) for p in abc]))


_PYR13 = _pyramid13_coefficients()


def isotropic_elasticity(E: np.ndarray, nu: np.ndarray) -> np.ndarray:
    """Isotropic moduli (n, 6, 6) in Voigt order with engineering shear strains.

    Examples
    --------
    >>> c = isotropic_elasticity(np.array([2.5]), np.array([0.25]))[0]
    >>> bool(np.allclose([c[0, 0], c[0, 1], c[3, 3]], [3.0, 1.0, 1.0]))
    True
    """
    E, nu = np.broadcast_arrays(np.atleast_1d(np.asarray(E, float)),
                                np.atleast_1d(np.asarray(nu, float)))
    lam = E * nu / ((1 + nu) * (1 - 2 * nu))
    mu = E / (2 * (1 + nu))
    c = np.zeros((E.size, 6, 6))
    c[:, :3, :3] = lam[:, None, None]
    for i in range(3):
        c[:, i, i] += 2 * mu
        c[:, i + 3, i + 3] = mu
    return c


def rotated_elasticity(c: np.ndarray, axes: np.ndarray) -> np.ndarray:
    """Moduli (6, 6) given in material axes (``axes`` rows: the material x, y, z in basic)
    turned to basic, Voigt order xx, yy, zz, xy, yz, zx with engineering shear strains (as
    NASTRAN's MAT9): C_basic = T^T C T, T the strain map from basic to material axes.

    Examples
    --------
    An isotropic material is the same in any axes:

    >>> c = isotropic_elasticity(np.array([2.0]), np.array([0.3]))[0]
    >>> a = np.array([[0.0, 0.6, 0.8], [1.0, 0.0, 0.0], [0.0, 0.8, -0.6]])
    >>> bool(np.allclose(rotated_elasticity(c, a), c))
    True
    """
    a = np.asarray(axes, float)
    pairs = ((0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (2, 0))
    t = np.zeros((6, 6))
    for col in range(6):
        e = np.zeros((3, 3))
        i, j = pairs[col]
        e[i, j] = e[j, i] = 1.0 if i == j else 0.5
        e = a @ e @ a.T
        t[:, col] = [e[i, j] * (1 if i == j else 2) for i, j in pairs]
    return t.T @ np.asarray(c, float) @ t


def _gauss(n: int) -> tuple[np.ndarray, np.ndarray]:
    return np.polynomial.legendre.leggauss(n)


def _tet_rule(n: int) -> list[tuple[np.ndarray, float]]:
    """Collapsed Gauss-Legendre (Stroud's conical product) rule on the unit tetrahedron,
    exact for polynomials of degree 2 n - 3."""
    x, w = _gauss(n)
    x, w = (x + 1) / 2, w / 2
    out = []
    for a, wa in zip(x, w, strict=True):
        for b, wb in zip(x, w, strict=True):
            for c, wc in zip(x, w, strict=True):
                p = np.array([a, b * (1 - a), c * (1 - a) * (1 - b)])
                out.append((p, wa * wb * wc * (1 - a) ** 2 * (1 - b)))
    return out


def _tet5_rule() -> list[tuple[np.ndarray, float]]:
    """Stroud's 5-point rule on the unit tetrahedron (weight -4/5 of the volume at the
    centre, 9/20 at (1/6, 1/6, 1/6) and its permutations with one 1/2), exact for cubics:
    NASTRAN's CTETRA10 stiffness (MSC's static displacements of pyn_tet10 within 1e-5,
    tests/io/test_shell_decks.py); on straight-edged elements it is the exact integral."""
    a, b = 1 / 6, 0.5
    pts = [np.full(3, 0.25)] + [np.array(p) for p in ([a, a, a], [b, a, a], [a, b, a],
                                                      [a, a, b])]
    return list(zip(pts, [-2 / 15] + [3 / 40] * 4, strict=True))


def _hex_rule(n: int) -> list[tuple[np.ndarray, float]]:
    x, w = _gauss(n)
    return [(np.array([a, b, c]), wa * wb * wc) for a, wa in zip(x, w, strict=True)
            for b, wb in zip(x, w, strict=True) for c, wc in zip(x, w, strict=True)]


def _wedge_rule(n: int) -> list[tuple[np.ndarray, float]]:
    tri = [((1 / 6, 1 / 6), 1 / 6), ((2 / 3, 1 / 6), 1 / 6), ((1 / 6, 2 / 3), 1 / 6)]
    x, w = _gauss(n)
    return [(np.array([r, s, z]), wt * wz) for (r, s), wt in tri
            for z, wz in zip(x, w, strict=True)]


def _quadratic(kind: str, p) -> np.ndarray:
    """Shape functions of CHEXA20 (serendipity) and CPENTA15 at p (complex allowed)."""
    r, s, t = p
    if kind == "CHEXA20":
        out = []
        for a, b, c in _HEX20:
            f = [1 + x * y if y else 1 - x * x for x, y in ((r, a), (s, b), (t, c))]
            if a and b and c:
                out.append(f[0] * f[1] * f[2] * (r * a + s * b + t * c - 2) / 8)
            else:
                out.append(f[0] * f[1] * f[2] / 4)
        return np.array(out)
    L = [1 - r - s, r, s]
    corners = [L[i] * ((2 * L[i] - 1) * (1 + z * t) - (1 - t * t)) / 2
               for z in (-1, 1) for i in range(3)]
    edges = [2 * L[a] * L[b] * (1 - t) for a, b in ((0, 1), (1, 2), (2, 0))]
    edges += [L[i] * (1 - t * t) for i in range(3)]
    edges += [2 * L[a] * L[b] * (1 + t) for a, b in ((0, 1), (1, 2), (2, 0))]
    return np.array(corners + edges)


def _wedge15_rule() -> list[tuple[np.ndarray, float]]:
    """Collapsed 3 x 3 Gauss on the triangle (exact to degree 4) times 3-point Gauss
    through the thickness: exact for CPENTA15's stiffness and mass on a right prism."""
    x, w = _gauss(3)
    a, wa = (x + 1) / 2, w / 2
    out = []
    for ai, wi in zip(a, wa, strict=True):
        for bi, wj in zip(a, wa, strict=True):
            for z, wz in zip(x, w, strict=True):
                out.append((np.array([ai, bi * (1 - ai), z]), wi * wj * (1 - ai) * wz))
    return out


def _pyramid_rule(n: int) -> list[tuple[np.ndarray, float]]:
    """Gauss-Legendre n x n x n on CPYRAM5's collapsed cube (a, b) in [-1, 1]^2, c in
    [0, 1]; the (1 - c)^2 of the collapse is in the Jacobian of :func:`_shape`."""
    x, w = _gauss(n)
    c, wc = (x + 1) / 2, w / 2
    return [(np.array([a, b, z]), wa * wb * wz) for a, wa in zip(x, w, strict=True)
            for b, wb in zip(x, w, strict=True) for z, wz in zip(c, wc, strict=True)]


def _shape(kind: str, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Shape functions N (k,) and natural gradients (3, k) at natural point p."""
    if kind == "CPYRAM13":
        h = 1e-30
        dN = np.array([_pyramid13_span(*(np.asarray(p, complex) + 1j * h * e)).imag / h
                       for e in np.eye(3)]) @ _PYR13
        return _pyramid13_span(*np.asarray(p, float)) @ _PYR13, dN
    if kind == "CPYRAM5":
        # Bedrosian's rational pyramid (1992): with xi = (1 - c) a, eta = (1 - c) b,
        # zeta = c, N_i = (1 - zeta + xi_i xi)(1 - zeta + eta_i eta) / (4 (1 - zeta)) for
        # the base corners and zeta for the apex, polynomial in (a, b, c)
        a, b, c = p
        fa, fb = 1 + _HEX[:4, 0] * a, 1 + _HEX[:4, 1] * b
        N = np.append((1 - c) * fa * fb / 4, c)
        dN = np.array([np.append((1 - c) * _HEX[:4, 0] * fb / 4, 0.0),
                       np.append((1 - c) * fa * _HEX[:4, 1] / 4, 0.0),
                       np.append(-fa * fb / 4, 1.0)])
        return N, dN
    if kind in ("CHEXA20", "CPENTA15"):
        # gradients by the complex step: exact to rounding for these polynomials
        h = 1e-30
        dN = np.array([_quadratic(kind, np.asarray(p, complex) + 1j * h * e).imag / h
                       for e in np.eye(3)])
        return _quadratic(kind, np.asarray(p, float)), dN
    r, s, t = p
    if kind in ("CTETRA4", "CTETRA10"):
        L = np.array([1 - r - s - t, r, s, t])
        dL = np.array([[-1.0, 1, 0, 0], [-1.0, 0, 1, 0], [-1.0, 0, 0, 1]])
        if kind == "CTETRA4":
            return L, dL
        a, b = _TET_EDGES.T
        N = np.concatenate([L * (2 * L - 1), 4 * L[a] * L[b]])
        dN = np.concatenate([dL * (4 * L - 1), 4 * (dL[:, a] * L[b] + L[a] * dL[:, b])], axis=1)
        return N, dN
    if kind == "CPENTA6":
        L = np.array([1 - r - s, r, s])
        dL = np.array([[-1.0, 1, 0], [-1.0, 0, 1]])
        lo, hi = (1 - t) / 2, (1 + t) / 2
        N = np.concatenate([L * lo, L * hi])
        dN = np.vstack([np.hstack([dL * lo, dL * hi]), np.concatenate([-L / 2, L / 2])])
        return N, dN
    f = 1 + _HEX * p  # (8, 3)
    N = f.prod(axis=1) / 8
    dN = np.stack([_HEX[:, 0] * f[:, 1] * f[:, 2], f[:, 0] * _HEX[:, 1] * f[:, 2],
                   f[:, 0] * f[:, 1] * _HEX[:, 2]]) / 8
    return N, dN


def _rule(kind: str, mass: bool) -> list[tuple[np.ndarray, float]]:
    if kind == "CTETRA4":
        return _tet_rule(2 if not mass else 3)
    if kind == "CPYRAM5":
        return _pyramid_rule(3)  # exact for a parallelogram base's stiffness and mass
    if kind == "CPYRAM13":
        return _pyramid_rule(4)
    if kind == "CTETRA10":
        return _tet5_rule() if not mass else _tet_rule(4)
    if kind == "CPENTA6":
        return _wedge_rule(2 if not mass else 3)
    if kind == "CPENTA15":
        return _wedge15_rule()
    if kind == "CHEXA20":
        return _hex_rule(3)  # exact for a parallelepiped's stiffness and mass
    return _hex_rule(2 if not mass else 3)


def _kind(xyz: np.ndarray) -> str:
    k = xyz.shape[1]
    for name, nodes in NODES.items():
        if nodes == k:
            return name
    raise ValueError(f"{k} nodes: solids have 4, 5, 6, 8, 10, 13, 15 or 20")


def _jacobians(kind: str, xyz: np.ndarray, rule, labels) -> list[tuple]:
    """(N, det |J|, Cartesian gradients (n, 3, k)) at each point of ``rule``; checks
    that det J keeps one sign over the points and the corners."""
    corners = [(c, 0.0) for c in _NODES.get(kind, ())]
    found = []
    for p, w in list(rule) + corners:
        N, dn = _shape(kind, p)
        J = np.einsum("ak,nkb->nab", dn, xyz)
        found.append((N, dn, w, J, np.linalg.det(J)))
    dets = np.array([f[4] for f in found])
    size = np.max(np.ptp(xyz, axis=1), axis=1) ** 3
    bad = np.flatnonzero(~((np.all(dets > MIN_DET * size, axis=0))
                           | np.all(dets < -MIN_DET * size, axis=0)))
    if bad.size:
        name = labels[bad[0]] if labels else f"element {bad[0]}"
        raise InputError(f"{name}: zero or changing-sign Jacobian (a flat, inside-out or "
                         "folded element, nodes out of order, or thinner than 1e-6 of its "
                         "size)")
    return [(N, w * np.abs(det), np.linalg.solve(J, np.broadcast_to(dn, (xyz.shape[0],)
                                                                     + dn.shape)))
            for N, dn, w, J, det in found if w]


MIN_DET = 1e-7
"""Smallest |det J| over the cube of the element's size: a brick L x L x t has L^2 t / 8,
so aspect ratios L / t beyond about 1e6 are refused. Its stiffness spans (L / t)^2,
and the eigen-solver's relative error on the lowest frequencies, about 1e-16 (L / t)^2,
would pass 1e-4 unseen (at 1e9 the plate's own modes fell below the rigid-body cut)."""

MAX_MID_OFFSET = 0.5
"""Largest distance of a mid-edge node from the middle of its edge, over the edge's
length: beyond it (NASTRAN's edge-point angular deviation above 45 degrees; it warns
at 30) the node is a wrong grid, not a curve: a semicircle's sagitta is half its chord,
more than one quadratic edge can follow."""

MID_EDGES = {"CHEXA20": HEX_EDGES, "CPENTA15": PENTA_EDGES, "CTETRA10": _TET_EDGES,
             "CPYRAM13": PYRAM_EDGES}


def check_mid_edges(xyz: np.ndarray, edges: np.ndarray, labels: list[str] | None = None
                    ) -> None:
    """InputError naming the first element (nodes xyz (n, k, 3): corners, then one
    mid-edge node per row of ``edges`` (m, 2) of corner indices) with a mid-edge node
    further than :data:`MAX_MID_OFFSET` edge lengths from its edge's middle. A zero
    edge is left to the Jacobian checks."""
    xyz = np.asarray(xyz, float)
    nc = xyz.shape[1] - len(edges)
    a, b = xyz[:, edges[:, 0]], xyz[:, edges[:, 1]]
    chord = np.linalg.norm(b - a, axis=2)
    off = np.linalg.norm(xyz[:, nc:] - (a + b) / 2, axis=2)
    with np.errstate(invalid="ignore", divide="ignore"):
        rel = np.where(chord > 0, off / chord, 0.0)
    bad = np.argwhere(~(rel <= MAX_MID_OFFSET))
    if bad.size:
        i, j = bad[0]
        name = labels[i] if labels else f"element {i}"
        raise InputError(f"{name}: mid-edge node G{nc + j + 1} is {rel[i, j]:.3g} edge lengths "
                         f"from the middle of its edge G{edges[j, 0] + 1}-G{edges[j, 1] + 1} "
                         f"(at most {MAX_MID_OFFSET}: a wrong grid?)")


def _strain(g: np.ndarray) -> np.ndarray:
    """B (n, 6, 3k) from Cartesian gradients g (n, 3, k)."""
    n, _, k = g.shape
    b = np.zeros((n, 6, 3 * k))
    for i in range(3):
        b[:, i, i::3] = g[:, i]
    for row, (i, j) in zip((3, 4, 5), ((0, 1), (1, 2), (2, 0)), strict=True):
        b[:, row, i::3] = g[:, j]
        b[:, row, j::3] = g[:, i]
    return b


def solid_stiffness(xyz: np.ndarray, elasticity: np.ndarray,
                    labels: list[str] | None = None) -> np.ndarray:
    """Stiffness (n, 3k, 3k) of solids with nodes xyz (n, k, 3) (k = 4, 5, 6, 8, 10, 13, 15,
    20: CTETRA4, CPYRAM5, CPENTA6, CHEXA8, CTETRA10, CPYRAM13, CPENTA15, CHEXA20) and moduli
    (n, 6, 6) or (6, 6).

    Examples
    --------
    A unit cube's stiffness has six zero eigenvalues (rigid-body motions):

    >>> xyz = (np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1],
    ...                  [1, 0, 1], [1, 1, 1], [0, 1, 1]], float) + 0.1)[None]
    >>> lam = np.linalg.eigvalsh(solid_stiffness(xyz, isotropic_elasticity(1.0, 0.3))[0])
    >>> int(np.sum(np.abs(lam) < 1e-12 * lam.max()))
    6
    """
    xyz = np.asarray(xyz, float)
    n = xyz.shape[0]
    kind = _kind(xyz)
    C = np.broadcast_to(np.asarray(elasticity, float), (n, 6, 6))
    K = np.zeros((n, 3 * xyz.shape[1], 3 * xyz.shape[1]))
    points = _jacobians(kind, xyz, _rule(kind, False), labels)
    for _, w, g in points:
        b = _strain(g)
        K += np.transpose(b, (0, 2, 1)) @ (C @ b) * w[:, None, None]
    if kind != "CHEXA8":
        return K
    # incompatible modes: gradients of 1 - xi^2 ... with the centre's Jacobian, so that
    # they integrate to zero over any element and constant strains stay exact
    _, dn0 = _shape(kind, np.zeros(3))
    J0 = np.einsum("ak,nkb->nab", dn0, xyz)
    det0 = np.abs(np.linalg.det(J0))
    Kaa = np.zeros((n, 9, 9))
    Kua = np.zeros((n, 24, 9))
    for (p, _), (_, w, g) in zip(_rule(kind, False), points, strict=True):
        ga = np.linalg.solve(J0, np.broadcast_to(np.diag(-2 * p), (n, 3, 3)))
        # Taylor's det J0 / det J; the 2 x 2 x 2 Gauss weights are 1, so w = |det J|
        ba = _strain(ga) * (det0 / w)[:, None, None]
        Kaa += np.transpose(ba, (0, 2, 1)) @ (C @ ba) * w[:, None, None]
        Kua += np.transpose(_strain(g), (0, 2, 1)) @ (C @ ba) * w[:, None, None]
    return K - Kua @ np.linalg.solve(Kaa, np.transpose(Kua, (0, 2, 1)))


def solid_mass(xyz: np.ndarray, lumped: bool, labels: list[str] | None = None) -> np.ndarray:
    """Mass (n, 3k, 3k) per unit density of the solids of :func:`solid_stiffness`.

    Examples
    --------
    Either formulation keeps a unit tetrahedron's mass, 1/6 per direction:

    >>> xyz = np.array([[[0., 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]])
    >>> [bool(np.isclose(solid_mass(xyz, c)[0, 0::3, 0::3].sum(), 1 / 6)) for c in (0, 1)]
    [True, True]
    """
    xyz = np.asarray(xyz, float)
    n, k = xyz.shape[:2]
    kind = _kind(xyz)
    m = np.zeros((n, k, k))
    for N, w, _ in _jacobians(kind, xyz, _rule(kind, True), labels):
        m += w[:, None, None] * np.outer(N, N)
    if lumped:
        d = np.diagonal(m, axis1=1, axis2=2)
        d = d * (m.sum(axis=(1, 2)) / d.sum(axis=1))[:, None]
        m = d[:, :, None] * np.eye(k)
    out = np.zeros((n, 3 * k, 3 * k))
    for i in range(3):
        out[:, i::3, i::3] = m
    return out
