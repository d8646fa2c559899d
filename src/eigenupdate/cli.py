"""Command line: a thin shell over the library.

Exit status: 0 success, 1 the update did not converge (the result is still printed) or an
iterative solver stopped (NotConvergedError), 2 bad input or a singular matrix or repeated
eigenvalue (a one-line message naming the file and the field; no traceback).
"""

from __future__ import annotations

import argparse
import contextlib
import errno
import io
import json
import os
import re
import shlex
import sys
import time
import warnings
from collections.abc import Sequence
from pathlib import Path

import numpy as np

# only what the parser and the error handling need: the commands import the rest, so
# that --help starts in about the time NumPy and SciPy do
from eigenupdate import __version__, budget
from eigenupdate.choices import ESTIMATORS, FRF_KINDS, OPTIMIZERS, SCHEDULER_ENV
from eigenupdate.errors import (
    MAX_MESSAGE,
    EigenupdateWarning,
    InputError,
    NotConvergedError,
    NumericalError,
    shorten,
)
from eigenupdate.io import outputs
from eigenupdate.io.atomic import make_dir, transaction, write_text
from eigenupdate.solve import parallel
from eigenupdate.solve.memory import keep_freed_memory


def _output_file(path: str | None, flag: str) -> None:
    """Refuse an output file that cannot be written, before any work is done."""
    outputs.check_file(path, flag)


def _not_inputs(outputs_: dict[str, str | Path | None], inputs: Sequence[Path]) -> None:
    """Refuse an output that is an input of the same run, or two outputs in one file."""
    outputs.check_not_inputs(outputs_, inputs)


def _output_dir(path: str | None, flag: str) -> None:
    """Refuse an output directory that is a file or cannot receive files."""
    outputs.check_dir(path, flag)


def _files_in(directory: str | Path, names: Sequence[str], flag: str,
              inputs: Sequence[Path]) -> None:
    """The files a run writes into an output directory: regular files, none an input."""
    paths = {f"{flag} {n}": Path(directory) / n for n in names}
    if Path(directory).is_dir():
        for f, p in paths.items():
            outputs.check_file(p, f)
    outputs.check_not_inputs(paths, inputs)


_SCHEDULER = re.compile(r"(tcp://)?(\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9._-]+):\d{1,5}")


def _scheduler(address: str | None, flag: str) -> None:
    """Refuse a scheduler address Dask cannot use as given (tls:// needs certificates
    this command does not take; a missing port)."""
    if address is None:
        return
    if not _SCHEDULER.fullmatch(address) or int(address.rsplit(":", 1)[1]) > 65535:
        raise InputError(f"{address!r} is not a scheduler address tcp://HOST:PORT (tls:// and "
                         f"other protocols are not supported)", field=flag)


def _finite(value: float | None, flag: str, *, positive: bool = False) -> None:
    if value is None:
        return
    if not np.isfinite(value) or value < 0 or (positive and value == 0):
        raise InputError(f"{value!r} must be a finite number {'>' if positive else '>='} 0",
                         field=flag)


