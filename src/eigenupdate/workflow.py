"""The commands as library functions: each takes a loaded :class:`~eigenupdate.io.study.Study`
and returns a typed result, so a notebook does what ``eigenupdate <command>`` does.

>>> from pathlib import Path
>>> from eigenupdate.io.study import load_study
>>> examples = Path(__file__).parents[2] / "examples"     # in the source tree
>>> study = load_study(examples / "paper_fig2" / "study.toml")
>>> check_study(study).rank
10
>>> res = update_study(study)
>>> res.success, res.nit, round(res.parameters["k6"])
(True, 4, 500000)
"""

from __future__ import annotations

import math
import os
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, fields, replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from eigenupdate.budget import require
from eigenupdate.choices import SCHEDULER_ENV
from eigenupdate.design.montecarlo import (  # its own imports are light
    MIN_CONVERGED,
    MonteCarloResult,
)
from eigenupdate.errors import InputError, shorten
from eigenupdate.identify.checked import checked_update
from eigenupdate.identify.identifiability import IdentifiabilityReport, check
from eigenupdate.identify.updating import UpdateResult
from eigenupdate.identify.weights import estimator_weights
from eigenupdate.io.frf_files import read_frf_files, require_distinct
from eigenupdate.io.results import read_json, read_loss_factors, read_result
from eigenupdate.io.study import Study, load_study
from eigenupdate.measure.frf import FRF
from eigenupdate.measure.measurement import Measurement
from eigenupdate.measure.survey import TestExtraction, extract_test
from eigenupdate.measure.synthetic import simulate_measurements, synthetic_frfs
from eigenupdate.model.configurations import Configuration
from eigenupdate.model.coordinates import CoordinateTable
from eigenupdate.report.data import FrfComparison
from eigenupdate.solve.jacobian import solve_configurations
from eigenupdate.solve.response import receptance
from eigenupdate.solve.sweep import MassSweep, mass_sweep

if TYPE_CHECKING:  # report imports jinja2, matplotlib: only when used
    from eigenupdate.design.plan import DesignResult
    from eigenupdate.design.validate import Validation
    from eigenupdate.report.data import ReportData


def _rows(study: Study) -> list[tuple[str, int]]:
    return [(c.name, k) for c in study.configurations for k in sorted(set(study.require_modes()))]


def check_study(study: Study, method: str | None = None) -> IdentifiabilityReport:
    """Identifiability of the study's plan as its estimator sees it (``eigenupdate check``).

    The equations are weighted by the measured std when the method is weighted and the
    study has a measurement file, else by 1 (a plan checked before the test); the Bayesian
    method adds its prior rows. ``method`` defaults to the study's.
    """
    method = method or study.method
    meas = study.measurements() if study.frequencies is not None else None
    w = estimator_weights(study.model, method, _rows(study), meas, str(study.frequencies))
    return check(study.model, study.configurations, study.require_modes(), weights=w.rows,
                 prior=w.prior)


def update_study(study: Study, method: str | None = None, optimizer: str | None = None,
                 progress: Callable[[str], None] | None = None) -> UpdateResult:
    """The update with the study's measurements and settings (``eigenupdate update``);
    ``progress`` gets one line per iteration.

    The measured frequencies are checked against the ordering laws first (with the bare
    structure's rigid-body modes: added stiffness cannot lower an eigenvalue of a grounded
    structure), and a converged fit that the data reject (chi-square test of the
    residuals, :mod:`eigenupdate.identify.consistency`) is returned as not converged,
    naming the configurations and modes that do not fit; so is a fit that a fit from a
    draw of the prior matches within noise far from it (a second solution), and a fit
    whose data another labelling fits as well (a mode's values exchanged between two
    configurations): :func:`eigenupdate.identify.checked.checked_update`.
    """
    return checked_update(
        study.model, study.configurations, study.require_modes(), study.measurements(),
        method=method or study.method, optimizer=optimizer or study.optimizer,
        max_iterations=study.max_iterations, xtol=study.tolerance,
        source=str(study.frequencies), progress=progress,
    ).result


