"""Screening candidate mass additions for test planning: eigenvalues and sensitivities of
many single-mass configurations from one factorisation of the bare structure.

Every candidate (coordinate, mass) is a configuration of its own. On the sparse path
the candidates at one coordinate share one Krylov subspace
(:mod:`eigenupdate.solve.perturbed`), each gets a dense Rayleigh-Ritz step and the same
certificate as in updating; a candidate that fails it is solved by shift-invert Lanczos
on the base factorisation, so every number returned is accurate, and ``certified`` says
which path gave it. Small models (dense path) are solved directly.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from eigenupdate.errors import InputError, NumericalError
from eigenupdate.model.configurations import Addition, Configuration
from eigenupdate.model.parametric import ParametricModel
from eigenupdate.solve import perturbed
from eigenupdate.solve.eigen import DENSE_LIMIT, base_operator
from eigenupdate.solve.jacobian import modes_and_updated, solve_configurations, solve_one
from eigenupdate.solve.restricted import ProjectedTerms, RestrictedTerms
from eigenupdate.solve.sensitivity import check_distinct

CHUNK = 20
"""Coordinates whose subspaces are built together (bounds the memory: each holds
(levels + 1) vectors of the model's size)."""


@dataclass(frozen=True)
class Screening:
    """Eigenvalues and sensitivities of every candidate.

    Attributes
    ----------
    coordinates, masses : (N,) the candidates, in the order given.
    modes : elastic mode numbers (1-based).
    eigenvalues : (N, modes) eigenvalues with the mass added, (rad/s)^2.
    J : (N, modes, parameters) d lambda / d s of the updated parameters, physical units.
    names : the updated parameters.
    certified : (N,) True where the Rayleigh-Ritz certificate held (False: solved by
        Lanczos, or the model is small enough for the dense solver).
    bound : (N,) certified bound on the relative eigenvalue error (NaN if not certified).
    base_eigenvalues : (modes,) of the bare structure; base_J : (modes, parameters).
    """

    coordinates: np.ndarray
    masses: np.ndarray
    modes: list[int]
    eigenvalues: np.ndarray
    J: np.ndarray
    names: list[str]
    certified: np.ndarray
    bound: np.ndarray
    base_eigenvalues: np.ndarray
    base_J: np.ndarray


def screen(
    model: ParametricModel,
    candidates: Sequence[tuple[int, float]],
    modes: Sequence[int],
    values: Sequence[float] | None = None,
) -> Screening:
    """Eigenvalues and d lambda / d s of each single-mass candidate (coordinate, mass).

    Parameters
    ----------
    model : the model; ``values`` its parameter values (default: the model's).
    candidates : (user coordinate, added mass) pairs; a rotational coordinate takes a
        rotary inertia (kg m^2).
    modes : elastic mode numbers.

    Examples
    --------
    A 2 kg mass on a 800 N/m spring; candidates add 2 kg or 6 kg at coordinate 1:
    lambda = 800 / (2 + m), d lambda / dk = 1 / (2 + m), d lambda / dm = -k / (2 + m)^2.

    >>> from eigenupdate.model.parameters import Parameter
    >>> from eigenupdate.model.spring_mass import Mass, Spring, spring_mass_model
    >>> model = spring_mass_model([Mass(Parameter("m", 2.0), 1)],
    ...                           [Spring(Parameter("k", 800.0), (0, 1))])
    >>> s = screen(model, [(1, 2.0), (1, 6.0)], [1])
    >>> s.eigenvalues.round(9).tolist(), s.J[:, 0, :].round(9).tolist()
    ([[200.0], [100.0]], [[-50.0, 0.25], [-12.5, 0.125]])
    """
    modes, upd = modes_and_updated(model, modes, "modes")
    if len(candidates) == 0:
        raise InputError("no candidate to screen", field="candidates")
    coords = np.array([int(c) for c, _ in candidates])
    masses = np.array([float(m) for _, m in candidates])
    configs = []
    for i, (c, m) in enumerate(zip(coords, masses, strict=True)):
        try:
            configs.append(Configuration(f"candidate {i + 1}", (Addition(int(c), mass=m),)))
        except (InputError, NumericalError) as exc:
            raise type(exc)(str(exc), field=f"candidate {i + 1} ({c}, {m:g})") from None
    terms = RestrictedTerms([model.k_terms[j] for j in upd], [model.m_terms[j] for j in upd])
    idx = np.asarray(modes) - 1
    n_modes = modes[-1]
    K, M = model.stiffness(values), model.mass(values)
    lam = np.empty((len(configs), idx.size))
    J = np.empty((len(configs), idx.size, upd.size))
    bound = np.full(len(configs), np.nan)

    def derivatives(sol, name):
        check_distinct(sol, modes, name)
        return sol.eigenvalues[idx], terms.derivatives(sol.modes[:, idx], sol.eigenvalues[idx])

    if model.n <= DENSE_LIMIT:
        sols = solve_configurations(model, [Configuration("base"), *configs], n_modes, values,
                                    dense=True)
        base_lam, base_J = derivatives(sols[0], "the bare structure")
        for i, (c, sol) in enumerate(zip(configs, sols[1:], strict=True)):
            lam[i], J[i] = derivatives(sol, c.name)
        return Screening(coords, masses, modes, lam, J, [model.names[j] for j in upd],
                         np.isfinite(bound), bound, base_lam, base_J)
    try:
        base_op, base_sol = base_operator(K, M, n_modes)
    except (InputError, NumericalError) as exc:
        raise type(exc)(str(exc), field="the bare structure") from None
    base_lam, base_J = derivatives(base_sol, "the bare structure")
    base = perturbed.make_base(K, M, base_op, *base_sol.computed)
    projected = ProjectedTerms(terms, base.phi)
    rows = np.empty(len(configs), dtype=int)
    for i, c in enumerate(configs):
        rows[i] = c.rows(model)[0]
    unique = np.unique(rows)
    for start in range(0, unique.size, CHUNK):
        chunk = unique[start:start + CHUNK]
        fams = perturbed.families(base, [(int(r),) for r in chunk])
        for r in chunk:
            members = np.flatnonzero(rows == r)
            done: dict[int, tuple] = {}  # id(subspace) -> (subspace, [(i, coefficients)])
            for i in members:
                res, sub = fams[(int(r),)].solve(np.array([r]), [0.0], [masses[i]], n_modes,
                                                 vectors=False)
                if res is not None and res.passed:
                    check_distinct(res.solution, modes, configs[i].name)
                    lam[i] = res.solution.eigenvalues[idx]
                    bound[i] = float(np.max(res.eig_bound))
                    done.setdefault(id(sub), (sub, []))[1].append((i, res.coefficients[:, idx]))
                else:  # Lanczos on the base factorisation
                    sol = solve_one(model, K, M, configs[i], n_modes, base_op, base_sol.n_rigid)
                    lam[i], J[i] = derivatives(sol, configs[i].name)
            for sub, items in done.values():
                ids = [i for i, _ in items]
                d = projected.derivatives(sub.Q, np.hstack([c for _, c in items]),
                                          lam[ids].ravel())
                J[ids] = d.reshape(len(ids), idx.size, -1)
    return Screening(coords, masses, modes, lam, J, [model.names[j] for j in upd],
                     np.isfinite(bound), bound, base_lam, base_J)
