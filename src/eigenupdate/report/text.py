"""Plain-text tables and JSON documents for the command line."""

from __future__ import annotations

import json
import math
import sys
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # types only: the command line imports this module before any command
    from eigenupdate.identify.identifiability import IdentifiabilityReport
    from eigenupdate.identify.updating import UpdateResult
    from eigenupdate.measure.survey import TestExtraction


def table(header: Sequence[str], rows: Sequence[Sequence[Any]]) -> str:
    """Right-aligned text table; floats printed with 6 significant digits."""

    def fmt(v: Any) -> str:
        if v is None:
            return "-"
        if isinstance(v, float):
            return f"{v:.6g}" if math.isfinite(v) else str(v)
        return str(v)

    cells = [[fmt(v) for v in r] for r in rows]
    widths = [max([len(h), *(len(r[i]) for r in cells)]) for i, h in enumerate(header)]
    lines = ["  ".join(h.rjust(w) for h, w in zip(header, widths, strict=True))]
    lines.append("  ".join("-" * w for w in widths))
    lines += ["  ".join(c.rjust(w) for c, w in zip(r, widths, strict=True)) for r in cells]
    return "\n".join(lines)


def _clean(obj: Any) -> Any:
    """JSON has no NaN or infinity: write null."""
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        return {k: _clean(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_clean(v) for v in obj]
    return obj


def dumps(doc: dict) -> str:
    return json.dumps(_clean(doc), indent=2)


def check_text(r: IdentifiabilityReport, title: str) -> str:
    p = len(r.parameters)
    verdict = (
        "all parameters identifiable" if r.identifiable
        else f"NOT identifiable: rank {r.rank} < {p} parameters"
    )
    lines = [
        f"{title}: identifiability of the test plan",
        f"  updated parameters   {p}",
        f"  equations            {r.equations}",
        f"  weights besides J    {r.weighting}",
        f"  rank of J            {r.rank}   ({verdict})",
        f"  condition of J       {r.condition_J:.3g}",
        f"  condition of J^T J   {r.condition_JTJ:.3g}",
        "",
        "Worst-determined parameter combination (smallest singular vector):",
        table(["parameter", "weight"], [[k, v] for k, v in r.weakest.items() if abs(v) >= 0.05]),
        "",
        "Singular values of J: " + ", ".join(f"{s:.3g}" for s in r.singular_values),
    ]
    return "\n".join(lines)


def _pct(x: float | None) -> str:
    return "-" if x is None or not math.isfinite(x) else f"{x:+.3f}"


def _sig3(x: float | None) -> str:
    return "-" if x is None or not math.isfinite(x) else f"{x:.3g}"


def update_text(r: UpdateResult, initial: dict[str, float], title: str) -> str:
    head = f"{title}: {r.method} ({r.optimizer}), {r.message} after {r.nit} iteration(s)"
    params = table(
        ["parameter", "unit", "initial", "updated", "std", "change %"],
        [[n, r.units.get(n, "-"), initial[n], v, _sig3(r.std.get(n)),
          _pct(100 * (v - initial[n]) / initial[n] if initial[n] else None)]
         for n, v in r.parameters.items() if n in r.std],
    )
    steps = table(
        ["iteration", "objective", "step", "note"],
        [[h.iteration, _sig3(h.objective), h.step, h.kind.value] for h in r.history],
    )
    freqs = table(
        ["configuration", "mode", "measured Hz", "initial Hz", "updated Hz", "error %"],
        [[c, k, float(m), float(i), float(u), _pct(100 * (u - m) / m)]
         for (c, k), m, i, u in zip(r.rows, r.measured_hz, r.initial_hz, r.updated_hz,
                                    strict=True)],
    )
    notes = (r.pairing or {}).get("notes", [])
    pairing = table(
        ["pairing", "configuration", "modes", "iteration", "why"],
        [[n["kind"], n["configuration"], ", ".join(map(str, n["modes"])), n["iteration"],
          n["reason"]] for n in notes],
    ) if notes else None
    return "\n\n".join(x for x in [head, params, steps, freqs, pairing] if x)


def extraction_text(result: TestExtraction) -> str:
    """Per configuration: accepted modes, rejected candidates, missing/unexpected modes."""
    blocks = []
    for ex in result.configurations:
        lines = [f"{ex.configuration} ({ex.line_spacing_hz:.4g} Hz lines; "
                 + "; ".join(ex.notes) + ")"]
        if not ex.modes:
            lines.append("  no validated resonance")
        else:
            lines.append(table(
                ["mode", "f Hz", "std Hz", "loss factor", "std", "fit R2", "check diff/std",
                 "model Hz", "note"],
                [[m.mode, m.frequency_hz, m.std_hz, m.loss_factor, m.loss_factor_std,
                  m.fit_quality, m.disagreement, m.model_hz,
                  "under-resolved" if m.under_resolved else ""] for m in ex.modes]))
        for r in ex.rejected:
            lines.append(f"  rejected {r.frequency_hz:.6g} Hz (band {r.band_hz[0]:.5g}-"
                         f"{r.band_hz[1]:.5g} Hz): {r.reason}")
        for k, f in ex.missing:
            lines.append(f"  missing: model mode {k} ({f:.6g} Hz) expected, not found")
        for m in ex.unexpected:
            lines.append(f"  unexpected: {m.frequency_hz:.6g} Hz matches no model mode")
        blocks.append("\n".join(lines))
    return "\n\n".join(blocks)



def frequencies_doc(freqs: dict[str, Any]) -> dict:
    """``frequencies --json``: every configuration's elastic frequencies (Hz)."""
    return {"configurations": [{"name": name, "frequencies_hz": f.tolist()}
                               for name, f in freqs.items()]}


def frequencies_text(freqs: dict[str, Any], title: str) -> str:
    n = len(next(iter(freqs.values())))
    return (f"{title}: elastic natural frequencies (Hz)\n"
            + table(["configuration", *[f"mode {k}" for k in range(1, n + 1)]],
                    [[name, *[float(x) for x in f]] for name, f in freqs.items()]))


def montecarlo_text(doc: dict, title: str, units: dict[str, str] | None = None) -> str:
    """``montecarlo``: the counts and, when given, the statistics per parameter of the
    summary ``doc`` (:meth:`~eigenupdate.design.montecarlo.MonteCarloResult.summary`);
    ``units`` (the model's, by parameter name) adds a unit column (bias and stds are in
    it; emp/pred and the coverage are pure numbers)."""
    caught = doc.get("caught") or {}
    held = "".join(f", {k} {v}" for k, v in caught.items() if v)
    lines = [f"{title}: {doc['trials']} virtual tests: {doc['converged']} converged, "
             f"{doc['not_converged']} not converged, {doc['refused']} refused, "
             f"{sum(caught.values())} caught by the checks{' (' + held[2:] + ')' if held else ''}"
             f"; seed entropy {doc['seed_entropy']}"]
    if doc["statistics_refused"] is not None:
        return lines[0]
    if "prior_draws" in doc:
        lines.append(f"predicted std: averaged over {doc['prior_draws']} draws of the truth "
                     f"from the prior ({doc['prior_draw_seconds']:.1f} s), +- its Monte Carlo "
                     f"error; linear: at the prior mean")
    if "predicted_gross_error_fraction" in doc:
        lines.append(f"gross errors (not converged or caught): {doc['gross_error_fraction']:.1%}"
                     f" of the trials; predicted {doc['predicted_gross_error_fraction']:.1%} +- "
                     f"{doc['predicted_gross_error_fraction_error']:.1%} from "
                     f"{doc['predicted_gross_draws']} checked tests at prior draws")
    if doc.get("converged_with_clusters"):
        lines.append(f"{doc['converged_with_clusters']} of the {doc['converged']} converged "
                     f"trials fitted close modes through their sums (less information than "
                     f"the predicted std assumes): compare the mean reported std")
    unit = [] if units is None else ["unit"]
    lines.append(table(
        ["parameter", *unit, "bias", "empirical std", "predicted std", "+-", "emp/pred",
         "linear std", "coverage 2 std", "mean reported std"],
        [[n, *([] if units is None else [units.get(n) or "-"]), p["bias"],
          p["empirical_std"], p["predicted_std"], p["predicted_std_error"],
          p["ratio_empirical_to_predicted"], p["linear_std"], p["coverage_2std"],
          p["mean_reported_std"]]
         for n, p in doc["parameters"].items()]))
    return "\n".join(lines)


def progress_bar(done: int, total: int) -> None:
    """``done`` of ``total`` as a bar on standard error (a terminal), redrawn in place."""
    n = 30 * done // total
    end = "\n" if done == total else ""
    print(f"\r[{'#' * n}{'.' * (30 - n)}] {done}/{total}", end=end, file=sys.stderr, flush=True)


def progress(msg: str) -> None:
    """One line on standard error; names in it come from input files: one printable line."""
    from eigenupdate.errors import MAX_MESSAGE, shorten

    print(shorten(msg, MAX_MESSAGE), file=sys.stderr, flush=True)
