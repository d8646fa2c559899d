"""The test planner behind ``eigenupdate design``: candidates, constraints, search, and the
predicted accuracy of the designed plan, of the study's own plan and of every candidate.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence
from dataclasses import asdict, dataclass, replace
from functools import partial
from typing import ClassVar

import numpy as np

from eigenupdate.budget import require
from eigenupdate.design.covariance import posterior_covariance
from eigenupdate.design.criteria import criterion_value
from eigenupdate.design.prior import PriorScorer, has_prior, predict, screen_draws
from eigenupdate.design.screen import Screened, screen_candidates, screen_on
from eigenupdate.design.search import PlanScorer, exhaustive, greedy_exchange
from eigenupdate.design.spec import DesignSpec
from eigenupdate.errors import InputError
from eigenupdate.identify.weights import prior_weights
from eigenupdate.measure.measurement import eigenvalue_std
from eigenupdate.model.configurations import Addition, Configuration
from eigenupdate.model.parametric import ParametricModel
from eigenupdate.schema import finite_or_none, reader
from eigenupdate.solve.jacobian import solve_configurations


@dataclass(frozen=True)
class CandidateReport:
    """One candidate configuration and the constraints it meets.

    Attributes
    ----------
    configuration : the candidate.
    shifts_hz : bare minus perturbed frequency of each used mode.
    shift_in_std : largest shift over the used modes, in measurement std.
    relative_gap : smallest relative frequency gap of a used mode to its neighbours.
    order_kept : the used modes keep their order (mass-weighted MAC with the bare modes).
    admissible : every constraint is met.
    exchange_risk : fraction of the prior's draws in which the candidate reorders a used
        mode or brings it within min_relative_gap of another (None: not drawn).
    """

    configuration: Configuration
    shifts_hz: list[float]
    shift_in_std: float
    relative_gap: float
    order_kept: bool
    admissible: bool
    exchange_risk: float | None = None


@dataclass(frozen=True)
class PlanSummary:
    """Predicted accuracy of one plan (the bare structure is always part of it).

    Attributes
    ----------
    std : the accuracy the plan is predicted to deliver: averaged over the prior's draws
        (:mod:`eigenupdate.design.prior`) where they were made, else ``linear_std``.
    linear_std : linearised posterior std at the prior mean.
    std_error : Monte Carlo standard error of ``std`` (0 without draws).
    gross_risk : fraction of the draws risking a gross error (None without draws).
    criterion : the criterion of the covariance ``std`` comes from; with draws divided by
        1 - ``gross_risk`` (:class:`eigenupdate.design.prior.PriorScorer`), the value the
        search minimised.
    """

    label: str
    configurations: list[str]
    criterion: float
    std: dict[str, float]
    linear_std: dict[str, float]
    std_error: dict[str, float]
    gross_risk: float | None


@dataclass(frozen=True)
class DesignResult:
    """Outcome of :func:`design_plan`.

    Attributes
    ----------
    names, modes, method, criterion : what was designed for.
    candidates : every candidate with its constraint report.
    chosen : indices into ``candidates`` of the designed plan.
    swaps : exchanges the exchange passes made after the greedy selection.
    plans : the designed plan, the exhaustive optimum (if enumerable), the study's own plan
        (if any) and every admissible candidate at once.
    draws : draws of the truth from the prior behind the criterion (0: prior mean only).
    draw_seconds : what screening the candidates at the draws cost.
    """

    names: list[str]
    modes: list[int]
    method: str
    criterion: str | tuple[str, ...]
    candidates: list[CandidateReport]
    chosen: list[int]
    swaps: int
    plans: list[PlanSummary]
    draws: int = 0
    draw_seconds: float = 0.0

    SCHEMA: ClassVar[str] = "eigenupdate.design/1"

    @property
    def configurations(self) -> list[Configuration]:
        return [self.candidates[i].configuration for i in self.chosen]

    def to_dict(self) -> dict:
        """JSON-ready document (``eigenupdate design --json``); read back by
        :meth:`from_dict`. An infinite shift or gap (no noise, one mode) is null."""
        return {
            "schema": self.SCHEMA, "names": self.names, "modes": self.modes,
            "method": self.method,
            "criterion": self.criterion if isinstance(self.criterion, str)
            else list(self.criterion),
            "candidates": [{
                "name": c.configuration.name,
                "additions": [asdict(a) for a in c.configuration.additions],
                "shifts_hz": c.shifts_hz, "shift_in_std": finite_or_none(c.shift_in_std),
                "relative_gap": finite_or_none(c.relative_gap), "order_kept": c.order_kept,
                "admissible": c.admissible, "exchange_risk": c.exchange_risk,
            } for c in self.candidates],
            "chosen": self.chosen, "swaps": self.swaps,
            "plans": [asdict(p) for p in self.plans],
            "draws": self.draws, "draw_seconds": self.draw_seconds,
        }

    @classmethod
    def from_dict(cls, doc: dict, source: str | None = None) -> DesignResult:
        """The design :meth:`to_dict` wrote; InputError naming the field otherwise."""
        r = reader(doc, cls.SCHEMA, source)
        names = [str(n) for n in r.raw("names", list)]
        crit = r.raw("criterion", (str, list))
        candidates = []
        for c in r.items("candidates"):
            try:
                adds = tuple(Addition(a.int("coordinate"), a.number("mass", minimum=0.0),
                                      a.number("stiffness", minimum=0.0))
                             for a in c.items("additions"))
            except InputError as exc:
                raise c.fail("additions", str(exc)) from None
            candidates.append(CandidateReport(
                Configuration(c.str("name"), adds), c.array("shifts_hz").tolist(),
                _inf(c.number("shift_in_std", optional=True)),
                _inf(c.number("relative_gap", optional=True)), c.bool("order_kept"),
                c.bool("admissible"), c.number("exchange_risk", optional=True)))
        chosen = [int(i) for i in r.array("chosen")]
        if any(not 0 <= i < len(candidates) for i in chosen):
            raise r.fail("chosen", "must index 'candidates'")
        plans = []
        for p in r.items("plans"):
            per = {k: p.mapping(k, lambda m, n: m.number(n)) for k in
                   ("std", "linear_std", "std_error")}
            plans.append(PlanSummary(p.str("label"), [str(x) for x in p.raw(
                "configurations", list)], p.number("criterion"), per["std"],
                per["linear_std"], per["std_error"], p.number("gross_risk", optional=True)))
        return cls(names, [int(k) for k in r.array("modes")], r.str("method"),
                   crit if isinstance(crit, str) else tuple(str(x) for x in crit),
                   candidates, chosen, r.int("swaps"), plans, r.int("draws"),
                   r.number("draw_seconds", minimum=0.0))


def _inf(v: float | None) -> float:
    return math.inf if v is None else v


def candidate_configurations(spec: DesignSpec) -> list[Configuration]:
    """Every candidate configuration: single additions and, if ``spec.additions`` > 1,
    combinations of them at distinct coordinates; ``max_added_mass`` filters.

    >>> from eigenupdate.design.spec import DesignSpec
    >>> spec = DesignSpec(coordinates=(1, 2), masses=(0.1, 0.2), configurations=1, modes=(1,),
    ...                   additions=2, max_added_mass=0.3)
    >>> [c.name for c in candidate_configurations(spec)]      # doctest: +NORMALIZE_WHITESPACE
    ['0.1 kg at 1', '0.2 kg at 1', '0.1 kg at 2', '0.2 kg at 2',
     '0.1 kg at 1 + 0.1 kg at 2', '0.1 kg at 1 + 0.2 kg at 2', '0.2 kg at 1 + 0.1 kg at 2']
    """
    n = candidate_count(spec)
    require("candidates", n, f"the [design] table asks for {n:,} candidate configurations "
            f"({len(spec.coordinates)} coordinates, {spec.values} values each, up to "
            f"{spec.additions:,} additions)", field="design")
    singles = [Addition(c, mass=m) for c in spec.coordinates for m in spec.masses]
    singles += [Addition(c, stiffness=k) for c in spec.coordinates for k in spec.stiffnesses]
    groups = [g for k in range(1, min(spec.additions, len(spec.coordinates)) + 1)
              for g in _distinct(singles, k)]
    if spec.max_added_mass is not None:
        limit = spec.max_added_mass * (1 + 1e-12)  # 0.1 + 0.2 is not above 0.3 kg
        groups = [g for g in groups if sum(a.mass for a in g) <= limit]
    labels = dict(spec.labels)
    return [Configuration(" + ".join(_label(a, labels) for a in g), g) for g in groups]


def candidate_count(spec: DesignSpec) -> int:
    """Candidates before the ``max_added_mass`` filter: sum over k = 1..additions of
    C(coordinates, k) v^k, v values (masses and springs) per coordinate; known before
    any is built."""
    nc = len(spec.coordinates)
    return sum(math.comb(nc, k) * spec.values ** k for k in range(1, min(spec.additions, nc) + 1))


def _distinct(singles: list[Addition], k: int, start: int = 0,
              used: frozenset[int] = frozenset()) -> Iterator[tuple[Addition, ...]]:
    """The k-combinations of ``singles`` at distinct coordinates, in the order of
    ``itertools.combinations``, without visiting the others."""
    if k == 0:
        yield ()
        return
    for i in range(start, len(singles) - k + 1):
        a = singles[i]
        if a.coordinate not in used:
            for rest in _distinct(singles, k - 1, i + 1, used | {a.coordinate}):
                yield (a, *rest)


def _label(a: Addition, labels: dict[int, str]) -> str:
    parts = ([f"{a.mass:g} kg"] if a.mass else []) + ([f"{a.stiffness:g} N/m"] if a.stiffness
                                                      else [])
    return f"{' and '.join(parts)} at {labels.get(a.coordinate, a.coordinate)}"


def measured_modes(model: ParametricModel, spec: DesignSpec) -> list[int]:
    """The spec's modes, or every elastic mode of the bare structure below its upper frequency."""
    if spec.modes is not None:
        return sorted(spec.modes)
    # the elastic modes there are: coordinates less rigid-body modes (asked of one mode)
    n = model.n - solve_configurations(model, [Configuration("base")], 1)[0].n_rigid
    f = solve_configurations(model, [Configuration("base")], min(n, 200))[0].frequencies_hz
    modes = [k + 1 for k in range(f.size) if f[k] <= spec.max_frequency_hz]
    if not modes:
        raise InputError(f"no elastic mode below {spec.max_frequency_hz:g} Hz (mode 1 is at "
                         f"{f[0]:.4g} Hz)", field="design.max_frequency_hz")
    return modes


