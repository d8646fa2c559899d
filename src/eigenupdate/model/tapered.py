"""Tapered 3-D beam elements (CBEAM with a PBEAM or PBEAML whose section differs
between its ends), vectorised over elements, in :mod:`eigenupdate.model.frame3d`'s local
axes and degree-of-freedom order.

The section is given at quadrature points along each element (fractions ``s`` of its
length, weights ``w``).

Stiffness: the flexibility of the cantilever held at end A, inverted and carried to both
ends by equilibrium: ``int (L - x)^2 / EI + 1 / (K G A)``, ``int (L - x) / EI``,
``int 1 / EI`` in bending, ``int 1 / EA`` axially, ``int 1 / GJ`` in torsion. With exact
integrals this is the exact element of the beam's statics (a constant section gives the
Euler-Bernoulli element, or Przemieniecki's Timoshenko element with shear, and a linear
area the rod ``E (A_a - A_b) / (L ln(A_a / A_b))``); MSC Nastran takes the integrals by
3-point Gauss (:mod:`eigenupdate.io.nastran_tapered`).

Mass: *coupled*, the cubic Hermite (bending) and linear (axial, torsion) shape functions
integrated with the mass per length; *lumped*, each end takes ``int m N_i dx`` with the
linear N_i (the mass's first moment kept, as MSC Nastran's grid point weight generator
shows for the fmondsp deck's tapered tubes), rotations massless.
"""

from __future__ import annotations

import numpy as np

from eigenupdate.errors import InputError

# the local dofs of each plane's (translation, rotation) at end A; end B is 6 further;
# plane 2's rotation ry = -w' (frame3d.stiffness_parts' sign)
_PLANES = {"bend1": (1, 5, 1.0), "bend2": (2, 4, -1.0)}


