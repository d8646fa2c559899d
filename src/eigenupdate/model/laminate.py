"""Classical laminate theory: the A, B, D and transverse shear stiffness of a ply stack.

A ply k of thickness t_k spans z_k .. z_k+1 (z_0 the bottom surface, NASTRAN's PCOMP Z0)
and has plane-stress moduli Q_k in its material axes 1, 2 (:func:`orthotropic_plane`:
MAT8 E1, E2, NU12, G12; an isotropic MAT1 ply is E1 = E2, G12 = E / (2 (1 + NU))) turned
by its angle to the element's x axis (:func:`rotate_plane`). Then, on the strains
``[exx, eyy, gxy]`` and curvatures of :mod:`eigenupdate.model.shells`,

    A = sum Q_k (z_k+1 - z_k),  B = sum Q_k (z_k+1^2 - z_k^2) / 2,
    D = sum Q_k (z_k+1^3 - z_k^3) / 3

(Jones, *Mechanics of Composite Materials*, 2nd ed., 1999, section 4.2), and the
transverse shear stiffness is first-order shear deformation theory's
``H = k sum G_k t_k`` with the ply shear moduli [G1Z, G2Z] turned likewise and
k = 5/6 (exact for one homogeneous ply, where it is PSHELL's default TS/T).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

SHEAR_FACTOR = 5.0 / 6.0


def orthotropic_plane(E1, E2, nu12, G12) -> np.ndarray:
    """Plane-stress moduli (..., 3, 3) of an orthotropic ply in its material axes.

    Examples
    --------
    An isotropic ply is :func:`eigenupdate.model.shells.plane_stress`:

    >>> orthotropic_plane(2.0, 2.0, 0.0, 1.0).tolist()
    [[2.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 1.0]]
    """
    # complex-safe (complex-step derivatives of the moduli)
    E1, E2, nu12, G12 = np.broadcast_arrays(*(np.asarray(x) + 0.0 for x in (E1, E2, nu12, G12)))
    nu21 = nu12 * E2 / E1
    d = 1.0 - nu12 * nu21
    q = np.zeros(E1.shape + (3, 3), dtype=np.result_type(E1, E2, nu12, G12))
    q[..., 0, 0] = E1 / d
    q[..., 1, 1] = E2 / d
    q[..., 0, 1] = q[..., 1, 0] = nu12 * E2 / d
    q[..., 2, 2] = G12
    return q


def rotate_plane(q: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """Moduli ``q`` (..., 3, 3) of axes 1, 2 in axes x, y, axis 1 at ``angle`` (radians,
    counter-clockwise) from x: T^T q T with T the engineering-strain transformation."""
    c, s = np.cos(angle), np.sin(angle)
    T = np.zeros(np.shape(angle) + (3, 3))
    T[..., 0, 0] = T[..., 1, 1] = c * c
    T[..., 0, 1] = T[..., 1, 0] = s * s
    T[..., 0, 2] = c * s
    T[..., 1, 2] = -c * s
    T[..., 2, 0] = -2 * c * s
    T[..., 2, 1] = 2 * c * s
    T[..., 2, 2] = c * c - s * s
    return np.swapaxes(T, -1, -2) @ q @ T


def rotate_shear(g: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """Transverse shear moduli ``g`` (..., 2, 2) on [g1z, g2z] in axes x, y."""
    c, s = np.cos(angle), np.sin(angle)
    T = np.zeros(np.shape(angle) + (2, 2))
    T[..., 0, 0] = T[..., 1, 1] = c
    T[..., 0, 1] = s
    T[..., 1, 0] = -s
    return np.swapaxes(T, -1, -2) @ g @ T


def abd(q: np.ndarray, g: np.ndarray, thickness: np.ndarray, z0: float,
        angle: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A, B, D (each (n, 3, 3)) and H (n, 2, 2) of n elements sharing one stack of p
    plies: moduli ``q`` (p, 3, 3) and ``g`` (p, 2, 2) in ply axes, ``thickness`` (p,),
    bottom surface at ``z0``, ply angles to each element's x axis ``angle`` (n, p), radians.

    Examples
    --------
    One isotropic ply about the mid-plane: A = Q t, B = 0, D = Q t^3 / 12.

    >>> q = orthotropic_plane(1.0, 1.0, 0.3, 1 / 2.6)[None]
    >>> A, B, D, H = abd(q, np.eye(2)[None], np.array([0.2]), -0.1, np.zeros((1, 1)))
    >>> bool(np.allclose(A[0], 0.2 * q[0]) and np.allclose(D[0], 0.2**3 / 12 * q[0]))
    True
    >>> bool(np.allclose(B, 0.0, atol=1e-15))
    True
    """
    t = np.asarray(thickness, float)
    z = z0 + np.concatenate([[0.0], np.cumsum(t)])
    qbar = rotate_plane(np.asarray(q, float)[None], angle)  # (n, p, 3, 3)
    gbar = rotate_shear(np.asarray(g, float)[None], angle)
    w = [np.diff(z ** k) / k for k in (1, 2, 3)]
    A, B, D = (np.einsum("p,npij->nij", wk, qbar) for wk in w)
    H = SHEAR_FACTOR * np.einsum("p,npij->nij", t, gbar)
    return A, B, D, H


