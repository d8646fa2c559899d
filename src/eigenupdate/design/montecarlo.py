"""Virtual tests of a study's plan (``eigenupdate montecarlo``).

Each trial draws the true parameters (from the prior N(s_0, sigma_s), truncated at 0, or
fixed at a given truth), simulates the measured frequencies of every configuration with the
stated noise, and runs :func:`eigenupdate.identify.updating.update` exactly as
``eigenupdate update`` does. Trial i draws from the i-th child of ``SeedSequence(seed)``,
so results do not depend on where or in which order the trials run.
"""

from __future__ import annotations

import time
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from eigenupdate.budget import require
from eigenupdate.design.covariance import posterior_covariance
from eigenupdate.design.executor import InProcess, Progress
from eigenupdate.design.plan import frequency_std
from eigenupdate.design.prior import PriorPrediction, draw_values, predict_plan
from eigenupdate.design.spec import DesignSpec
from eigenupdate.errors import InputError, NumericalError
from eigenupdate.identify.checked import (
    CONVERGED,
    EXCHANGE,
    OUTCOMES,
    REJECTED,
    SECOND_SOLUTION,
    checked_update,
)
from eigenupdate.identify.weights import prior_weights
from eigenupdate.measure.measurement import Measurement, eigenvalue_std
from eigenupdate.model.configurations import Configuration
from eigenupdate.model.parametric import ParametricModel
from eigenupdate.schema import finite_or_none, reader
from eigenupdate.solve.jacobian import linearise, solve_configurations

TRIAL_REFITS = 4
"""Exchange refits per trial: the closest candidates in std, where an exchange is most
likely to fit as well; ``eigenupdate update`` refits up to
:data:`eigenupdate.identify.exchange.MAX_REFITS`."""


@dataclass(frozen=True)
class TrialSetup:
    """Everything a trial needs; sent to each worker once."""

    model: ParametricModel
    configurations: tuple[Configuration, ...]
    modes: tuple[int, ...]
    std_hz: dict[tuple[str, int], float]  # noise std (and std_hz column) of each row
    method: str
    max_iterations: int
    tolerance: float
    truth: np.ndarray | None = None  # all parameter values; None: draw from the prior
    optimizer: str = "trust-region"  # as the study's [updating] optimizer
    max_refits: int = TRIAL_REFITS  # exchange refits per trial (the closest candidates)
    starts: int | None = None  # fits from prior draws testing uniqueness (None: default)


def simulate(setup: TrialSetup, truth: np.ndarray, rng: np.random.Generator
             ) -> dict[tuple[str, int], Measurement]:
    """The measured frequencies of the plan at ``truth`` (all parameter values), each with
    Gaussian noise of its stated std."""
    sols = solve_configurations(setup.model, setup.configurations, max(setup.modes), truth)
    meas = {}
    for c, sol in zip(setup.configurations, sols, strict=True):
        for k in setup.modes:
            std = setup.std_hz[(c.name, k)]
            meas[(c.name, k)] = Measurement(
                c.name, k, float(sol.frequencies_hz[k - 1] + rng.normal(0.0, std)), std)
    return meas


def run_trial(seed: np.random.SeedSequence, setup: TrialSetup) -> dict:
    """One virtual test, updated and checked as ``eigenupdate update`` does
    (:func:`eigenupdate.identify.checked.checked_update`); returns truth, estimate and
    reported std of the updated parameters and the outcome (a trial whose fit the checks
    catch keeps its estimate but is not counted as converged)."""
    rng = np.random.default_rng(seed)
    model = setup.model
    upd = model.updated
    truth = setup.truth.copy() if setup.truth is not None else draw_values(model, rng)
    out = {"truth": truth[upd], "estimate": np.full(upd.size, np.nan),
           "std": np.full(upd.size, np.nan), "converged": False, "refused": False, "nit": 0,
           "outcome": "refused", "message": "", "clusters": 0}
    try:
        meas = simulate(setup, truth, rng)
        checked = checked_update(model, setup.configurations, setup.modes, meas,
                                 method=setup.method, optimizer=setup.optimizer,
                                 max_iterations=setup.max_iterations, xtol=setup.tolerance,
                                 max_refits=setup.max_refits, starts=setup.starts,
                                 seed=rng.integers(2**63))
    except (InputError, NumericalError) as exc:  # a truth or its data the update refuses
        out.update(refused=True, message=str(exc))
        return out
    res = checked.result
    names = [model.names[j] for j in upd]
    out.update(estimate=np.array([res.parameters[n] for n in names]),
               std=np.array([np.nan if res.std[n] is None else res.std[n] for n in names]),
               converged=checked.outcome == CONVERGED, nit=res.nit,
               outcome=checked.outcome, message=res.message,
               clusters=len((res.pairing or {}).get("clusters", [])))
    return out


