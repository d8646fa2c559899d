"""One self-contained HTML report of a study: what was tested, what was updated and how
well the updated model predicts.

:func:`render_report` draws the results :func:`eigenupdate.workflow.report_data` read or
computed (:class:`~eigenupdate.report.data.ReportData`) with matplotlib as SVG and renders
``templates/report.html.j2`` with Jinja2; it computes nothing itself. Figures are base64
``data:`` URIs and the stylesheet is inlined, so the page needs no network, no script and
no font file: it can be mailed or opened from a share, and printed to PDF (sections start
on a new page, figures and table rows are not split).

Sections appear when their data exist:

* the study and the identifiability of its plan - always (the plan at the initial model
  when the report solved, else the saved update's check at its solution);
* the FRF extraction - from the study's FRF files or a saved extraction, and an
  extraction CSV (its table is then shown as the numbers the update used);
* the update - from a saved result or run by the workflow;
* the FRF comparison (paper Fig. 7) of the base configuration at every measured
  response point, and the mass sweep (Fig. 4) of every perturbed coordinate;
* the test design and the Monte Carlo virtual tests (their JSON), or any other JSON
  object, rendered generically;
* provenance - package version, SHA-256 of every input file, date, command.
"""

from __future__ import annotations

import hashlib
import math
import os
import shlex
import sys
from datetime import UTC, datetime
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import Any

import jinja2

from eigenupdate.design.montecarlo import MonteCarloResult
from eigenupdate.design.plan import DesignResult
from eigenupdate.identify.identifiability import IdentifiabilityReport
from eigenupdate.identify.updating import UpdateResult
from eigenupdate.io.report_inputs import ExtractedRow
from eigenupdate.io.study import Study
from eigenupdate.measure.extraction import DISAGREEMENT_WARNING
from eigenupdate.measure.frf import FRF
from eigenupdate.plot.plots import plot_extraction_fit, plot_frf_comparison, plot_mass_sweep
from eigenupdate.report import figures
from eigenupdate.report.data import ReportData
from eigenupdate.report.page import Section, figure_image, plot_image, table

GENERATOR = '<meta name="generator" content="eigenupdate report">'
"""A line of the template's head: what makes a page an earlier output of ``report -o``."""


PathLike = str | os.PathLike
TEMPLATES = Path(__file__).with_name("templates")


def _sha256(path: PathLike) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


# ---------------------------------------------------------------------- sections


def _study_section(study: Study) -> Section:
    model = study.model
    n_upd = len(model.updated)
    sec = Section("study", "The study")
    meas = []
    if study.frequencies is not None:
        meas.append(f"frequencies from {study.frequencies.name}")
    if study.frf:
        n_files = sum(len(v) for v in study.frf.values())
        meas.append(f"FRFs in {n_files} file(s) for {len(study.frf)} configuration(s)")
    sec.facts = [
        ("title", study.title),
        ("study file", study.path.name),
        ("model", f"{study.model_type}, {model.n} coordinates"),
        ("parameters", f"{len(model.parameters)} ({n_upd} updated)"),
        ("configurations", f"{len(study.configurations)} (base + "
                           f"{len(study.configurations) - 1} perturbed)"),
        ("elastic modes used", ", ".join(map(str, study.modes)) or "none given"),
        ("measurement", "; ".join(meas) or "none"),
        ("method", f"{study.method}, at most {study.max_iterations} iterations, "
                   f"tolerance {study.tolerance:g}"),
    ]
    # a NASTRAN deck has no units: its own, masses after WTMASS (README, "Units")
    deck = study.model_type == "nastran"
    sec.blocks.append(table(
        "Parameters of the initial model (" + ("the deck's units" if deck else "SI units") + ")",
        ["parameter", "unit", "initial value", "prior std", "updated"],
        [[p.name, p.unit or None, p.value, p.std, p.update] for p in model.parameters],
        "parameters"))
    rows = []
    for c in study.configurations:
        if not c.additions:
            rows.append([c.name, "-", None, None])
        for a in c.additions:
            rows.append([c.name, a.coordinate, a.mass or None, a.stiffness or None])
    sec.blocks.append(table(
        "Test configurations: known masses and grounded springs added, in the deck's mass "
        "and force per length units (coordinate = 10 x GRID + component)" if deck else
        "Test configurations: known masses (kg; kg m^2 on a rotation) and grounded "
        "springs (N/m) added", ["configuration", "coordinate", "added mass", "added stiffness"],
        rows, "configurations"))
    return sec