def study_frequencies(study: Study, n_modes: int | None = None) -> dict[str, np.ndarray]:
    """Elastic natural frequencies (Hz) of every configuration (``eigenupdate frequencies``);
    ``n_modes`` defaults to the study's highest mode."""
    if n_modes is not None and n_modes < 1:
        raise InputError(f"must be >= 1, got {n_modes}", field="--modes")
    n = n_modes or max(study.require_modes())
    sols = solve_configurations(study.model, study.configurations, n)
    return {c.name: s.frequencies_hz for c, s in zip(study.configurations, sols, strict=True)}


def simulate_study(study: Study, noise_hz: float = 0.0, std_hz: float | None = None,
                   seed: int | None = None, noise_relative: float = 0.0) -> list[Measurement]:
    """The measurements this study's model, taken as the truth, would give
    (``eigenupdate simulate``); see :func:`eigenupdate.measure.synthetic.simulate_measurements`."""
    rows = simulate_measurements(study.model, study.configurations, study.require_modes(),
                                 noise_hz=noise_hz, std_hz=std_hz, seed=seed,
                                 noise_relative=noise_relative)
    for m in rows:  # what the measurement CSV refuses is not written
        if m.std_hz is not None and m.std_hz >= m.frequency_hz:
            raise InputError(f"std {m.std_hz:g} Hz of {m.configuration!r} mode {m.mode} is "
                             f"not below its frequency {m.frequency_hz:g} Hz",
                             field="--std-hz" if std_hz is not None else "--noise-hz")
    return rows


@dataclass(frozen=True)
class StudyExtraction:
    """The FRFs read for each configuration and what was extracted from them; ``label``
    names an FRF's (node, direction) points by the model's coordinates (None: no model)."""

    frfs: dict[str, list[FRF]]
    result: TestExtraction
    label: Callable[[tuple[int, int]], str] | None = None


def extract_study(study: Study, progress: Callable[[str], None] | None = None
                  ) -> StudyExtraction:
    """Validated, numbered modes of every configuration from the study's FRF files
    (``eigenupdate extract``), with the study's bands, low-frequency cut and FRF kinds.
    With a model, modes are numbered by the initial model's frequencies; without one, by
    order. Problems (a used mode not found) are in ``result.problems``, not raised."""
    missing = [c.name for c in study.configurations if not study.frf.get(c.name)]
    if missing:
        raise InputError(f"no FRF file for configuration(s) {missing}", source=str(study.path),
                         field="measurement.frf")
    require_distinct({c.name: study.frf[c.name] for c in study.configurations},
                     str(study.path))
    frfs = {c.name: read_frf_files(study.frf[c.name],
                                   [study.frf_kinds.get(p) for p in study.frf[c.name]])
            for c in study.configurations}
    res = extract_test(frfs, model=study.model, configurations=study.configurations,
                       used_modes=study.modes, bands_hz=study.bands_hz,
                       exclude_below_hz=study.exclude_below_hz, progress=progress)
    return StudyExtraction(frfs, res, None if study.model is None
                           else study.model.coordinate_table.point_label)


def extract_files(paths: Sequence[str | Path], kind: str | None = None,
                  progress: Callable[[str], None] | None = None) -> StudyExtraction:
    """Modes of FRF files without a study (``eigenupdate extract a.uff b.uff``): one
    configuration per file, named by its stem, numbered by order; ``kind`` for files whose
    header does not say what they hold."""
    paths = [Path(p) for p in paths]
    names = [p.stem for p in paths]
    if len(set(names)) != len(names):
        raise InputError(f"two files with one name in {[str(p) for p in paths]}",
                         field="inputs")
    require_distinct({p.stem: [p] for p in paths})
    frfs = {p.stem: read_frf_files([p], [kind]) for p in paths}
    return StudyExtraction(frfs, extract_test(frfs, progress=progress))