def frequency_std(spec: DesignSpec, f_hz: np.ndarray) -> np.ndarray:
    """Measurement std (Hz) of the used modes of one configuration."""
    if spec.frequency_std_relative is not None:
        return spec.frequency_std_relative * f_hz
    s = np.asarray(spec.frequency_std_hz, dtype=float)
    return np.broadcast_to(s, f_hz.shape).copy()


def design_plan(model: ParametricModel, spec: DesignSpec, method: str,
                study_plan: Sequence[Configuration] = (), executor=None) -> DesignResult:
    """Choose ``spec.configurations`` perturbations that minimise the criterion.

    Parameters
    ----------
    model : the initial model; the prediction linearises it at its parameter values.
    spec : candidates, constraints, noise and criterion.
    method : the updating method the plan will be used with (decides the covariance).
    study_plan : the study's own perturbations, scored for comparison (may be empty).
    executor : screen the candidates on it (:mod:`eigenupdate.design.executor`); default:
        one direct call in this process.
    """
    modes = measured_modes(model, spec)
    idx = np.asarray(modes) - 1
    upd = model.updated
    names = [model.names[j] for j in upd]
    scale = np.array([model.parameters[j].scale for j in upd])
    prior = prior_weights(model) if method == "bayesian" else np.zeros(len(upd))
    cands = candidate_configurations(spec)
    if not cands:
        raise InputError("no candidate configuration (max_added_mass below every mass?)",
                         field="design")
    if executor is None:
        bare, screened = screen_candidates(model, [*cands, *study_plan], modes)
    else:
        bare, screened = screen_on(executor, model, [*cands, *study_plan], modes)
    screened, own = screened[:len(cands)], screened[len(cands):]

    def block(s: Screened) -> tuple[np.ndarray, np.ndarray]:
        f = s.frequencies_hz[idx]
        return s.J * scale, 1.0 / eigenvalue_std(f, frequency_std(spec, f))

    f0 = bare.frequencies_hz[idx]
    sigma0 = frequency_std(spec, f0)
    reports = [_constraints(c, s, f0, sigma0, idx, spec) for c, s in zip(cands, screened,
                                                                           strict=True)]
    ok = [i for i, r in enumerate(reports) if r.admissible]
    if len(ok) < spec.configurations:
        raise InputError(_bare_crowding(bare, modes, spec, reports) or _refusal(reports, spec),
                         field="design")

    blocks = [block(s) for s in screened]
    scorer = PlanScorer(blocks, block(bare), prior, method, spec.criterion, names)
    draws, seconds, pool = [], 0.0, []
    if spec.prior_draws > 0 and has_prior(model):
        pool = _shortlist(scorer, ok, spec.configurations)
        own_at = list(range(len(cands), len(cands) + len(study_plan)))

        def draw_scorer(b0: Screened, s: list[Screened]) -> PlanScorer:
            return PlanScorer([block(x) for x in s], block(b0), prior, method,
                              spec.criterion, names)

        draws, seconds = screen_draws(
            model, [cands[i] for i in pool] + list(study_plan), modes, spec.prior_draws, 0,
            draw_scorer, screen_candidates if executor is None else partial(screen_on, executor),
            spec.min_relative_gap)
        risk = np.mean([d.risk for d in draws], axis=0)
        for k, i in enumerate(pool):
            ok_now = bool(reports[i].admissible and risk[k] <= spec.max_exchange_risk)
            reports[i] = replace(reports[i], exchange_risk=float(risk[k]), admissible=ok_now)
        pool_of = {i: k for k, i in enumerate([*pool, *own_at])}
        ok = [i for i in pool if reports[i].admissible]
        if len(ok) < spec.configurations:
            raise InputError(_bare_crowding(bare, modes, spec, reports) or _refusal(reports, spec),
                             field="design")
        search = _Mapped(PriorScorer(draws, spec.criterion, names), pool_of)
    else:
        search = scorer
    chosen, swaps = greedy_exchange(search, ok, spec.configurations)
    if not np.isfinite(search.score(chosen)):
        raise InputError(
            f"no plan of {spec.configurations} configuration(s) found that determines the "
            f"{len(names)} parameters with modes {modes} (see 'eigenupdate check'); allow more "
            f"configurations, additions or modes, or give priors and use the bayesian method",
            field="design.configurations")

    def summary(label: str, plan: list[int], configs) -> PlanSummary:
        plan_blocks = [(blocks + [block(s) for s in own])[i] for i in plan]
        J = np.vstack([block(bare)[0], *(b[0] for b in plan_blocks)])
        w = np.concatenate([block(bare)[1], *(b[1] for b in plan_blocks)])
        cov = posterior_covariance(J, w, prior, method)
        linear = np.sqrt(np.diag(cov)) * scale
        std, err, risk, crit = linear, np.zeros_like(linear), None, criterion_value(
            cov, spec.criterion, names)
        if draws and all(i in search.index for i in plan):
            at = [search.index[i] for i in plan]
            pred = predict(search.scorer, at, scale, seconds)
            std, err, risk = pred.std, pred.std_error, pred.gross_risk
            crit = search.scorer.score(at)
        named = lambda v: dict(zip(names, np.asarray(v).tolist(), strict=True))  # noqa: E731
        return PlanSummary(label, [c.name for c in configs], crit, named(std), named(linear),
                           named(err), risk)

    own_idx = list(range(len(cands), len(cands) + len(study_plan)))
    plans = [summary("designed", chosen, [cands[i] for i in chosen])]
    best = exhaustive(search, ok, spec.configurations)
    if best is not None:
        plans.append(summary("exhaustive optimum", best[0], [cands[i] for i in best[0]]))
    if study_plan:
        plans.append(summary("study's plan", own_idx, study_plan))
    plans.append(summary("every admissible candidate", ok, [cands[i] for i in ok]))
    return DesignResult(names, modes, method, spec.criterion, reports, chosen, swaps, plans,
                        len(draws), seconds)