@dataclass(frozen=True, eq=False)
class PlyStackEntry:
    """One entry of a laminate's A, D or H (in its own axes) as a function of some ply
    thicknesses, for a :class:`~eigenupdate.model.parametric.FunctionTerm`.

    The stack (bottom to top) has moduli ``q`` (p, r, r) already turned by the plies'
    angles and thicknesses ``thickness`` (p,); ply k takes ``x[slots[k]]`` when
    ``slots[k] >= 0`` (a LAM=SYM ply and its mirror share a slot). The mid-plane stays
    at the stack's centre (Z0 = -T/2 moves with T). ``kind`` is "A" (sum q t), "D"
    (sum q (z_k+1^3 - z_k^3) / 3) or "H" (k sum g t, times T^2 / (T^2 + c) when c > 0: the
    CTRIA3, CTRIA6 shear stabilisation of :func:`eigenupdate.model.shells.
    shear_thickness` divided by T), or "H1": "H" (c = 0) times (T - T0), T0 the stack's
    own total thickness (the first-order part of a stabilisation linearised about T0).
    Complex-safe (complex-step derivatives).

    Examples
    --------
    Two plies of unit moduli: A = t1 + t2, D = (t1 + t2)^3 / 12.

    >>> q = np.ones((2, 1, 1))
    >>> a = PlyStackEntry(q, np.array([1.0, 1.0]), (0, -1), "A", (0, 0))
    >>> d = PlyStackEntry(q, np.array([1.0, 1.0]), (0, -1), "D", (0, 0))
    >>> float(a(np.array([2.0]))), float(d(np.array([2.0])))
    (3.0, 2.25)
    """

    q: np.ndarray
    thickness: np.ndarray
    slots: tuple[int, ...]
    kind: str
    entry: tuple[int, int]
    c: float = 0.0
    moduli: object = None

    def thicknesses(self, x: np.ndarray) -> np.ndarray:
        t = np.asarray(self.thickness, dtype=np.result_type(x, float)).copy()
        for k, s in enumerate(self.slots):
            if s >= 0:
                t[k] = x[s]
        return t

    def __call__(self, x: np.ndarray):
        t = self.thicknesses(np.asarray(x))
        T = t.sum()
        i, j = self.entry
        q = self.q if self.moduli is None else self.moduli(x)[self.kind[0] == "H"]
        if self.kind == "D":
            z = -T / 2 + np.concatenate([np.zeros(1, t.dtype), np.cumsum(t)])
            return np.sum(np.diff(z**3) / 3 * q[:, i, j])
        v = np.sum(t * q[:, i, j])
        if self.kind == "H":
            v = SHEAR_FACTOR * v * (T**2 / (T**2 + self.c) if self.c else 1.0)
        elif self.kind == "H1":
            v = SHEAR_FACTOR * v * (T - np.sum(self.thickness))
        return v
