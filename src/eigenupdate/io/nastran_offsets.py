"""Shell ZOFFS and a shell's mass off its grid plane, for
:mod:`eigenupdate.io.nastran_continuum` (the formulation: :mod:`eigenupdate.model.
shell_offsets` for CQUAD4/CTRIA3, :func:`eigenupdate.model.shells_quadratic.
offset_geometry` for CQUAD8/CTRIA6: the element on its reference surface, rigidly linked
to the grids, stiffness and mass alike; a CQUAD8's or CTRIA6's mass off that surface:
:mod:`eigenupdate.model.shells_quadratic_mass`).

The mass per area is a sum over components (each material of the property, its plies at
their centroid; NSM on the reference plane) of m_i at height H_i along the normal from
the grids, H_i = ZOFFS + the material's centroid above the reference plane (0 for a
PSHELL, and for a PCOMP whose plies of each material are symmetric about its mid-plane).
The three coefficients m0, m1, m2 (sum m_i H_i^k) are linear in each material's RHO, so
``MAT1 RHO`` stays a linear parameter; a PSHELL's T moves its mass, not its height (ZOFFS
stays where the card puts it, as in NASTRAN), so T stays one too.
"""

from __future__ import annotations

import warnings

import numpy as np

from eigenupdate.errors import EigenupdateWarning, InputError
from eigenupdate.io.nastran_fields import in_range
from eigenupdate.io.nastran_plates95 import READ_AS
from eigenupdate.model import (
    rigid_links,
    shell_normals,
    shell_offsets,
    shells,
    shells_quadratic_mass,
)
from eigenupdate.model import shells_quadratic as quadratic


def ply_heights(t: np.ndarray, z0: float, mids) -> dict:
    """Centroid height above the reference plane of each material's plies
    ({mid: h}) of a PCOMP whose plies ``t`` start at ``z0``.

    >>> ply_heights(np.array([1.0, 1.0, 2.0]), -2.0, [5, 5, 6])
    {5: -1.0, 6: 1.0}
    """
    z = z0 + np.concatenate([[0.0], np.cumsum(t)])
    mid = (z[:-1] + z[1:]) / 2
    out: dict = {}
    for m in dict.fromkeys(int(x) for x in mids):
        on = np.array([int(x) == m for x in mids])
        h = float(np.sum(t[on] * mid[on]) / np.sum(t[on]))
        out[m] = 0.0 if abs(h) <= 1e-12 * (z[-1] - z[0]) else h  # its rounding: on it
    return out


def element_offsets(elems, labels: list[str], rows: list[dict]) -> np.ndarray:
    """ZOFFS (n,) of the elements, with a PSHELL's MID2 given (NASTRAN requires MID1
    and MID2 with ZOFFS); a curved CTRIA6's facets are offset along their own normals."""
    z = np.zeros(len(elems))
    for i, (e, lab, p) in enumerate(zip(elems, labels, rows, strict=True)):
        if not e.zoffset:
            continue
        value = in_range(e.zoffset, f"{lab}: ZOFFS")
        if p["laminate"] is None and not p["mid2"]:
            raise InputError(f"{lab}: ZOFFS = {value:g} needs MID2 (bending) on PSHELL "
                             f"{e.pid} (NASTRAN requires MID1 and MID2 with ZOFFS)")
        if abs(value) > MAX_OFFSET * p["T"]:
            raise InputError(f"{lab}: ZOFFS = {value:g} is more than {MAX_OFFSET:g} times the "
                             f"thickness {p['T']:g}: the offset's z^2 A would swamp the bending "
                             f"stiffness D (12 (z/T)^2 > 1e7) and rounding its digits away")
        z[i] = value
    return z


MAX_OFFSET = 1000.0
"""Largest |ZOFFS| / T: in grid-plane strains D becomes D + z^2 A, 12 (z/T)^2 times D,
so 1000 T (1.2e7 D) leaves D to 3e-9 relative; 1e6 T would leave 3e-3, silently, and
ZOFFS = 1e10 m made K indefinite, reported as a coordinate "with stiffness and no mass"."""