SHORTLIST = 40
"""Most candidates screened again at every draw of the prior: the best single additions at
the prior mean (each screening of a draw costs as much as the first one)."""


def _shortlist(scorer: PlanScorer, ok: list[int], size: int) -> list[int]:
    if len(ok) <= SHORTLIST:
        return list(ok)
    ranked = sorted(ok, key=lambda i: scorer.key([i]))
    return sorted(ranked[:max(SHORTLIST, 4 * size)])


@dataclass
class _Mapped:
    """A PriorScorer seen through the planner's candidate indices (draws screen only the
    shortlist and the study's own configurations)."""

    scorer: PriorScorer
    index: dict[int, int]

    @property
    def prior(self) -> np.ndarray:
        return self.scorer.prior

    @property
    def evaluations(self) -> int:
        return self.scorer.evaluations

    def score(self, plan) -> float:
        return self.scorer.score([self.index[i] for i in plan])

    def key(self, plan) -> tuple[float, float]:
        return self.scorer.key([self.index[i] for i in plan])

    def keys_adding(self, plan, candidates) -> list[tuple[float, float]]:
        return self.scorer.keys_adding([self.index[i] for i in plan],
                                       [self.index[c] for c in candidates])


def _constraints(c: Configuration, s: Screened, f0: np.ndarray, sigma0: np.ndarray,
                 idx: np.ndarray, spec: DesignSpec) -> CandidateReport:
    f_all = s.frequencies_hz
    if s.next_eigenvalue is not None:
        f_all = np.append(f_all, np.sqrt(max(s.next_eigenvalue, 0.0)) / (2 * np.pi))
    f = f_all[idx]
    shifts = f0 - f
    gaps = []
    for i in idx:
        near = [f_all[j] for j in (i - 1, i + 1) if 0 <= j < f_all.size]
        if near:
            gaps.append(min(abs(f_all[i] - x) for x in near) / f_all[i])
    gap = float(min(gaps)) if gaps else float("inf")
    in_std = float(np.max(np.abs(shifts) / sigma0))
    ok = s.order_kept and in_std > spec.min_shift_in_std and gap >= spec.min_relative_gap
    return CandidateReport(c, shifts.tolist(), in_std, gap, s.order_kept, bool(ok))