def _weakest_in_words(r: IdentifiabilityReport) -> str:
    big = {k: v for k, v in r.weakest.items() if abs(v) >= 0.2} or dict(
        list(r.weakest.items())[:1])
    terms = " ".join(f"{'-' if v < 0 else '+'} {abs(v):.2f} {k}" for k, v in big.items())
    up = [k for k, v in big.items() if v > 0]
    down = [k for k, v in big.items() if v < 0]
    move = f"raising {', '.join(up)}" if up else ""
    if down:
        move += f"{' while ' if up else ''}lowering {', '.join(down)}"
    rest = len(r.weakest) - len(big)
    others = f", plus {rest} smaller weights in the table" if rest else ""
    return (f"The combination the plan determines worst is {terms.lstrip('+ ')}{others} "
            f"(parameters relative to their initial values): {move} in these proportions "
            f"changes the eigenvalues least.")


def _identifiability_section(data: ReportData) -> Section | None:
    r = data.plan or (data.update.identifiability if data.update is not None else None)
    if r is None:
        return None
    study = data.study
    p = len(r.parameters)
    sec = Section("identifiability", "Identifiability of the test plan")
    verdict = ("every updated parameter is identifiable (J^T J has full rank)"
               if r.identifiable else
               f"NOT identifiable: rank {r.rank} < {p} parameters; only the prior std of "
               "the Bayesian estimator can make up for it, other methods refuse the update")
    where = ("at the initial model" if data.plan is not None else
             f"at the saved update's solution, weighted as the {data.update.method} "
             f"estimator weights it ({r.weighting})")
    sec.paragraphs = [
        f"{r.equations} equations (configurations x modes) for {p} updated parameters: "
        f"{verdict}. J is the sensitivity of the eigenvalues to the parameters normalised by "
        f"their initial values, {where}.",
        _weakest_in_words(r),
    ]
    sec.facts = [
        ("equations", str(r.equations)),
        ("updated parameters", str(p)),
        ("rank of J", str(r.rank)),
        ("condition of J", f"{r.condition_J:.3g}"),
        ("condition of J^T J", f"{r.condition_JTJ:.3g}"),
    ]
    seen = data.seen
    if seen is not None:
        sec.facts += [
            (f"as the {study.method} estimator sees it",
             f"J weighted by {seen.weighting}: rank {seen.rank}, condition of J "
             f"{seen.condition_J:.3g}, of J^T J {seen.condition_JTJ:.3g}")]
    sec.blocks.append(figure_image(
        figures.singular_values_figure(r.singular_values),
        "Singular values of J, descending ((rad/s)^2 per unit relative change)",
        "singular values"))
    sec.blocks.append(table(
        "Weakest combination: right singular vector of the smallest singular value",
        ["parameter", "weight"], [[k, v] for k, v in r.weakest.items()], "weakest"))
    return sec


def _frf_label(study: Study, x: FRF) -> str:
    coords = study.model.coordinate_table
    return f"{coords.point_label(x.response)} / {coords.point_label(x.reference)}"


