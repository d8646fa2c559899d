"""Screening of candidate configurations: perturbed eigenvalues, sensitivities and mode order.

The planner's view of the one screening engine,
:func:`eigenupdate.solve.screening.screen_configurations` (Rayleigh-Ritz on Krylov
subspaces of the bare structure's factorisation on sparse models, certified, with Lanczos
where the certificate fails; dense solves on small ones).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from eigenupdate.model.configurations import Configuration
from eigenupdate.model.parametric import ParametricModel
from eigenupdate.solve.screening import screen_configurations


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
    """Screen the bare structure and each candidate configuration.

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
    s = screen_configurations(model, candidates, modes)

    def nxt(v: float) -> float | None:
        return None if np.isnan(v) else float(v)

    bare = Screened(s.base_all_eigenvalues, nxt(s.base_next_eigenvalue), s.base_J, True)
    return bare, [Screened(s.all_eigenvalues[i], nxt(s.next_eigenvalues[i]), s.J[i],
                           bool(s.order_kept[i])) for i in range(len(candidates))]


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
