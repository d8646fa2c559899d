"""Accuracy of a test plan averaged over the prior, and the risk of a gross error.

The linearised posterior covariance at the prior mean is what a test delivers only if the
truth sits at the prior mean. It does not: over a 25 % prior on the paper's Fig. 2 system
the empirical spread of Monte Carlo estimates was 1.06-1.42 times that figure for the
designed plan (200 trials; and up to 7.4 times for the study's 3-mode plan). Averaging
the linearised covariance over draws of the truth from the prior predicts the spread of
the estimates over repeated tests with the truth unknown (the quantity Monte Carlo
measures), tails included:

    C_prior = E_s[ C(s) ],   s ~ N(s_0, sigma_s) truncated at 0,

each C(s) the linearised posterior covariance of :mod:`eigenupdate.design.covariance` at
the truth s with the stated frequency noise. Its Monte Carlo error is reported with it.

A draw of the truth can also make an added mass reorder the used modes (measured mode k
of the perturbed structure is then not the bare structure's mode k), or bring a used mode
of the bare or a perturbed structure closer than ``min_relative_gap`` to a neighbour
(the test numbers such modes ambiguously). Such draws are counted as risks of a gross
error; a candidate that risks one in more than ``max_exchange_risk`` of the draws is not
admissible. A reordering of the bare structure's mode shapes relative to the initial
model is not counted: the update pairs frequencies by order and fits frequencies only
(on the Fig. 2 system 17 % of the draws of a 25 % prior reorder shapes that way, and the
Monte Carlo estimates still agree with the prediction). Whether the optimiser converges
from a draw is not predicted here: ``design --validate`` measures it.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from eigenupdate.design.criteria import criterion_value
from eigenupdate.design.search import PlanScorer
from eigenupdate.identify.checked import draw_values, has_prior  # noqa: F401 (re-exported)
from eigenupdate.model.configurations import Configuration
from eigenupdate.model.parametric import ParametricModel


def min_gap(f_all: np.ndarray, used: Sequence[int]) -> float:
    """Smallest relative frequency gap of a used mode to its neighbours."""
    gaps = [min(abs(f_all[k - 1] - f_all[j]) for j in (k - 2, k) if 0 <= j < f_all.size)
            / f_all[k - 1] for k in used if f_all.size > 1]
    return float(min(gaps)) if gaps else float("inf")


@dataclass(frozen=True)
class Draw:
    """One draw of the truth: its values, the scorer of every candidate at it, and the
    gross-error risks it shows (``bare_risk``: a used mode of the bare structure comes
    too close to another; ``risk[i]``: candidate i reorders or crowds a used mode)."""

    values: np.ndarray
    scorer: PlanScorer
    bare_risk: bool
    risk: np.ndarray


@dataclass
class PriorScorer:
    """Plan criterion on the covariance averaged over draws of the truth; the same
    interface as :class:`~eigenupdate.design.search.PlanScorer`, so the greedy, exchange
    and exhaustive searches use it unchanged.

    A plan whose test ends in a gross error (a used mode reordered or crowded, so the
    measured modes may be paired wrongly) in a fraction r of the draws delivers its
    accuracy only in the other 1 - r: 1 / (1 - r) tests are needed on average for one
    that can be used. The criterion is divided by 1 - r (:meth:`risk_factor`), so of two
    plans equally accurate the one with the smaller risk wins, and a plan at risk in
    every draw scores ``inf``."""

    draws: Sequence[Draw]
    criterion: str | Sequence[str]
    names: Sequence[str]
    penalise_risk: bool = True

    def __post_init__(self) -> None:
        self._risk = np.array([d.risk for d in self.draws], dtype=bool)
        self._bare = np.array([d.bare_risk for d in self.draws], dtype=bool)

    @property
    def prior(self) -> np.ndarray:
        return self.draws[0].scorer.prior

    @property
    def evaluations(self) -> int:
        """Covariances per plan score (one per draw)."""
        return len(self.draws)

    def covariance(self, plan: Sequence[int], ridge: bool = False) -> np.ndarray:
        """Mean over the draws of the posterior covariance (normalised parameters)."""
        covs = [d.scorer.covariance(plan, d.scorer._ridge if ridge else 0.0)
                for d in self.draws]
        return np.mean(covs, axis=0)

    def variances(self, plan: Sequence[int]) -> np.ndarray:
        """(draws, p) diagonal of each draw's covariance."""
        return np.array([np.diag(d.scorer.covariance(plan)) for d in self.draws])

    def risk_factor(self, plan: Sequence[int]) -> float:
        """1 / (1 - gross risk of ``plan``): the criterion's multiplier (1 when
        ``penalise_risk`` is off)."""
        if not self.penalise_risk:
            return 1.0
        r = self.gross_risk(plan)
        return np.inf if r >= 1.0 else 1.0 / (1.0 - r)

    def score(self, plan: Sequence[int]) -> float:
        crit = criterion_value(self.covariance(plan), self.criterion, self.names)
        return crit * self.risk_factor(plan)

    def key(self, plan: Sequence[int]) -> tuple[float, float]:
        reg = criterion_value(self.covariance(plan, ridge=True), self.criterion, self.names)
        f = self.risk_factor(plan)
        return self.score(plan), reg * f

    def keys_adding(self, plan: Sequence[int], candidates: Sequence[int]
                    ) -> list[tuple[float, float]]:
        """:meth:`key` of ``plan`` plus each candidate: the A and named-parameter criteria
        are linear in the covariance, so the draws' low-rank updates average."""
        if self.criterion not in ("D", "E"):
            terms = [d.scorer.variance_terms(plan, candidates) for d in self.draws]
            if all(t is not None for t in terms):
                v = self.draws[0].scorer._criterion_of_variances(np.mean(terms, axis=0))
                f = [self.risk_factor([*plan, c]) for c in candidates]
                return [(x * g, x * g) for x, g in zip(v.tolist(), f, strict=True)]
        return [self.key([*plan, c]) for c in candidates]

    def gross_risk(self, plan: Sequence[int]) -> float:
        """Fraction of the draws in which the bare structure or a configuration of the plan
        reorders a used mode or brings it too close to another."""
        idx = list(plan)
        return float(np.mean(self._bare | self._risk[:, idx].any(axis=1)))


