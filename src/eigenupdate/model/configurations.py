"""Perturbed configurations: the bare structure ("base") and the structure with known
masses or grounded springs added at chosen coordinates (paper Section 3)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from eigenupdate.errors import InputError
from eigenupdate.model.parametric import ParametricModel

BASE = "base"


@dataclass(frozen=True)
class Addition:
    """A known mass (kg; kg m^2 on a rotational coordinate) and/or grounded stiffness (N/m)
    added to the diagonal of M and/or K at one coordinate."""

    coordinate: int
    mass: float = 0.0
    stiffness: float = 0.0

    def __post_init__(self) -> None:
        for name in ("mass", "stiffness"):
            v = getattr(self, name)
            if not math.isfinite(v) or v < 0:
                raise InputError(f"added {name} must be >= 0, got {v}", field=name)
        if self.mass == 0 and self.stiffness == 0:
            raise InputError("an addition needs a mass or a stiffness > 0", field="add")


@dataclass(frozen=True)
class Configuration:
    """A named test configuration; ``additions`` is empty for the bare structure.

    Several configurations may put different masses at the same coordinate (paper Table 2).
    """

    name: str
    additions: tuple[Addition, ...] = ()

    def rows(self, model: ParametricModel) -> np.ndarray:
        """Model rows of the perturbed coordinates (InputError names this configuration)."""
        try:
            return np.array([model.index(a.coordinate) for a in self.additions], dtype=int)
        except InputError as exc:
            raise InputError(str(exc), field=f"perturbation {self.name!r}") from None

    def listed(self) -> list[list]:
        """The additions as [coordinate, mass, stiffness] lists (a saved result's record).

        >>> mass_at(4, 0.35).listed()
        [[4, 0.35, 0.0]]
        """
        return [[a.coordinate, a.mass, a.stiffness] for a in self.additions]

    def delta(self, model: ParametricModel) -> tuple[sp.csr_array, sp.csr_array]:
        """(Delta K, Delta M): diagonal matrices of the additions."""
        rows = self.rows(model)
        n = model.n
        dk = sp.csr_array(([a.stiffness for a in self.additions], (rows, rows)), shape=(n, n))
        dm = sp.csr_array(([a.mass for a in self.additions], (rows, rows)), shape=(n, n))
        return dk, dm


def mass_at(coordinate: int, mass: float, name: str | None = None) -> Configuration:
    """One mass added at one coordinate.

    >>> c = mass_at(4, 0.35)
    >>> c.name, c.additions[0].coordinate, c.additions[0].mass
    ('0.35 kg at 4', 4, 0.35)
    """
    return Configuration(name or f"{mass:g} kg at {coordinate}", (Addition(coordinate, mass=mass),))
