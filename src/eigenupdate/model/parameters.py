"""Named physical parameters of a model: value, prior standard deviation, updated or fixed."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from eigenupdate.errors import InputError


@dataclass(frozen=True)
class Parameter:
    """One physical parameter s_j on which K and M depend (linearly, or through the
    monomial terms of :class:`~eigenupdate.model.parametric.Term`).

    Parameters
    ----------
    name : str
        Unique name (``k1``, ``EI3``, ``m_L``).
    value : float
        Current (initial) value in SI units. Physical parameters are masses, stiffnesses,
        EI or mass per length, so the value must be >= 0.
    std : float or None
        Prior standard deviation (same units), used by the Bayesian estimator.
    update : bool
        True if the parameter is unknown and updated; False holds it fixed.
    unit : str
        Unit of ``value`` and ``std``, for tables and reports only (``""``: not stated).
        The models of this package state SI units (``"N/m"``, ``"kg"``, ``"N m^2"``); a
        NASTRAN field's is a dimension in the deck's own units (``"F/L^2"`` for MAT1 E).

    Examples
    --------
    >>> p = Parameter("k1", 1.2e6, std=1e5)
    >>> p.scale
    1200000.0
    >>> Parameter("m_L", 0.0).scale   # a zero initial value keeps scale 1
    1.0
    >>> Parameter("k1", 1.2e6, unit="N/m").with_value(1.3e6).unit
    'N/m'
    """

    name: str
    value: float
    std: float | None = None
    update: bool = True
    unit: str = ""

    def __post_init__(self) -> None:
        if not self.name:
            raise InputError("parameter name is empty", field="name")
        if not math.isfinite(self.value) or self.value < 0:
            raise InputError(
                f"value {self.value!r} must be a finite number >= 0", field=f"{self.name}.value"
            )
        if self.std is not None and not (math.isfinite(self.std) and self.std > 0):
            raise InputError(f"std {self.std!r} must be > 0", field=f"{self.name}.std")

    @property
    def scale(self) -> float:
        """Normalising scale: the initial value, or 1 when it is 0 (paper Section 4)."""
        return self.value if self.value != 0 else 1.0

    def with_value(self, value: float) -> Parameter:
        return replace(self, value=float(value))

    def with_unit(self, unit: str) -> Parameter:
        """The parameter with ``unit`` where none is stated (a stated one is kept)."""
        return self if self.unit else replace(self, unit=unit)


def check_unique(parameters: list[Parameter] | tuple[Parameter, ...], source: str | None = None):
    """Raise InputError on a duplicate parameter name."""
    seen: set[str] = set()
    for p in parameters:
        if p.name in seen:
            raise InputError(f"duplicate parameter name {p.name!r}", source=source, field="name")
        seen.add(p.name)
