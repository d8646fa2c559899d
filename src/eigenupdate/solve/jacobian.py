"""The sensitivity matrix J of Eq. (1): d lambda / d s for the chosen modes of every
configuration, stacked configuration by configuration.

Columns are the updated parameters. ``J`` is in physical units; ``normalised`` is
J * diag(scale), the derivative with respect to s_j / s_j0 (the paper normalises every
parameter by its initial value; a zero initial value keeps scale 1).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from eigenupdate.errors import InputError, NumericalError
from eigenupdate.model.configurations import Configuration
from eigenupdate.model.dense import DenseModel, dense_model
from eigenupdate.model.parametric import ParametricModel
from eigenupdate.solve import parallel, perturbed
from eigenupdate.solve.eigen import (
    DENSE_LIMIT,
    EigenSolution,
    ShiftInvert,
    WarmStart,
    base_operator,
    massless_hint,
    negative_count,
    solve_elastic,
    sturm_check,
    usable_shift,
)
from eigenupdate.solve.perturbed import CertificateReport
from eigenupdate.solve.restricted import RestrictedTerms
from eigenupdate.solve.sensitivity import (
    check_distinct,
    eigenvalue_derivatives,
    stacked_derivatives,
)


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
    certificate : sparse path: what the perturbed-configuration fast path did
        (:class:`eigenupdate.solve.perturbed.CertificateReport`); None on the dense path.
    shapes : the used modes of each configuration, (n, modes) mass-normalised, in the
        order of ``rows`` (to track mode identities from one linearisation to the next).
    next_eigenvalues : each configuration's eigenvalue above the highest mode used,
        where the solver computed it (NaN where not).
    """

    rows: list[tuple[str, int]]
    eigenvalues: np.ndarray
    J: np.ndarray
    scale: np.ndarray
    names: list[str]
    certificate: CertificateReport | None = None
    shapes: tuple[np.ndarray, ...] | None = None
    next_eigenvalues: np.ndarray | None = None

    @property
    def normalised(self) -> np.ndarray:
        return self.J * self.scale


class Rejected(Exception):
    """Raised when ``reject`` (see :func:`solve_configurations`) turns a trial point down
    before every configuration is solved."""


RejectTest = Callable[[dict[str, np.ndarray]], bool]


def solve_configurations(
    model: ParametricModel,
    configurations: Sequence[Configuration],
    n_modes: int,
    values: Sequence[float] | None = None,
    dense: bool | None = None,
    report: CertificateReport | None = None,
    warm: WarmStart | None = None,
    reject: RejectTest | None = None,
) -> list[EigenSolution]:
    """Elastic eigen-solutions of every configuration at parameter ``values``.

    On the sparse path K - sigma M is factorised once for the bare structure. Perturbed
    configurations are solved by Rayleigh-Ritz in a Krylov subspace built from that
    factorisation, with a certificate (:mod:`eigenupdate.solve.perturbed`, which
    ``report`` records); one that fails it reuses the factorisation in shift-invert
    Lanczos (see :class:`eigenupdate.solve.eigen.ShiftInvert`). A ``warm`` start from
    the previous call (an update's iterations) saves Lanczos solves and lets the
    missed-mode check factorise while Lanczos runs.

    ``reject`` (sparse path) is shown the eigenvalues known so far, by configuration
    name: the bare structure's, then those the fast path certified; if it returns True,
    :class:`Rejected` is raised before the rest are solved by Lanczos. A line search
    uses it to turn down a trial point whose objective already exceeds the current one
    (a step far outside the linearisation can leave many configurations to Lanczos).
    """
    sparse = not (dense if dense is not None else model.n <= DENSE_LIMIT)
    fast = None if sparse else dense_model(model)
    if fast is not None:
        s = model.values if values is None else np.asarray(values, dtype=float)
        K, M = fast.stiffness(s), fast.mass(s)
        return [solve_dense(model, fast, K, M, c, n_modes) for c in configurations]
    K, M = model.stiffness(values), model.mass(values)
    if not sparse:
        return [solve_one(model, K, M, c, n_modes, None, None) for c in configurations]
    def located(exc):
        return type(exc)(f"{exc}{massless_hint(K, M, model.coordinates)}",
                         field="the bare structure")

    # the missed-mode check factorises K - sigma M once more, in a thread: warm, at the
    # previous shift while Lanczos runs; cold, while the perturbed configurations are
    # solved (their numbers are only returned if the check passes)
    early = None  # without threads nothing would overlap it: a possibly wasted factorisation
    if warm is not None and warm.sturm_shift is not None and parallel.threads() > 1:
        early = (warm.sturm_shift,
                 parallel.in_background(negative_count, K - warm.sturm_shift * M))
    try:
        base_op, base_sol = base_operator(K, M, n_modes, check=False, warm=warm)
    except (InputError, NumericalError) as exc:
        raise located(exc) from None
    lam = base_sol.computed[0]
    counted = None
    if early is not None and usable_shift(early[0], lam, base_sol):
        counted = (early[0], early[1].result())
    check = parallel.in_background(sturm_check, K, M, lam, base_sol, base_op, counted)
    try:
        out = solve_on_base(model, K, M, base_op, base_sol, configurations, n_modes, report,
                            reject)
    finally:
        try:
            check.result()
        except (InputError, NumericalError) as exc:
            raise located(exc) from None
    return out


