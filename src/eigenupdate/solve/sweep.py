"""Natural frequencies against a mass added at one coordinate (paper Fig. 4).

How much a perturbation moves each frequency tells which masses make a good test plan;
:func:`eigenupdate.plot.plots.plot_mass_sweep` draws the result.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import scipy.sparse as sp

from eigenupdate.errors import InputError
from eigenupdate.model.configurations import Configuration
from eigenupdate.model.coordinates import Coordinate
from eigenupdate.model.parametric import ParametricModel
from eigenupdate.schema import reader
from eigenupdate.solve.eigen import DENSE_LIMIT, base_operator, solve_elastic
from eigenupdate.solve.response import configuration_matrices

__all__ = ["MassSweep", "mass_sweep"]


@dataclass(frozen=True)
class MassSweep:
    """Elastic natural frequencies against the mass added at one coordinate.

    Attributes
    ----------
    added_mass : (n_points,) added mass, kg (kg m^2 on a rotational coordinate).
    reference_mass : diagonal term of M at the coordinate (0 if massless), the 100 %
        of the percentage axis.
    frequencies_hz : (n_points, n_modes) elastic natural frequencies, Hz.
    coordinate : where the mass is added (its label and whether it is a rotation).
    configuration : name of the configuration the mass is added to (None: bare).
    """

    added_mass: np.ndarray
    reference_mass: float
    frequencies_hz: np.ndarray
    coordinate: Coordinate
    configuration: str | None = None

    SCHEMA: ClassVar[str] = "eigenupdate.sweep/1"

    def to_dict(self) -> dict:
        """JSON-ready document; read back by :meth:`from_dict`."""
        c = self.coordinate
        return {"schema": self.SCHEMA, "added_mass": self.added_mass.tolist(),
                "reference_mass": self.reference_mass,
                "frequencies_hz": self.frequencies_hz.tolist(),
                "coordinate": {"number": c.number, "node": c.node, "direction": c.direction},
                "configuration": self.configuration}

    @classmethod
    def from_dict(cls, doc: dict, source: str | None = None) -> MassSweep:
        """The sweep :meth:`to_dict` wrote; InputError naming the field otherwise."""
        r = reader(doc, cls.SCHEMA, source)
        mass, f = r.array("added_mass"), r.array("frequencies_hz", 2)
        if f.shape[0] != mass.size:
            raise r.fail("frequencies_hz", f"needs one row per added mass ({mass.size})")
        c = r.child("coordinate")
        try:
            coord = Coordinate(c.int("number"), c.int("node"), c.int("direction"))
        except InputError as exc:
            raise c.fail("direction", str(exc)) from None
        return cls(mass, r.number("reference_mass", minimum=0.0), f, coord,
                   r.str("configuration", optional=True))

    @property
    def percent(self) -> np.ndarray | None:
        """Added mass in % of ``reference_mass`` (None if that is 0)."""
        if self.reference_mass <= 0:
            return None
        return 100.0 * self.added_mass / self.reference_mass

    @property
    def eigenvalue_ratio(self) -> np.ndarray:
        """lambda / lambda(no added mass) for every point and mode."""
        return (self.frequencies_hz / self.frequencies_hz[0]) ** 2


def mass_sweep(
    model: ParametricModel,
    coordinate: int,
    max_mass: float,
    n_modes: int,
    configuration: Configuration | None = None,
    n_points: int = 41,
    *,
    values: Sequence[float] | Mapping[str, float] | None = None,
) -> MassSweep:
    """Elastic natural frequencies with 0..``max_mass`` added at ``coordinate``.

    The mass is added on top of ``configuration`` (the bare structure if None).

    Examples
    --------
    A 2 kg mass on an 800 N/m spring: f = sqrt(k / (m + dm)) / (2 pi).

    >>> from eigenupdate.model.spring_mass import Mass, Spring, spring_mass_model
    >>> from eigenupdate.model.parameters import Parameter
    >>> sdof = spring_mass_model([Mass(Parameter("m", 2.0), 1)],
    ...                          [Spring(Parameter("k", 800.0), (0, 1))])
    >>> sweep = mass_sweep(sdof, 1, 2.0, 1, n_points=3)
    >>> sweep.percent.tolist(), sweep.frequencies_hz.round(4).ravel().tolist()
    ([0.0, 50.0, 100.0], [3.1831, 2.599, 2.2508])
    """
    if not (np.isfinite(max_mass) and max_mass > 0):
        raise InputError(f"must be > 0, got {max_mass!r}", field="max_mass")
    if n_points < 2:
        raise InputError(f"at least 2 points are needed, got {n_points}", field="n_points")
    if n_modes < 1:
        raise InputError(f"at least one mode is needed, got {n_modes}", field="n_modes")
    try:
        row = model.index(coordinate)
    except InputError as exc:
        raise InputError(str(exc), field="coordinate") from None
    K, M = configuration_matrices(model, configuration, values)
    masses = np.linspace(0.0, float(max_mass), int(n_points))
    n = K.shape[0]
    freqs = np.empty((masses.size, n_modes))
    # Large models: factorise K - sigma M once; each added mass is a rank-one Woodbury update.
    op, base = base_operator(K, M, n_modes) if n > DENSE_LIMIT else (None, None)
    for i, dm in enumerate(masses):
        Mi = M + dm * _diag_unit(row, n)
        kw = {}
        if op is not None:
            kw["operator"] = op.updated(np.array([row]), np.array([0.0]), np.array([dm]))
            kw["n_rigid"] = base.n_rigid
        sol = solve_elastic(K, Mi, n_modes, **kw)
        if sol.eigenvalues.size < n_modes:
            raise InputError(
                f"the model has only {sol.eigenvalues.size} elastic modes", field="n_modes"
            )
        freqs[i] = sol.frequencies_hz
    return MassSweep(masses, float(M[row, row]), freqs, model.coordinate_table[coordinate],
                     None if configuration is None else configuration.name)


def _diag_unit(row: int, n: int) -> sp.csr_array:
    return sp.csr_array(([1.0], ([row], [row])), shape=(n, n))