@dataclass(frozen=True)
class PriorPrediction:
    """What a plan delivers over the prior.

    Attributes
    ----------
    std : sqrt of the prior-averaged posterior variance, physical units.
    std_error : Monte Carlo standard error of ``std`` from the finite number of draws.
    gross_risk : fraction of draws risking a gross error (see the module docstring).
    draws : number of draws.
    seconds : what the draws cost (screening the candidates at every draw).
    """

    std: np.ndarray
    std_error: np.ndarray
    gross_risk: float
    draws: int
    seconds: float


def predict(scorer: PriorScorer, plan: Sequence[int], scale: np.ndarray,
            seconds: float) -> PriorPrediction:
    """:class:`PriorPrediction` of ``plan`` (indices of the scorer's candidates)."""
    var = scorer.variances(plan)
    n = var.shape[0]
    mean = var.mean(axis=0)
    std = np.sqrt(mean)
    # delta method: se(sqrt(mean)) = se(mean) / (2 sqrt(mean))
    se = var.std(axis=0, ddof=1) / np.sqrt(n) / (2 * std) if n > 1 else np.full_like(std,
                                                                                    np.inf)
    return PriorPrediction(std * scale, se * scale, scorer.gross_risk(plan), n, seconds)


def screen_draws(model: ParametricModel, candidates: Sequence[Configuration],
                 modes: Sequence[int], n_draws: int, seed: int, make_scorer,
                 screen, min_relative_gap: float) -> tuple[list[Draw], float]:
    """Screen ``candidates`` at ``n_draws`` draws of the truth.

    ``make_scorer(bare, screened)`` builds the draw's PlanScorer from its screenings and
    ``screen(model, candidates, modes)`` screens (the planner's engine). Returns the draws
    and the wall time they took.
    """
    t0 = time.perf_counter()
    rng = np.random.default_rng(seed)
    draws = []
    for _ in range(n_draws):
        values = draw_values(model, rng)
        bare, screened = screen(model.with_values(values), candidates, modes)
        bare_risk = min_gap(_with_next(bare), modes) < min_relative_gap
        risk = np.array([not s.order_kept or min_gap(_with_next(s), modes) < min_relative_gap
                         for s in screened])
        draws.append(Draw(values, make_scorer(bare, screened), bool(bare_risk), risk))
    return draws, time.perf_counter() - t0


