"""Command line: a thin shell over the library. Each command parses its options
(:mod:`eigenupdate.arguments`), calls one function of :mod:`eigenupdate.workflow`, prints
through :mod:`eigenupdate.report` and writes through :mod:`eigenupdate.io`.

Exit status: 0 success, 1 the update did not converge (the result is still printed) or an
iterative solver stopped (NotConvergedError), 2 bad input or a singular matrix or repeated
eigenvalue (a one-line message naming the file and the field; no traceback).
"""

from __future__ import annotations

import contextlib
import io
import os
import shlex
import sys
import warnings
from collections.abc import Sequence
from pathlib import Path

import numpy as np

# only what the parser and the error handling need: the commands import the rest, so
# that --help starts in about the time NumPy and SciPy do
import eigenupdate as eu  # names resolve on first use (PEP 562): --help loads none
from eigenupdate import budget, errors
from eigenupdate.arguments import build_parser, check_scheduler
from eigenupdate.choices import SCHEDULER_ENV
from eigenupdate.errors import InputError, NotConvergedError, NumericalError, shorten
from eigenupdate.io import outputs
from eigenupdate.io.atomic import transaction, write_text
from eigenupdate.io.outputs import (
    check_dir,
    check_file,
    check_files_in,
    check_no_replaced,
    check_outputs,
    check_replaceable,
    schema_marker,
)
from eigenupdate.report import text
from eigenupdate.solve import parallel
from eigenupdate.solve.memory import keep_freed_memory


def cmd_frequencies(args) -> int:
    study = eu.load_study(args.study)
    freqs = eu.study_frequencies(study, args.modes)
    print(text.dumps(text.frequencies_doc(freqs)) if args.json
          else text.frequencies_text(freqs, study.title))
    return 0


def cmd_simulate(args) -> int:
    from eigenupdate.io.measurements import SIMULATED, write_measurements

    check_file(args.output, "-o")
    study = eu.load_study(args.study)
    # the study's measurement file is where simulated data may go (not read by this run),
    # if simulate wrote it or with --force: measured data look the same
    check_outputs({"-o": args.output}, study.inputs(frf=True), {"-o": SIMULATED}, args.force)
    rows = eu.simulate_study(study, args.noise_hz, args.std_hz, args.seed, args.noise_relative)
    name = Path(study.path).name
    write_measurements(args.output, rows, f"{SIMULATED[2:]} frequencies of "
                                          f"{name if name.isprintable() else ascii(name)}")
    text.progress(f"wrote {len(rows)} frequencies of {len(study.configurations)} "
                  f"configurations to {args.output}")
    return 0


def cmd_check(args) -> int:
    study = eu.load_study(args.study)
    r = eu.check_study(study, args.method)
    print(text.dumps(r.to_dict()) if args.json else text.check_text(r, study.title))
    return 0


def cmd_update(args) -> int:
    from eigenupdate.identify.result import UpdateResult
    from eigenupdate.io.nastran_write import SIGNATURE as BDF_SIGNATURE
    from eigenupdate.io.nastran_write import save_updated_bdf
    from eigenupdate.io.results import may_replace

    study = eu.load_study(args.study)
    if args.save_bdf and study.nastran is None:
        raise InputError("needs a study whose [model] type is \"nastran\"", field="--save-bdf")
    check_outputs({"--save": args.save, "--save-bdf": args.save_bdf},
                  study.inputs(measurements=True, frf=True),
                  {"--save": schema_marker(UpdateResult.SCHEMA),
                   "--save-bdf": "$ " + BDF_SIGNATURE}, args.force)
    res = eu.update_study(study, args.method, args.optimizer,
                          progress=lambda line: print(line, file=sys.stderr))
    kept = args.save and not (res.success or args.force or may_replace(args.save))
    if args.save and not kept:
        write_text(args.save, text.dumps(res.to_dict()) + "\n")
    if args.save_bdf and res.success:
        save_updated_bdf(study, res, args.save_bdf)
    initial = dict(zip(study.model.names, study.model.values.tolist(), strict=True))
    print(text.dumps(res.to_dict()) if args.json else text.update_text(res, initial, study.title))
    if not res.success:
        print(f"eigenupdate: not converged: {res.message}" + (f"; {shorten(args.save)} kept "
              "(it is not an unconverged result; --force replaces it)" if kept else ""),
              file=sys.stderr)
        return 1
    return 0


