"""What the HTML report shows, as typed results (and :class:`FrfComparison`, the
result of :func:`eigenupdate.workflow.compare_frf`): :func:`eigenupdate.workflow.report_data`
reads or computes them, :func:`eigenupdate.report.html.render_report` only draws them."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:  # types only: this module imports nothing heavy
    from eigenupdate.design.montecarlo import MonteCarloResult
    from eigenupdate.design.plan import DesignResult
    from eigenupdate.identify.identifiability import IdentifiabilityReport
    from eigenupdate.identify.updating import UpdateResult
    from eigenupdate.io.report_inputs import ExtractedRow
    from eigenupdate.io.study import Study
    from eigenupdate.measure.frf import FRF
    from eigenupdate.measure.survey import TestExtraction
    from eigenupdate.model.configurations import Configuration
    from eigenupdate.solve.sweep import MassSweep


@dataclass(frozen=True)
class ReportData:
    """Every number of the report.

    Attributes
    ----------
    study : the study (its description tables).
    plan : identifiability of the plan at the initial model, unweighted (the paper's J);
        ``seen`` as the study's estimator weights it (None: the same, or not computed).
    extraction, frfs : the modal extraction and the FRFs it was made from, by configuration.
    extracted, extracted_name : rows of an extraction CSV and its file name.
    update, update_origin : the update's result and where it comes from (or why none).
    comparisons, not_compared, loss_text : Fig. 7: predicted against measured receptance
        of the base configuration; FRFs without model coordinates; the damping used.
    sweeps : Fig. 4: frequencies against the mass added at each perturbed coordinate.
    design, validation : a test design and its virtual tests (``design --json``).
    montecarlo : the virtual tests of ``montecarlo -o``.
    summaries : other JSON objects given, rendered generically: (key, title, doc, name).
    files : every input file, (what, path), hashed in the provenance.
    solved : False when the report was asked to solve nothing (saved results only).
    """

    study: Study
    plan: IdentifiabilityReport | None = None
    seen: IdentifiabilityReport | None = None
    extraction: TestExtraction | None = None
    frfs: dict[str, list[FRF]] = field(default_factory=dict)
    extracted: list[ExtractedRow] | None = None
    extracted_name: str | None = None
    update: UpdateResult | None = None
    update_origin: str = ""
    comparisons: list[FrfComparison] = field(default_factory=list)
    not_compared: list[str] = field(default_factory=list)
    loss_text: str = ""
    sweeps: list[MassSweep] = field(default_factory=list)
    design: DesignResult | None = None
    design_name: str | None = None
    validation: dict | None = None
    montecarlo: MonteCarloResult | None = None
    montecarlo_name: str | None = None
    summaries: list[tuple[str, str, dict[str, Any], str]] = field(default_factory=list)
    files: list[tuple[str, Path]] = field(default_factory=list)
    solved: bool = True


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
    excitation: int
    response: int