def _seed(text: str) -> int:
    """argparse type: a random seed, an integer >= 0."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not an integer") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"{value} must be >= 0")
    return value


def cmd_frequencies(args) -> int:
    from eigenupdate import workflow
    from eigenupdate.io.study import load_study
    from eigenupdate.report import text as report

    study = load_study(args.study)
    freqs = workflow.study_frequencies(study, args.modes)
    doc = {"configurations": [{"name": name, "frequencies_hz": f.tolist()}
                              for name, f in freqs.items()]}
    if args.json:
        print(report.dumps(doc))
    else:
        n = len(next(iter(freqs.values())))
        print(f"{study.title}: elastic natural frequencies (Hz)")
        print(report.table(["configuration", *[f"mode {k}" for k in range(1, n + 1)]],
                           [[name, *[round(float(x), 4) for x in f]] for name, f in freqs.items()]))
    return 0


def cmd_simulate(args) -> int:
    from eigenupdate import workflow
    from eigenupdate.io.measurements import write_measurements
    from eigenupdate.io.study import load_study

    _output_file(args.output, "-o")
    _finite(args.noise_hz, "--noise-hz")
    _finite(args.std_hz, "--std-hz", positive=True)
    study = load_study(args.study)
    # the study's measurement file is where simulated data may go: not read by this run
    _not_inputs({"-o": args.output}, study.inputs(frf=True))
    rows = workflow.simulate_study(study, args.noise_hz, args.std_hz, args.seed)
    write_measurements(args.output, rows)
    print(f"wrote {len(rows)} frequencies of {len(study.configurations)} configurations to "
          f"{args.output}", file=sys.stderr)
    return 0


def cmd_check(args) -> int:
    from eigenupdate import workflow
    from eigenupdate.io.study import load_study
    from eigenupdate.report import text as report

    study = load_study(args.study)
    r = workflow.check_study(study, args.method)
    print(report.dumps(r.to_dict()) if args.json else report.check_text(r, study.title))
    return 0


def cmd_update(args) -> int:
    from eigenupdate import workflow
    from eigenupdate.io.nastran_write import save_updated_bdf
    from eigenupdate.io.study import load_study
    from eigenupdate.report import text as report

    _output_file(args.save, "--save")
    _output_file(args.save_bdf, "--save-bdf")
    study = load_study(args.study)
    if args.save_bdf and study.nastran is None:
        raise InputError("needs a study whose [model] type is \"nastran\"", field="--save-bdf")
    _not_inputs({"--save": args.save, "--save-bdf": args.save_bdf},
                study.inputs(measurements=True, frf=True))
    res = workflow.update_study(study, args.method, args.optimizer,
                                progress=lambda line: print(line, file=sys.stderr))
    doc = res.to_dict()
    kept = None
    if args.save and (res.success or args.force or _unconverged_result(args.save)):
        write_text(args.save, report.dumps({"study": str(study.path), **doc}) + "\n")
    elif args.save:
        kept = f"; {shorten(args.save)} kept (it is not an unconverged result; --force replaces it)"
    if args.save_bdf and res.success:
        save_updated_bdf(study, res, args.save_bdf)
    initial = dict(zip(study.model.names, study.model.values.tolist(), strict=True))
    print(report.dumps(doc) if args.json else report.update_text(res, initial, study.title))
    if not res.success:
        print(f"eigenupdate: not converged: {res.message}{kept or ''}", file=sys.stderr)
        return 1
    return 0


def cmd_design(args) -> int:
    from eigenupdate import workflow
    from eigenupdate.design.executor import executor_for
    from eigenupdate.design.plan_io import plan_study_text
    from eigenupdate.io.study import load_study
    from eigenupdate.report import text as report
    from eigenupdate.report.design import (
        design_text,
        validation_doc,
        validation_text,
    )

    _output_file(args.output, "-o")
    _scheduler(args.scheduler, "--scheduler")
    study = load_study(args.study)
    _not_inputs({"-o": args.output}, study.inputs(measurements=True, frf=True))
    ex = None
    if args.scheduler or args.workers:
        if args.workers is not None and args.workers < 1:
            raise InputError(f"must be >= 1, got {args.workers}", field="--workers")
        ex = executor_for(args.scheduler, n_workers=args.workers)
    try:
        done = workflow.design(study, validate=args.validate, seed=args.seed, executor=ex)
    finally:
        if ex is not None:
            ex.close()
    res, val = done.plan, done.validation
    write_text(args.output, plan_study_text(study.path, res.configurations, res.modes,
                                            args.output))
    initial = dict(zip(study.model.names, study.model.values.tolist(), strict=True))
    if args.json:
        doc = res.to_dict()
        if val is not None:
            doc["validation"] = validation_doc(val)
        print(report.dumps(doc))
    else:
        print(design_text(res, initial, study.title)
              + (validation_text(val) if val is not None else ""))
    _progress(f"wrote the plan to {args.output}")
    return 0


def cmd_montecarlo(args) -> int:
    from eigenupdate import workflow
    from eigenupdate.design.executor import executor_for
    from eigenupdate.io.montecarlo import FILES as MC_FILES
    from eigenupdate.io.montecarlo import write_montecarlo
    from eigenupdate.io.study import load_study
    from eigenupdate.report import text as report

    _output_dir(args.output, "-o")
    if args.trials < 1:
        raise InputError(f"must be >= 1, got {args.trials}", field="--trials")
    if args.workers is not None and args.workers < 1:
        raise InputError(f"must be >= 1, got {args.workers}", field="--workers")
    _scheduler(args.scheduler or (None if args.in_process else os.environ.get(SCHEDULER_ENV)),
               "--scheduler" if args.scheduler else SCHEDULER_ENV)
    study = load_study(args.study)
    if args.output:
        truth = load_study(args.truth).inputs() if args.truth else []
        _files_in(args.output, MC_FILES, "-o",
                  [*study.inputs(measurements=True, frf=True), *truth])
    bar = _progress_bar if sys.stderr.isatty() else None
    start = time.perf_counter()
    with executor_for(args.scheduler, args.in_process, args.workers) as ex:
        res = workflow.montecarlo(study, args.trials, truth=args.truth, seed=args.seed,
                                  executor=ex, progress=bar)
        where = repr(ex)
    wall = time.perf_counter() - start
    doc = {**res.summary(), "executor": where, "wall_time_s": wall}
    ok, bad, refused = res.counts()
    if refused == len(res.trials):  # nothing ran: the plan or its data are refused
        raise InputError(doc["statistics_refused"], source=str(study.path))
    if args.output:
        write_montecarlo(res, args.output, study.title,
                         {"executor": where, "wall_time_s": wall})
    if args.json:
        print(report.dumps(doc))
    else:
        print(f"{study.title}: {doc['trials']} virtual tests: {ok} converged, {bad} not "
              f"converged, {refused} refused; seed entropy {doc['seed_entropy']}")
    if doc["statistics_refused"] is not None:
        _progress(f"{args.trials} trials in {wall:.1f} s ({where})")
        raise NotConvergedError(f"no statistics: {doc['statistics_refused']}",
                                field="--trials")
    if not args.json:
        if "prior_draws" in doc:
            print(f"predicted std: averaged over {doc['prior_draws']} draws of the truth from "
                  f"the prior ({doc['prior_draw_seconds']:.1f} s), +- its Monte Carlo error; "
                  f"linear: at the prior mean")
        print(report.table(
            ["parameter", "bias", "empirical std", "predicted std", "+-", "emp/pred",
             "linear std", "coverage 2 std"],
            [[n, p["bias"], p["empirical_std"], p["predicted_std"], p["predicted_std_error"],
              p["ratio_empirical_to_predicted"], p["linear_std"], p["coverage_2std"]]
             for n, p in doc["parameters"].items()]))
    _progress(f"{args.trials} trials in {wall:.1f} s ({where})"
              + (f"; wrote {args.output}" if args.output else ""))
    return 0


def _progress_bar(done: int, total: int) -> None:
    n = 30 * done // total
    end = "\n" if done == total else ""
    print(f"\r[{'#' * n}{'.' * (30 - n)}] {done}/{total}", end=end, file=sys.stderr, flush=True)


def _unconverged_result(path: str) -> bool:
    """True if ``path`` does not exist or holds a result saved with converged false: only
    those may be replaced by an unconverged result."""
    try:
        doc = json.loads(Path(path).read_text(encoding="utf-8"))
    except FileNotFoundError:
        return True
    except (OSError, ValueError, RecursionError):
        return False
    return isinstance(doc, dict) and doc.get("success") is False


def _progress(msg: str) -> None:
    # names in it come from input files: one printable line
    print(shorten(msg, MAX_MESSAGE), file=sys.stderr, flush=True)


def _safe_name(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9.-]+", "_", name).strip("_") or "configuration"


def cmd_extract(args) -> int:
    from eigenupdate import workflow
    from eigenupdate.io.study import load_study
    from eigenupdate.io.uff import write_modes
    from eigenupdate.measure.extraction import extraction_csv
    from eigenupdate.measure.frf import dof_label
    from eigenupdate.measure.modes import Mode
    from eigenupdate.plot.plots import plot_extraction_fit
    from eigenupdate.report import text as report

    _output_file(args.output, "-o")
    _output_file(args.uff55, "--uff55")
    _output_file(args.save, "--save")
    _output_dir(args.plots, "--plots")
    inputs = args.inputs
    if len(inputs) == 1 and Path(inputs[0]).suffix.lower() == ".toml":
        if args.kind:
            raise InputError("goes with FRF files; a study says kind in "
                             "[measurement.frf_options]", field="--kind")
        study = load_study(inputs[0], require_model=False)
        # the study's measurement file is where the extracted frequencies go
        _not_inputs({"-o": args.output, "--uff55": args.uff55, "--save": args.save},
                    study.inputs(frf=True))
        done = workflow.extract_study(study, progress=_progress)
        label = study.model.coordinate_table.point_label if study.model is not None else None
    else:  # FRF files on the command line: one configuration per file, named by its stem
        _not_inputs({"-o": args.output, "--uff55": args.uff55, "--save": args.save},
                    [Path(p) for p in inputs])
        done = workflow.extract_files(inputs, args.kind, progress=_progress)
        label = None
    res = done.result
    print(report.dumps(res.to_dict()) if args.json else report.extraction_text(res))
    if res.problems:  # a failed run writes nothing; one line, the others counted
        more = len(res.problems) - 1
        raise InputError(res.problems[0] + (f" (and {more} more problem(s): "
                                            f"{'; '.join(res.problems[1:])})" if more else ""))
    results = res.modes
    if args.plots:
        make_dir(args.plots)
        for ex in res.configurations:
            for j, x in enumerate(done.frfs[ex.configuration]):
                shown = [m for m in ex.modes if m.fits[j] is not None]
                if shown:
                    out = Path(args.plots) / f"extract_{_safe_name(ex.configuration)}_{j + 1}.png"
                    points = [label(p) if label else dof_label(p) for p in (x.response,
                                                                            x.reference)]
                    plot_extraction_fit(out, x.frequency_hz, x.receptance,
                                        [m.fits[j] for m in shown],
                                        mode_numbers=[m.mode for m in shown],
                                        title=f"{ex.configuration}: {points[0]} / {points[1]}")
        _progress(f"wrote the fit plots to {args.plots}")
    write_text(args.output, extraction_csv(results))
    if args.save:
        write_text(args.save, report.dumps(res.to_dict()) + "\n")
    if args.uff55:
        write_modes(args.uff55, [
            Mode(m.frequency_hz, loss_factor=m.loss_factor, mode_number=m.mode,
                 label=m.configuration)
            for m in results])
    _progress(f"wrote {len(results)} frequencies to {args.output}")
    return 0


def cmd_simulate_frf(args) -> int:
    from eigenupdate import workflow
    from eigenupdate.io.study import load_study
    from eigenupdate.io.uff import write_frfs

    _output_dir(args.output, "-o")
    _finite(args.fmax, "--fmax", positive=True)
    _finite(args.df, "--df", positive=True)
    _finite(args.noise, "--noise")
    for eta in args.loss_factor:
        _finite(eta, "--loss-factor")
    if args.fmax <= args.df or args.fmax / args.df > 1e7:
        raise InputError(f"need --df < --fmax and at most 1e7 lines, got --df {args.df:g}, "
                         f"--fmax {args.fmax:g}", field="--fmax")
    study = load_study(args.study)
    f = np.arange(args.df, args.fmax + 0.5 * args.df, args.df)  # 0 Hz: rigid modes are infinite
    # everything is computed before the directory is made: no half-done output
    sets = workflow.simulate_study_frfs(study, f, args.input, args.outputs, args.loss_factor,
                               noise=args.noise, seed=args.seed)
    out = Path(args.output)
    _files_in(out, [f"{_safe_name(c.name)}.uff" for c, _ in sets], "-o",
              study.inputs(measurements=True, frf=True))
    make_dir(out)
    lines = ["[measurement.frf]"]
    for c, frfs in sets:
        name = f"{_safe_name(c.name)}.uff"
        write_frfs(out / name, frfs, binary=args.binary)
        lines.append(f'"{c.name}" = "{out.name}/{name}"')
    print("\n".join(lines))
    return 0


def cmd_frf(args) -> int:
    from eigenupdate import workflow
    from eigenupdate.io.study import load_study
    from eigenupdate.plot.plots import plot_frf_comparison

    _output_file(args.o, "-o")
    _finite(args.fmax, "--fmax", positive=True)
    _finite(args.loss_factor, "--loss-factor")
    study = load_study(args.study)
    _not_inputs({"-o": args.o}, [*study.inputs(measurements=True, frf=True), *(Path(p) for p in
                                  (args.measured, args.updated, args.damping) if p)])
    c = workflow.compare_frf(study, args.input, args.output, configuration=args.configuration,
                    measured=args.measured, updated=args.updated, loss_factor=args.loss_factor,
                    damping=args.damping, fmax_hz=args.fmax)
    plot_frf_comparison(
        args.o, None, measured=c.measured, initial=(c.frequency_hz, c.initial),
        updated=None if c.updated is None else (c.frequency_hz, c.updated), title=c.title)
    _progress(f"wrote {args.o}")
    return 0


def cmd_sweep(args) -> int:
    from eigenupdate import workflow
    from eigenupdate.io.study import load_study
    from eigenupdate.plot.plots import plot_mass_sweep

    _output_file(args.o, "-o")
    _finite(args.max_mass, "--max-mass", positive=True)
    study = load_study(args.study)
    _not_inputs({"-o": args.o}, study.inputs(measurements=True, frf=True))
    sweep = workflow.sweep(study, args.coordinate, args.max_mass, args.modes, args.configuration)
    plot_mass_sweep(args.o, sweep, title=study.title)
    _progress(f"wrote {args.o}")
    return 0


def cmd_report(args) -> int:
    from eigenupdate import workflow
    from eigenupdate.io.study import load_study

    _output_file(args.o, "-o")
    files = {"--result": args.result, "--extraction": args.extraction,
             "--extracted": args.extracted, "--design": args.design,
             "--montecarlo": args.montecarlo}
    command = ["eigenupdate", "report", args.study, *[x for k, v in files.items() if v
                                                      for x in (k, v)],
               *(["--saved-only"] if args.saved_only else []), "-o", args.o]
    read = [Path(args.study), *(Path(v) for v in files.values() if v)]
    study = load_study(args.study)
    _not_inputs({"-o": args.o}, [*read, *study.inputs(measurements=True, frf=True)])
    page = workflow.report(study, result=args.result, extraction=args.extraction,
                           extracted=args.extracted, design=args.design,
                           montecarlo=args.montecarlo, solve=not args.saved_only,
                           command=shlex.join(command))
    write_text(args.o, page)
    _progress(f"wrote {args.o} ({len(page.encode()) / 1024:.0f} kB)")
    return 0


class _Parser(argparse.ArgumentParser):
    """Usage errors in one line, like every other bad input (exit status 2)."""

    def error(self, message: str):
        self.exit(2, f"{self.prog}: error: {shorten(message, MAX_MESSAGE)} "
                     f"(see {self.prog} --help)\n")


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(
        prog="eigenupdate",
        description="Update FE model parameters from natural frequencies of the bare and "
                    "mass/stiffness-perturbed structure.",
    )
    p.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
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
    s.add_argument("--seed", type=_seed)
    s.set_defaults(func=cmd_simulate)

    s = sub.add_parser("check", help="identifiability of the test plan (condition, rank of J)")
    s.add_argument("study")
    s.add_argument("--method", choices=ESTIMATORS,
                   help="weight J as this estimator does (default: the study's; "
                        "least-squares: the plan's own J, as the paper)")
    s.add_argument("--json", action="store_true")
    s.set_defaults(func=cmd_check)

    s = sub.add_parser("update", help="update the parameters from the measured frequencies")
    s.add_argument("study")
    s.add_argument("--method", choices=ESTIMATORS)
    s.add_argument("--optimizer", choices=OPTIMIZERS,
                   help="default: the study's (trust-region unless it says gauss-newton)")
    s.add_argument("--json", action="store_true")
    s.add_argument("--save", metavar="RESULT.json", help="also write the result as JSON")
    s.add_argument("--save-bdf", metavar="UPDATED.bdf",
                   help="NASTRAN model: write its BDF with the updated values in their cards")
    s.add_argument("--force", action="store_true",
                   help="let an unconverged result replace an existing --save file")
    s.set_defaults(func=cmd_update)

    s = sub.add_parser("design", help="choose the added masses from the study's [design] table")
    s.add_argument("study")
    s.add_argument("-o", "--output", required=True, metavar="PLAN.toml",
                   help="the plan as a study file")
    s.add_argument("--scheduler", metavar="tcp://HOST:PORT",
                   help="screen the candidates on this Dask scheduler (default: in this process)")
    s.add_argument("--workers", type=int,
                   help="screen the candidates on a local Dask cluster of this many processes")
    s.add_argument("--validate", type=int, metavar="N",
                   help="then run N virtual tests of the plan (truth drawn from the prior) and "
                        "print predicted against empirical std")
    s.add_argument("--seed", type=_seed, default=0, help="seed of the --validate trials")
    s.add_argument("--json", action="store_true")
    s.set_defaults(func=cmd_design)

    s = sub.add_parser("montecarlo", help="virtual tests of the study's plan: bias, std, coverage")
    s.add_argument("study")
    s.add_argument("--trials", type=int, required=True)
    s.add_argument("--truth", metavar="STUDY", help="study whose model holds the true values "
                   "(default: draw them from the priors)")
    s.add_argument("--seed", type=_seed)
    s.add_argument("-o", "--output", metavar="DIR", help="write trials.csv, summary.json, plots")
    s.add_argument("--scheduler", metavar="tcp://HOST:PORT",
                   help=f"existing Dask scheduler (or ${SCHEDULER_ENV}); default: a local "
                        f"cluster, one worker process per core")
    s.add_argument("--workers", type=int, help="worker processes of the local cluster")
    s.add_argument("--in-process", action="store_true", help="no Dask: run here, one by one")
    s.add_argument("--json", action="store_true")
    s.set_defaults(func=cmd_montecarlo)

    s = sub.add_parser("extract", help="natural frequencies from the study's measured FRFs "
                                       "(a study, or FRF files: one configuration per file)")
    s.add_argument("inputs", nargs="+", metavar="STUDY.toml | FRF")
    s.add_argument("-o", "--output", required=True, help="measurement CSV to write")
    s.add_argument("--kind", choices=FRF_KINDS,
                   help="what FRF files on the command line hold if their header does not say")
    s.add_argument("--json", action="store_true", help="print the table as JSON")
    s.add_argument("--uff55", help="also write the modes (with loss factors) as UFF 55")
    s.add_argument("--plots", metavar="DIR", help="save a plot of every fit in DIR")
    s.add_argument("--save", metavar="EXTRACTION.json",
                   help="also write the whole extraction as JSON (for 'report --extraction')")
    s.set_defaults(func=cmd_extract)

    s = sub.add_parser("simulate-frf", help="synthetic noisy FRFs of every configuration (UFF 58)")
    s.add_argument("study")
    s.add_argument("-o", "--output", required=True, metavar="DIR")
    s.add_argument("--input", type=int, required=True, help="excitation coordinate")
    s.add_argument("--outputs", type=int, nargs="+", required=True, help="response coordinates")
    s.add_argument("--loss-factor", type=float, nargs="+", default=[0.01],
                   help="hysteretic loss factor, one value or one per elastic mode")
    s.add_argument("--noise", type=float, default=0.01,
                   help="complex noise std as a fraction of the largest peak")
    s.add_argument("--fmax", type=float, required=True, help="highest frequency (Hz)")
    s.add_argument("--df", type=float, default=0.5, help="frequency resolution (Hz)")
    s.add_argument("--binary", action="store_true", help="write binary UFF 58b")
    s.add_argument("--seed", type=_seed)
    s.set_defaults(func=cmd_simulate_frf)

    s = sub.add_parser("frf", help="plot predicted (and measured) receptance, paper Fig. 7")
    s.add_argument("study")
    s.add_argument("--input", type=int, required=True, help="excitation coordinate")
    s.add_argument("--output", type=int, required=True, help="response coordinate")
    s.add_argument("--configuration", help="configuration name (default: base)")
    s.add_argument("--measured", help="FRF file (UFF 58 or CSV) to compare with")
    s.add_argument("--updated", metavar="RESULT.json", help="result of 'update --save'")
    s.add_argument("--loss-factor", type=float, default=0.01,
                   help="hysteretic loss factor of every mode (default 0.01)")
    s.add_argument("--damping", metavar="UFF55",
                   help="per-mode loss factors from 'extract --uff55' (modes above the last "
                        "take its value)")
    s.add_argument("--fmax", type=float, help="highest frequency without --measured (Hz)")
    s.add_argument("-o", required=True, metavar="FIG", help="figure file (.png, .svg, .pdf)")
    s.set_defaults(func=cmd_frf)

    s = sub.add_parser("sweep", help="frequencies against added mass at a coordinate, Fig. 4")
    s.add_argument("study")
    s.add_argument("--coordinate", type=int, required=True)
    s.add_argument("--max-mass", type=float, required=True, help="largest added mass (kg)")
    s.add_argument("--modes", type=int, help="number of elastic modes")
    s.add_argument("--configuration", help="configuration to add the mass to (default: base)")
    s.add_argument("-o", required=True, metavar="FIG")
    s.set_defaults(func=cmd_sweep)

    s = sub.add_parser("report", help="self-contained HTML report of the study (print to PDF)")
    s.add_argument("study")
    s.add_argument("--result", metavar="RESULT.json", help="result of 'update --save' (default: "
                   "the report runs the update)")
    s.add_argument("--extraction", metavar="EXTRACTION.json",
                   help="result of 'extract --save' (default: the report extracts)")
    s.add_argument("--extracted", metavar="CSV", help="extraction CSV of 'extract -o'")
    s.add_argument("--design", metavar="DESIGN.json",
                   help="'design --json' (or any JSON object, shown as it is)")
    s.add_argument("--montecarlo", metavar="SUMMARY.json",
                   help="summary.json of 'montecarlo -o' (or any JSON object)")
    s.add_argument("--saved-only", action="store_true",
                   help="solve nothing: show the saved results given, without the plan's "
                        "check at the initial model and the predictions of Fig. 4 and 7")
    s.add_argument("-o", required=True, metavar="REPORT.html")
    s.set_defaults(func=cmd_report)
    return p


def _located(exc: InputError | NumericalError, args) -> str:
    """The message, prefixed by the study file when the library could not name a file.

    Errors found deep in the numerics (too few elastic modes, an indefinite mass matrix)
    come from the study's model all the same; options (``--x``) name themselves.
    """
    study = getattr(args, "study", None)
    inputs = getattr(args, "inputs", None) or []
    if study is None and len(inputs) == 1 and str(inputs[0]).endswith(".toml"):
        study = inputs[0]  # extract on a study
    if exc.source is None and study and not (exc.field or "").startswith("-"):
        return f"{shorten(study)}: {exc}"
    return str(exc)


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    print(f"eigenupdate: warning: {message}", file=sys.stderr, flush=True)


def main(argv: Sequence[str] | None = None) -> int:
    """Run one command; its standard output is held until its files are written, so a
    closed or broken stdout cannot lose them, and is then reported (exit status 2)."""
    out = sys.stdout
    held = io.StringIO()
    try:
        with contextlib.redirect_stdout(held):
            status = _main(argv)
    except SystemExit as exc:  # argparse: --help, usage errors
        with contextlib.suppress(OSError, ValueError, AttributeError):  # --help into a
            out.write(held.getvalue())  # closed pipe: the usage status stands
        raise exc from None
    text = held.getvalue()
    if not text:
        return status
    try:
        if out is None:  # started with stdout closed
            raise BrokenPipeError(errno.EBADF, "standard output is closed")
        out.write(text)
        out.flush()
    except (OSError, ValueError) as exc:
        with contextlib.suppress(OSError, ValueError, AttributeError):  # none at exit
            os.dup2(os.open(os.devnull, os.O_WRONLY), out.fileno())
        why = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
        with contextlib.suppress(OSError, ValueError, AttributeError):
            print(f"eigenupdate: error: standard output: {why}; the files asked for were "
                  f"written, the printed result was not", file=sys.stderr, flush=True)
        return status or 2
    return status


def _main(argv: Sequence[str] | None) -> int:
    args = build_parser().parse_args(argv)
    if argv is None:  # this process is the command's own: see solve/memory.py
        keep_freed_memory()
    try:
        # every output is renamed into place only if the command returns; floating-point
        # warnings are not printed: results are checked to be finite instead
        with transaction(), np.errstate(all="ignore"), warnings.catch_warnings():
            warnings.simplefilter("always", EigenupdateWarning)
            warnings.showwarning = _show_warning  # one line, no source location
            parallel.threads()  # a bad EIGENUPDATE_THREADS stops every command at once
            budget.check_environment()  # and so does a bad limit
            return args.func(args)
    except (InputError, NumericalError) as exc:
        # exit 2: bad input, singular matrix, repeated eigenvalue; 1: not converged
        print(f"eigenupdate: error: {_located(exc, args)}", file=sys.stderr)
        return exc.exit_status
    except BrokenPipeError:  # output piped into `head` and the like
        sys.stderr.close()
        return 0
    except (np.linalg.LinAlgError, MemoryError) as exc:  # a last resort, not a traceback
        why = "out of memory" if isinstance(exc, MemoryError) else f"numerical failure ({exc})"
        print(f"eigenupdate: error: {shorten(getattr(args, 'study', None) or '')}: {why}; "
              f"input values or sizes out of range?", file=sys.stderr)
        return 2
    except OSError as exc:  # a file that cannot be read or written, named by the OS
        where = f"{shorten(exc.filename)}: " if exc.filename else ""
        print(f"eigenupdate: error: {where}{shorten(exc.strerror or exc, MAX_MESSAGE)}",
              file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
