"""Command line: a thin shell over the library.

Exit status: 0 success, 1 the update did not converge (the result is still printed),
2 bad input (a one-line message naming the file and the field; no traceback).
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

import numpy as np

from eigenupdate import report
from eigenupdate.atomic import write_text
from eigenupdate.errors import InputError
from eigenupdate.identifiability import check
from eigenupdate.jacobian import solve_configurations
from eigenupdate.measurements import Measurement, write_measurements
from eigenupdate.study import Study, load_study
from eigenupdate.updating import METHODS, update


def _n_modes(study: Study, requested: int | None) -> int:
    if requested is not None:
        if requested < 1:
            raise InputError("--modes must be >= 1")
        return requested
    return max(study.require_modes())


def cmd_frequencies(args) -> int:
    study = load_study(args.study)
    n = _n_modes(study, args.modes)
    sols = solve_configurations(study.model, study.configurations, n)
    doc = {"configurations": [
        {"name": c.name, "frequencies_hz": s.frequencies_hz.tolist()}
        for c, s in zip(study.configurations, sols, strict=True)
    ]}
    if args.json:
        print(report.dumps(doc))
    else:
        print(f"{study.title}: elastic natural frequencies (Hz)")
        print(report.table(["configuration", *[f"mode {k}" for k in range(1, n + 1)]],
                           [[c["name"], *[round(f, 4) for f in c["frequencies_hz"]]]
                            for c in doc["configurations"]]))
    return 0


def cmd_simulate(args) -> int:
    study = load_study(args.study)
    modes = study.require_modes()
    if args.noise_hz < 0:
        raise InputError("--noise-hz must be >= 0")
    std = args.std_hz if args.std_hz is not None else (args.noise_hz or None)
    sols = solve_configurations(study.model, study.configurations, max(modes))
    rng = np.random.default_rng(args.seed)
    rows = []
    for c, s in zip(study.configurations, sols, strict=True):
        for k in modes:
            f = float(s.frequencies_hz[k - 1])
            if args.noise_hz > 0:
                f += float(rng.normal(0.0, args.noise_hz))
            rows.append(Measurement(c.name, k, f, std))
    write_measurements(args.output, rows)
    print(f"wrote {len(rows)} frequencies of {len(sols)} configurations to {args.output}",
          file=sys.stderr)
    return 0


def cmd_check(args) -> int:
    study = load_study(args.study)
    r = check(study.model, study.configurations, study.require_modes())
    print(report.dumps(report.check_doc(r)) if args.json else report.check_text(r, study.title))
    return 0


def cmd_update(args) -> int:
    study = load_study(args.study)
    method = args.method or study.method
    res = update(
        study.model, study.configurations, study.require_modes(), study.measurements(),
        method=method, max_iterations=study.max_iterations, xtol=study.tolerance,
        source=str(study.frequencies),
    )
    doc = report.update_doc(res)
    if args.save:
        write_text(args.save, report.dumps({"study": str(study.path), **doc}) + "\n")
    initial = dict(zip(study.model.names, study.model.values.tolist(), strict=True))
    print(report.dumps(doc) if args.json else report.update_text(res, initial, study.title))
    if not res.converged:
        print(f"eigenupdate: not converged: {res.message}", file=sys.stderr)
        return 1
    return 0


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="eigenupdate",
        description="Update FE model parameters from natural frequencies of the bare and "
                    "mass/stiffness-perturbed structure.",
    )
    sub = p.add_subparsers(dest="command", required=True)

    s = sub.add_parser("frequencies", help="elastic natural frequencies of every configuration")
    s.add_argument("study")
    s.add_argument("--modes", type=int, help="number of elastic modes (default: study's highest)")
    s.add_argument("--json", action="store_true")
    s.set_defaults(func=cmd_frequencies)

    s = sub.add_parser("simulate", help="measurement CSV this model (as the truth) would give")
    s.add_argument("study")
    s.add_argument("-o", "--output", required=True)
    s.add_argument("--noise-hz", type=float, default=0.0, help="Gaussian noise std (Hz)")
    s.add_argument("--std-hz", type=float, help="std_hz column (default: the noise level)")
    s.add_argument("--seed", type=int)
    s.set_defaults(func=cmd_simulate)

    s = sub.add_parser("check", help="identifiability of the test plan (condition, rank of J)")
    s.add_argument("study")
    s.add_argument("--json", action="store_true")
    s.set_defaults(func=cmd_check)

    s = sub.add_parser("update", help="update the parameters from the measured frequencies")
    s.add_argument("study")
    s.add_argument("--method", choices=METHODS)
    s.add_argument("--json", action="store_true")
    s.add_argument("--save", metavar="RESULT.json", help="also write the result as JSON")
    s.set_defaults(func=cmd_update)
    return p


def main(argv: Sequence[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except InputError as exc:
        print(f"eigenupdate: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