def _bare_crowding(bare: Screened, modes: Sequence[int], spec: DesignSpec,
                   reports: list[CandidateReport]) -> str:
    """The likely cause of a refusal, or "": two used modes of the bare structure are
    already closer than min_relative_gap (a candidate keeps them apart only by chance)."""
    f = bare.frequencies_hz
    if bare.next_eigenvalue is not None:
        f = np.append(f, math.sqrt(max(bare.next_eigenvalue, 0.0)) / (2 * math.pi))
    for k in modes:
        for j in (k - 1, k + 1):
            if 1 <= j <= f.size and abs(f[k - 1] - f[j - 1]) < spec.min_relative_gap * f[k - 1]:
                a, b = sorted((k, j))
                return (f"only {sum(r.admissible for r in reports)} of {len(reports)} "
                        f"candidates are admissible, {spec.configurations} configurations "
                        f"asked for: the bare structure's modes {a} and {b} "
                        f"({f[a - 1]:.6g} and {f[b - 1]:.6g} Hz) are already closer than "
                        f"min_relative_gap = {spec.min_relative_gap:g}; leave one of them out "
                        f"of design.modes or lower min_relative_gap")
    return ""


def _refusal(reports: list[CandidateReport], spec: DesignSpec) -> str:
    n = len(reports)
    small = sum(r.shift_in_std <= spec.min_shift_in_std for r in reports)
    order = sum(not r.order_kept or r.relative_gap < spec.min_relative_gap for r in reports)
    risky = sum(r.exchange_risk is not None and r.exchange_risk > spec.max_exchange_risk
                for r in reports)
    return (f"only {sum(r.admissible for r in reports)} of {n} candidates are admissible, "
            f"{spec.configurations} configurations asked for: {order} change the mode order or "
            f"leave a relative gap below min_relative_gap = {spec.min_relative_gap:g} (masses "
            f"too large?), {small} shift no used mode by more than min_shift_in_std = "
            f"{spec.min_shift_in_std:g} std (masses too small?), {risky} do either in more "
            f"than max_exchange_risk = {spec.max_exchange_risk:g} of the prior's draws")