def cmd_design(args) -> int:
    from eigenupdate.design.plan_io import SIGNATURE, plan_study_text
    from eigenupdate.report.design import design_text, validation_doc, validation_text

    if not args.scheduler:  # the environment's scheduler, as montecarlo's
        check_scheduler(os.environ.get(SCHEDULER_ENV), SCHEDULER_ENV)
    study = eu.load_study(args.study)
    check_outputs({"-o": args.output}, study.inputs(measurements=True, frf=True),
                  {"-o": SIGNATURE}, args.force)  # not another study's file
    done = eu.design(study, validate=args.validate, seed=args.seed, scheduler=args.scheduler,
                     workers=args.workers)
    res, val = done.plan, done.validation
    write_text(args.output, plan_study_text(study.path, res.configurations, res.modes,
                                            args.output))
    initial = dict(zip(study.model.names, study.model.values.tolist(), strict=True))
    if args.json:
        print(text.dumps({**res.to_dict(), **({"validation": validation_doc(val)} if val
                                               else {})}))
    else:
        print(design_text(res, initial, study.title, study.model.units)
              + (validation_text(val) if val else ""))
    text.progress(f"wrote the plan to {args.output}")
    return 0


def cmd_montecarlo(args) -> int:
    from eigenupdate.design.montecarlo import MonteCarloResult
    from eigenupdate.io.montecarlo import FILES, TRIALS_HEADER, write_montecarlo
    from eigenupdate.plot.plots import FIGURE_CREATOR

    check_dir(args.output, "-o")
    if not (args.scheduler or args.in_process):
        check_scheduler(os.environ.get(SCHEDULER_ENV), SCHEDULER_ENV)
    study = eu.load_study(args.study)
    if args.output:
        truth = eu.load_study(args.truth).inputs() if args.truth else []
        figure = FIGURE_CREATOR.encode()
        check_files_in(args.output, FILES, "-o",
                       [*study.inputs(measurements=True, frf=True), *truth],
                       dict(zip(FILES, (TRIALS_HEADER, schema_marker(MonteCarloResult.SCHEMA),
                                        figure, figure), strict=True)), args.force)
    res = eu.montecarlo(study, args.trials, truth=args.truth, seed=args.seed,
                        scheduler=args.scheduler, workers=args.workers,
                        in_process=args.in_process,
                        progress=text.progress_bar if sys.stderr.isatty() else None)
    doc = {**res.summary(), **res.run_info()}
    if args.output:
        write_montecarlo(res, args.output, study.title, res.run_info())
    print(text.dumps(doc) if args.json else text.montecarlo_text(
        doc, study.title, study.model.units))
    text.progress(f"{args.trials} trials in {res.wall_time_s:.1f} s ({res.executor})"
                  + (f"; wrote {args.output}" if args.output else ""))
    if doc["statistics_refused"] is not None:
        raise NotConvergedError(f"no statistics: {doc['statistics_refused']}", field="--trials")
    return 0


def cmd_extract(args) -> int:
    from eigenupdate.io.extraction import write_extraction
    from eigenupdate.io.uff.dataset55 import MODE_ID
    from eigenupdate.measure.extraction import EXTRACTION_COLUMNS
    from eigenupdate.measure.survey import TestExtraction

    files = {"-o": args.output, "--uff55": args.uff55, "--save": args.save}
    own = {"-o": ",".join(EXTRACTION_COLUMNS), "--uff55": MODE_ID.encode(),
           "--save": schema_marker(TestExtraction.SCHEMA)}
    for flag, path in files.items():
        check_file(path, flag)
    check_dir(args.plots, "--plots")
    if args.plots and Path(args.plots).is_dir():  # any fit plot extract may write there
        from eigenupdate.plot.plots import FIGURE_CREATOR

        for fig in sorted(Path(args.plots).glob("extract_*.png")):
            check_replaceable(fig, "--plots", FIGURE_CREATOR.encode(), args.force)
    if len(args.inputs) == 1 and Path(args.inputs[0]).suffix.lower() == ".toml":
        if args.kind:
            raise InputError("goes with FRF files; a study says kind in "
                             "[measurement.frf_options]", field="--kind")
        study = eu.load_study(args.inputs[0], require_model=False)
        # the study's measurement file is where the extracted frequencies go
        check_outputs(files, study.inputs(frf=True), own, args.force)
        done = eu.extract_study(study, progress=text.progress)
    else:  # FRF files on the command line: one configuration per file, named by its stem
        check_outputs(files, [Path(p) for p in args.inputs], own, args.force)
        done = eu.extract_files(args.inputs, args.kind, progress=text.progress)
    res = done.result
    print(text.dumps(res.to_dict()) if args.json else text.extraction_text(res))
    write_extraction(res, done.frfs, args.output, uff55=args.uff55, save=args.save,
                     plots=args.plots, label=done.label)
    text.progress(f"wrote {len(res.modes)} frequencies to {args.output}"
                  + (f", the fit plots to {args.plots}" if args.plots else ""))
    return 0


def cmd_simulate_frf(args) -> int:
    from eigenupdate.io.frf_files import frf_set_names, write_frf_sets

    check_dir(args.output, "-o")
    study = eu.load_study(args.study)
    names = frf_set_names(study.configurations, str(study.path))
    check_files_in(args.output, names, "-o", study.inputs(measurements=True, frf=True))
    if not args.force:  # measured FRFs of another study, or of a real test, look the same
        check_no_replaced(args.output, names, "-o")
    # everything is computed before the directory is made: no half-done output
    sets = eu.simulate_study_frfs(study, args.fmax, args.df, args.input, args.outputs,
                                  args.loss_factor, noise=args.noise, seed=args.seed)
    print("\n".join(write_frf_sets(args.output, sets, args.binary)))
    return 0