GROSS_DRAWS = 32
"""Virtual tests behind the predicted chance of a gross error (binomial standard error
at most 0.09, 0.05 at a 10 % chance) and the predicted std (with n converged ones its
relative standard error is about sqrt((kurtosis - 1) / 4 n): 0.18 with 16 at a
kurtosis of 3; resolving 15 % needs some 100 converged)."""
GROSS_SEED = 0x67726F7373
"""Root seed of those tests: a stream of its own, apart from any Monte Carlo's trials."""


@dataclass(frozen=True)
class GrossPrediction:
    """Chance that a test of the plan ends in a gross error: not converged, or a fit the
    checks catch (data reject it, a second solution, a mode exchange).

    Not a linear figure: the linearised posterior has no second solutions, exchanges or
    failed iterations. It is the fraction of ``draws`` checked updates of data simulated
    at draws of the truth from the prior with the stated noise (a refused draw counts
    as gross too), with its binomial standard error; ``by_outcome`` counts each kind and
    ``seconds`` is their share of the run's wall time."""

    fraction: float
    std_error: float
    draws: int
    by_outcome: dict[str, int]
    seconds: float
    std: np.ndarray | None = None
    std_of_std: np.ndarray | None = None

    # std, std_of_std: the spread of (estimate - truth) over the converged ones of these
    # tests, and its standard error (:func:`std_with_error`); None with fewer than
    # MIN_CONVERGED converged. It is the nonlinear estimator with its checks at draws of
    # the truth, so it includes what the linearised posterior misses (on the 6-mass
    # network at a 25 % prior the converged trials' errors are 1.2-2.2 times the
    # linearised std at their own truths).


def gross_seeds(draws: int = GROSS_DRAWS, seed: int = GROSS_SEED
                ) -> list[np.random.SeedSequence]:
    """Seeds of the virtual tests behind :class:`GrossPrediction`."""
    return np.random.SeedSequence(seed).spawn(draws)


def predict_gross(trials: Sequence[dict], seconds: float) -> GrossPrediction:
    """:class:`GrossPrediction` from the checked virtual tests ``trials`` (run with
    :func:`run_trial` on :func:`gross_seeds`), which took ``seconds``."""
    outcome = Counter(t["outcome"] for t in trials)
    n = len(trials)
    p = (n - outcome.get(CONVERGED, 0)) / n
    ok = [t for t in trials if t["converged"]]
    std = se = None
    if len(ok) >= MIN_CONVERGED:
        std, se = std_with_error(np.array([t["estimate"] - t["truth"] for t in ok]))
    return GrossPrediction(p, float(np.sqrt(max(p * (1 - p), 1 / n) / n)), n,
                           dict(outcome), seconds, std, se)


