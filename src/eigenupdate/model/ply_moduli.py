"""A laminate's ply moduli as functions of their materials' fields (MAT8 E1, E2, NU12,
G12, G1Z, G2Z as parameters), for :class:`~eigenupdate.model.laminate.PlyStackEntry`.

Each ply's plane moduli are :func:`~eigenupdate.model.laminate.orthotropic_plane` of its
material's E1, E2, NU12, G12 (Q11 = E1 / (1 - NU12 NU21), NU21 = NU12 E2 / E1; Jones,
*Mechanics of Composite Materials*, 2nd ed., eq. 2.61) and its transverse shear moduli
diag(G1Z, G2Z), both turned by the ply's angle; a material whose G1Z, G2Z are blank
(MSC: rigid) has a shear of a fixed multiple of :func:`reference_shear`, which follows
its plane moduli. Everything is complex-safe (complex-step derivatives).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from eigenupdate.errors import InputError
from eigenupdate.model import laminate

NAMES = ("E1", "E2", "NU12", "G12", "G1Z", "G2Z")
"""The material fields a ply's moduli depend on, in :class:`PlyModuli`'s order."""


def reference_shear(q: np.ndarray):
    """The shear modulus a rigid transverse shear is a multiple of: an isotropic MAT1's
    E / (2 (1 + NU)); for a MAT8 max(E1, E2) / (2 (1 + NU12)) (NU12 < 0 taken as 0).
    Complex-safe (branches chosen on the real parts).

    >>> round(float(reference_shear(laminate.orthotropic_plane(2.6, 2.6, 0.3, 1.0))), 12)
    1.0
    >>> round(float(reference_shear(laminate.orthotropic_plane(1.0, 5.2, 0.3, 1.0))), 12)
    2.0
    """
    nu = q[0, 1] / q[1, 1]  # NU12 (Q12 = NU12 Q22)
    big = q[0, 0] if np.real(q[0, 0]) >= np.real(q[1, 1]) else q[1, 1]
    r = nu * nu * q[1, 1] / q[0, 0]
    r = r if np.real(r) < 1 else 1.0
    return big * (1.0 - r) / (2.0 * (1.0 + (nu if np.real(nu) > 0 else 0.0)))


@dataclass(frozen=True, eq=False)
class PlyModuli:
    """Turned moduli of a stack's plies, some of their materials' fields taken from x.

    ``values`` (m, 6) are each material's deck E1, E2, NU12, G12, G1Z, G2Z (:data:`NAMES`)
    and ``slots`` (m tuples of 6) the index in x of a field that is a parameter (-1:
    fixed). A material without parameters keeps ``q`` (m, 3, 3), ``g`` (m, 2, 2), its
    deck moduli in ply axes (a MAT1 ply, say). ``rigid`` (m,) is 0, or the multiple of
    :func:`reference_shear` that is a material's transverse shear (G1Z, G2Z blank).
    ``ply`` (p,) is each ply's material, ``theta`` (p,) its angle (radians) in the
    laminate's axes, ``labels`` the materials' names for messages.

    Examples
    --------
    One 0-degree ply of E1 = 2, E2 = 1, NU12 = 0, G12 = 0.5, E1 from x:

    >>> pm = PlyModuli(np.array([[2.0, 1.0, 0.0, 0.5, 0.4, 0.3]]), ((0, -1, -1, -1, -1, -1),),
    ...                np.zeros((1, 3, 3)), np.zeros((1, 2, 2)), (0.0,), (0,), np.zeros(1),
    ...                ("MAT8 1",))
    >>> q, g = pm(np.array([3.0]))
    >>> q[0].diagonal().tolist(), g[0].diagonal().tolist()
    ([3.0, 1.0, 0.5], [0.4, 0.3])
    """

    values: np.ndarray
    slots: tuple[tuple[int, ...], ...]
    q: np.ndarray
    g: np.ndarray
    rigid: tuple[float, ...]
    ply: tuple[int, ...]
    theta: np.ndarray
    labels: tuple[str, ...]

    def material(self, m: int, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Plane (3, 3) and transverse shear (2, 2) moduli of material m in its axes."""
        if all(s < 0 for s in self.slots[m]):
            return self.q[m], self.g[m]
        v = [x[s] if s >= 0 else self.values[m, k] for k, s in enumerate(self.slots[m])]
        e1, e2, nu, g12, g1z, g2z = v
        for name, y in zip(NAMES, v, strict=True):
            if name != "NU12" and not (self.rigid[m] and name in ("G1Z", "G2Z")) \
                    and not np.real(y) > 0:
                raise InputError(f"{self.labels[m]}: {name} = {np.real(y):g} (reached by the "
                                 f"update) must be > 0")
        if not np.real(nu * nu * e2 / e1) < 1:
            raise InputError(f"{self.labels[m]}: NU12 = {np.real(nu):g} with E1 = "
                             f"{np.real(e1):g}, E2 = {np.real(e2):g} (reached by the update) "
                             f"makes the ply's moduli indefinite (NU12^2 >= E1 / E2)")
        q = laminate.orthotropic_plane(e1, e2, nu, g12)
        if self.rigid[m]:
            g = np.eye(2) * (self.rigid[m] * reference_shear(q))
        else:
            g = np.zeros((2, 2), dtype=np.result_type(q, g1z, g2z))
            g[0, 0], g[1, 1] = g1z, g2z
        return q, g

    def __call__(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Plane (p, 3, 3) and transverse shear (p, 2, 2) moduli of the plies, turned."""
        x = np.asarray(x)
        mats = [self.material(m, x) for m in range(len(self.slots))]
        q = np.stack([mats[m][0] for m in self.ply]).astype(np.result_type(x, float))
        g = np.stack([mats[m][1] for m in self.ply]).astype(q.dtype)
        return laminate.rotate_plane(q, self.theta), laminate.rotate_shear(g, self.theta)
