"""The sensitivity matrix J of Eq. (1): d lambda / d s for the chosen modes of every
configuration, stacked configuration by configuration.

Columns are the updated parameters. ``J`` is in physical units; ``normalised`` is
J * diag(scale), the derivative with respect to s_j / s_j0 (the paper normalises every
parameter by its initial value; a zero initial value keeps scale 1).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from eigenupdate.errors import InputError, NumericalError
from eigenupdate.model.configurations import Configuration
from eigenupdate.model.parametric import ParametricModel
from eigenupdate.solve.eigen import DENSE_LIMIT, EigenSolution, base_operator, solve_elastic
from eigenupdate.solve.sensitivity import eigenvalue_derivatives


@dataclass(frozen=True)
class Linearisation:
    """Model eigenvalues and their sensitivities at one parameter vector.

    Attributes
    ----------
    rows : (configuration name, mode) of each equation.
    eigenvalues : model eigenvalue of each equation, (rad/s)^2.
    J : (equations, updated parameters) d lambda / d s in physical units.
    scale : normalising scale of each updated parameter.
    names : names of the updated parameters.
    """

    rows: list[tuple[str, int]]
    eigenvalues: np.ndarray
    J: np.ndarray
    scale: np.ndarray
    names: list[str]

    @property
    def normalised(self) -> np.ndarray:
        return self.J * self.scale


def solve_configurations(
    model: ParametricModel,
    configurations: Sequence[Configuration],
    n_modes: int,
    values: Sequence[float] | None = None,
    dense: bool | None = None,
) -> list[EigenSolution]:
    """Elastic eigen-solutions of every configuration at parameter ``values``.

    On the sparse path K - sigma M is factorised once for the bare structure and each
    perturbed configuration reuses it (see :class:`eigenupdate.solve.eigen.ShiftInvert`).
    """
    K, M = model.stiffness(values), model.mass(values)
    sparse = not (dense if dense is not None else model.n <= DENSE_LIMIT)
    out = []
    try:
        base_op, base_sol = base_operator(K, M, n_modes) if sparse else (None, None)
    except (InputError, NumericalError) as exc:
        raise type(exc)(str(exc), field="the bare structure") from None
    for c in configurations:
        try:
            if not c.additions and base_sol is not None:
                out.append(base_sol)
                continue
            dk, dm = c.delta(model)
            op = None
            if base_op is not None:
                rows = c.rows(model)
                op = base_op.updated(
                    rows, [a.stiffness for a in c.additions], [a.mass for a in c.additions]
                )
            # added masses and grounded springs never create rigid-body modes
            hint = base_sol.n_rigid if base_sol is not None else None
            out.append(solve_elastic(K + dk, M + dm, n_modes, operator=op, dense=not sparse,
                                     n_rigid=hint))
        except (InputError, NumericalError) as exc:
            raise type(exc)(str(exc), field=f"configuration {c.name!r}") from None
    return out


def linearise(
    model: ParametricModel,
    configurations: Sequence[Configuration],
    modes: Sequence[int],
    values: Sequence[float] | None = None,
    dense: bool | None = None,
) -> Linearisation:
    """Eigenvalues and the sensitivity matrix J at ``values`` (default: the model's).

    Examples
    --------
    >>> import numpy as np
    >>> from eigenupdate.model.parameters import Parameter
    >>> from eigenupdate.model.spring_mass import Mass, Spring, spring_mass_model
    >>> from eigenupdate.model.configurations import Configuration, mass_at
    >>> model = spring_mass_model([Mass(Parameter("m", 2.0), 1)],
    ...                           [Spring(Parameter("k", 800.0), (0, 1))])
    >>> lin = linearise(model, [Configuration("base"), mass_at(1, 2.0)], [1])
    >>> np.round(lin.eigenvalues, 9).tolist()   # 800/2 and 800/4
    [400.0, 200.0]
    >>> np.round(lin.J, 9).tolist()    # [[-k/m^2, 1/m], [-k/(m+2)^2, 1/(m+2)]]
    [[-200.0, 0.5], [-50.0, 0.25]]
    """
    modes = sorted(set(int(k) for k in modes))
    if not modes or modes[0] < 1:
        raise InputError("modes must be elastic mode numbers >= 1", field="measurement.modes")
    upd = model.updated
    if upd.size == 0:
        raise InputError("no parameter is updated (every parameter has update = false)")
    kt = [model.k_terms[j] for j in upd]
    mt = [model.m_terms[j] for j in upd]
    sols = solve_configurations(model, configurations, modes[-1], values, dense)
    rows, lam, blocks = [], [], []
    for c, sol in zip(configurations, sols, strict=True):
        blocks.append(eigenvalue_derivatives(sol, modes, kt, mt, f"configuration {c.name!r}"))
        lam.extend(sol.eigenvalues[np.asarray(modes) - 1])
        rows.extend((c.name, k) for k in modes)
    scale = np.array([model.parameters[j].scale for j in upd])  # initial values, not current
    return Linearisation(
        rows, np.array(lam), np.vstack(blocks), scale, [model.names[j] for j in upd]
    )