def _with_next(s) -> np.ndarray:
    f = s.frequencies_hz
    if s.next_eigenvalue is not None:
        f = np.append(f, np.sqrt(max(s.next_eigenvalue, 0.0)) / (2 * np.pi))
    return f


def linear_variances(model: ParametricModel, configurations: Sequence[Configuration],
                     modes: Sequence[int], std_hz: dict[tuple[str, int], float], method: str,
                     truths: Sequence[np.ndarray]) -> np.ndarray:
    """(len(truths), p) diagonal of the linearised posterior covariance (physical units)
    of the plan at each truth (all parameter values), with a fixed noise std (Hz) per
    (configuration, mode) row."""
    return np.array([_linear_at(model, configurations, modes, std_hz, method, v)[0]
                     for v in truths]).reshape(len(truths), model.updated.size)


def _linear_at(model, configurations, modes, std_hz, method, values):
    from eigenupdate.design.covariance import posterior_covariance
    from eigenupdate.identify.weights import prior_weights
    from eigenupdate.measure.measurement import eigenvalue_std
    from eigenupdate.solve.jacobian import linearise

    prior = prior_weights(model) if method == "bayesian" else np.zeros(model.updated.size)
    lin = linearise(model, configurations, modes, values)
    f = np.sqrt(np.maximum(lin.eigenvalues, 0.0)) / (2 * np.pi)
    w = 1.0 / eigenvalue_std(f, np.array([std_hz[r] for r in lin.rows]))
    var = np.diag(posterior_covariance(lin.normalised, w, prior, method)) * lin.scale**2
    return var, f.reshape(len(configurations), -1)


def predict_plan(model: ParametricModel, configurations: Sequence[Configuration],
                 modes: Sequence[int], std_hz: dict[tuple[str, int], float], method: str,
                 n_draws: int = 64, seed: int = 0, min_relative_gap: float = 0.02
                 ) -> PriorPrediction:
    """:class:`PriorPrediction` of a given plan (the bare structure first) with a fixed
    noise std (Hz) per (configuration, mode) row, as a Monte Carlo of the plan draws it.
    The gross-error risk here counts draws in which two used modes of a configuration
    come within ``min_relative_gap`` (the modes between them are not solved)."""
    t0 = time.perf_counter()
    rng = np.random.default_rng(seed)
    var, risky = [], 0
    for _ in range(n_draws):
        v, fc = _linear_at(model, configurations, modes, std_hz, method,
                           draw_values(model, rng))
        var.append(v)
        risky += any(min_gap(x, range(1, x.size + 1)) < min_relative_gap for x in fc)
    std, se = _root_mean(np.array(var))
    return PriorPrediction(std, se, risky / n_draws, n_draws, time.perf_counter() - t0)


def _root_mean(var: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """sqrt of the mean of the rows of ``var`` and its standard error (delta method:
    se(sqrt(mean)) = se(mean) / (2 sqrt(mean)))."""
    n = var.shape[0]
    std = np.sqrt(var.mean(axis=0))
    if n < 2:
        return std, np.full_like(std, np.inf)
    with np.errstate(invalid="ignore"):  # a draw the plan cannot identify: variance inf
        sd = var.std(axis=0, ddof=1)
    return std, np.where(np.isfinite(std), sd / np.sqrt(n) / (2 * std), np.inf)
