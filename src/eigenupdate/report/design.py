"""Text tables of a :class:`~eigenupdate.design.plan.DesignResult` and of its validation."""

from __future__ import annotations

from eigenupdate.design.plan import DesignResult
from eigenupdate.report.text import table


def design_text(r: DesignResult, initial: dict[str, float], title: str,
                units: dict[str, str] | None = None) -> str:
    """The design's tables; ``units`` (the model's, by parameter name) adds a unit
    column to the predicted accuracy."""
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
    if r.draws:
        lines += ["", f"predicted std of the updated parameters, averaged over {r.draws} draws "
                      f"of the truth from the prior ({r.draw_seconds:.1f} s), +- its Monte "
                      f"Carlo error:"]
    else:
        lines += ["", "predicted std of the updated parameters (linearised at the prior mean; "
                      "no draws: prior_draws = 0 or a parameter without a prior std):"]
    labels = [p.label for p in r.plans]
    unit = [] if units is None else [None]  # the column's cell in the summary rows
    rows = [[n, *([] if units is None else [units.get(n) or "-"]), initial[n],
             *[_pm(p.std[n], p.std_error[n]) for p in r.plans]] for n in r.names]
    rows.append([f"criterion {crit}" + (" / (1 - gross risk)" if r.draws else ""), *unit,
                 None, *[p.criterion for p in r.plans]])
    rows.append(["perturbed configurations", *unit, None,
                 *[len(p.configurations) for p in r.plans]])
    if r.draws:
        rows.append(["risk of reordered or crowded modes", *unit, None,
                     *[_pct(p.gross_risk) for p in r.plans]])
    lines.append(table(["parameter", *([] if units is None else ["unit"]), "initial",
                        *labels], rows))
    if r.draws:
        p = r.plans[0]
        lines += ["", "designed plan: over the prior against linearised at the prior mean:"]
        lines.append(table(["parameter", "over the prior", "at the prior mean", "ratio"],
                           [[n, p.std[n], p.linear_std[n], p.std[n] / p.linear_std[n]]
                            for n in r.names]))
        lines.append("(risk of reordered or crowded modes: the share of the prior draws in "
                     "which a configuration reorders a used mode or brings it within "
                     "min_relative_gap of another, a risk of pairing measured modes wrongly; "
                     "the search divides the criterion by 1 - that risk, the share of tests "
                     "that can be used, so it prefers the plan that risks less. 'design "
                     "--validate N' predicts the chance of a gross error otherwise: checked "
                     "updates of virtual tests, counting non-convergence and caught fits)")
    rejected = [c for c in r.candidates if not c.admissible]
    if rejected:
        lines += ["", "rejected candidates:"]
        lines.append(table(["configuration", "max shift/std", "min rel gap", "order kept",
                            "exchange risk"],
                           [[c.configuration.name, c.shift_in_std, c.relative_gap,
                             "yes" if c.order_kept else "no", _pct(c.exchange_risk)]
                            for c in rejected]))
    return "\n".join(lines)


def validation_text(v) -> str:
    """Predicted against empirical std of a :class:`~eigenupdate.design.validate.Validation`."""
    t = v.montecarlo.trials
    conv = sum(x["converged"] for x in t)
    refused = sum(x["refused"] for x in t)
    lines = ["", f"validation: {len(t)} virtual tests of the designed plan: {conv} converged, "
                 f"{len(t) - conv - refused} not converged, {refused} refused "
                 f"(predicted chance of a gross error {_pct(v.predicted_gross_risk)}, "
                 f"from checked updates of virtual tests at prior draws)"]
    if v.empirical_std is None:
        lines.append("too few converged trials for an empirical std")
        return "\n".join(lines)
    ci = v.ratio_interval()
    lines.append(table(
        ["parameter", "predicted std", "+-", "empirical std", "+-", "empirical/predicted",
         "95 % interval", "linear over prior", "at prior mean", "coverage 2 std"],
        [[n, v.predicted_std[i], v.predicted_error[i], v.empirical_std[i],
          v.empirical_error[i], ci[i, 0], f"{ci[i, 1]:.2f}-{ci[i, 2]:.2f}",
          v.prior_std[i], v.linear_std[i], v.coverage_2std[i]]
         for i, n in enumerate(v.names)]))
    source = (f"the spread of {v.virtual_tests} checked virtual tests at draws of the prior "
              f"(another seed stream; they cost as much as the trials)" if v.virtual_tests
              else "the linearised std averaged over the prior's draws")
    lines.append(f"(predicted std: {source}; +-: standard errors from the kurtosis of the "
                 f"errors; the interval: the ratio +- 1.96 standard errors)")
    return "\n".join(lines)


def validation_doc(v) -> dict:
    """JSON-ready per-parameter comparison of a Validation."""
    t = v.montecarlo.trials
    conv = int(sum(bool(x["converged"]) for x in t))
    refused = int(sum(bool(x["refused"]) for x in t))
    out = {"trials": len(t), "converged": conv, "not_converged": len(t) - conv - refused,
           "refused": refused, "predicted_gross_risk": v.predicted_gross_risk,
           "predicted_by_virtual_tests": v.virtual_tests, "parameters": {}}
    for i, n in enumerate(v.names):
        out["parameters"][n] = {
            "predicted_std": float(v.predicted_std[i]),
            "predicted_std_error": float(v.predicted_error[i]),
            "prior_std": None if v.prior_std is None else float(v.prior_std[i]),
            "linear_std": float(v.linear_std[i]),
            "empirical_std_error": (None if v.empirical_error is None
                                    else float(v.empirical_error[i])),
            "empirical_std": None if v.empirical_std is None else float(v.empirical_std[i]),
            "coverage_2std": None if v.coverage_2std is None else float(v.coverage_2std[i])}
    return out


def _pm(value: float, error: float) -> str:
    return f"{value:.4g} +- {error:.2g}" if error else f"{value:.6g}"


def _pct(x: float | None) -> str:
    return "-" if x is None else f"{100 * x:.1f} %"
