"""CTRIA6's transverse shear stabilisation (the Lyly-Stenberg factor of
:func:`eigenupdate.model.shells.shear_thickness`): the element size h_e and the section's
ratio that scales it, for :mod:`eigenupdate.model.shells_quadratic` (re-exported there).
A CQUAD8's MITC8 shear needs none (size 0)."""

from __future__ import annotations

import numpy as np

from eigenupdate.model import laminate
from eigenupdate.model import shells_transition as transition


def stabilisation_size(xyz: np.ndarray) -> np.ndarray:
    """h_e (n,) of :func:`eigenupdate.model.shells.shear_thickness`: half a CTRIA6's
    longest corner-to-corner edge, 0 for a CQUAD8 (MITC8 shear needs none)."""
    xyz, present = transition.fill(xyz)
    if xyz.shape[1] == 8:
        return np.zeros(xyz.shape[0])
    return transition.edge_spacing(xyz, present)


def stabilisation_ratio(bending: np.ndarray, shear: np.ndarray,
                        membrane: np.ndarray | None = None,
                        coupling: np.ndarray | None = None) -> np.ndarray:
    """rho (n,) scaling CTRIA6's alpha h_e^2 (:func:`stabilisation_size` times sqrt(rho)):
    the transverse shear stiffness over the bending's, H T^2 / (6 k (U1 - U4)), against
    an isotropic plate's (1 for any NU: U1 - U4 = (1 - NU) D there, k = 5/6). The
    stabilisation's added shear compliance alpha h^2 / (H T^2) then is alpha h^2 /
    (6 k (U1 - U4)): a fraction of the bending's, as Lyly & Stenberg's T^2 is for an
    isotropic plate, whatever H. U1 - U4 = (D11 + D22) / 4 - D12 / 2 + D66 and the trace
    of H are invariant under turning the axes. ``bending`` (n, 3, 3) and ``shear``
    (n, 2, 2): moduli per T^3 and per T; rho = 1 where either is zero. With ``coupling``
    (B / T^2, :func:`eigenupdate.model.shells_quadratic.local_parts`) and ``membrane``
    (per T), the bending is the coupled section's D - B A^-1 B. For plies of one
    material and B = 0 rho is that material's (U1 - U4 and tr H are sums over the plies
    of a ply's invariants), whatever the stack.

    A shear-soft laminate ([0/90/90/0], E1/G13 = 50: rho 0.10) was stabilised ten times
    too much: -6.7, -1.9 % at 4, 8 per side against Navier (a/h = 100), -0.51 % at 16.

    >>> from eigenupdate.model.shells import pshell_moduli
    >>> [round(float(stabilisation_ratio(*pshell_moduli(1.0, nu)[1:])[0]), 12)
    ...  for nu in (0.0, 0.3, 0.45)]
    [1.0, 1.0, 1.0]
    """
    cb, cs = np.asarray(bending, float), np.asarray(shear, float)
    if coupling is not None and np.any(coupling):
        cc, cm = np.asarray(coupling, float), np.asarray(membrane, float)
        ok = np.linalg.det(cm) > 0  # no membrane: no coupled bending
        safe = np.where(ok[..., None, None], cm, np.eye(3))
        cb = cb - np.where(ok[..., None, None], cc @ np.linalg.solve(safe, cc), 0.0)
    u = (cb[..., 0, 0] + cb[..., 1, 1]) / 4 - cb[..., 0, 1] / 2 + cb[..., 2, 2]
    h = (cs[..., 0, 0] + cs[..., 1, 1]) / 2
    with np.errstate(invalid="ignore", divide="ignore"):
        r = h / (6 * laminate.SHEAR_FACTOR * u)
    return np.where(np.isfinite(r) & (r > 0), r, 1.0)