def simulate_study_frfs(study: Study, fmax_hz: float, df_hz: float, excitation: int,
                        outputs: Sequence[int], loss_factor: float | Sequence[float],
                        noise: float = 0.01,
                        seed: int | None = None) -> list[tuple[Configuration, list[FRF]]]:
    """Synthetic noisy FRFs of every configuration (``eigenupdate simulate-frf``) on
    ``df_hz``, 2 ``df_hz``, ... ``fmax_hz`` (not 0 Hz: rigid-body modes are infinite
    there), one random stream for all of them."""
    if not 0 < df_hz < fmax_hz or fmax_hz / df_hz > 1e7:
        raise InputError(f"need --df < --fmax and at most 1e7 lines, got --df {df_hz:g}, "
                         f"--fmax {fmax_hz:g}", field="--fmax")
    frequency_hz = np.arange(df_hz, fmax_hz + 0.5 * df_hz, df_hz)
    if len(set(outputs)) != len(outputs):
        raise InputError(f"coordinates repeated in {list(outputs)}", field="--outputs")
    rng = np.random.default_rng(seed)
    return [(c, synthetic_frfs(study.model, c, frequency_hz, excitation, outputs, loss_factor,
                               noise=noise, seed=rng))
            for c in study.configurations]


def compare_frf(study: Study, excitation: int, response: int, *,
                configuration: str | None = None, measured: str | None = None,
                updated: str | None = None, loss_factor: float = 0.01,
                damping: str | None = None, fmax_hz: float | None = None) -> FrfComparison:
    """Receptance ``response``/``excitation`` of the initial and updated model against the
    measured FRF (``eigenupdate frf``, paper Fig. 7).

    ``measured`` is an FRF file (UFF 58 or CSV), ``updated`` a result of ``update --save``,
    ``damping`` the UFF 55 of ``extract --uff55`` (per-mode loss factors; else
    ``loss_factor`` for every mode). Without a measured FRF the axis runs to ``fmax_hz``
    (default twice the highest mode used).
    """
    config = study.configuration(configuration)
    table = study.model.coordinate_table
    frf = None
    if measured:
        frf = _matching_frf(read_frf_files([measured]), table, response, excitation, measured)
        f = frf.frequency_hz
    else:
        top = solve_configurations(study.model, [config], max(study.modes or [1]))[0]
        fmax = fmax_hz or 2.0 * top.frequencies_hz[-1]
        f = np.linspace(fmax / 2000, fmax, 2000)
    f = f[f > 0]
    eta = [loss_factor]
    eta_text = f"loss factor {loss_factor:g}"
    if damping:
        eta = read_loss_factors(damping, config.name)
        eta_text = "extracted loss factors " + ", ".join(f"{e:.3g}" for e in eta)
    models = [study.model]
    if updated:
        saved = read_result(updated, study.model)
        _same_model(saved, study, updated, [config])
        models.append(saved.model)
    curves = [receptance(m, f, excitation, response, configuration=config,
                         loss_factor=eta if damping else loss_factor) for m in models]
    return FrfComparison(
        config, f, curves[0], curves[1] if updated else None, frf, eta,
        f"{study.title}\n{config.name}: receptance {response}/{excitation}, {eta_text}",
        excitation, response)


def _matching_frf(frfs: list[FRF], table: CoordinateTable, response: int, excitation: int,
                  source: str) -> FRF:
    """The FRF of ``response``/``excitation`` among those read from ``source``."""
    want = (table[response].uff_point, table[excitation].uff_point)
    match = [x for x in frfs if (x.response, x.reference) == want]
    if not match and len(frfs) == 1 and frfs[0].response == (0, 0):
        match = frfs  # a CSV FRF carries no points: take it as the one asked for
    if not match:
        have = "; ".join(f"{table.point_label(x.response)} / {table.point_label(x.reference)}"
                         for x in frfs)
        raise InputError(f"no FRF for response {table.label(response)}, reference "
                         f"{table.label(excitation)} (file has {have})", source=source)
    return match[0]


