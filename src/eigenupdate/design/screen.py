"""Screening of candidate configurations: perturbed eigenvalues, sensitivities and mode order.

This is the one seam between the planner and the eigen-solver: a faster screening path
(rank-one updates of the bare structure's factorisation on large sparse models) can replace
:func:`screen_candidates` without touching the search.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from eigenupdate.model.configurations import BASE, Configuration
from eigenupdate.model.parametric import ParametricModel
from eigenupdate.solve.jacobian import solve_configurations
from eigenupdate.solve.sensitivity import eigenvalue_derivatives


@dataclass(frozen=True)
class Screened:
    """One configuration, screened at the model's parameter values.

    Attributes
    ----------
    eigenvalues : elastic eigenvalues of modes 1..max(modes), (rad/s)^2.
    next_eigenvalue : the next elastic eigenvalue above them, or None if the model has none.
    J : (len(modes), updated parameters) d lambda / d s in physical units.
    order_kept : every used mode correlates best (mass-weighted MAC) with the bare
        structure's mode of the same number, so pairing modes by order stays valid.
    """

    eigenvalues: np.ndarray
    next_eigenvalue: float | None
    J: np.ndarray
    order_kept: bool

    @property
    def frequencies_hz(self) -> np.ndarray:
        return np.sqrt(np.maximum(self.eigenvalues, 0.0)) / (2 * np.pi)


def screen_candidates(
    model: ParametricModel, candidates: Sequence[Configuration], modes: Sequence[int]
) -> tuple[Screened, list[Screened]]:
    """Screen the bare structure and each candidate configuration (direct solves).

    Returns ``(bare, [candidate, ...])``.

    Examples
    --------
    A 2 kg mass on an 800 N/m spring; 2 kg more halves the eigenvalue:

    >>> from eigenupdate.model.parameters import Parameter
    >>> from eigenupdate.model.spring_mass import Mass, Spring, spring_mass_model
    >>> from eigenupdate.model.configurations import mass_at
    >>> model = spring_mass_model([Mass(Parameter("m", 2.0), 1)],
    ...                           [Spring(Parameter("k", 800.0), (0, 1))])
    >>> bare, (c,) = screen_candidates(model, [mass_at(1, 2.0)], [1])
    >>> round(float(bare.eigenvalues[0]), 9), round(float(c.eigenvalues[0]), 9), c.order_kept
    (400.0, 200.0, True)
    """
    modes = sorted(set(int(k) for k in modes))
    upd = model.updated
    kt = [model.k_terms[j] for j in upd]
    mt = [model.m_terms[j] for j in upd]
    configs = [Configuration(BASE), *candidates]
    sols = solve_configurations(model, configs, modes[-1])
    M = model.mass()
    base_phi = sols[0].modes
    out = []
    for c, sol in zip(configs, sols, strict=True):
        J = eigenvalue_derivatives(sol, modes, kt, mt, f"configuration {c.name!r}")
        x = base_phi.T @ (M @ sol.modes)  # both mass-normalised: x_ij = correlation
        mac = x**2 / np.outer(np.einsum("ij,ij->j", base_phi, M @ base_phi),
                              np.einsum("ij,ij->j", sol.modes, M @ sol.modes))
        kept = all(int(np.argmax(mac[:, k - 1])) == k - 1 for k in modes)
        out.append(Screened(sol.eigenvalues, sol.next_eigenvalue, J, kept))
    return out[0], out[1:]


SCREEN_CHUNK = 16
"""Candidates per task when screening runs on an executor."""


def _screen_chunk(chunk: Sequence[Configuration], shared: tuple) -> list[Screened]:
    model, modes = shared
    return screen_candidates(model, chunk, modes)[1]


def screen_on(executor, model: ParametricModel, candidates: Sequence[Configuration],
              modes: Sequence[int]) -> tuple[Screened, list[Screened]]:
    """:func:`screen_candidates` with the candidates split into tasks on ``executor`` (see
    :mod:`eigenupdate.design.executor`). On the dense path the results are those of a
    single call; on the sparse path each chunk solves the bare structure again, so they
    agree with a single call's within the fast path's certified bounds (about 1e-11
    relative on the eigenvalues), not to the last digit."""
    chunks = [list(candidates[i:i + SCREEN_CHUNK])
              for i in range(0, len(candidates), SCREEN_CHUNK)]
    bare, _ = screen_candidates(model, [], modes)
    parts = executor.map(_screen_chunk, (model, list(modes)), chunks)
    return bare, [s for part in parts for s in part]