def cmd_frf(args) -> int:
    from eigenupdate.plot.plots import FIGURE_CREATOR, plot_frf_comparison

    check_file(args.o, "-o")
    study = eu.load_study(args.study)
    check_outputs({"-o": args.o}, [*study.inputs(measurements=True, frf=True), *(
        Path(p) for p in (args.measured, args.updated, args.damping) if p)],
        {"-o": FIGURE_CREATOR.encode()}, args.force)
    c = eu.compare_frf(study, args.input, args.output, configuration=args.configuration,
                       measured=args.measured, updated=args.updated,
                       loss_factor=args.loss_factor, damping=args.damping, fmax_hz=args.fmax)
    plot_frf_comparison(
        args.o, None, measured=c.measured, initial=(c.frequency_hz, c.initial),
        updated=None if c.updated is None else (c.frequency_hz, c.updated), title=c.title)
    text.progress(f"wrote {args.o}")
    return 0


def cmd_sweep(args) -> int:
    from eigenupdate.plot.plots import FIGURE_CREATOR, plot_mass_sweep

    check_file(args.o, "-o")
    study = eu.load_study(args.study)
    check_outputs({"-o": args.o}, study.inputs(measurements=True, frf=True),
                  {"-o": FIGURE_CREATOR.encode()}, args.force)
    sweep = eu.sweep(study, args.coordinate, args.max_mass, args.modes, args.configuration)
    plot_mass_sweep(args.o, sweep, title=study.title)
    text.progress(f"wrote {args.o}")
    return 0


def cmd_report(args) -> int:
    from eigenupdate.report.html import GENERATOR

    check_file(args.o, "-o")
    saved = [args.result, args.extraction, args.extracted, args.design, args.montecarlo]
    study = eu.load_study(args.study)
    check_outputs({"-o": args.o}, [Path(args.study), *(Path(v) for v in saved if v),
                                   *study.inputs(measurements=True, frf=True)],
                  {"-o": GENERATOR.encode()}, args.force)
    page = eu.report(study, result=args.result, extraction=args.extraction,
                     extracted=args.extracted, design=args.design, montecarlo=args.montecarlo,
                     solve=not args.saved_only, command=shlex.join(["eigenupdate", *args.argv]))
    write_text(args.o, page)
    text.progress(f"wrote {args.o} ({len(page.encode()) / 1024:.0f} kB)")
    return 0


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
    why = outputs.write_stdout(held.getvalue(), out)
    if why is not None:
        with contextlib.suppress(OSError, ValueError, AttributeError):
            print(f"eigenupdate: error: standard output: {why}; the files asked for were "
                  f"written, the printed result was not", file=sys.stderr, flush=True)
        return status or 2
    return status


def _main(argv: Sequence[str] | None) -> int:
    args = build_parser().parse_args(argv)
    args.argv = list(sys.argv[1:] if argv is None else argv)
    if argv is None:  # this process is the command's own: see solve/memory.py
        keep_freed_memory()
    try:
        # every output is renamed into place only if the command returns; floating-point
        # warnings are not printed: results are checked to be finite instead
        with transaction(), np.errstate(all="ignore"), warnings.catch_warnings():
            warnings.simplefilter("always", errors.EigenupdateWarning)
            warnings.showwarning = _show_warning  # one line, no source location
            parallel.threads()  # a bad EIGENUPDATE_THREADS stops every command at once
            budget.check_environment()  # and so does a bad limit
            return globals()[f"cmd_{args.command.replace('-', '_')}"](args)
    except (InputError, NumericalError) as exc:
        # exit 2: bad input, singular matrix, repeated eigenvalue; 1: not converged
        inputs = getattr(args, "inputs", None) or []  # extract on one study names it
        study = getattr(args, "study", None) or (inputs[0] if len(inputs) == 1 and str(
            inputs[0]).endswith(".toml") else None)
        print(f"eigenupdate: error: {exc.located(study)}", file=sys.stderr)
        return exc.exit_status
    except BrokenPipeError:  # output piped into `head` and the like
        sys.stderr.close()
        return 0
    except (np.linalg.LinAlgError, MemoryError) as exc:  # a last resort, not a traceback
        why = ("out of memory" if isinstance(exc, MemoryError) else
               "numerical failure (a matrix that had to be solved is singular or not "
               "positive definite)")
        print(f"eigenupdate: error: {shorten(getattr(args, 'study', None) or '')}: {why}; "
              f"input values or sizes out of range?", file=sys.stderr)
        return 2
    except OSError as exc:  # a file that cannot be read or written, named by the OS
        where = f"{shorten(exc.filename)}: " if exc.filename else ""
        print(f"eigenupdate: error: {where}{shorten(exc.strerror or exc, errors.MAX_MESSAGE)}",
              file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