def _extraction_section(data: ReportData) -> Section | None:
    study, fitted, extracted = data.study, data.extraction, data.extracted
    extracted_name = data.extracted_name
    if fitted is None and extracted is None:
        return None
    sec = Section("extraction", "Measured FRFs and modal extraction")
    intro = []
    if fitted is not None:
        intro.append("Fitted from the study's FRF files with the method of 'eigenupdate "
                     "extract': Dobson's inverse-receptance line fit (hysteretic damping) in "
                     "each resonance band, the FRFs of a configuration combined by inverse "
                     "variance, a rational-fraction fit as an independent cross-check, "
                     f"modes numbered by {fitted.numbered_by}.")
    if extracted is not None:
        intro.append(f"The mode tables show {extracted_name}, the extraction the update read.")
    intro.append(f"'diff/std' is the Dobson - rational-fraction difference in combined "
                 f"standard deviations (flagged above {DISAGREEMENT_WARNING:g}); 'fit R2' the "
                 "fit quality. 'not used' marks modes the study does not use; 'no peak in' "
                 "lists the FRFs in which a mode was not fitted (a response point near its "
                 "node). Rejected candidates are resonances that are not modes, with the "
                 "reason.")
    sec.paragraphs = [" ".join(intro)]
    if fitted is not None and fitted.problems:
        sec.paragraphs.append("WARNING: " + "; ".join(fitted.problems) + ".")
    used = set(study.modes)
    by_cfg: dict[str, list[ExtractedRow]] = {}
    for row in extracted or []:
        by_cfg.setdefault(row.configuration, []).append(row)
    results = {ex.configuration: ex for ex in fitted.configurations} if fitted else {}
    notes = []
    for c in study.configurations:
        part = Section(f"extraction-{len(sec.parts) + 1}", c.name)
        ex = results.get(c.name)
        frfs = data.frfs.get(c.name, []) if fitted else []
        modes = ex.modes if ex else []
        fits = {m.mode: m for m in modes}
        if ex is not None:
            part.paragraphs = [f"{ex.line_spacing_hz:.4g} Hz lines, {ex.frequency_range_hz[0]:.5g}"
                               f"-{ex.frequency_range_hz[1]:.5g} Hz; {len(frfs)} FRF(s)"
                               + "".join(f"; {n}" for n in ex.notes) + "."]
            part.paragraphs += [f"Model mode {k} ({f:.6g} Hz) expected, not found."
                                for k, f in ex.missing]
            part.paragraphs += [f"Unexpected resonance at {m.frequency_hz:.6g} Hz: no model "
                                "mode explains it." for m in ex.unexpected]
        rows = by_cfg.get(c.name) if extracted is not None else [
            ExtractedRow(m.configuration, m.mode, m.frequency_hz, m.std_hz, m.loss_factor,
                         m.loss_factor_std, m.check_hz, m.check_std_hz) for m in modes]
        table_rows = []
        for r in rows or []:
            d = r.disagreement
            flags = []
            if r.mode not in used:
                flags.append("not used")
            if d is not None and d > DISAGREEMENT_WARNING:
                flags.append(f"methods differ by {d:.1f} std")
            m = fits.get(r.mode)
            if m is not None:
                if m.under_resolved:
                    flags.append("under-resolved")
                missing = [_frf_label(study, x)
                           for x, ft in zip(frfs, m.fits, strict=True) if ft is None]
                if missing:
                    flags.append("no peak in " + ", ".join(missing))
                if extracted is not None and not math.isclose(m.frequency_hz, r.frequency_hz,
                                                              rel_tol=1e-9):
                    notes.append(f"{c.name} mode {r.mode}: {extracted_name} has "
                                 f"{r.frequency_hz:.6g} Hz, the FRF files give "
                                 f"{m.frequency_hz:.6g} Hz")
            table_rows.append([r.mode, r.frequency_hz, r.std_hz, r.loss_factor,
                               r.loss_factor_std, m.fit_quality if m else None, r.check_hz, d,
                               m.model_hz if m else None, "; ".join(flags) or None])
        if table_rows:
            part.blocks.append(table(
                f"{c.name}: fitted modes",
                ["mode", "f Hz", "std Hz", "loss factor", "loss factor std", "fit R2",
                 "check f Hz", "diff/std", "model Hz", "remarks"], table_rows, "extraction"))
        if ex is not None and ex.rejected:
            part.blocks.append(table(
                f"{c.name}: rejected candidates",
                ["f Hz", "band from Hz", "band to Hz", "reason"],
                [[r.frequency_hz, r.band_hz[0], r.band_hz[1], r.reason] for r in ex.rejected],
                "rejected"))
        for j, x in enumerate(frfs):
            shown = [m for m in modes if m.fits[j] is not None and m.mode in used]
            if not shown:
                continue
            title = f"{c.name}: {_frf_label(study, x)}"
            img, _ = plot_image(
                plot_extraction_fit, f"{title}: fitted modes against the measured receptance",
                f"extraction fit {title}", x.frequency_hz, x.receptance,
                [m.fits[j] for m in shown], mode_numbers=[m.mode for m in shown], title=title)
            part.blocks.append(img)
        if part.blocks:
            sec.parts.append(part)
    if notes:
        sec.paragraphs.append("WARNING: the extraction file does not match the study's FRF "
                              "files: " + "; ".join(notes) + ".")
    return sec