def std_with_error(err: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Sample std of each column of ``err`` (n, p) and its standard error, from the
    sample kurtosis k: var(s^2) = s^4 (k - (n - 3) / (n - 1)) / n, se(s) = se(s^2) / (2 s)
    (delta method). Not the Gaussian s / sqrt(2 (n - 1)): the errors over a prior are
    heavy-tailed (kurtosis 2-5 on the network at 25 %), which that would understate.

    >>> s, se = std_with_error(np.random.default_rng(0).normal(size=(4000, 1)))
    >>> bool(abs(s[0] - 1) < 4 * se[0]), bool(abs(se[0] - 1 / np.sqrt(8000)) < 2e-3)
    (True, True)
    """
    n = err.shape[0]
    s = err.std(axis=0, ddof=1)
    d = err - err.mean(axis=0)
    with np.errstate(invalid="ignore", divide="ignore"):
        k = (d**4).mean(axis=0) / (d**2).mean(axis=0) ** 2
        var_s2 = s**4 * np.maximum(k - (n - 3) / (n - 1), 0.0) / n
        return s, np.sqrt(var_s2) / (2 * s)


MIN_CONVERGED = 3
"""Fewest converged trials the statistics are given over: with 2 the empirical std has
one degree of freedom (a 90 % interval spanning a factor of 30), with 1 none at all."""


@dataclass(frozen=True)
class MonteCarloResult:
    """Trials and their summary.

    Attributes
    ----------
    names : updated parameters.
    trials : one dict per trial (see :func:`run_trial`).
    linear_std : linearised posterior std at the initial model (at the truth if one is
        given) with the stated noise.
    entropy : the root seed; the same entropy repeats the run exactly.
    prior : the plan's accuracy averaged over draws of the truth from the prior
        (:func:`eigenupdate.design.prior.predict_plan`), what the trials' spread is to
        match; None when a truth is given.
    gross : the predicted chance of a gross error (:func:`predict_gross`), None when a
        truth is given.
    """

    names: list[str]
    trials: list[dict]
    linear_std: np.ndarray
    entropy: int
    prior: PriorPrediction | None = None
    gross: GrossPrediction | None = None

    SCHEMA: ClassVar[str] = "eigenupdate.montecarlo/1"

    def to_dict(self) -> dict:
        """JSON-ready document: the :meth:`summary` (its keys at the top, for readers of
        the figures) and what :meth:`from_dict` needs to rebuild the result (trials with
        truth, estimate and reported std; NaN is null)."""
        def values(a: np.ndarray) -> list[float | None]:
            return [finite_or_none(v) for v in np.asarray(a, dtype=float).tolist()]

        return {
            "schema": self.SCHEMA, **self.summary(), "names": self.names,
            "trial_results": [{**t, **{k: values(t[k]) for k in ("truth", "estimate", "std")},
                               "converged": bool(t["converged"]),
                               "refused": bool(t["refused"]), "nit": int(t["nit"]),
                               "outcome": str(t["outcome"])}
                              for t in self.trials],
            "linear_std": values(self.linear_std), "entropy": str(self.entropy),
            "prior": None if self.prior is None else {
                "std": values(self.prior.std), "std_error": values(self.prior.std_error),
                "gross_risk": self.prior.gross_risk, "draws": self.prior.draws,
                "seconds": self.prior.seconds},
            "gross": None if self.gross is None else {
                "fraction": self.gross.fraction, "std_error": self.gross.std_error,
                "draws": self.gross.draws, "by_outcome": dict(self.gross.by_outcome),
                "seconds": self.gross.seconds,
                "std": None if self.gross.std is None else values(self.gross.std),
                "std_of_std": None if self.gross.std_of_std is None
                else values(self.gross.std_of_std)},
        }

    @classmethod
    def from_dict(cls, doc: dict, source: str | None = None) -> MonteCarloResult:
        """The result :meth:`to_dict` wrote; InputError naming the field otherwise."""
        r = reader(doc, cls.SCHEMA, source)
        names = [str(n) for n in r.raw("names", list)]
        trials = []
        for t in r.items("trial_results"):
            arrays = {k: t.array(k, nulls=True) for k in ("truth", "estimate", "std")}
            if any(a.size != len(names) for a in arrays.values()):
                raise t.fail("truth", f"truth, estimate and std need {len(names)} values")
            outcome = t.str("outcome")
            if outcome not in (*OUTCOMES, "refused"):
                raise t.fail("outcome", f"{outcome!r} is not one of {[*OUTCOMES, 'refused']}")
            trials.append({**arrays, "converged": t.bool("converged"),
                           "refused": t.bool("refused"), "nit": t.int("nit"),
                           "outcome": outcome, "message": t.str("message"),
                           "clusters": t.int("clusters", optional=True) or 0})
        p = r.child("prior", optional=True)
        prior = None if p is None else PriorPrediction(
            p.array("std"), p.array("std_error"), p.number("gross_risk"), p.int("draws"),
            p.number("seconds"))
        g = r.child("gross", optional=True)
        gross = None if g is None else GrossPrediction(
            g.number("fraction"), g.number("std_error"), g.int("draws"),
            {str(k): int(v) for k, v in g.raw("by_outcome", dict).items()}, g.number("seconds"),
            g.array("std", optional=True), g.array("std_of_std", optional=True))
        entropy = r.str("entropy")
        if not entropy.isdigit():
            raise r.fail("entropy", f"{entropy!r} is not a seed's entropy (digits)")
        return cls(names, trials, r.array("linear_std"), int(entropy), prior, gross)

    @property
    def predicted_std(self) -> np.ndarray:
        """The prediction the trials test: the spread of the checked virtual tests at
        draws of the prior (:class:`GrossPrediction`) where they give one, else the
        linearised std averaged over the prior, or linear at a given truth."""
        if self.gross is not None and self.gross.std is not None:
            return self.gross.std
        return self.prior.std if self.prior is not None else self.linear_std

    @property
    def predicted_std_error(self) -> np.ndarray | None:
        """Standard error of :attr:`predicted_std` (None at a given truth)."""
        if self.gross is not None and self.gross.std is not None:
            return self.gross.std_of_std
        return None if self.prior is None else self.prior.std_error

    def counts(self) -> tuple[int, int, int]:
        """Trials converged, not converged (the update ran out of iterations or could not
        lower the objective) and refused (the update refused the truth or its data); the
        trials the checks caught are counted apart (:meth:`caught`)."""
        refused = sum(bool(t["refused"]) for t in self.trials)
        ok = sum(bool(t["converged"]) for t in self.trials)
        return ok, len(self.trials) - ok - refused - sum(self.caught().values()), refused

    def caught(self) -> dict[str, int]:
        """Trials whose converged fit the checks caught, by check: the data reject it
        (``rejected``), a second solution fits as well, or a mode exchange does."""
        return {k: sum(t.get("outcome") == k for t in self.trials)
                for k in (REJECTED, SECOND_SOLUTION, EXCHANGE)}

    def refusal(self) -> str | None:
        """Why the statistics are not given (None when they are)."""
        ok, bad, refused = self.counts()
        if ok >= MIN_CONVERGED:
            return None
        first = next((t["message"] for t in self.trials if t["refused"] or not t["converged"]),
                     "")
        if refused == len(self.trials):
            return (f"every one of the {refused} trials was refused by the update, e.g.: "
                    f"{first}")
        return (f"statistics need at least {MIN_CONVERGED} converged trials, {ok} of "
                f"{len(self.trials)} converged ({bad} not converged, {refused} refused, "
                f"{sum(self.caught().values())} caught by the checks), e.g.: {first}")

    def summary(self) -> dict:
        """Per parameter over the converged trials: bias, empirical std of the error,
        predicted std, mean reported std, coverage of estimate +- 2 reported std; none
        (and ``statistics_refused`` says why) with fewer than MIN_CONVERGED."""
        ok = [t for t in self.trials if t["converged"]]
        n = len(self.trials)
        _, bad, refused = self.counts()
        caught = self.caught()
        gross = sum(caught.values())
        doc = {"trials": n, "converged": len(ok), "not_converged": bad, "refused": refused,
               "caught": caught, "caught_fraction": gross / n,
               "gross_error_fraction": (n - len(ok)) / n,
               "not_converged_fraction": bad / n, "refused_fraction": refused / n,
               "minimum_converged": MIN_CONVERGED,
               "statistics_refused": self.refusal(),
               "seed_entropy": self.entropy, "parameters": {}}
        if doc["statistics_refused"] is not None:
            return doc
        # the predicted std fits every mode alone; a trial that fitted close modes
        # through their sums had less information (its reported std says how much)
        doc["converged_with_clusters"] = sum(t.get("clusters", 0) > 0 for t in ok)
        err = np.array([t["estimate"] - t["truth"] for t in ok])
        rep = np.array([t["std"] for t in ok])
        emp, emp_se = std_with_error(err)
        with np.errstate(invalid="ignore"):
            cover = np.mean(np.abs(err) <= 2 * rep, axis=0)
        if self.prior is not None:
            doc["prior_draws"] = self.prior.draws
            doc["prior_draw_seconds"] = self.prior.seconds
            doc["predicted_gross_risk"] = self.prior.gross_risk
        if self.gross is not None:
            doc["predicted_gross_error_fraction"] = self.gross.fraction
            doc["predicted_gross_error_fraction_error"] = self.gross.std_error
            doc["predicted_gross_by_outcome"] = self.gross.by_outcome
            doc["predicted_gross_draws"] = self.gross.draws
            doc["predicted_gross_seconds"] = self.gross.seconds
            if self.gross.std is not None:
                doc["predicted_std_by_tests"] = dict(zip(self.names,
                                                         self.gross.std.tolist(), strict=True))
        for i, name in enumerate(self.names):
            doc["parameters"][name] = {
                "bias": float(err[:, i].mean()), "empirical_std": float(emp[i]),
                "predicted_std": float(self.predicted_std[i]),
                "predicted_std_error": (None if self.predicted_std_error is None
                                        else float(self.predicted_std_error[i])),
                "prior_std": (float(self.prior.std[i]) if self.prior is not None
                              else None),
                "empirical_std_error": float(emp_se[i]),
                "linear_std": float(self.linear_std[i]),
                "mean_reported_std": float(np.nanmean(rep[:, i])) if np.isfinite(
                    rep[:, i]).any() else None,
                "ratio_empirical_to_predicted": float(emp[i] / self.predicted_std[i]),
                "coverage_2std": float(cover[i]),
            }
        return doc

    def z_scores(self) -> np.ndarray:
        """(estimate - truth) / reported std of every converged trial and parameter."""
        ok = [t for t in self.trials if t["converged"]]
        if not ok:
            return np.zeros((0, len(self.names)))
        return np.array([(t["estimate"] - t["truth"]) / t["std"] for t in ok])


def noise_std(model: ParametricModel, configurations: Sequence[Configuration],
              modes: Sequence[int], measured: dict | None, spec: DesignSpec | None,
              source: str) -> dict[tuple[str, int], float]:
    """Noise std (Hz) of every row: the measurement file's std_hz, else the [design] table's."""
    rows = [(c.name, k) for c in configurations for k in modes]
    if measured is not None and all(measured.get(r) is not None and measured[r].std_hz
                                    for r in rows):
        return {r: float(measured[r].std_hz) for r in rows}
    if spec is None:
        raise InputError("no noise level: give std_hz for every row of the measurement file, "
                         "or frequency_std_hz in a [design] table", source=source,
                         field="measurement.frequencies")
    sols = solve_configurations(model, configurations, max(modes))
    idx = np.asarray(modes) - 1
    out = {}
    for c, sol in zip(configurations, sols, strict=True):
        s = frequency_std(spec, sol.frequencies_hz[idx])
        out.update({(c.name, k): float(v) for k, v in zip(modes, s, strict=True)})
    return out


def predicted_std(setup: TrialSetup) -> np.ndarray:
    """Linearised posterior std (physical units) at the truth if one is given (the data
    are drawn there), else at the initial model; stated noise."""
    model = setup.model
    lin = linearise(model, setup.configurations, setup.modes, setup.truth)
    f = np.sqrt(lin.eigenvalues) / (2 * np.pi)
    w = 1.0 / eigenvalue_std(f, np.array([setup.std_hz[r] for r in lin.rows]))
    prior = prior_weights(model)
    cov = posterior_covariance(lin.normalised, w, prior, setup.method)
    return np.sqrt(np.diag(cov)) * lin.scale


def montecarlo(setup: TrialSetup, trials: int, seed: int | None = None, executor=None,
               progress: Progress | None = None, virtual_tests: int = GROSS_DRAWS
               ) -> MonteCarloResult:
    """Run ``trials`` virtual tests of the plan in ``setup`` on ``executor``, and (truth
    drawn from the prior) the :data:`GROSS_DRAWS` tests of the predicted chance of a gross
    error with them (``progress(done, total)`` counts both); ``virtual_tests`` sets their
    number (they cost as much as trials: the predicted std's standard error falls as
    1 / sqrt of the converged ones).

    Examples
    --------
    One mass on one spring, both unknown with priors, two configurations:

    >>> from eigenupdate.model.parameters import Parameter
    >>> from eigenupdate.model.spring_mass import Mass, Spring, spring_mass_model
    >>> from eigenupdate.model.configurations import Configuration, mass_at
    >>> model = spring_mass_model([Mass(Parameter("m", 2.0, 0.1), 1)],
    ...                           [Spring(Parameter("k", 800.0, 40.0), (0, 1))])
    >>> configs = (Configuration("base"), mass_at(1, 1.0))
    >>> setup = TrialSetup(model, configs, (1,), {(c.name, 1): 0.01 for c in configs},
    ...                    "bayesian", 20, 1e-8)
    >>> s = montecarlo(setup, 20, seed=1).summary()
    >>> p = s["parameters"]["m"]     # linear over 64 draws of the prior, at the prior mean
    >>> s["converged"], round(p["prior_std"], 4), round(p["linear_std"], 4)
    (20, 0.0467, 0.0468)
    >>> p["predicted_std"] == s["predicted_std_by_tests"]["m"]  # 32 checked virtual tests
    True
    """
    if trials < 1:
        raise InputError(f"must be >= 1, got {trials}", field="--trials")
    require("trials", trials, f"{trials:,} trials asked for", field="--trials")
    if setup.truth is None:
        draw_values(setup.model, np.random.default_rng(0))  # refuses a parameter without prior
    root = np.random.SeedSequence(seed)
    names = [setup.model.names[j] for j in setup.model.updated]
    linear = predicted_std(setup)
    prior = None if setup.truth is not None else predict_plan(
        setup.model, setup.configurations, setup.modes, setup.std_hz, setup.method,
        PRIOR_DRAWS)
    # the tests behind the predicted chance of a gross error run with the trials, on one
    # executor: a seed stream of their own, so the trials do not depend on them
    extra = [] if setup.truth is not None else gross_seeds(virtual_tests)
    t0 = time.perf_counter()
    results = (executor or InProcess()).map(run_trial, setup, [*root.spawn(trials), *extra],
                                            progress)
    share = (time.perf_counter() - t0) * len(extra) / (trials + len(extra))
    gross = predict_gross(results[trials:], share) if extra else None
    return MonteCarloResult(names, results[:trials], linear, int(root.entropy), prior, gross)


PRIOR_DRAWS = 64
"""Draws of the truth behind the prediction over the prior a Monte Carlo is compared with
(the design's default)."""


def study_setup(study, truth: dict[str, float] | None = None,
                truth_source: str | None = None) -> TrialSetup:
    """The trial setup of a study: its plan, modes, method, noise, and optional true value
    of every parameter by name (read from ``truth_source``, for the messages)."""
    modes = tuple(study.require_modes())
    measured = study.measurements() if study.frequencies is not None else None
    std = noise_std(study.model, study.configurations, modes, measured, study.design,
                    str(study.path))
    values = None
    if truth is not None:
        missing = [n for n in study.model.names if n not in truth]
        if missing:
            raise InputError(f"no true value for parameter(s) {missing}", source=truth_source,
                             field="model")
        values = np.array([truth[n] for n in study.model.names])
    return TrialSetup(study.model, tuple(study.configurations), modes, std, study.method,
                      study.max_iterations, study.tolerance, values, study.optimizer)