def heights(rows: list[dict], zo: np.ndarray) -> list[dict]:
    """Per element, each material's height above the grids ({mid: H})."""
    return [{m: h + z for m, h in p["heights"].items()} for p, z in zip(rows, zo,
                                                                      strict=True)]


def mass_moments(rows: list[dict], zo: np.ndarray, wtmass: float) -> np.ndarray:
    """(3, n): WTMASS times m0, m1, m2 (mass per area and its first and second moments
    about the grid plane) of each element."""
    out = np.zeros((3, len(rows)))
    for i, (p, H) in enumerate(zip(rows, heights(rows, zo), strict=True)):
        parts = [(r * t, H[m]) for m, (r, t) in p["mass"].items()] + [(p["nsm"], zo[i])]
        out[:, i] = [sum(m * h**k for m, h in parts) for k in range(3)]
    return wtmass * out


def rho_moments(rows: list[dict], zo: np.ndarray, wtmass: float, mid: int) -> np.ndarray:
    """(3, n): d(m0, m1, m2) / d RHO of material ``mid`` (WTMASS t_j H_j^k)."""
    out = np.zeros((3, len(rows)))
    for i, (p, H) in enumerate(zip(rows, heights(rows, zo), strict=True)):
        if mid in p["mass"]:
            t = p["mass"][mid][1]
            out[:, i] = [t * H[mid] ** k for k in range(3)]
    return wtmass * out


def at_height(weights: np.ndarray, z: np.ndarray) -> np.ndarray:
    """(3, n) moments of a mass ``weights`` (n,) on the reference plane, z above the grids."""
    return np.stack([weights, weights * z, weights * z * z])


def stiffness_parts(elem, xyz: np.ndarray, cm, cb, cs, k6rot: float, labels: list[str],
                    zk: np.ndarray, **kw) -> tuple:
    """``elem.local_parts`` (:mod:`~eigenupdate.model.shells` or its quadratic
    module) of elements whose reference plane lies ``zk`` (n,) from their grids."""
    if elem is quadratic:  # its blocks are global: the offset enters its geometry
        return quadratic.local_parts(xyz, cm, cb, cs, k6rot, labels,
                                     offset=zk if np.any(zk) else None,
                                     coupling=kw.get("coupling"), profile=kw.get("profile"))
    R, parts = elem.local_parts(xyz, cm, cb, cs, k6rot, labels, **kw)
    if xyz.shape[1] == 4:
        _warn_warp(xyz, R, labels)
    return R, rigid_links.offset_parts(parts, zk) if np.any(zk) else parts


def _warn_warp(xyz: np.ndarray, R: np.ndarray, labels: list[str]) -> None:
    """Warn, as NASTRAN's GEOMCHECK does, of quadrilaterals warped beyond
    :data:`eigenupdate.model.shells.WARN_WARP` (accepted up to ``MAX_WARP``)."""
    warp = rigid_links.warp(xyz, R[:, 2])
    bad = np.flatnonzero(warp > shells.WARN_WARP)
    if bad.size:
        worst = bad[np.argmax(warp[bad])]
        more = f" and {bad.size - 1} more" if bad.size > 1 else ""
        warnings.warn(f"{labels[worst]}{more}: warped by up to {warp[worst]:.3g} (nodes' "
                      f"distance from the mean plane / sqrt(area); NASTRAN warns from "
                      f"{shells.WARN_WARP}): computed on the mean plane, rigidly linked to "
                      f"the grids", EigenupdateWarning, stacklevel=2)