def _update_section(study: Study, res: UpdateResult, origin: str) -> Section:
    model = study.model
    initial = dict(zip(model.names, model.values.tolist(), strict=True))
    names = [n for n in model.names if n in res.std]
    sec = Section("update", "The update")
    status = "converged" if res.success else "DID NOT CONVERGE"
    sec.paragraphs = [
        f"{res.method}, {status} after {res.nit} iteration(s) "
        f"({res.message.removeprefix('converged: ')}); {origin}.",
        "Change % is relative to the initial value; the posterior std is that of the "
        "estimator (a parameter without a defined std shows '-').",
    ]
    rows = []
    for n in names:
        v0, v = initial[n], res.parameters[n]
        rows.append([n, res.units.get(n), v0, v, None if v0 == 0 else 100.0 * (v - v0) / v0,
                     res.std.get(n)])
    sec.blocks.append(table("Parameters: initial, updated, change and posterior std",
                             ["parameter", "unit", "initial", "updated", "change %",
                              "posterior std"],
                             rows, "parameters-updated"))
    if any(initial[n] != 0 for n in names):
        sec.blocks.append(figure_image(
            figures.parameter_change_figure(names, initial, res.parameters, res.std),
            "Change of each updated parameter (% of initial) with +-1 posterior std "
            "(parameters starting at 0 are in the table only)", "parameter changes"))
    history = [h.parameters for h in res.history]
    sec.blocks.append(table(
        "Iterations (0 is the initial model): objective, fraction of the Gauss-Newton step "
        "taken, note", ["iteration", "objective", "step", "note"],
        [[h.iteration, h.objective, h.step, h.kind.value or None] for h in res.history],
        "steps"))
    sec.blocks.append(table(
        "Parameter values at each iteration",
        ["parameter", *[f"it. {i}" for i in range(len(history))]],
        [[n, *[h[n] for h in history]] for n in names], "history"))
    sec.blocks.append(figure_image(
        figures.history_figure([h.objective for h in res.history], history, names),
        "Objective and parameters (relative to initial) against iteration", "history"))
    fr = list(zip(res.rows, res.measured_hz.tolist(), res.initial_hz.tolist(),
                  res.updated_hz.tolist(), strict=True))
    sec.blocks.append(table(
        "Natural frequencies: measured, initial and updated model (Hz), errors in %",
        ["configuration", "mode", "measured", "initial", "updated", "initial error %",
         "updated error %"],
        [[c, k, m, i, u, 100 * (i - m) / m, 100 * (u - m) / m] for (c, k), m, i, u in fr],
        "frequencies"))
    sec.blocks.append(figure_image(
        figures.frequency_error_figure(
            [f"{c} / {k}" for (c, k), *_ in fr], [m for _, m, _, _ in fr],
            [i for _, _, i, _ in fr], [u for *_, u in fr]),
        "Model minus measured frequency in % of measured: initial model, updated model "
        "(each panel on its own scale)", "frequency errors"))
    return sec


def _comparison_section(data: ReportData) -> Section | None:
    if not data.solved:
        return None
    res = data.update
    sec = Section("comparison", "Predicted against measured")
    for c in data.comparisons:
        img, _ = plot_image(plot_frf_comparison, f"Paper Fig. 7: {c.title}",
                             f"FRF comparison {c.response}/{c.excitation}", None,
                             measured=c.measured,
                             initial=(c.frequency_hz, c.initial),
                             updated=None if c.updated is None else (c.frequency_hz,
                                                                    c.updated),
                             title=c.title)
        sec.blocks.append(img)
    intro = ["Receptance of the base configuration at every measured response point: "
             "measured, initial model" + (" and updated model" if res else "") + "."]
    if data.not_compared:
        intro.append("Not compared (no model coordinate in the file): "
                     f"{', '.join(data.not_compared)}.")
    if not data.comparisons and not data.not_compared:
        intro = ["No measured FRFs in the study: no receptance comparison."]
    which = "updated" if res is not None else "initial"
    for sweep in data.sweeps:
        cd = sweep.coordinate.number
        img, _ = plot_image(plot_mass_sweep, f"Paper Fig. 4: mass added at coordinate {cd}",
                             f"mass sweep {cd}", sweep, title=f"{which} model")
        sec.blocks.append(img)
    if data.sweeps:
        intro.append(f"Mass sweeps (paper Fig. 4): natural frequencies of the {which} model "
                     "against the mass added at each perturbed coordinate, up to twice the "
                     "largest mass added there in the test.")
    sec.paragraphs = [" ".join(intro)]
    return sec


