"""Tapered CBEAM sections (issue 20): a PBEAM whose A, I1, I2, J, NSM or NSI differ
between end A and end B, or a PBEAML with different dimensions (or NSM) at its ends.

As MSC Nastran forms them, established against MSC Nastran 2005's modes of the
published fmondsp deck (tapered PBEAML TUBEs; tests/io/test_nastran_tapered.py):

* a PBEAML becomes the PBEAM of its section at each end (the equivalent PBEAMs in the
  deck's .op2), whose A, I1, I2, J, NSM vary linearly between the ends;
* the stiffness is the flexibility's (:mod:`eigenupdate.model.tapered`) with its
  integrals taken by 3-point Gauss. On fmondsp this meets MSC's 12 elastic frequencies
  to 3.0e-7; the exact integrals (12 points) miss by 1.1e-3, 2 points by 1.5e-3,
  4 by 6.2e-4, Simpson by 8.7e-3, the section of linearly interpolated dimensions
  (exact integrals) by 1.1e-2, and Hermite shape functions with linear I by 8.9e-3;
* lumped mass: each end takes the first moment of the linear mass per length (the .f06's
  grid point weight generator: centre of gravity 0.9990629 against 0.9995975 with half
  the mass at each end). Coupled mass integrates the Hermite functions exactly (4
  points); NASTRAN's rule for it is not established here.

Not built, and refused naming the card: intermediate stations (their integration is not
established), a PBEAML whose shear factors differ between its ends (which one NASTRAN's
single K1, K2 takes is not established), I12, S1/S2 shear relief, pin flags, parameters
on a tapered property.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from eigenupdate.errors import EigenupdateWarning, InputError
from eigenupdate.io.nastran_fields import in_range
from eigenupdate.model import tapered

STIFFNESS_POINTS = 3  # MSC Nastran's (module docstring)
MASS_POINTS = 4  # exact for the linear mass per length times two cubics
ROUNDING = 1e-4
"""Relative spread of a PBEAM's station values taken as the rounding of one value (the
first station's is used): the shared pyn_solid_shell_bar deck writes I1 as .0052083 at
end A and .005208 at end B (6e-5 apart); a larger spread is a taper."""


@dataclass(frozen=True)
class Taper:
    """One tapered property: its section at ends A and B, linear between."""

    where: str  # "PBEAM 8"
    ends: np.ndarray  # (2, 6): A, I1, I2, J, NSM, NSI at end A and end B

    def profile(self, s: np.ndarray) -> np.ndarray:
        """(q, 6) A, I1, I2, J, NSM, NSI at the fractions ``s`` of the length."""
        return self.ends[0] + (self.ends[1] - self.ends[0]) * np.asarray(s)[:, None]

    def means(self) -> np.ndarray:
        """A, I1, I2, J, NSM, NSI averaged over the length (the element's reference)."""
        return self.ends.mean(axis=0)


def _varies(v) -> bool:
    v = np.asarray(v, float)
    return bool(np.ptp(v) > ROUNDING * np.abs(v).max())


def _two_stations(prop, where: str) -> None:
    x = np.asarray(prop.xxb, float)
    if x.size != 2 or x[0] != 0.0 or x[1] != 1.0:
        raise InputError(f"{where}: stations X/XB = {x.tolist()}: a tapered section with "
                         f"intermediate stations is not supported (only ends A and B, "
                         f"X/XB 1.0)")


def pbeam_taper(prop) -> Taper | None:
    """The taper of a PBEAM, None when its section is constant (to ``ROUNDING``)."""
    where = f"PBEAM {prop.pid}"
    names = ("A", "i1", "i2", "j", "nsm")
    cols = [np.array([0.0 if v is None else v for v in np.ravel(getattr(prop, n))], float)
            for n in names]
    nsia = prop.nsia or 0.0
    nsib = nsia if prop.nsib is None else prop.nsib
    if not any(_varies(c) for c in cols) and not _varies([nsia, nsib]):
        return None
    _two_stations(prop, where)
    if np.any(np.asarray(prop.i12, float) != 0):
        raise InputError(f"{where}: a tapered section with I12 != 0 is not supported")
    if getattr(prop, "s1", 0.0) or getattr(prop, "s2", 0.0):
        raise InputError(f"{where}: S1, S2 (shear relief of a taper) are not supported")
    ends = np.stack([*cols, np.array([nsia, nsib], float)], axis=1)
    for k, name in enumerate(names):
        if np.any(ends[:, k] < 0) or (k < 3 and np.any(ends[:, k] <= 0)):
            raise InputError(f"{where}: {name.upper()} = {ends[:, k].tolist()} at the ends "
                             f"must be > 0")
        for end, v in zip("AB", ends[:, k], strict=True):  # as a constant section's
            in_range(v, f"{where}: {name.upper()} at end {end}")
    return Taper(where, ends)


def pbeaml_taper(prop, section_values, shear_factors) -> Taper | None:
    """The taper of a PBEAML, None when constant. ``section_values(dim)``: A, I1, I2, J of
    one end's dimensions; ``shear_factors(dim, A)``: its K1, K2."""
    where = f"PBEAML {prop.pid}"
    rows = np.atleast_2d(np.asarray(prop.dim, float))
    nsm = np.ravel(np.asarray(prop.nsm, float))
    if not np.ptp(rows, axis=0).any() and np.ptp(nsm) == 0:
        return None
    _two_stations(prop, where)
    values = [section_values(d) for d in rows]
    ka, kb = (np.array(shear_factors(d, v[0])) for d, v in zip(rows, values, strict=True))
    if np.any(np.abs(ka - kb) > ROUNDING * np.maximum(np.abs(ka), np.abs(kb))):
        raise InputError(f"{where}: the shear factors differ between the ends (K1, K2 = "
                         f"{ka[0]:.6g}, {ka[1]:.6g} at A, {kb[0]:.6g}, {kb[1]:.6g} at B): "
                         f"not supported (NASTRAN's PBEAM has one K1, K2)")
    ends = np.array([[*v, m, 0.0] for v, m in zip(values, nsm, strict=True)])
    return Taper(where, ends)


def element_parts(tapers: list[Taper], L: np.ndarray, E: np.ndarray, G: np.ndarray,
                  rho: np.ndarray, K1: np.ndarray, K2: np.ndarray, consistent: bool
                  ) -> dict[str, np.ndarray]:
    """The frame parts (nastran_lines' names, (n, 12, 12) local) of tapered elements, each
    per unit of its coefficient at the mean section (:meth:`Taper.means`): E A, G J,
    E I1, E I2, rho A + NSM, rho (I1 + I2) + NSI. K1, K2 = 0: shear-rigid."""
    if consistent:
        warnings.warn(f"{tapers[0].where}: coupled mass (COUPMASS) of a tapered CBEAM "
                      f"integrates the Hermite functions exactly; NASTRAN's rule for it is "
                      f"not established (its lumped mass is)", EigenupdateWarning,
                      stacklevel=3)
    n = len(tapers)

    def col(x) -> np.ndarray:
        return np.asarray(x, float)[:, None]

    out_k, out_m = {}, {}
    for points, kind in ((STIFFNESS_POINTS, "k"), (MASS_POINTS, "m")):
        s, w = tapered.gauss(points)
        prof = np.stack([t.profile(s) for t in tapers])  # (n, q, 6)
        a, i1, i2, j, nsm, nsi = np.moveaxis(prof, 2, 0)
        S, W = np.broadcast_to(s, (n, points)), np.broadcast_to(w, (n, points))
        if kind == "k":
            with np.errstate(divide="ignore"):
                kga1 = np.where(col(K1) > 0, col(K1 * G) * a, np.inf)
                kga2 = np.where(col(K2) > 0, col(K2 * G) * a, np.inf)
            out_k = tapered.stiffness(L, S, W, col(E) * a, col(G) * j, col(E) * i1,
                                      col(E) * i2, kga1, kga2)
        else:
            out_m = tapered.mass(L, S, W, col(rho) * a + nsm, col(rho) * (i1 + i2) + nsi,
                                 consistent)
    A, I1, I2, J, NSM, NSI = np.array([t.means() for t in tapers]).T
    coef = {"k_axial": (out_k["axial"], E * A), "k_torsion": (out_k["torsion"], G * J),
            "k_bend1": (out_k["bend1"], E * I1), "k_bend2": (out_k["bend2"], E * I2),
            "m_translation": (out_m["translation"], rho * A + NSM),
            "m_torsion": (out_m["torsion"], rho * (I1 + I2) + NSI)}
    out = {}
    for name, (mat, c) in coef.items():
        scale = np.divide(1.0, c, out=np.zeros_like(c), where=c != 0)
        out[name] = mat * scale[:, None, None]
    return out


def refuse_parameters(pindex: dict, mids: np.ndarray, pkeys: list, taper_of: list,
                      K1: np.ndarray, K2: np.ndarray, tied: np.ndarray) -> None:
    """InputError for a parameter a tapered element's parts do not scale linearly: any
    field of a tapered PBEAM/PBEAML; MAT1 E with shear flexibility and G given (E / G
    shapes the parts); MAT1 RHO with NSM or NSI (rho A + NSM's profile follows rho)."""
    tap = np.array([t is not None for t in taper_of])
    for (card, cid), slots in pindex.items():
        if card != "MAT1":
            if any(pkeys[e] == (card, cid) for e in np.flatnonzero(tap)):
                raise InputError(f"{card} {cid}: parameters on a tapered section are not "
                                 f"supported")
            continue
        hit = tap & (mids == cid)
        flexible = hit & ((K1 > 0) | (K2 > 0)) & ~tied
        if "E" in slots and flexible.any():
            raise InputError(f"MAT1 {cid}: E as a parameter of the shear-flexible tapered "
                             f"{taper_of[int(np.flatnonzero(flexible)[0])].where} with G "
                             f"given is not supported")
        if "RHO" in slots:
            for e in np.flatnonzero(hit):
                if np.any(taper_of[e].ends[:, 4:] != 0):
                    raise InputError(f"MAT1 {cid}: RHO as a parameter of the tapered "
                                     f"{taper_of[e].where} with NSM or NSI is not supported")