def solve_on_base(
    model: ParametricModel,
    K,
    M,
    base_op: ShiftInvert,
    base_sol: EigenSolution,
    configurations: Sequence[Configuration],
    n_modes: int,
    report: CertificateReport | None = None,
    reject: RejectTest | None = None,
) -> list[EigenSolution]:
    """The sparse path of :func:`solve_configurations` once the bare structure is solved
    (``base_sol`` from ``base_operator(K, M, n_modes)``)."""
    bare = {c.name: base_sol.eigenvalues for c in configurations if not c.additions}
    if reject is not None and bare and reject(bare):
        raise Rejected("the bare structure's eigenvalues")
    fast = perturbed.solve_perturbed(model, K, M, base_op, base_sol, configurations,
                                     n_modes, report)
    if reject is not None and any(r is None for c, r in zip(configurations, fast, strict=True)
                                  if c.additions):
        known = {**bare, **{c.name: r.eigenvalues
                            for c, r in zip(configurations, fast, strict=True) if r is not None}}
        if reject(known):
            raise Rejected("the eigenvalues certified before the Lanczos fallbacks")
    out = []
    for c, ritz in zip(configurations, fast, strict=True):
        if not c.additions:
            out.append(base_sol)
        elif ritz is not None:
            out.append(ritz)
        else:
            out.append(solve_one(model, K, M, c, n_modes, base_op, base_sol.n_rigid))
    return out


def solve_one(model, K, M, c: Configuration, n_modes: int, base_op, n_rigid):
    """One configuration by Lanczos reusing the base factorisation (Woodbury), or dense."""
    try:
        dk, dm = c.delta(model)
        op = None
        if base_op is not None:
            op = base_op.updated(
                c.rows(model), [a.stiffness for a in c.additions], [a.mass for a in c.additions]
            )
        # added masses and grounded springs never create rigid-body modes
        return solve_elastic(K + dk, M + dm, n_modes, operator=op, dense=base_op is None,
                             n_rigid=n_rigid)
    except (InputError, NumericalError) as exc:
        raise type(exc)(f"{exc}{massless_hint(K, M, model.coordinates)}",
                        field=f"configuration {c.name!r}") from None


def solve_dense(model, fast: DenseModel, K: np.ndarray, M: np.ndarray, c: Configuration,
                n_modes: int) -> EigenSolution:
    """One configuration, dense, from the dense K and M of the bare structure."""
    try:
        return solve_elastic(*fast.added(K, M, c, model), n_modes, dense=True)
    except (InputError, NumericalError) as exc:
        raise type(exc)(f"{exc}{massless_hint(K, M, model.coordinates)}",
                        field=f"configuration {c.name!r}") from None


def modes_and_updated(
    model: ParametricModel, modes: Sequence[int], field: str = "measurement.modes"
) -> tuple[list[int], np.ndarray]:
    """Sorted distinct elastic mode numbers and the updated parameters' indices, or
    InputError."""
    modes = sorted(set(int(k) for k in modes))
    if not modes or modes[0] < 1:
        raise InputError("modes must be elastic mode numbers >= 1", field=field)
    upd = model.updated
    if upd.size == 0:
        raise InputError("no parameter is updated (every parameter has update = false)")
    return modes, upd


def linearise(
    model: ParametricModel,
    configurations: Sequence[Configuration],
    modes: Sequence[int],
    values: Sequence[float] | None = None,
    dense: bool | None = None,
    warm: WarmStart | None = None,
    reject: RejectTest | None = None,
) -> Linearisation | None:
    """Eigenvalues and the sensitivity matrix J at ``values`` (default: the model's);
    ``warm``, ``reject``: see :func:`solve_configurations`; None if ``reject`` turned
    the point down.

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
    modes, upd = modes_and_updated(model, modes)
    scale = np.array([model.parameters[j].scale for j in upd])  # initial values, not current
    sparse = not (dense if dense is not None else model.n <= DENSE_LIMIT)
    fast = None if sparse else dense_model(model)
    stacks = None if fast is None else fast.stacks(upd)
    if fast is not None:
        kt, mt = fast.derivatives(model.values if values is None else
                                  np.asarray(values, dtype=float), upd)
    else:
        model = model.at(values)  # a nonlinear model's K_j, M_j at the values
        kt = [model.k_terms[j] for j in upd]
        mt = [model.m_terms[j] for j in upd]
    report = CertificateReport() if sparse else None
    # the restricted parameter matrices do not depend on the solution: made meanwhile
    terms = parallel.in_background(RestrictedTerms, kt, mt) if sparse else None
    try:
        sols = solve_configurations(model, configurations, modes[-1], values, dense, report,
                                    warm, reject)
    except Rejected:
        return None
    idx = np.asarray(modes) - 1
    rows, lam, blocks = [], [], []
    phi = tuple(s.modes if s.modes.shape[1] == idx.size else s.modes[:, idx] for s in sols)
    for c, sol in zip(configurations, sols, strict=True):
        if sparse:
            check_distinct(sol, modes, f"configuration {c.name!r}")
        elif stacks is not None:
            blocks.append(stacked_derivatives(sol, modes, *stacks,
                                              f"configuration {c.name!r}"))
        else:
            blocks.append(eigenvalue_derivatives(sol, modes, kt, mt,
                                                 f"configuration {c.name!r}"))
        lam.extend(sol.eigenvalues[idx])
        rows.extend((c.name, k) for k in modes)
    if sparse:  # all configurations' modes in one product per parameter
        blocks = [terms.result().derivatives(list(phi), np.array(lam))]
    following = np.array([np.nan if s.next_eigenvalue is None else s.next_eigenvalue
                          for s in sols])
    return Linearisation(rows, np.array(lam), np.vstack(blocks), scale,
                         [model.names[j] for j in upd], report, phi, following)
