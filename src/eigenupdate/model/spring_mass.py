"""Spring-mass networks: lumped masses at coordinates 1..n, springs between two
coordinates or from a coordinate to ground (coordinate 0)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import scipy.sparse as sp

from eigenupdate.budget import require_model_size
from eigenupdate.errors import InputError
from eigenupdate.model.parameters import Parameter
from eigenupdate.model.parametric import ParametricModel


@dataclass(frozen=True)
class Spring:
    parameter: Parameter
    coordinates: tuple[int, int]  # 0 = ground


@dataclass(frozen=True)
class Mass:
    parameter: Parameter
    coordinate: int


def spring_mass_model(
    masses: Sequence[Mass], springs: Sequence[Spring], n: int | None = None
) -> ParametricModel:
    """Assemble a spring-mass network.

    Each mass and each spring is a parameter; K and M are exactly linear in them.
    ``n`` defaults to the highest coordinate used.

    Examples
    --------
    Two 1 kg masses, ground-1-2 chain of 1 N/m springs: lambda = (3 -+ sqrt 5)/2.

    >>> import numpy as np, scipy.linalg
    >>> P = Parameter
    >>> model = spring_mass_model(
    ...     [Mass(P("m1", 1.0), 1), Mass(P("m2", 1.0), 2)],
    ...     [Spring(P("k1", 1.0), (0, 1)), Spring(P("k2", 1.0), (1, 2))])
    >>> lam = scipy.linalg.eigh(model.stiffness().toarray(), model.mass().toarray(),
    ...                         eigvals_only=True)
    >>> np.round(lam, 6).tolist()
    [0.381966, 2.618034]
    """
    used = [m.coordinate for m in masses] + [c for s in springs for c in s.coordinates]
    n = n if n is not None else max(used, default=0)
    if n < 1:
        raise InputError("the model has no coordinates", field="model")
    require_model_size(n, len(masses) + len(springs))
    for m in masses:
        if not 1 <= m.coordinate <= n:
            raise InputError(f"unknown coordinate {m.coordinate}", field=f"mass {m.parameter.name}")
        if m.parameter.value <= 0:
            raise InputError(
                f"mass must be > 0, got {m.parameter.value}", field=f"mass {m.parameter.name}"
            )
    for s in springs:
        a, b = s.coordinates
        if not (0 <= a <= n and 0 <= b <= n) or a == b:
            raise InputError(
                f"coordinates {list(s.coordinates)} must be two different coordinates in 0..{n}",
                field=f"spring {s.parameter.name}",
            )
        if s.parameter.value <= 0:
            raise InputError(
                f"stiffness must be > 0, got {s.parameter.value}",
                field=f"spring {s.parameter.name}",
            )
    params, kt, mt = [], [], []
    for m in masses:
        params.append(m.parameter.with_unit("kg"))
        kt.append(None)
        mt.append(sp.csr_array(([1.0], ([m.coordinate - 1], [m.coordinate - 1])), shape=(n, n)))
    for s in springs:
        params.append(s.parameter.with_unit("N/m"))
        rows, cols, vals = [], [], []
        coords = [c - 1 for c in s.coordinates if c != 0]
        for i in coords:
            for j in coords:
                rows.append(i)
                cols.append(j)
                vals.append(1.0 if i == j else -1.0)
        kt.append(sp.csr_array((vals, (rows, cols)), shape=(n, n)))
        mt.append(None)
    zero = sp.csr_array((n, n))
    return ParametricModel(zero, zero, tuple(params), tuple(kt), tuple(mt))
