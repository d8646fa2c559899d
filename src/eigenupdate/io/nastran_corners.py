"""Corner thicknesses T1-T4 (TFLAG) of CQUAD4, CTRIA3, CQUADR, CTRIAR, CQUAD8 and
CTRIA6, for :mod:`eigenupdate.io.nastran_continuum`.

NASTRAN's convention (MSC QRG CQUAD4/CTRIA3/CQUAD8/CTRIA6 and PSHELL field T; NASTRAN
CoFE's QRG):
TFLAG 0 or blank: Ti is the thickness at grid Gi, a blank Ti the PSHELL's T;
TFLAG 1: Ti is a fraction of the PSHELL's T (thickness Ti T), blank 1. A Ti of 0.0 is a
thickness of zero (a bevelled edge: MSC's "Real >= 0.0 or blank, not all zero"; pyNastran's
aero model ha145z tapers its 0.041 plate to 0.0 at its leading and trailing edges;
NASTRAN-95's quad4d.f and t3setd.f instead replace a zero Ti by T: MSC's reading is taken).
The thickness is interpolated from the corners by the element's shape functions to each
integration point (NASTRAN-95's quad4d.f: THK = sum SHP_i GPTH_i at each Gauss point,
then I = 12I/T^3 THK^3 / 12 and TS/T THK there; NASTRAN CoFE's Cquad4.m the same), which
:func:`eigenupdate.model.shells.local_parts` does with the corners' ``profile``, the
thickness relative to the PSHELL's T. CQUAD8 (T1-T4 at G1-G4) and CTRIA6 (T1-T3 at
G1-G3) take the corners' bilinear and linear field: their mid-side nodes the mean of
their edge's corners (:func:`eigenupdate.model.shells_quadratic.nodal_profile`), which
their shape functions interpolate exactly; a curved CTRIA6's four flat CTRIA3 (its
facets) take that field at their grids, which they interpolate exactly too. The mass
per area is RHO t at each point and NSM uniform (per area, as CoFE and NASTRAN-95's
tria3d.f; its quad4d.f scales the whole mass matrix by (rho V + NSM A) / (rho V),
spreading NSM as the thickness: the same total).
The transverse shear's stabilisation (CTRIA3's and CTRIA6's, CQUAD4's residual bending
flexibility: element-level corrections that vanish with the mesh size) takes the
element's mean corner thickness (a CTRIA6's mean over its six nodes is its corners'),
where NASTRAN-95 evaluates its own per point.

A PSHELL's T as a parameter: under TFLAG 1 the element scales with T (membrane T,
bending T^3, mass RHO T, the profile fixed); under TFLAG 0 with every Ti given it does
not depend on T at all; with some given and some blank its thickness is an affine, not a
proportional, function of T: refused.
"""

from __future__ import annotations

import numpy as np

from eigenupdate.errors import InputError
from eigenupdate.io.nastran_fields import in_range
from eigenupdate.model import shells_quadratic as quadratic

CORNERS = ("T1", "T2", "T3", "T4")
SUPPORTED = {"CQUAD4": 4, "CTRIA3": 3, "CQUADR": 4, "CTRIAR": 3, "CQUAD8": 4, "CTRIA6": 3}
"""Element types whose corner thicknesses may differ from the property's T: their
number of corners."""


def profiles(elems, rows: list[dict], labels: list[str], pindex: dict, k: int
             ) -> tuple[np.ndarray | None, np.ndarray, np.ndarray]:
    """(profile, tapered, fixed) of shell elements with ``k`` nodes and their property
    rows: profile (n, k) each node's thickness over the property's T (None when no
    element's differs from it; rows of ones where they agree; a CQUAD8's or CTRIA6's
    mid-side nodes from their corners, a facet of a curved CTRIA6 (``facet``, its three
    nodes of the six) from the CTRIA6's), ``tapered`` (n,) where they differ, ``fixed``
    (n,) the elements whose thickness is their own (TFLAG 0, every Ti given), which a
    parameter on the PSHELL's T leaves unchanged."""
    n = len(elems)
    out = np.ones((n, k))
    fixed = np.zeros(n, bool)
    for i, (e, p, lab) in enumerate(zip(elems, rows, labels, strict=True)):
        given = [getattr(e, name, None) for name in CORNERS[:SUPPORTED.get(e.type, min(k, 4))]]
        flag = e.tflag or 0
        if all(t is None for t in given) and flag in (0, 1):
            continue  # the property's T everywhere
        where = f"{lab}: corner thicknesses T1-T{len(given)} (TFLAG {flag})"
        if flag not in (0, 1):
            raise InputError(f"{lab}: TFLAG = {flag} must be 0 (blank) or 1")
        t = [None if x is None else in_range(x, f"{where} {CORNERS[j]}")
             for j, x in enumerate(given)]
        if any(x is not None and x < 0 for x in t):
            raise InputError(f"{where}: {given} must be >= 0")
        if flag == 0 and None in t and ("T" in pindex.get(("PSHELL", e.pid), {})):
            raise InputError(f"PSHELL {e.pid} field T: not a parameter of {lab}, whose "
                             f"corner thicknesses are partly its own (T1-T4 with TFLAG 0) "
                             f"and partly the PSHELL's (blank): its thickness is not "
                             f"proportional to T (give all or none, or TFLAG 1)")
        T = p["T"]
        for j, x in enumerate(t):  # under TFLAG 1 the thickness is a product of two fields
            if flag and x:
                in_range(x * T, f"{where} {CORNERS[j]} times T = {T:g}, the thickness")
        rel = np.array([1.0 if x is None else x if flag else x / T for x in t])
        fixed[i] = flag == 0 and None not in t
        if np.allclose(rel, 1.0, rtol=1e-12, atol=0):
            continue  # the property's T at every corner, as read without them
        if e.type not in SUPPORTED:
            raise InputError(f"{where}: differing from the property's T are supported on "
                             f"{', '.join(SUPPORTED)} only")
        if p["laminate"] is not None:
            raise InputError(f"{where}: differing from {p['card']} {e.pid}'s thickness "
                             f"{T:g} (the sum of its plies) are not supported")
        if not np.any(rel > 0):
            raise InputError(f"{where}: all zero (NASTRAN: not all zero)")
        if e.type in ("CQUAD8", "CTRIA6"):  # the corners' field at the six or eight nodes
            rel = quadratic.nodal_profile(rel[None])[0]
            rel = rel if getattr(e, "facet", None) is None else rel[list(e.facet)]
        out[i] = rel
    tapered = np.array([not np.all(r == 1.0) for r in out], bool)
    return (out if tapered.any() else None), tapered, fixed