def unit_masses(elem, xyz: np.ndarray, lumped: bool, labels: list[str], zo: np.ndarray,
                moments: np.ndarray, off_surface: bool = False,
                profile: np.ndarray | None = None) -> list:
    """The masses per unit m0, m1, m2 (:func:`mass_moments`; global axes): CQUAD4's and
    CTRIA3's translation, first and second moment (per unit thickness with the corners'
    ``profile``, :func:`eigenupdate.model.shells.shell_mass`); a quadratic element's
    translation on its reference surface (its ``profile`` too), or with ``off_surface``
    (a property's mass off it, :func:`off_surface`) its three of
    :mod:`eigenupdate.model.shells_quadratic_mass`."""
    if elem is quadratic and off_surface:
        if profile is not None:  # a laminate's (nastran_corners refuses its taper)
            raise ValueError("a mass off the reference surface with a profile is not formed")
        return shells_quadratic_mass.unit_masses(xyz, lumped, labels, zo)
    if elem is quadratic:
        return [quadratic.shell_mass(xyz, lumped, labels, zo if np.any(zo) else None,
                                     profile)]
    out = [shells.shell_mass(xyz, lumped, labels, profile)]
    if np.any(moments[1:]) or np.any(zo):  # a mass off the grid plane
        out += list(shell_offsets.offset_mass(xyz, lumped, labels, profile))
    return out


def off_surface(rows: list[dict], labels: list[str], xyz: np.ndarray) -> np.ndarray:
    """(n,) whether an element's property has mass off its reference plane (a PCOMP's
    plies of one material not centred on it: an unsymmetric stack, Z0 != -T/2); on a
    CQUAD8/CTRIA6 with blank mid-side grids (NaN in ``xyz``) refused: the mass's moments
    (:mod:`eigenupdate.model.shells_quadratic_mass`) are built for all nodes present."""
    out = np.array([any(p["heights"].values()) for p in rows], dtype=bool)
    holes = np.flatnonzero(out & np.isnan(xyz).any(axis=(1, 2)))
    if holes.size:
        raise InputError(f"{labels[holes[0]]}: blank mid-side grids with its property's mass "
                         f"off its reference plane (an unsymmetric PCOMP or Z0 != -T/2) are "
                         f"not supported")
    return out


SNORM = 0.0
"""PARAM SNORM where a deck sets none: no grid normals, the plain facets of NASTRAN-95
and MSC V70.7 (MSC's default has been 20 since V2001, model/shell_normals.py). The
published decks we compare with were run without them: the MSC 70.7 cylinder's n = 2
modes are -0.36/-0.56 % off with plain facets, +0.17/+1.02 % with normals
(tests/io/test_shell_decks.py). A deck that sets PARAM SNORM > 0 gets them."""


def curvature(bdf, grid, xyz: np.ndarray, n_nodes: int, snorm: float):
    """``nodes (n, k) -> curvature (n,)`` of CQUAD4 (k = 4) or CTRIA3 (k = 3) elements
    from the normals of their grids (model/shell_normals.py) under PARAM SNORM ``snorm``
    (degrees), None when the deck has no such shells; when it is <= 0, a warped
    CQUAD4's own twist (:func:`~eigenupdate.model.shell_normals.warped_curvature`).
    Normals from every CQUAD4, CTRIA3 and a CTRIA6's four facets (quadratic.FACETS, as a
    curved one is modelled) at a grid."""
    if not snorm > 0:
        # a warped CQUAD4's own corner normals (flat facets: none, NASTRAN-95's and
        # MSC 70.7's plain facets)
        return lambda nodes: shell_normals.warped_curvature(xyz[nodes])
    facets = []
    for card, corners in (("CQUAD4", [(0, 1, 2, 3)]), ("CTRIA3", [(0, 1, 2)]),
                          ("CTRIA6", quadratic.FACETS)):
        nodes = np.array([[grid(g, f"{card} {e.eid}") for g in e.node_ids] for e in
                          bdf.elements.values() if READ_AS.get(e.type, e.type) == card
                          and all(e.node_ids)], int)
        facets += [(shell_normals.facet_normals(xyz[nodes[:, c]]), nodes[:, c])
                   for c in map(list, corners) if nodes.size]
    if not facets:
        return None
    normals = shell_normals.grid_normals(facets, n_nodes, snorm)
    return lambda nodes: shell_normals.facet_curvature(xyz[nodes], normals[nodes], snorm)
