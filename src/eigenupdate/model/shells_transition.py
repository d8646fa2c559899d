"""Variable-node CQUAD8 (4 to 8 nodes) and CTRIA6 (3 to 6): blank mid-side grids.

NASTRAN lets G5-G8 of a CQUAD8 (G4-G6 of a CTRIA6) be blank: that edge is straight and
the displacement along it linear. These are the transition elements of Bathe (Finite
Element Procedures, 1996, Fig. 5.4 and its table of interpolation functions): a missing
mid-side node's function is dropped and half of it added to each of its edge's corner
functions (N1 = g1 - g5/2 - g8/2 with only the present mid-sides' g subtracted). That
is the full element's interpolation with the missing node's value set to the mean of
its corners', u_m = (u_a + u_b) / 2: :func:`tie` gives that matrix C (N_t = N C).

A blank node is passed to :mod:`eigenupdate.model.shells_quadratic` as NaN coordinates;
:func:`fill` puts it at its edge's middle (so the full element's geometry on the filled
nodes is the transition element's: a straight edge) and says which nodes are present.

Transverse shear (CQUAD8). Tying the missing nodes to their corners under MITC8's
assumed shear locks: its five tying conditions per component are too many for the
fewer nodes. :func:`tying_weights` keeps the MITC construction but lets it follow the
nodes: along each edge s = +-1, e_rt is linear in r (tied at r = +-1/sqrt(3)) where the
edge has its mid-side node, constant (tied at r = 0, MITC4) where it has none; between
the two edges linear in s, plus c (1 - s^2) fixed by e_rt's mean over the element only
when a node at s = 0 (G6 or G8) is present (e_st likewise with r and s swapped). With
all nodes this is exactly MITC8's space 1, r, s, rs, s^2 and its conditions; with none,
MITC4 (Dvorkin & Bathe, Eng. Comput. 1, 1984).
"""

from __future__ import annotations

import numpy as np

TYING_A = 1 / np.sqrt(3.0)
EDGES = {8: np.array([[0, 1], [1, 2], [2, 3], [3, 0]]),  # G5..G8
         6: np.array([[0, 1], [1, 2], [2, 0]])}  # G4..G6
POINTS = [(-TYING_A, -1.0), (TYING_A, -1.0), (0.0, -1.0),
          (-TYING_A, 1.0), (TYING_A, 1.0), (0.0, 1.0)]
"""e_rt's tying points (then its mean over the element: seven values); e_st's are these
with r and s swapped."""
# per component: the mid-side node of the edge s = -1, of s = +1, the two at s = 0
_ROLES = ((4, 6, (5, 7)), (7, 5, (4, 6)))