def _design_section(d: DesignResult, validation: dict | None, initial: dict[str, float],
                    name: str, units: dict[str, str]) -> Section:
    """A test design (``eigenupdate design --json``, optionally with ``--validate``): the
    plan with its shifts and mode gaps, the predicted accuracy per parameter (over the
    prior, with its Monte Carlo error, and at the prior mean), and the validation."""
    sec = Section("design", "Test design")
    crit = d.criterion if isinstance(d.criterion, str) else list(d.criterion)
    sec.paragraphs = [
        f"From {name}: {len(d.chosen)} configuration(s) chosen by criterion "
        f"{crit} for the {d.method} estimator, modes {', '.join(map(str, d.modes))}. "
        + (f"The predicted accuracy is averaged over {d.draws} draws of the truth from the "
           f"prior ({d.draw_seconds:.1f} s), with its Monte Carlo error; "
           f"the linearised figure at the prior mean stands beside it."
           if d.draws else "The predicted accuracy is linearised at the prior mean.")]
    sec.blocks.append(table(
        "Designed plan: bare minus perturbed frequency of each used mode (Hz), the largest "
        "shift in measurement std, the smallest relative gap of a used mode to its "
        "neighbours, and the fraction of the prior's draws that reorder or crowd a used mode",
        ["configuration", *[f"shift {k}" for k in d.modes], "shift / std", "min gap",
         "order kept", "exchange risk"],
        [[c.configuration.name, *c.shifts_hz, c.shift_in_std, c.relative_gap, c.order_kept,
          c.exchange_risk] for c in (d.candidates[i] for i in d.chosen)],
        "design-plan"))
    plan = d.plans[0]
    sec.blocks.append(table(
        "Predicted std of each updated parameter for the plans compared",
        ["parameter", "unit", "initial", *[p.label for p in d.plans],
         "+- (designed)", "at prior mean (designed)"],
        [[n, units.get(n) or None, initial.get(n), *[p.std[n] for p in d.plans],
          plan.std_error.get(n), plan.linear_std.get(n)] for n in plan.std]
        + [["risk of reordered or crowded modes", None, None,
            *[p.gross_risk for p in d.plans], None, None]],
        "design-accuracy"))
    val = validation
    if val:
        sec.blocks.append(table(
            f"Validation: {val['trials']} virtual tests of the designed plan ("
            f"{val['converged']} converged, {val['not_converged']} not converged, "
            f"{val['refused']} refused): predicted against empirical std",
            ["parameter", "predicted", "+-", "empirical", "empirical / predicted",
             "at prior mean", "coverage 2 std"],
            [[n, v["predicted_std"], v["predicted_std_error"], v["empirical_std"],
              (v["empirical_std"] / v["predicted_std"]) if v["empirical_std"] is not None
              else None, v["linear_std"], v["coverage_2std"]]
             for n, v in val["parameters"].items()],
            "design-validation"))
    return sec


def _montecarlo_section(r: MonteCarloResult, name: str) -> Section:
    """Virtual tests (``eigenupdate montecarlo``): counts, and per parameter the bias,
    empirical against predicted std and the coverage of the reported std."""
    s = r.summary()
    sec = Section("montecarlo", "Monte Carlo virtual tests")
    sec.paragraphs = [f"From {name}: {s['trials']} virtual tests, {s['converged']} converged, "
                      f"{s['not_converged']} not converged, {s['refused']} refused; seed "
                      f"entropy {s['seed_entropy']}."]
    if s["statistics_refused"] is not None:
        sec.paragraphs.append(f"WARNING: no statistics: {s['statistics_refused']}.")
        return sec
    sec.blocks.append(table(
        "Per parameter: bias and empirical std of the error over the converged trials, the "
        "predicted std (+- its Monte Carlo error), the linearised std and the fraction of "
        "trials within 2 reported std of the truth",
        ["parameter", "bias", "empirical std", "predicted std", "+-", "emp / pred",
         "linear std", "coverage 2 std"],
        [[n, p["bias"], p["empirical_std"], p["predicted_std"], p["predicted_std_error"],
          p["ratio_empirical_to_predicted"], p["linear_std"], p["coverage_2std"]]
         for n, p in s["parameters"].items()], "montecarlo"))
    return sec


