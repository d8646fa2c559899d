"""Identifiability of the updated parameters (paper Section 3, Tables 1-3), from one SVD.

The estimator of :mod:`eigenupdate.identify.updating` solves, in parameters normalised by
their initial values, the stacked least-squares problem with the matrix

    A = [ W_lambda^1/2 J ]        (weighted sensitivities, one row per eigenvalue)
        [ W_s^1/2        ]        (prior rows of the Bayesian estimator, Eq. 6)

One singular value decomposition A = U S V^T gives everything the check and the
update report, so they cannot disagree:

* the rank: singular values above s_max max(rows, p) eps (NumPy's and MATLAB's default
  tolerance on A; the deficient plans of the paper's Table 1 have s_min / s_max ~ 1e-17);
* the condition numbers of A and of A^T A (the square of the first);
* the worst-determined parameter combination: the last right singular vector;
* the covariance (A^T A)^-1 = V S^-2 V^T, without forming or inverting the normal
  equations, whose condition number is the square of A's.

Without weights and priors A is the plan's normalised J, which needs no measurements.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from eigenupdate.model.configurations import Configuration
from eigenupdate.model.parametric import ParametricModel
from eigenupdate.schema import finite_or_none, reader
from eigenupdate.solve.jacobian import linearise


@dataclass(frozen=True)
class IdentifiabilityReport:
    """Rank and condition of the (weighted, prior-augmented, normalised) sensitivity matrix.

    Attributes
    ----------
    parameters : names of the updated parameters (columns of J).
    equations : number of eigenvalues used (rows of J, without the prior rows).
    rank : rank of A with NumPy's default tolerance (as MATLAB's ``rank``).
    condition_J, condition_JTJ : condition numbers of A and A^T A (inf if singular).
    singular_values : singular values of A, descending.
    weakest : the right singular vector of the smallest singular value, by parameter: the
        parameter combination the plan determines worst (largest weight first, sign
        chosen so that the largest weight is positive).
    weighting : ``"none"``, ``"measurement std"`` or ``"measurement std and prior std"``
        (the rows A holds besides J).
    cov : (A^T A)^-1 in normalised parameters, None when the rank is deficient.
    """

    parameters: list[str]
    equations: int
    rank: int
    condition_J: float
    condition_JTJ: float
    singular_values: list[float]
    weakest: dict[str, float]
    weighting: str = "none"
    cov: np.ndarray | None = field(default=None, repr=False, compare=False)

    @property
    def identifiable(self) -> bool:
        return self.rank == len(self.parameters)

    SCHEMA = "eigenupdate.check/1"

    def to_dict(self) -> dict:
        """JSON-ready document (``eigenupdate check --json``); an infinite condition
        (a singular J) is null."""
        return {
            "schema": self.SCHEMA,
            "parameters": self.parameters,
            "equations": self.equations,
            "rank": self.rank,
            "identifiable": self.identifiable,
            "condition_J": finite_or_none(self.condition_J),
            "condition_JTJ": finite_or_none(self.condition_JTJ),
            "singular_values": self.singular_values,
            "weakest": self.weakest,
            "weighting": self.weighting,
        }

    @classmethod
    def from_dict(cls, doc: dict, source: str | None = None) -> IdentifiabilityReport:
        """The report :meth:`to_dict` wrote (without ``cov``, which it does not write)."""
        r = reader(doc, cls.SCHEMA, source)
        names = [str(n) for n in r.raw("parameters", list)]
        cond = [r.number(k, optional=True, minimum=1.0) for k in ("condition_J", "condition_JTJ")]
        weakest = r.mapping("weakest", lambda w, k: w.number(k))
        if set(weakest) - set(names):
            raise r.fail("weakest", "names parameters not in 'parameters'")
        return cls(names, r.int("equations"), r.int("rank"),
                   *[np.inf if c is None else c for c in cond],
                   r.array("singular_values").tolist(), weakest, r.str("weighting"))


def identifiability(
    J: np.ndarray,
    names: Sequence[str],
    weights: np.ndarray | None = None,
    prior: np.ndarray | None = None,
) -> IdentifiabilityReport:
    """Identifiability from one SVD of A = [diag(weights) J; diag(prior)].

    Parameters
    ----------
    J : (equations, parameters) sensitivities in normalised parameters.
    names : parameter names (columns).
    weights : sqrt of W_lambda per equation (1 / sigma_lambda); None for unit weights.
    prior : sqrt of W_s per parameter in normalised units (0 for no prior); None for none.

    Examples
    --------
    Two equations, one twice as sensitive to s2 as to s1, the other the same:

    >>> r = identifiability(np.array([[1.0, 2.0], [1.0, 2.0]]), ["s1", "s2"])
    >>> r.rank, r.identifiable, [round(v, 4) for v in r.weakest.values()]
    (1, False, [0.8944, -0.4472])

    A prior on s1 makes the pair determined:

    >>> r = identifiability(np.array([[1.0, 2.0], [1.0, 2.0]]), ["s1", "s2"],
    ...                     prior=np.array([1.0, 0.0]))
    >>> r.rank, r.weighting, np.round(r.cov, 6).tolist()
    (2, 'prior std', [[1.0, -0.5], [-0.5, 0.375]])
    """
    J = np.asarray(J, dtype=float)
    m, p = J.shape
    A = J if weights is None else np.asarray(weights, dtype=float)[:, None] * J
    has_prior = prior is not None and np.any(prior)
    if has_prior:
        A = np.vstack([A, np.diag(np.asarray(prior, dtype=float))])
    # full V when there are fewer rows than parameters: its last row spans the null space
    _, s, vt = np.linalg.svd(A, full_matrices=A.shape[0] < p)
    # numpy.linalg.matrix_rank(A): the estimator solves with A, not with A^T A, so a
    # condition up to ~1/eps is usable (a tolerance on A^T A would refuse good plans
    # whose measured std span a few decades)
    tol = (s[0] if s.size else 0.0) * max(A.shape) * np.finfo(float).eps
    rank = int(np.count_nonzero(s > tol))
    v = vt[-1]
    v = v * np.sign(v[np.argmax(np.abs(v))])
    order = np.argsort(-np.abs(v), kind="stable")
    cond = _condition(s, p)
    cov = (vt.T / s**2) @ vt if rank == p else None
    weighting = " and ".join(
        w for w, on in (("measurement std", weights is not None), ("prior std", has_prior)) if on
    ) or "none"
    return IdentifiabilityReport(
        parameters=list(names),
        equations=m,
        rank=rank,
        condition_J=cond,
        condition_JTJ=cond**2,
        singular_values=s.tolist(),
        weakest={names[i]: float(v[i]) for i in order},
        weighting=weighting,
        cov=cov,
    )


def check(
    model: ParametricModel,
    configurations: Sequence[Configuration],
    modes: Sequence[int],
    values: Sequence[float] | None = None,
    *,
    weights: np.ndarray | None = None,
    prior: np.ndarray | None = None,
) -> IdentifiabilityReport:
    """Identifiability of the updated parameters of ``model`` from this test plan.

    Without ``weights`` and ``prior`` it is the plan's own J (the paper's Tables 1-3);
    with those of an estimator (:func:`eigenupdate.identify.weights.estimator_weights`)
    it is what :func:`eigenupdate.identify.updating.update` sees.

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
    return identifiability(lin.normalised, lin.names, weights, prior)


def _condition(sv: np.ndarray, p: int) -> float:
    # Fewer equations than parameters: the missing singular values are zero.
    if sv.size < p or sv[-1] == 0:
        return float("inf")
    return float(sv[0] / sv[-1])
