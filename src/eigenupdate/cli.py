"""Command line: a thin shell over the library.

Exit status: 0 success, 1 the update did not converge (the result is still printed),
2 bad input (a one-line message naming the file and the field; no traceback).
"""

from __future__ import annotations

import argparse
import json
import re
import shlex
import sys
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from eigenupdate.errors import InputError
from eigenupdate.identify.identifiability import check
from eigenupdate.identify.updating import METHODS, update
from eigenupdate.io.atomic import write_text
from eigenupdate.io.frf_options import frf_options
from eigenupdate.io.measurements import Measurement, write_measurements
from eigenupdate.io.study import Study, load_study
from eigenupdate.io.uff import Mode, read_frf_files, read_modes, write_frfs, write_modes
from eigenupdate.measure.extraction import extract_configuration, extraction_csv
from eigenupdate.measure.frf import dof_label
from eigenupdate.measure.synthetic import synthetic_frfs
from eigenupdate.plot.plots import plot_extraction_fit, plot_frf_comparison, plot_mass_sweep
from eigenupdate.report import text as report
from eigenupdate.report.html import write_report
from eigenupdate.solve.jacobian import solve_configurations
from eigenupdate.solve.response import receptance, uff_point


def _output_file(path: str | None, flag: str) -> None:
    """Refuse an output file that cannot be written, before any work is done."""
    if path is None:
        return
    p = Path(path)
    if not str(path) or p.is_dir():
        raise InputError("is a directory or empty; give a file name", source=str(path),
                         field=flag)
    if not p.resolve().parent.is_dir():
        raise InputError(f"directory {str(p.parent)!r} does not exist", source=str(path),
                         field=flag)


def _output_dir(path: str | None, flag: str) -> None:
    """Refuse an output directory that is a file or whose parent does not exist."""
    if path is None:
        return
    p = Path(path)
    if not str(path) or (p.exists() and not p.is_dir()):
        raise InputError("exists and is not a directory", source=str(path), field=flag)
    if not p.resolve().parent.is_dir():
        raise InputError(f"directory {str(p.parent)!r} does not exist", source=str(path),
                         field=flag)


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


def _n_modes(study: Study, requested: int | None) -> int:
    if requested is not None:
        if requested < 1:
            raise InputError(f"{requested} must be >= 1", field="--modes")
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
    _output_file(args.output, "-o")
    _finite(args.noise_hz, "--noise-hz")
    _finite(args.std_hz, "--std-hz", positive=True)
    study = load_study(args.study)
    modes = study.require_modes()
    std = args.std_hz if args.std_hz is not None else (args.noise_hz or None)
    sols = solve_configurations(study.model, study.configurations, max(modes))
    rng = np.random.default_rng(args.seed)
    rows = []
    for c, s in zip(study.configurations, sols, strict=True):
        for k in modes:
            f = float(s.frequencies_hz[k - 1])
            if args.noise_hz > 0:
                f += float(rng.normal(0.0, args.noise_hz))
                if f <= 0:
                    raise InputError(f"noise of {args.noise_hz:g} Hz made the frequency of "
                                     f"{c.name!r} mode {k} negative; use less noise",
                                     field="--noise-hz")
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
    _output_file(args.save, "--save")
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