def sweep(study: Study, coordinate: int, max_mass: float, n_modes: int | None = None,
          configuration: str | None = None) -> MassSweep:
    """Elastic frequencies against a mass added at ``coordinate`` from 0 to ``max_mass`` kg
    (``eigenupdate sweep``, paper Fig. 4), on ``configuration`` (default: the first);
    ``n_modes`` defaults to the study's highest mode (3 without modes)."""
    if n_modes is not None and n_modes < 1:
        raise InputError(f"must be >= 1, got {n_modes}", field="--modes")
    return mass_sweep(study.model, coordinate, max_mass, n_modes or max(study.modes or [3]),
                      configuration=study.configuration(configuration))


@dataclass(frozen=True)
class StudyDesign:
    """The plan chosen for a study and, if asked for, its virtual tests."""

    plan: DesignResult
    validation: Validation | None


def design(study: Study, *, validate: int | None = None, seed: int | None = 0,
           executor=None, scheduler: str | None = None,
           workers: int | None = None) -> StudyDesign:
    """The added masses the study's ``[design]`` table asks for (``eigenupdate design``),
    then ``validate`` virtual tests of that plan (truth drawn from the prior) if given.

    ``executor`` screens the candidates and runs the trials (default: this process; the
    caller closes it), or else a Dask cluster at ``scheduler`` (or
    ``$EIGENUPDATE_SCHEDULER``) or of ``workers`` local processes, closed here; see
    :mod:`eigenupdate.design.executor`.
    """
    from eigenupdate.design.executor import executor_for

    if executor is None and (scheduler or workers or os.environ.get(SCHEDULER_ENV)):
        with executor_for(scheduler, n_workers=workers) as ex:
            return design(study, validate=validate, seed=seed, executor=ex)
    from eigenupdate.design.plan import design_plan
    from eigenupdate.design.validate import validate_design

    if study.design is None:
        raise InputError("the study has no [design] table", source=str(study.path),
                         field="design")
    if validate is not None and validate < MIN_CONVERGED:
        raise InputError(f"must be >= {MIN_CONVERGED} (the statistics need at least "
                         f"{MIN_CONVERGED} converged trials), got {validate}",
                         field="--validate")
    if validate is not None:  # before the design's search, not after
        require("trials", validate, f"{validate:,} virtual tests asked for",
                field="--validate")
    res = design_plan(study.model, study.design, study.method, study.configurations[1:],
                      executor=executor)
    val = None
    if validate:
        val = validate_design(study.model, study.design, res, study.method, validate,
                              study.max_iterations, study.tolerance, seed, executor,
                              optimizer=study.optimizer)
    return StudyDesign(res, val)


@dataclass(frozen=True)
class StudyMonteCarlo(MonteCarloResult):
    """A study's Monte Carlo trials (:class:`MonteCarloResult`), and where and for how long
    they ran (wall time including starting and closing a cluster)."""

    executor: str = "in-process"
    wall_time_s: float = 0.0

    def run_info(self) -> dict:
        """Where and how long, as ``eigenupdate montecarlo`` prints and saves them."""
        return {"executor": self.executor, "wall_time_s": self.wall_time_s}


def montecarlo(study: Study, trials: int, *, truth: str | Path | None = None,
               seed: int | None = None, executor=None, scheduler: str | None = None,
               workers: int | None = None, in_process: bool | None = None,
               progress: Callable[[int, int], None] | None = None) -> StudyMonteCarlo:
    """``trials`` virtual tests of the study's plan (``eigenupdate montecarlo``): the truth
    drawn from the priors, or the values of the study file ``truth``; noise as the study's
    measurements or design say. ``progress(done, total)`` after each batch.

    ``executor`` runs the trials (the caller closes it); else ``in_process`` runs them
    here, or else they go to the Dask scheduler ``scheduler`` (or
    ``$EIGENUPDATE_SCHEDULER``), a local cluster of ``workers`` processes, or the automatic
    choice (:func:`eigenupdate.design.executor.executor_for`), closed here. ``in_process``
    defaults to True unless ``scheduler`` or ``workers`` is given.
    """
    from eigenupdate.design.executor import executor_for
    from eigenupdate.design.montecarlo import montecarlo as run
    from eigenupdate.design.montecarlo import study_setup

    if trials < MIN_CONVERGED:  # fewer could never give statistics: refused before running
        raise InputError(f"must be >= {MIN_CONVERGED} (the statistics need at least "
                         f"{MIN_CONVERGED} converged trials), got {trials}", field="--trials")
    require("trials", trials, f"{trials:,} virtual tests asked for", field="--trials")
    if executor is None:
        here = not (scheduler or workers) if in_process is None else in_process
        start = time.perf_counter()
        with executor_for(scheduler, here, workers) as ex:
            res = montecarlo(study, trials, truth=truth, seed=seed, executor=ex,
                             progress=progress)
        return replace(res, wall_time_s=time.perf_counter() - start)
    start = time.perf_counter()
    values = None
    if truth is not None:
        t = load_study(truth).model
        values = dict(zip(t.names, t.values.tolist(), strict=True))
    setup = study_setup(study, values, None if truth is None else str(truth))
    res = run(setup, trials, seed, executor, progress)
    if res.counts()[2] == trials:  # nothing ran: the plan or its data are refused
        raise InputError(res.refusal(), source=str(study.path))
    return StudyMonteCarlo(**{f.name: getattr(res, f.name) for f in fields(res)},
                           executor=repr(executor), wall_time_s=time.perf_counter() - start)


