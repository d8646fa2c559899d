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
from dataclasses import dataclass, replace

import numpy as np

from eigenupdate.errors import InputError, NumericalError
from eigenupdate.model.configurations import Addition, Configuration
from eigenupdate.model.parametric import ParametricModel
from eigenupdate.solve import krylov, perturbed
from eigenupdate.solve.eigen import DENSE_LIMIT, base_operator
from eigenupdate.solve.jacobian import modes_and_updated, solve_configurations, solve_one
from eigenupdate.solve.restricted import ProjectedTerms, RestrictedTerms
from eigenupdate.solve.sensitivity import check_distinct

CHUNK = 20
"""Row sets whose subspaces are built together (bounds the memory: each holds
(levels + 1) vectors of the model's size per row)."""


@dataclass(frozen=True)
class Screening:
    """Eigenvalues and sensitivities of every candidate.

    Attributes
    ----------
    coordinates, masses : (N,) the candidates, in the order given (single-mass
        candidates of :func:`screen`; empty from :func:`screen_configurations`).
    modes : elastic mode numbers (1-based).
    eigenvalues : (N, modes) eigenvalues with the mass added, (rad/s)^2.
    J : (N, modes, parameters) d lambda / d s of the updated parameters, physical units.
    names : the updated parameters.
    certified : (N,) True where the Rayleigh-Ritz certificate held (False: solved by
        Lanczos, or the model is small enough for the dense solver).
    bound : (N,) certified bound on the relative eigenvalue error (NaN if not certified).
    base_eigenvalues : (modes,) of the bare structure; base_J : (modes, parameters).
    all_eigenvalues : (N, max(modes)) elastic eigenvalues of modes 1..max(modes);
        base_all_eigenvalues likewise for the bare structure.
    next_eigenvalues : (N,) the next elastic eigenvalue above them (NaN: none computed);
        base_next_eigenvalue likewise.
    order_kept : (N,) every used mode correlates best (mass-weighted MAC) with the bare
        structure's mode of the same number, so pairing modes by order stays valid.
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
    all_eigenvalues: np.ndarray
    base_all_eigenvalues: np.ndarray
    next_eigenvalues: np.ndarray
    base_next_eigenvalue: float
    order_kept: np.ndarray


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
    return replace(screen_configurations(model, configs, modes, values),
                   coordinates=coords, masses=masses)


def screen_configurations(
    model: ParametricModel,
    configurations: Sequence[Configuration],
    modes: Sequence[int],
    values: Sequence[float] | None = None,
) -> Screening:
    """:class:`Screening` of any perturbed configurations (masses, rotary inertias,
    grounded springs, several at once): the one screening engine of the planner.

    On the sparse path the configurations perturbing the same rows share one Krylov
    subspace (built CHUNK row sets at a time), solved without forming their modes; mode
    order comes from the Ritz coefficients on the bare modes, which are the mass-weighted
    correlations with them. Configurations of more than MAX_ROWS rows, or failing the
    certificate, are solved by Lanczos on the base factorisation.
    """
    modes, upd = modes_and_updated(model, modes, "modes")
    model = model.at(values)  # a nonlinear model's K_j, M_j at the values
    configs = list(configurations)
    terms = RestrictedTerms([model.k_terms[j] for j in upd], [model.m_terms[j] for j in upd])
    idx = np.asarray(modes) - 1
    n_modes = modes[-1]
    K, M = model.stiffness(values), model.mass(values)
    N = len(configs)
    lam = np.empty((N, idx.size))
    lam_all = np.empty((N, n_modes))
    nxt = np.full(N, np.nan)
    kept = np.ones(N, bool)
    J = np.empty((N, idx.size, upd.size))
    bound = np.full(N, np.nan)
    names = [model.names[j] for j in upd]

    def derivatives(sol, name):
        check_distinct(sol, modes, name)
        return sol.eigenvalues[idx], terms.derivatives(sol.modes[:, idx], sol.eigenvalues[idx])

    def by_mac(base_modes, sol) -> bool:
        x = base_modes.T @ (M @ sol.modes)
        return all(int(np.argmax(x[:, k - 1] ** 2)) == k - 1 for k in modes)

    def fill(i, sol, base_modes):
        lam[i], J[i] = derivatives(sol, configs[i].name)
        lam_all[i] = sol.eigenvalues[:n_modes]
        nxt[i] = np.nan if sol.next_eigenvalue is None else sol.next_eigenvalue
        kept[i] = by_mac(base_modes, sol)

    def result(base_sol, base_lam, base_J) -> Screening:
        empty = np.zeros(0)
        return Screening(empty, empty, modes, lam, J, names, np.isfinite(bound), bound,
                         base_lam, base_J, lam_all, base_sol.eigenvalues[:n_modes].copy(), nxt,
                         np.nan if base_sol.next_eigenvalue is None
                         else float(base_sol.next_eigenvalue), kept)

    if model.n <= DENSE_LIMIT:
        sols = solve_configurations(model, [Configuration("base"), *configs], n_modes, values,
                                    dense=True)
        base_lam, base_J = derivatives(sols[0], "the bare structure")
        for i, sol in enumerate(sols[1:]):
            fill(i, sol, sols[0].modes)
        return result(sols[0], base_lam, base_J)
    try:
        base_op, base_sol = base_operator(K, M, n_modes)
    except (InputError, NumericalError) as exc:
        raise type(exc)(str(exc), field="the bare structure") from None
    base_lam, base_J = derivatives(base_sol, "the bare structure")
    base = krylov.make_base(K, M, base_op, *base_sol.computed)
    projected = ProjectedTerms(terms, base.phi)
    elastic = base_sol.n_rigid + np.arange(n_modes)  # bare elastic modes among base.phi's
    groups: dict[tuple[int, ...], list[int]] = {}
    rows_of = {}
    for i, c in enumerate(configs):
        rows = c.rows(model)
        key = tuple(np.unique(rows).tolist())
        if not c.additions or len(key) > perturbed.MAX_ROWS:
            sol = solve_one(model, K, M, c, n_modes, base_op, base_sol.n_rigid)
            fill(i, sol, base_sol.modes)
            continue
        rows_of[i] = rows
        groups.setdefault(key, []).append(i)
    keys = list(groups)
    for start in range(0, len(keys), CHUNK):
        chunk = keys[start:start + CHUNK]
        fams = perturbed.families(base, chunk)
        for key in chunk:
            done: dict[int, tuple] = {}  # id(subspace) -> (subspace, [(i, coefficients)])
            for i in groups[key]:
                c = configs[i]
                res, sub = fams[key].solve(rows_of[i], [a.stiffness for a in c.additions],
                                           [a.mass for a in c.additions], n_modes,
                                           vectors=False)
                if res is not None and res.passed:
                    check_distinct(res.solution, modes, c.name)
                    lam[i] = res.solution.eigenvalues[idx]
                    lam_all[i] = res.solution.eigenvalues[:n_modes]
                    nxt[i] = (np.nan if res.solution.next_eigenvalue is None
                              else res.solution.next_eigenvalue)
                    on_bare = res.coefficients[elastic]  # phi_j^T M x_k
                    kept[i] = all(int(np.argmax(on_bare[:, k - 1] ** 2)) == k - 1
                                  for k in modes)
                    bound[i] = float(np.max(res.eig_bound))
                    done.setdefault(id(sub), (sub, []))[1].append((i, res.coefficients[:, idx]))
                else:  # Lanczos on the base factorisation
                    fill(i, solve_one(model, K, M, c, n_modes, base_op, base_sol.n_rigid),
                         base_sol.modes)
            for sub, items in done.values():
                ids = [i for i, _ in items]
                d = projected.derivatives(sub.Q, np.hstack([c for _, c in items]),
                                          lam[ids].ravel())
                J[ids] = d.reshape(len(ids), idx.size, -1)
    return result(base_sol, base_lam, base_J)
