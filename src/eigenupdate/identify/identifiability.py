"""Identifiability check of a test plan (paper Section 3, Tables 1-3).

Needs no measurements: the sensitivity matrix J of the initial model tells whether the
chosen perturbations and modes give enough independent equations. The algorithm can
identify every updated parameter when J^T J has full rank and a moderate condition number.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from eigenupdate.model.configurations import Configuration
from eigenupdate.model.parametric import ParametricModel
from eigenupdate.solve.jacobian import linearise


@dataclass(frozen=True)
class IdentifiabilityReport:
    """Condition and rank of the (normalised) sensitivity matrix.

    Attributes
    ----------
    parameters : names of the updated parameters (columns of J).
    equations : number of eigenvalues used (rows of J).
    rank : rank of J^T J with NumPy's default tolerance (as MATLAB's ``rank``).
    condition_J, condition_JTJ : ratio of the extreme singular values (inf if singular).
    singular_values : singular values of J, descending.
    weakest : the right singular vector of the smallest singular value, by parameter: the
        parameter combination the plan determines worst.
    """

    parameters: list[str]
    equations: int
    rank: int
    condition_J: float
    condition_JTJ: float
    singular_values: list[float]
    weakest: dict[str, float]

    @property
    def identifiable(self) -> bool:
        return self.rank == len(self.parameters)


def check(
    model: ParametricModel,
    configurations: Sequence[Configuration],
    modes: Sequence[int],
    values: Sequence[float] | None = None,
) -> IdentifiabilityReport:
    """Identifiability of the updated parameters of ``model`` from this test plan.

    Examples
    --------
    One mass on one spring, mass and stiffness unknown: the bare structure alone gives
    rank 1 (only k/m is seen); adding a known mass separates them.

    >>> from eigenupdate.model.parameters import Parameter
    >>> from eigenupdate.model.spring_mass import Mass, Spring, spring_mass_model
    >>> from eigenupdate.model.configurations import Configuration, mass_at
    >>> model = spring_mass_model([Mass(Parameter("m", 2.0), 1)],
    ...                           [Spring(Parameter("k", 800.0), (0, 1))])
    >>> check(model, [Configuration("base")], [1]).rank
    1
    >>> check(model, [Configuration("base"), mass_at(1, 0.5)], [1]).rank
    2
    """
    lin = linearise(model, configurations, modes, values)
    J = lin.normalised
    sv_J = np.linalg.svd(J, compute_uv=False)
    JTJ = J.T @ J
    _, sv, vt = np.linalg.svd(JTJ)
    v = vt[-1]
    v = v * np.sign(v[np.argmax(np.abs(v))])
    order = np.argsort(-np.abs(v))
    return IdentifiabilityReport(
        parameters=list(lin.names),
        equations=J.shape[0],
        rank=int(np.linalg.matrix_rank(JTJ)),
        condition_J=_condition(sv_J, J.shape[1]),
        condition_JTJ=_condition(sv, J.shape[1]),
        singular_values=sv_J.tolist(),
        weakest={lin.names[i]: float(v[i]) for i in order},
    )


def _condition(sv: np.ndarray, p: int) -> float:
    # Fewer equations than parameters: the missing singular values are zero.
    if sv.size < p or sv[-1] == 0:
        return float("inf")
    return float(sv[0] / sv[-1])