_DEFAULT_LOSS_FACTOR = 0.01  # as `eigenupdate frf` without --damping


def _same_data(res: UpdateResult, study: Study, path) -> None:
    """The saved update fitted the study's measurement file and added masses as they
    are now: a result of other data was shown beside the file's name, its 'measured'
    column not the file's (results saved before they recorded their additions are only
    checked against the file)."""
    now_adds = {c.name: c.listed() for c in study.configurations}
    for name, adds in res.perturbations.items():
        if now_adds.get(name) != adds:
            raise InputError(f"the saved update's configuration {name!r} added "
                             f"{adds} ([coordinate, mass, stiffness]); the study has "
                             f"{now_adds.get(name, 'no such configuration')}: a result of "
                             f"another version of the study; update again",
                             source=str(path), field=f"perturbations.{name}")
    updated = [p.name for p in study.model.parameters if p.update]
    if res.names != updated:
        raise InputError(f"the saved update updated {res.names}, the study updates "
                         f"{updated}: a result of another version of the study; update "
                         f"again", source=str(path), field="names")
    rows = {(c.name, k) for c in study.configurations for k in study.modes}
    if set(res.rows) != rows:
        diff = [f"{what} {shorten(str(sorted(v)), 80)}" for what, v in (
            ("also", set(res.rows) - rows), ("not", rows - set(res.rows))) if v]
        raise InputError(f"the saved update fitted other modes than the study uses "
                         f"({'; '.join(diff)}): a result of another version of the study; "
                         f"update again", source=str(path), field="frequencies")
    if study.frequencies is None or not Path(study.frequencies).is_file():
        return
    now = study.measurements()
    for (c, k), f in zip(res.rows, res.measured_hz.tolist(), strict=True):
        m = now.get((c, k))
        if m is None or not np.isclose(m.frequency_hz, f, rtol=1e-12, atol=0.0):
            got = "no row" if m is None else f"{m.frequency_hz!r} Hz"
            raise InputError(f"the saved update fitted {c!r} mode {k} at {f!r} Hz, "
                             f"{Path(study.frequencies).name} has {got}: a result of other "
                             f"data; update again", source=str(path), field="frequencies")


SAME_MODEL_RTOL = 1e-6
"""A saved update's initial frequencies and the study's model's agree to this: far above
the solvers' rounding (1e-8 relative on stiff models, README "Numerical notes") and far
below what an edit of the model does (a spring moved: several per cent)."""


