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

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from eigenupdate.errors import InputError
from eigenupdate.identify.checked import checked_update
from eigenupdate.identify.identifiability import IdentifiabilityReport, check
from eigenupdate.identify.updating import UpdateResult
from eigenupdate.identify.weights import estimator_weights
from eigenupdate.io.frf_files import read_frf_files
from eigenupdate.io.results import read_loss_factors, read_updated_values
from eigenupdate.io.study import Study
from eigenupdate.measure.frf import FRF
from eigenupdate.measure.measurement import Measurement
from eigenupdate.measure.survey import TestExtraction, extract_test
from eigenupdate.measure.synthetic import simulate_measurements, synthetic_frfs
from eigenupdate.model.configurations import Configuration
from eigenupdate.model.coordinates import CoordinateTable
from eigenupdate.solve.jacobian import solve_configurations
from eigenupdate.solve.response import receptance
from eigenupdate.solve.sweep import MassSweep, mass_sweep

if TYPE_CHECKING:  # design and report import Dask, jinja2, matplotlib: only when used
    from eigenupdate.design.montecarlo import MonteCarloResult
    from eigenupdate.design.plan import DesignResult
    from eigenupdate.design.validate import Validation


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
                   seed: int | None = None) -> list[Measurement]:
    """The measurements this study's model, taken as the truth, would give
    (``eigenupdate simulate``); see :func:`eigenupdate.measure.synthetic.simulate_measurements`."""
    return simulate_measurements(study.model, study.configurations, study.require_modes(),
                                 noise_hz=noise_hz, std_hz=std_hz, seed=seed)


@dataclass(frozen=True)
class StudyExtraction:
    """The FRFs read for each configuration and what was extracted from them."""

    frfs: dict[str, list[FRF]]
    result: TestExtraction


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
    frfs = {c.name: read_frf_files(study.frf[c.name],
                                   [study.frf_kinds.get(p) for p in study.frf[c.name]])
            for c in study.configurations}
    res = extract_test(frfs, model=study.model, configurations=study.configurations,
                       used_modes=study.modes, bands_hz=study.bands_hz,
                       exclude_below_hz=study.exclude_below_hz, progress=progress)
    return StudyExtraction(frfs, res)


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
    frfs = {p.stem: read_frf_files([p], [kind]) for p in paths}
    return StudyExtraction(frfs, extract_test(frfs, progress=progress))


def simulate_study_frfs(study: Study, frequency_hz: np.ndarray, excitation: int,
                        outputs: Sequence[int], loss_factor: float | Sequence[float],
                        noise: float = 0.01,
                        seed: int | None = None) -> list[tuple[Configuration, list[FRF]]]:
    """Synthetic noisy FRFs of every configuration (``eigenupdate simulate-frf``), one
    random stream for all of them."""
    if len(set(outputs)) != len(outputs):
        raise InputError(f"coordinates repeated in {list(outputs)}", field="--outputs")
    rng = np.random.default_rng(seed)
    return [(c, synthetic_frfs(study.model, c, frequency_hz, excitation, outputs, loss_factor,
                               noise=noise, seed=rng))
            for c in study.configurations]


@dataclass(frozen=True)
class FrfComparison:
    """Predicted receptance of the initial (and updated) model, and the measured one."""

    configuration: Configuration
    frequency_hz: np.ndarray
    initial: np.ndarray
    updated: np.ndarray | None
    measured: FRF | None
    loss_factors: list[float]
    title: str


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
        models.append(study.model.with_values(read_updated_values(updated, study.model)))
    curves = [receptance(m, f, excitation, response, configuration=config,
                         loss_factor=eta if damping else loss_factor) for m in models]
    return FrfComparison(
        config, f, curves[0], curves[1] if updated else None, frf, eta,
        f"{study.title}\n{config.name}: receptance {response}/{excitation}, {eta_text}")


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
           executor=None) -> StudyDesign:
    """The added masses the study's ``[design]`` table asks for (``eigenupdate design``),
    then ``validate`` virtual tests of that plan (truth drawn from the prior) if given.

    ``executor`` screens the candidates and runs the trials (default: this process); see
    :mod:`eigenupdate.design.executor`. The caller closes it.
    """
    from eigenupdate.design.plan import design_plan
    from eigenupdate.design.validate import validate_design

    if study.design is None:
        raise InputError("the study has no [design] table", source=str(study.path),
                         field="design")
    if validate is not None and validate < 2:
        raise InputError(f"must be >= 2, got {validate}", field="--validate")
    res = design_plan(study.model, study.design, study.method, study.configurations[1:],
                      executor=executor)
    val = None
    if validate:
        val = validate_design(study.model, study.design, res, study.method, validate,
                              study.max_iterations, study.tolerance, seed, executor,
                              optimizer=study.optimizer)
    return StudyDesign(res, val)


def montecarlo(study: Study, trials: int, *, truth: str | Path | None = None,
               seed: int | None = None, executor=None,
               progress: Callable[[int, int], None] | None = None) -> MonteCarloResult:
    """``trials`` virtual tests of the study's plan (``eigenupdate montecarlo``): the truth
    drawn from the priors, or the values of the study file ``truth``; noise as the study's
    measurements or design say. ``executor`` as in :func:`design` (default: this process);
    ``progress(done, total)`` after each batch."""
    from eigenupdate.design.montecarlo import montecarlo as run
    from eigenupdate.design.montecarlo import study_setup

    if trials < 1:
        raise InputError(f"must be >= 1, got {trials}", field="--trials")
    setup = study_setup(study, None if truth is None else str(truth))
    return run(setup, trials, seed, executor, progress)


def report(study: Study, *, result: str | Path | None = None,
           extracted: str | Path | None = None, design: str | Path | None = None,
           montecarlo: str | Path | None = None, command: str | None = None) -> str:
    """The study's self-contained HTML report (``eigenupdate report``) from the saved
    files of the other commands (without ``result``, the report runs the update); see
    :func:`eigenupdate.report.html.render_report`."""
    from eigenupdate.report.html import render_report

    return render_report(study.path, result=result, extracted=extracted, design=design,
                         montecarlo=montecarlo, command=command)