def _progress(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


def _safe_name(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9.-]+", "_", name).strip("_") or "configuration"


def cmd_extract(args) -> int:
    _output_file(args.output, "-o")
    _output_file(args.uff55, "--uff55")
    _output_dir(args.plots, "--plots")
    study = load_study(args.study)
    modes = study.require_modes()
    bands, low = frf_options(study)
    missing = [c.name for c in study.configurations if not study.frf.get(c.name)]
    if missing:
        raise InputError(f"no FRF file for configuration(s) {missing}", source=str(study.path),
                         field="measurement.frf")
    done = []  # everything is extracted before anything is written
    n = len(study.configurations)
    for i, c in enumerate(study.configurations, 1):
        files = study.frf[c.name]
        frfs = read_frf_files(files)
        _progress(f"[{i}/{n}] {c.name}: {len(frfs)} FRF(s) from {len(files)} file(s)")
        ex = extract_configuration(frfs, modes, c.name, bands_hz=bands.get(c.name),
                                   exclude_below_hz=low)
        for m in ex:
            d = m.disagreement
            if d is not None and d > 4:
                _progress(f"  warning: {c.name} mode {m.mode}: Dobson {m.frequency_hz:.4f} Hz and "
                          f"rational fraction {m.check_hz:.4f} Hz differ by {d:.1f} std")
        done.append((c, frfs, ex))
    results = [m for _, _, ex in done for m in ex]
    if args.plots:
        Path(args.plots).mkdir(parents=True, exist_ok=True)
        for c, frfs, ex in done:
            for j, x in enumerate(frfs):
                shown = [m for m in ex if m.fits[j] is not None]
                if shown:
                    out = Path(args.plots) / f"extract_{_safe_name(c.name)}_{j + 1}.png"
                    plot_extraction_fit(out, x.frequency_hz, x.receptance,
                                        [m.fits[j] for m in shown],
                                        mode_numbers=[m.mode for m in shown],
                                        title=f"{c.name}: {dof_label(x.response)}/"
                                              f"{dof_label(x.reference)}")
        _progress(f"wrote the fit plots to {args.plots}")
    write_text(args.output, extraction_csv(results))
    if args.uff55:
        write_modes(args.uff55, [
            Mode(m.frequency_hz, loss_factor=m.loss_factor, mode_number=m.mode,
                 label=m.configuration)
            for m in results])
    print(report.table(
        ["configuration", "mode", "f Hz", "std Hz", "loss factor", "check f Hz", "diff/std"],
        [[m.configuration, m.mode, m.frequency_hz, m.std_hz, m.loss_factor, m.check_hz,
          m.disagreement] for m in results]))
    _progress(f"wrote {len(results)} frequencies to {args.output}")
    return 0


def cmd_simulate_frf(args) -> int:
    _output_dir(args.output, "-o")
    _finite(args.fmax, "--fmax", positive=True)
    _finite(args.df, "--df", positive=True)
    if args.fmax <= args.df or args.fmax / args.df > 1e7:
        raise InputError(f"need --df < --fmax and at most 1e7 lines, got --df {args.df:g}, "
                         f"--fmax {args.fmax:g}", field="--fmax")
    if len(set(args.outputs)) != len(args.outputs):
        raise InputError(f"coordinates repeated in {args.outputs}", field="--outputs")
    study = load_study(args.study)
    f = np.arange(args.df, args.fmax + 0.5 * args.df, args.df)  # 0 Hz: rigid modes are infinite
    out = Path(args.output)
    rng = np.random.default_rng(args.seed)
    lines = ["[measurement.frf]"]
    sets = []  # everything is computed before the directory is made: no half-done output
    for c in study.configurations:
        sets.append((c, synthetic_frfs(study.model, c, f, args.input, args.outputs,
                                       args.loss_factor, noise=args.noise, seed=rng)))
    out.mkdir(parents=True, exist_ok=True)
    for c, frfs in sets:
        name = f"{_safe_name(c.name)}.uff"
        write_frfs(out / name, frfs, binary=args.binary)
        lines.append(f'"{c.name}" = "{out.name}/{name}"')
    print("\n".join(lines))
    return 0


def _updated_values(study: Study, path: str) -> dict[str, float]:
    try:
        doc = json.loads(Path(path).read_text(encoding="utf-8"))
        values = doc["parameters"]
        if not isinstance(values, dict):
            raise TypeError
    except OSError as exc:
        raise InputError(f"cannot read result: {exc.strerror or exc}", source=path) from None
    except (ValueError, KeyError, TypeError):
        raise InputError("not a result of 'eigenupdate update --save' (no parameters table)",
                         source=path, field="parameters") from None
    unknown = set(values) - set(study.model.names)
    if unknown:
        raise InputError(f"parameters {sorted(unknown)} are not in the study's model",
                         source=path, field="parameters")
    missing = [n for n in study.model.names if n not in values]
    if missing:
        raise InputError(f"no value for {missing} (a result of another study?)",
                         source=path, field="parameters")
    for p in study.model.parameters:
        v = values[p.name]
        ok = isinstance(v, int | float) and not isinstance(v, bool) and np.isfinite(v)
        if not ok or v < 0 or (v == 0 and p.value > 0):
            raise InputError(f"{v!r} is not a physical value (initial {p.value:g})",
                             source=path, field=f"parameters.{p.name}")
    return values


def cmd_frf(args) -> int:
    _output_file(args.o, "-o")
    _finite(args.fmax, "--fmax", positive=True)
    _finite(args.loss_factor, "--loss-factor")
    study = load_study(args.study)
    config = _configuration(study, args.configuration)
    kind = study.model_type
    measured = None
    if args.measured:
        frfs = read_frf_files([args.measured])
        want = (uff_point(kind, args.output), uff_point(kind, args.input))
        match = [x for x in frfs if (x.response, x.reference) == want]
        if not match and len(frfs) == 1 and frfs[0].response == (0, 0):
            match = frfs  # a CSV FRF carries no points: take it as the one asked for
        if not match:
            have = ", ".join(f"{dof_label(x.response)}/{dof_label(x.reference)}" for x in frfs)
            raise InputError(f"no FRF for response {dof_label(want[0])}, reference "
                             f"{dof_label(want[1])} (file has {have})", source=args.measured)
        measured = match[0]
        f = measured.frequency_hz
    else:
        modes = study.modes or [1]
        top = solve_configurations(study.model, [config], max(modes))[0].frequencies_hz[-1]
        fmax = args.fmax or 2.0 * top
        f = np.linspace(fmax / 2000, fmax, 2000)
    f_pos = f[f > 0]
    eta, eta_text = args.loss_factor, f"loss factor {args.loss_factor:g}"
    if args.damping:
        eta = _extracted_loss_factors(args.damping, config.name)
        eta_text = "extracted loss factors " + ", ".join(f"{e:.3g}" for e in eta)
    curves = {}
    models = {"initial": study.model}
    if args.updated:
        models["updated"] = study.model.with_values(_updated_values(study, args.updated))
    for label, model in models.items():
        h = receptance(model, f_pos, args.input, args.output, configuration=config,
                       loss_factor=eta)
        curves[label] = (f_pos, h)
    plot_frf_comparison(
        args.o, None, measured=measured, initial=curves["initial"], updated=curves.get("updated"),
        title=f"{study.title}\n{config.name}: receptance {args.output}/{args.input}, {eta_text}")
    _progress(f"wrote {args.o}")
    return 0


def _extracted_loss_factors(path: str, configuration: str) -> list[float]:
    """Loss factors of elastic modes 1, 2, ... of a configuration from `extract --uff55`."""
    modes = sorted((m.mode_number, m.loss_factor) for m in read_modes(path)
                   if m.label == configuration)
    if not modes or [k for k, _ in modes] != list(range(1, len(modes) + 1)):
        raise InputError(f"no loss factors of modes 1, 2, ... for configuration "
                         f"{configuration!r}", source=path)
    return [eta for _, eta in modes]


def _configuration(study: Study, name: str | None):
    if name is None:
        return study.configurations[0]
    for c in study.configurations:
        if c.name == name:
            return c
    raise InputError(f"no configuration {name!r} (have {[c.name for c in study.configurations]})")


def cmd_sweep(args) -> int:
    _output_file(args.o, "-o")
    _finite(args.max_mass, "--max-mass", positive=True)
    if args.modes is not None and args.modes < 1:
        raise InputError(f"{args.modes} must be >= 1", field="--modes")
    study = load_study(args.study)
    n = args.modes or max(study.modes or [3])
    plot_mass_sweep(args.o, study.model, args.coordinate, args.max_mass, n,
                    configuration=_configuration(study, args.configuration),
                    title=study.title)
    _progress(f"wrote {args.o}")
    return 0


def cmd_report(args) -> int:
    _output_file(args.o, "-o")
    files = {"--result": args.result, "--extracted": args.extracted, "--design": args.design,
             "--montecarlo": args.montecarlo}
    command = ["eigenupdate", "report", args.study, *[x for k, v in files.items() if v
                                                      for x in (k, v)], "-o", args.o]
    out = write_report(args.study, output=args.o, result=args.result, extracted=args.extracted,
                       design=args.design, montecarlo=args.montecarlo,
                       command=shlex.join(command))
    _progress(f"wrote {out} ({out.stat().st_size / 1024:.0f} kB)")
    return 0


class _Parser(argparse.ArgumentParser):
    """Usage errors in one line, like every other bad input (exit status 2)."""

    def error(self, message: str):
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(
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
    s.add_argument("--seed", type=_seed)
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

    s = sub.add_parser("extract", help="natural frequencies from the study's measured FRFs")
    s.add_argument("study")
    s.add_argument("-o", "--output", required=True, help="measurement CSV to write")
    s.add_argument("--uff55", help="also write the modes (with loss factors) as UFF 55")
    s.add_argument("--plots", metavar="DIR", help="save a plot of every fit in DIR")
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
    s.add_argument("--extracted", metavar="CSV", help="extraction CSV of 'extract -o'")
    s.add_argument("--design", metavar="PLAN.json", help="test design, any JSON object")
    s.add_argument("--montecarlo", metavar="SUMMARY.json", help="Monte Carlo summary, any JSON "
                   "object")
    s.add_argument("-o", required=True, metavar="REPORT.html")
    s.set_defaults(func=cmd_report)
    return p


def _located(exc: InputError, args) -> str:
    """The message, prefixed by the study file when the library could not name a file.

    Errors found deep in the numerics (too few elastic modes, an indefinite mass matrix)
    come from the study's model all the same; options (``--x``) name themselves.
    """
    study = getattr(args, "study", None)
    if exc.source is None and study and not (exc.field or "").startswith("-"):
        return f"{study}: {exc}"
    return str(exc)


def main(argv: Sequence[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except InputError as exc:
        print(f"eigenupdate: error: {_located(exc, args)}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # output piped into `head` and the like
        sys.stderr.close()
        return 0
    except OSError as exc:  # a file that cannot be read or written, named by the OS
        where = f"{exc.filename}: " if exc.filename else ""
        print(f"eigenupdate: error: {where}{exc.strerror or exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