def _same_model(res: UpdateResult, study: Study, path,
                configurations: Sequence[Configuration] | None = None) -> None:
    """The saved update started from the study's model as it is now (its rows of
    ``configurations``, default all): with the same initial values but a spring moved
    (k5 at [1, 4] for [2, 4]) the report drew the receptances and sweeps of values
    fitted to another model."""
    configs = list(configurations or study.configurations)
    rows = [(i, c, k) for i, (c, k) in enumerate(res.rows) if c in {x.name for x in configs}]
    if not rows:
        return
    top = max(k for _, _, k in rows)
    sols = dict(zip([c.name for c in configs], solve_configurations(study.model, configs, top),
                    strict=True))
    for i, c, k in rows:
        f = float(res.initial_hz[i])
        now = float(sols[c].frequencies_hz[k - 1])
        if not math.isclose(now, f, rel_tol=SAME_MODEL_RTOL):
            raise InputError(f"the saved update's initial model had {c!r} mode {k} at "
                             f"{f:.7g} Hz, the study's model has {now:.7g} Hz: a result of "
                             f"another version of the model; update again",
                             source=str(path), field="frequencies")


def report_data(study: Study, *, result: str | Path | None = None,
                extraction: str | Path | None = None, extracted: str | Path | None = None,
                design: str | Path | None = None, montecarlo: str | Path | None = None,
                solve: bool = True) -> ReportData:
    """Every number of the study's report: the saved results given (``update --save``,
    ``extract --save``, an extraction CSV, ``design --json``, ``montecarlo``'s
    summary.json), read through their classes' ``from_dict``; with ``solve``, what they do
    not give is computed here: the plan's identifiability, the extraction from the
    study's FRF files, the update, the receptances of Fig. 7 and the sweeps of Fig. 4.
    With ``solve`` false nothing is solved (the report of saved results only)."""
    from eigenupdate.design.plan import DesignResult
    from eigenupdate.io.report_inputs import read_extracted, read_summary
    from eigenupdate.report.data import ReportData

    files = [("study", study.path), *[("model", p) for p in study.model_files]]
    if study.frequencies is not None:
        files.append(("measurement", study.frequencies))
    files += [("FRF", p) for c in study.configurations for p in study.frf.get(c.name, [])]
    files += [(what, Path(p)) for what, p in (
        ("result", result), ("extraction", extraction), ("extraction CSV", extracted),
        ("design", design), ("Monte Carlo", montecarlo)) if p is not None]
    names = [c.name for c in study.configurations]
    out: dict = {"study": study, "files": files, "solved": solve}
    if extracted is not None:
        out.update(extracted=read_extracted(extracted, names),
                   extracted_name=Path(extracted).name)
    if extraction is not None:
        out["extraction"] = TestExtraction.from_dict(read_json(extraction), str(extraction))
    if study.frf and (extraction is not None or not solve):
        out["frfs"] = _study_frfs(study)  # read, for the fit plots: nothing is solved
        if extraction is not None:
            out["extraction"].require_frfs(out["frfs"], str(extraction))
    elif study.frf:
        done = extract_study(study)
        out.update(frfs=done.frfs, extraction=done.result)
    if result is not None:
        out.update(update=read_result(result, study.model),
                   update_origin="read from the saved result")
        _same_data(out["update"], study, result)
        if solve:
            _same_model(out["update"], study, result)
    elif solve and study.frequencies is not None and study.modes:
        study.measurements()  # a bad file stops the report
        try:
            out.update(update=update_study(study), update_origin=(
                "computed by this report (no saved result was given), with the study's "
                "settings"))
        except InputError as exc:  # e.g. a rank-deficient plan: the page says why
            out["update_origin"] = f"The update was not run: {exc}"
    if solve and study.modes:
        out["plan"] = check_study(study, "least-squares")  # the plan's own J, as the paper
        if study.method != "least-squares":
            out["seen"] = check_study(study)
    if solve:
        out.update(_predictions(study, out.get("update"), out.get("frfs", {}),
                                out.get("extraction"), out.get("extracted")))
    for key, title, path in (("design", "Test design", design),
                             ("montecarlo", "Monte Carlo summary", montecarlo)):
        if path is None:
            continue
        doc = read_summary(path)
        kind = DesignResult if key == "design" else MonteCarloResult
        if doc.get("schema") == kind.SCHEMA:
            out[key] = kind.from_dict(doc, str(path))
            updated = [p.name for p in study.model.parameters if p.update]
            if list(out[key].names) != updated:  # another study's, under this one's title
                raise InputError(f"is about parameters {shorten(str(out[key].names), 120)}, "
                                 f"the study updates {shorten(str(updated), 120)}: a result "
                                 f"of another study", source=str(path), field="names")
            out[f"{key}_name"] = Path(path).name
            if key == "design" and isinstance(doc.get("validation"), dict):
                out["validation"] = doc["validation"]
        else:  # any other JSON object: shown as it is
            out.setdefault("summaries", []).append((key, title, doc, Path(path).name))
    return ReportData(**out)