def gauss(points: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre points and weights on [0, 1].

    >>> s, w = gauss(3)
    >>> s.round(6).tolist(), w.round(6).tolist()
    ([0.112702, 0.5, 0.887298], [0.277778, 0.444444, 0.277778])
    """
    x, wx = np.polynomial.legendre.leggauss(points)
    return (x + 1) / 2, wx / 2


def _hermite(s: np.ndarray, L: np.ndarray) -> np.ndarray:
    """Cubic Hermite functions (n, q, 4) of (v_A, rz_A, v_B, rz_B) at fractions s (n, q)
    of lengths L (n,)."""
    Lq = L[:, None]
    return np.stack([1 - 3 * s**2 + 2 * s**3, Lq * (s - 2 * s**2 + s**3),
                     3 * s**2 - 2 * s**3, Lq * (s**3 - s**2)], axis=-1)


def stiffness(L: np.ndarray, s: np.ndarray, w: np.ndarray, ea: np.ndarray, gj: np.ndarray,
              ei1: np.ndarray, ei2: np.ndarray, kga1: np.ndarray | None = None,
              kga2: np.ndarray | None = None) -> dict[str, np.ndarray]:
    """Local stiffness (n, 12, 12) of each part (axial, torsion, bend1, bend2) of tapered
    elements: rigidities EA, GJ, EI1, EI2 and shear rigidities K G A of planes 1 and 2
    (None or inf: shear-rigid) at the points ``s`` (n, q) with weights ``w`` (n, q).

    Examples
    --------
    A constant section gives the constant element (here 12 EI / L^3 and the rod EA / L):

    >>> s, w = gauss(3)
    >>> one = np.ones((1, 3))
    >>> k = stiffness(np.array([2.0]), s[None], w[None], one, one, one, one)
    >>> round(float(k["bend1"][0, 1, 1]), 12), round(float(k["axial"][0, 0, 0]), 12)
    (1.5, 0.5)
    """
    L = np.asarray(L, float)
    n = L.size
    out = {name: np.zeros((n, 12, 12)) for name in ("axial", "torsion", "bend1", "bend2")}
    dx = w * L[:, None]
    for name, dof, rig in (("axial", 0, ea), ("torsion", 3, gj)):
        with np.errstate(divide="ignore"):
            flex = np.sum(dx / rig, axis=1)
        k = np.where(np.isfinite(flex) & (flex > 0), 1.0 / flex, 0.0)  # GJ = 0: none
        i = np.ix_([dof, dof + 6], [dof, dof + 6])
        out[name][:, i[0], i[1]] = k[:, None, None] * np.array([[1.0, -1.0], [-1.0, 1.0]])
    for name, kga, ei in (("bend1", kga1, ei1), ("bend2", kga2, ei2)):
        t, r, sign = _PLANES[name]
        d = [t, r, t + 6, r + 6]
        k4 = _flexibility_bending(L, s, dx, ei, kga)
        sg = np.array([1.0, sign, 1.0, sign])
        out[name][:, np.ix_(d, d)[0], np.ix_(d, d)[1]] = k4 * np.outer(sg, sg)
    return out


def _flexibility_bending(L, s, dx, ei, kga) -> np.ndarray:
    """(n, 4, 4) plane bending stiffness of (v_A, rz_A, v_B, rz_B) from end B's
    cantilever flexibility (end A held)."""
    arm = (1 - s) * L[:, None]  # lever of end B's shear force about the point x
    with np.errstate(divide="ignore"):
        c = dx / ei
        shear = 0.0 if kga is None else np.sum(dx / kga, axis=1)
    f = np.empty((L.size, 2, 2))
    f[:, 0, 0] = np.sum(c * arm**2, axis=1) + shear
    f[:, 0, 1] = f[:, 1, 0] = np.sum(c * arm, axis=1)
    f[:, 1, 1] = np.sum(c, axis=1)
    if not np.all(np.isfinite(f)):
        raise InputError("a tapered beam's section has zero bending rigidity at a point")
    kbb = np.linalg.inv(f)
    # forces at end A balance those at B: (V_A, M_A) = H (V_B, M_B)
    h = np.zeros((L.size, 2, 2))
    h[:, 0, 0] = h[:, 1, 1] = -1.0
    h[:, 1, 0] = -L
    k = np.empty((L.size, 4, 4))
    k[:, :2, :2] = h @ kbb @ np.transpose(h, (0, 2, 1))
    k[:, :2, 2:] = h @ kbb
    k[:, 2:, :2] = kbb @ np.transpose(h, (0, 2, 1))
    k[:, 2:, 2:] = kbb
    return 0.5 * (k + np.transpose(k, (0, 2, 1)))


def mass(L: np.ndarray, s: np.ndarray, w: np.ndarray, m: np.ndarray, ix: np.ndarray,
         consistent: bool) -> dict[str, np.ndarray]:
    """Local mass (n, 12, 12) of tapered elements: translation from the mass per length
    ``m`` and torsion from the torsional inertia per length ``ix`` at the points ``s``.

    Examples
    --------
    Lumped, the ends take the mass's first moments: a mass per length rising linearly
    from 0 to 3 on a unit element puts 0.5 at end A and 1.0 at end B.

    >>> s, w = gauss(2)
    >>> mm = mass(np.array([1.0]), s[None], w[None], 3 * s[None], 0 * s[None], False)
    >>> [round(float(x), 12) for x in (mm["translation"][0, 0, 0], mm["translation"][0, 7, 7])]
    [0.5, 1.0]
    """
    L = np.asarray(L, float)
    n = L.size
    dx = w * L[:, None]
    lin = np.stack([1 - s, s], axis=-1)
    tr = np.zeros((n, 12, 12))
    tor = np.zeros((n, 12, 12))
    if not consistent:
        ends = np.einsum("nq,nqi->ni", dx * m, lin)
        ends_t = np.einsum("nq,nqi->ni", dx * ix, lin)
        for a in (0, 1, 2):
            tr[:, a, a] = ends[:, 0]
            tr[:, a + 6, a + 6] = ends[:, 1]
        tor[:, 3, 3] = ends_t[:, 0]
        tor[:, 9, 9] = ends_t[:, 1]
        return {"translation": tr, "torsion": tor}
    ml = np.einsum("nq,nqi,nqj->nij", dx * m, lin, lin)
    tl = np.einsum("nq,nqi,nqj->nij", dx * ix, lin, lin)
    i = np.ix_([0, 6], [0, 6])
    tr[:, i[0], i[1]] = ml
    i = np.ix_([3, 9], [3, 9])
    tor[:, i[0], i[1]] = tl
    h = _hermite(s, L)
    mh = np.einsum("nq,nqi,nqj->nij", dx * m, h, h)
    for name in ("bend1", "bend2"):
        t, r, sign = _PLANES[name]
        d = [t, r, t + 6, r + 6]
        sg = np.array([1.0, sign, 1.0, sign])
        tr[:, np.ix_(d, d)[0], np.ix_(d, d)[1]] = mh * np.outer(sg, sg)
    return {"translation": tr, "torsion": tor}
