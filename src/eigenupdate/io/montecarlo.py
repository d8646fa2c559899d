"""Files of a Monte Carlo run: every trial as CSV, the summary as JSON, two figures."""

from __future__ import annotations

import csv
import io
from pathlib import Path

from eigenupdate.design.montecarlo import MonteCarloResult
from eigenupdate.io.atomic import make_dir, write_text
from eigenupdate.plot.montecarlo import plot_std_comparison, plot_zscores
from eigenupdate.report.text import dumps

FILES = ("trials.csv", "summary.json", "std.png", "zscores.png")
TRIALS_HEADER = "trial,converged,refused,iterations,"
"""The start of trials.csv: an earlier output of ``montecarlo -o``."""


def trials_csv(r: MonteCarloResult) -> str:
    """One row per trial: status, then truth, estimate and reported std of each parameter."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow([*TRIALS_HEADER.split(",")[:-1],
                *[f"{k}_{n}" for n in r.names for k in ("true", "estimate", "std")], "message"])
    for i, t in enumerate(r.trials):
        vals = [repr(float(t[k][j])) for j in range(len(r.names))
                for k in ("truth", "estimate", "std")]
        w.writerow([i, int(t["converged"]), int(t["refused"]), t["nit"], *vals, t["message"]])
    return buf.getvalue()


def write_montecarlo(r: MonteCarloResult, directory: str | Path, title: str = "",
                     extra: dict | None = None) -> list[Path]:
    """Write :data:`FILES` into ``directory`` (created if needed): summary.json is
    :meth:`MonteCarloResult.to_dict` (with ``extra`` keys, e.g. where it ran); returns
    their paths."""
    d = Path(directory)
    make_dir(d)
    s = r.summary()
    write_text(d / FILES[0], trials_csv(r))
    write_text(d / FILES[1], dumps({**r.to_dict(), **(extra or {})}) + "\n")
    p = s["parameters"]
    if p:
        plot_std_comparison(d / FILES[2], r.names, [p[n]["empirical_std"] for n in r.names],
                            [p[n]["predicted_std"] for n in r.names], title)
        plot_zscores(d / FILES[3], r.z_scores(), title)
    return [d / f for f in FILES]