def _summary_section(key: str, title: str, doc: dict, name: str) -> Section:
    """A JSON object rendered generically: scalars as one key/value table, a list of
    objects as a table (columns = their keys), an object of objects as a table (one row
    per key), another object as a key/value table; deeper values as compact JSON text."""
    import json

    def short(v: Any) -> Any:  # 6 significant digits inside nested values, as in cells
        if isinstance(v, float):
            return float(f"{v:.6g}")
        if isinstance(v, dict):
            return {k: short(x) for k, x in v.items()}
        return [short(x) for x in v] if isinstance(v, list) else v

    def text(v: Any) -> Any:
        if isinstance(v, str | int | float | bool) or v is None:
            return v
        return json.dumps(short(v), separators=(", ", ": "))

    sec = Section(key, title)
    sec.paragraphs = [f"From {name}, shown generically: the report does not interpret this "
                      "file's keys."]
    scalars = [[k, text(v)] for k, v in doc.items() if not isinstance(v, dict | list)
               or (isinstance(v, list) and not all(isinstance(i, dict) for i in v))
               or (isinstance(v, list) and not v)]
    if scalars:
        sec.blocks.append(table(title, ["key", "value"], scalars, "summary"))
    for k, v in doc.items():
        if isinstance(v, list) and v and all(isinstance(i, dict) for i in v):
            cols = list(dict.fromkeys(c for i in v for c in i))
            sec.blocks.append(table(k, cols, [[text(i.get(c)) for c in cols] for i in v],
                                     "summary"))
        elif isinstance(v, dict) and v and all(isinstance(i, dict) for i in v.values()):
            cols = list(dict.fromkeys(c for i in v.values() for c in i))
            sec.blocks.append(table(k, ["", *cols],
                                     [[a, *[text(i.get(c)) for c in cols]] for a, i in v.items()],
                                     "summary"))
        elif isinstance(v, dict):
            sec.blocks.append(table(k, ["key", "value"], [[a, text(b)] for a, b in v.items()],
                                     "summary"))
    return sec


# ------------------------------------------------------------------------- public


def _package_version() -> str:
    try:
        return version("eigenupdate")
    except PackageNotFoundError:  # running from a source tree
        return "unknown"


def render_report(data: ReportData, *, command: str | None = None,
                  now: datetime | None = None) -> str:
    """The report of ``data`` as one HTML document (see the module notes for the sections).

    Parameters
    ----------
    data : the numbers, from :func:`eigenupdate.workflow.report_data`.
    command : the command line, for the provenance (default: ``sys.argv``).
    now : the report's date (default: now, UTC).

    Examples
    --------
    >>> from eigenupdate.workflow import report_data
    >>> from eigenupdate.io.study import load_study
    >>> data = report_data(load_study("examples/paper_fig2/study.toml"))
    >>> page = render_report(data, now=datetime(2026, 1, 1))
    >>> page.startswith("<!DOCTYPE html>"), page.count("<table"), "http" in page
    (True, 10, False)
    """
    study = data.study
    initial = dict(zip(study.model.names, study.model.values.tolist(), strict=True))
    update = data.update
    sections = [_study_section(study)]
    for s in (_identifiability_section(data), _extraction_section(data),
              _update_section(study, update, data.update_origin) if update is not None else
              (Section("update", "The update", paragraphs=[data.update_origin])
               if data.update_origin else None),
              _comparison_section(data),
              _design_section(data.design, data.validation, initial, data.design_name,
                              study.model.units)
              if data.design is not None else None,
              _montecarlo_section(data.montecarlo, data.montecarlo_name)
              if data.montecarlo is not None else None):
        if s is not None:
            sections.append(s)
    sections += [_summary_section(*s) for s in data.summaries]
    stamp = (now or datetime.now(UTC)).strftime("%Y-%m-%d %H:%M:%S %Z").strip()
    provenance = [
        ("eigenupdate version", _package_version()),
        ("date", stamp),
        ("command", command if command is not None else shlex.join(sys.argv)),
        *[(f"{what} file", f"{Path(p).name}  SHA-256 {_sha256(p)}") for what, p in data.files],
    ]
    env = jinja2.Environment(loader=jinja2.FileSystemLoader(TEMPLATES),
                             autoescape=True, undefined=jinja2.StrictUndefined,
                             trim_blocks=True, lstrip_blocks=True)
    return env.get_template("report.html.j2").render(
        title=study.title, sections=sections, provenance=provenance,
        stylesheet=(TEMPLATES / "report.css").read_text(encoding="utf-8"))