def fill(xyz: np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
    """Nodes (n, k, 3) with every blank (NaN) mid-side node at its edge's middle, and
    the present nodes (n, k) bool, or None when all are (the full elements' fast path).

    >>> x = np.array([[[0., 0, 0], [2, 0, 0], [0, 2, 0], [np.nan] * 3, [1, 1, 0],
    ...                [0, 1, 0]]])
    >>> f, present = fill(x)
    >>> f[0, 3].tolist(), present.tolist()
    ([1.0, 0.0, 0.0], [[True, True, True, False, True, True]])
    """
    xyz = np.asarray(xyz, float)
    blank = np.isnan(xyz).any(axis=2)
    if not blank.any():
        return xyz, None
    k = xyz.shape[1]
    e = EDGES[k]
    nc = k - len(e)
    if blank[:, :nc].any():
        raise ValueError("a corner node is blank: only mid-side nodes may be")
    mid = 0.5 * (xyz[:, e[:, 0]] + xyz[:, e[:, 1]])
    out = xyz.copy()
    out[:, nc:] = np.where(blank[:, nc:, None], mid, xyz[:, nc:])
    return out, ~blank


def refill(xyz: np.ndarray, present: np.ndarray | None) -> np.ndarray:
    """``xyz`` with its absent mid-side nodes moved back to their edges' middles (after
    the present nodes moved, e.g. along their directors for an offset)."""
    if present is None:
        return xyz
    return fill(np.where(present[:, :, None], xyz, np.nan))[0]


def tie(present: np.ndarray) -> np.ndarray:
    """C (n, k, k), u_node = C u: a present node its own value, a missing mid-side node
    the mean of its edge's corners (and no value of its own: its column is zero)."""
    n, k = present.shape
    e = EDGES[k]
    nc = k - len(e)
    C = np.broadcast_to(np.eye(k), (n, k, k)).copy()
    for j, (a, b) in enumerate(e):
        gone = ~present[:, nc + j]
        C[gone, nc + j, nc + j] = 0.0
        C[gone, nc + j, a] = C[gone, nc + j, b] = 0.5
    return C


def tying_weights(present: np.ndarray | None, p: float, q: float) -> np.ndarray:
    """Weights (n or 1, 2, 7) giving CQUAD8's assumed covariant shear (e_rt, e_st) at
    (r, s) = (p, q) from its values at :data:`POINTS` (e_st's with r, s swapped) and its
    means. ``present`` (n, 8) or None (all nodes).

    >>> w = tying_weights(None, 0.3, -0.5)
    >>> bool(np.allclose(w.sum(axis=2), 1.0))
    True
    """
    full = np.ones((1, 8), bool) if present is None else present
    out = np.zeros((full.shape[0], 2, 7))
    for row, (lo, hi, centre) in enumerate(_ROLES):
        r, s = (p, q) if row == 0 else (q, p)  # e_st: r and s swapped
        w = out[:, row]
        for side, node, cols in ((0, lo, (0, 1, 2)), (1, hi, (3, 4, 5))):
            along = 0.5 * (1 - s) if side == 0 else 0.5 * (1 + s)
            quad = full[:, node]
            lin = np.array([0.5 - r / (2 * TYING_A), 0.5 + r / (2 * TYING_A), 0.0])
            const = np.array([0.0, 0.0, 1.0])
            at0 = np.array([0.5, 0.5, 0.0])  # the edge's value at r = 0 (mean along it)
            bub = full[:, centre[0]] & full[:, centre[1]]
            f = np.where(quad[:, None], lin, const)
            f0 = np.where(quad[:, None], at0, const)
            # c (1 - s^2), c = 3/2 (mean - (f_lo(0) + f_hi(0)) / 2)
            w[:, list(cols)] += along * f - np.where(bub[:, None],
                                                     0.75 * (1 - s * s) * f0, 0.0)
        w[:, 6] += np.where(full[:, centre[0]] & full[:, centre[1]], 1.5 * (1 - s * s), 0.0)
    return out


def edge_spacing(xyz: np.ndarray, present: np.ndarray | None) -> np.ndarray:
    """Largest node spacing (n,) along a CTRIA6's edges: half an edge with its mid-side
    node, the whole edge without (the h of its shear stabilisation)."""
    c = xyz[:, :3]
    edge = np.linalg.norm(c[:, EDGES[6][:, 1]] - c[:, EDGES[6][:, 0]], axis=2)
    if present is None:
        return np.max(edge, axis=1) / 2
    return np.max(np.where(present[:, 3:], edge / 2, edge), axis=1)


# CTRIA6: natural corners, the edges G4 (1-2), G5 (2-3), G6 (3-1), their tying points
_CORNERS = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
_GRAD = np.array([[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]])  # grad of L1, L2, L3 in r, s
_ALONG = (0.5 - TYING_A / 2, 0.5 + TYING_A / 2, 0.5)
TRIA_POINTS = [(e, _CORNERS[a] + x * (_CORNERS[b] - _CORNERS[a]))
               for e, (a, b) in enumerate(EDGES[6]) for x in _ALONG]
"""A transition CTRIA6's tying points (edge, (r, s)): per edge its two Gauss points,
then its middle (nine)."""


def _tria_basis(edges: tuple[int, ...], r: float, s: float) -> np.ndarray:
    """(2, 3 + len(edges)) covariant fields at (r, s): the three Whitney edge fields
    L_a grad L_b - L_b grad L_a (RT0: MITC3's space), then grad(L_a L_b) of ``edges``
    (tangential component linear along its edge, zero along the others)."""
    L = np.array([1 - r - s, r, s])
    cols = [L[a] * _GRAD[b] - L[b] * _GRAD[a] for a, b in EDGES[6]]
    cols += [L[a] * _GRAD[b] + L[b] * _GRAD[a] for a, b in EDGES[6][list(edges)]]
    return np.array(cols).T


def tangents() -> np.ndarray:
    """(9, 2) each tying point's edge vector in r, s (the tied value is its dot
    product with the covariant shear)."""
    t = _CORNERS[EDGES[6][:, 1]] - _CORNERS[EDGES[6][:, 0]]
    return np.array([t[e] for e, _ in TRIA_POINTS])


def tria_tying_weights(present: np.ndarray, p: float, q: float) -> np.ndarray:
    """Weights (n, 2, 9) giving a transition CTRIA6's assumed covariant shear at (r, s) =
    (p, q) from its tangential shear at :data:`TRIA_POINTS`: the space of
    :func:`_tria_basis` with the quadratic term of each edge that has its mid-side node,
    tied along that edge at its two Gauss points, along an edge without at its middle
    (all three blank: MITC3, Lee & Bathe 2004)."""
    t = tangents()
    out = np.zeros((present.shape[0], 2, 9))
    mids = present[:, 3:]
    for pattern in {tuple(m) for m in mids.tolist()}:
        edges = tuple(e for e in range(3) if pattern[e])
        rows = [3 * e + i for e in range(3) for i in ((0, 1) if pattern[e] else (2,))]
        A = np.array([t[i] @ _tria_basis(edges, *TRIA_POINTS[i][1]) for i in rows])
        w = _tria_basis(edges, p, q) @ np.linalg.inv(A)
        sel = np.all(mids == pattern, axis=1)
        out[np.ix_(sel, [0, 1], rows)] = w
    return out
