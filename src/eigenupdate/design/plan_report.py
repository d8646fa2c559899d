"""Text table and JSON document of a :class:`~eigenupdate.design.plan.DesignResult`."""

from __future__ import annotations

from eigenupdate.design.plan import DesignResult
from eigenupdate.report.text import table


def design_doc(r: DesignResult, initial: dict[str, float]) -> dict:
    """JSON-ready document: chosen perturbations, candidates and the plans compared."""
    return {
        "method": r.method,
        "criterion": r.criterion if isinstance(r.criterion, str) else list(r.criterion),
        "modes": r.modes,
        "exchange_swaps": r.swaps,
        "chosen": [_candidate(r.candidates[i], r.modes) for i in r.chosen],
        "plans": [{"label": p.label, "configurations": p.configurations,
                   "criterion": p.criterion, "std": p.std} for p in r.plans],
        "initial": {n: initial[n] for n in r.names},
        "candidates": [_candidate(c, r.modes) for c in r.candidates],
    }


def _candidate(c, modes) -> dict:
    return {"name": c.configuration.name,
            "additions": [{"coordinate": a.coordinate, "mass": a.mass, "stiffness": a.stiffness}
                          for a in c.configuration.additions],
            "shifts_hz": dict(zip((str(k) for k in modes), c.shifts_hz, strict=True)),
            "shift_in_std": c.shift_in_std, "relative_gap": c.relative_gap,
            "order_kept": c.order_kept, "admissible": c.admissible}


def design_text(r: DesignResult, initial: dict[str, float], title: str) -> str:
    crit = r.criterion if isinstance(r.criterion, str) else "sum over " + ", ".join(r.criterion)
    lines = [f"{title}: test plan, criterion {crit}, method {r.method}, modes "
             f"{', '.join(map(str, r.modes))}",
             f"{sum(c.admissible for c in r.candidates)} of {len(r.candidates)} candidates "
             f"admissible; greedy selection then {r.swaps} exchange swap(s)", "",
             "designed plan (shift = bare minus perturbed frequency):"]
    chosen = [r.candidates[i] for i in r.chosen]
    lines.append(table(
        ["configuration", *[f"shift {k} Hz" for k in r.modes], "max shift/std", "min rel gap",
         "order kept"],
        [[c.configuration.name, *c.shifts_hz, c.shift_in_std, c.relative_gap,
          "yes" if c.order_kept else "no"] for c in chosen]))
    lines += ["", "predicted std of the updated parameters:"]
    labels = [p.label for p in r.plans]
    rows = [[n, initial[n], *[p.std[n] for p in r.plans]] for n in r.names]
    rows.append([f"criterion {crit}", None, *[p.criterion for p in r.plans]])
    rows.append(["perturbed configurations", None, *[len(p.configurations) for p in r.plans]])
    lines.append(table(["parameter", "initial", *labels], rows))
    rejected = [c for c in r.candidates if not c.admissible]
    if rejected:
        lines += ["", "rejected candidates:"]
        lines.append(table(["configuration", "max shift/std", "min rel gap", "order kept"],
                           [[c.configuration.name, c.shift_in_std, c.relative_gap,
                             "yes" if c.order_kept else "no"] for c in rejected]))
    return "\n".join(lines)