def _study_frfs(study: Study) -> dict[str, list[FRF]]:
    require_distinct(study.frf, str(study.path))
    return {c.name: read_frf_files(study.frf[c.name],
                                   [study.frf_kinds.get(p) for p in study.frf[c.name]])
            for c in study.configurations if study.frf.get(c.name)}


def _predictions(study: Study, res: UpdateResult | None, frfs: dict[str, list[FRF]],
                 extraction: TestExtraction | None, extracted) -> dict:
    """Fig. 7 (receptance of the base configuration at every measured FRF, initial and
    updated model) and Fig. 4 (a sweep of every perturbed coordinate up to twice its
    largest added mass), of the updated model when there is one."""
    base = study.configurations[0]
    eta, eta_text = _base_loss_factors(base.name, extraction, extracted)
    models = [study.model] + ([study.model.with_values(res.parameters)] if res else [])
    table = study.model.coordinate_table
    comparisons, skipped = [], []
    for x in frfs.get(base.name, []):
        label = f"{table.point_label(x.response)} / {table.point_label(x.reference)}"
        try:
            out, inp = (table.from_uff(p).number for p in (x.response, x.reference))
        except InputError:
            skipped.append(label)  # e.g. a CSV FRF, which names no points
            continue
        f = x.frequency_hz[x.frequency_hz > 0]
        curves = [receptance(m, f, inp, out, configuration=base, loss_factor=eta)
                  for m in models]
        comparisons.append(FrfComparison(
            base, f, curves[0], curves[1] if res else None, x,
            eta if isinstance(eta, list) else [eta],
            f"{base.name}: receptance {out}/{inp} ({label}), {eta_text}", inp, out))
    biggest: dict[int, float] = {}
    for c in study.configurations:
        for a in c.additions:
            if a.mass > 0:
                biggest[a.coordinate] = max(biggest.get(a.coordinate, 0.0), a.mass)
    values = res.parameters if res is not None else None
    sweeps = [mass_sweep(study.model, cd, 2.0 * m, max(study.modes or [3]), values=values)
              for cd, m in sorted(biggest.items())]
    return {"comparisons": comparisons, "not_compared": skipped, "loss_text": eta_text,
            "sweeps": sweeps}


def _base_loss_factors(base: str, extraction: TestExtraction | None, extracted
                       ) -> tuple[list[float] | float, str]:
    """Per-mode loss factors of the base configuration: extracted ones when known."""
    etas = {r.mode: r.loss_factor for r in extracted or [] if r.configuration == base}
    if etas.get(1) is None and extraction is not None:
        etas = {m.mode: m.loss_factor for ex in extraction.configurations
                if ex.configuration == base for m in ex.modes}
    out = []
    while etas.get(len(out) + 1) is not None:
        out.append(etas[len(out) + 1])
    if out:
        return out, "extracted loss factors " + ", ".join(f"{e:.3g}" for e in out)
    return _DEFAULT_LOSS_FACTOR, f"loss factor {_DEFAULT_LOSS_FACTOR:g} (none extracted)"


def report(study: Study, *, result: str | Path | None = None,
           extraction: str | Path | None = None, extracted: str | Path | None = None,
           design: str | Path | None = None, montecarlo: str | Path | None = None,
           solve: bool = True, command: str | None = None) -> str:
    """The study's self-contained HTML report (``eigenupdate report``): the numbers of
    :func:`report_data` drawn by :func:`eigenupdate.report.html.render_report`."""
    from eigenupdate.report.html import render_report

    return render_report(report_data(study, result=result, extraction=extraction,
                                     extracted=extracted, design=design,
                                     montecarlo=montecarlo, solve=solve), command=command)
