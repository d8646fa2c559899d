"""The command line's parser: commands, options and the checks of their values (argparse
types), so that a bad value is a usage error naming its option before any work.

Imports nothing numerical: ``eigenupdate --help`` starts in about the time NumPy does.
"""

from __future__ import annotations

import argparse
import os
import re

from eigenupdate import __version__
from eigenupdate.choices import ESTIMATORS, FRF_KINDS, OPTIMIZERS, SCHEDULER_ENV
from eigenupdate.errors import MAX_MESSAGE, InputError, shorten
from eigenupdate.io.study_table import in_limits


def _number(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None


# as numbers in a study (io/study_table.in_limits): beyond, sums and ratios overflow (a sweep's
# --max-mass 1e308 made its percentage axis inf: a traceback from matplotlib)
_RANGE = "of magnitude 1e-100 to 1e100"


def nonnegative(text: str) -> float:
    """argparse type: 0 or a number >= 1e-100 and <= 1e100."""
    v = _number(text)
    if not in_limits(v) or v < 0:
        raise argparse.ArgumentTypeError(f"{text!r} must be 0 or a number {_RANGE}")
    return v


def positive(text: str) -> float:
    """argparse type: a number > 0, 1e-100 to 1e100."""
    v = _number(text)
    if not in_limits(v) or v <= 0:
        raise argparse.ArgumentTypeError(f"{text!r} must be a number > 0 {_RANGE}")
    return v


def _integer(text: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not an integer") from None


def seed(text: str) -> int:
    """argparse type: a random seed, an integer >= 0."""
    value = _integer(text)
    if value < 0:
        raise argparse.ArgumentTypeError(f"{value} must be >= 0")
    return value


def count(text: str) -> int:
    """argparse type: an integer >= 1 (workers)."""
    value = _integer(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be >= 1, got {value}")
    return value


def workers(text: str) -> int:
    """argparse type: worker processes of a local cluster, 1 to 4 per core (each is a
    Python process with NumPy and SciPy: --workers 1000000 forked until the run hung)."""
    value = count(text)
    most = 4 * (os.cpu_count() or 1)
    if value > most:
        raise argparse.ArgumentTypeError(
            f"must be at most {most} (4 per core of this machine), got {value}")
    return value


_SCHEDULER = re.compile(r"(tcp://)?(\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9._-]+):\d{1,5}")


_NOT_SCHEDULER = ("is not a scheduler address tcp://HOST:PORT (tls:// and other protocols "
                  "are not supported)")


def _is_scheduler(address: str) -> bool:
    # tls:// needs certificates this command does not take
    # port 0 is "any free port" to a server, no port a client can reach
    return bool(_SCHEDULER.fullmatch(address)) and 1 <= int(address.rsplit(":", 1)[1]) <= 65535


def check_scheduler(address: str | None, flag: str) -> None:
    """Refuse a scheduler address Dask cannot use as given (of ``flag``, e.g. an
    environment variable)."""
    if address is not None and not _is_scheduler(address):
        raise InputError(f"{address!r} {_NOT_SCHEDULER}", field=flag)


def scheduler(text: str) -> str:
    """argparse type: a Dask scheduler address."""
    if not _is_scheduler(text):
        raise argparse.ArgumentTypeError(f"{text!r} {_NOT_SCHEDULER}")
    return text


class _Parser(argparse.ArgumentParser):
    """Usage errors in one line, like every other bad input (exit status 2)."""

    def error(self, message: str):
        self.exit(2, f"{self.prog}: error: {shorten(message, MAX_MESSAGE)} "
                     f"(see {self.prog} --help)\n")


_FORCE = "replace an existing output file that this command did not write (never an input)"


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

    s = sub.add_parser("simulate", help="measurement CSV this model (as the truth) would give")
    s.add_argument("study")
    s.add_argument("-o", "--output", required=True)
    s.add_argument("--noise-hz", type=nonnegative, default=0.0, help="Gaussian noise std (Hz)")
    s.add_argument("--noise-relative", type=nonnegative, default=0.0,
                   help="Gaussian noise std as a fraction of each frequency (0.001: 0.1 %%); "
                        "adds in quadrature to --noise-hz")
    s.add_argument("--std-hz", type=positive,
                   help="std_hz column (default: each frequency's noise level)")
    s.add_argument("--seed", type=seed)
    s.add_argument("--force", action="store_true", help=_FORCE)

    s = sub.add_parser("check", help="identifiability of the test plan (condition, rank of J)")
    s.add_argument("study")
    s.add_argument("--method", choices=ESTIMATORS,
                   help="weight J as this estimator does (default: the study's; "
                        "least-squares: the plan's own J, as the paper)")
    s.add_argument("--json", action="store_true")

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
                   help="let an unconverged result replace an existing --save file, and "
                        "--save-bdf replace a file it did not write")

    s = sub.add_parser("design", help="choose the added masses from the study's [design] table")
    s.add_argument("study")
    s.add_argument("-o", "--output", required=True, metavar="PLAN.toml",
                   help="the plan as a study file")
    s.add_argument("--force", action="store_true",
                   help="replace an existing PLAN.toml that design did not write")
    s.add_argument("--scheduler", metavar="tcp://HOST:PORT", type=scheduler,
                   help="screen the candidates on this Dask scheduler (default: in this process)")
    s.add_argument("--workers", type=workers,
                   help="screen the candidates on a local Dask cluster of this many processes")
    s.add_argument("--validate", type=int, metavar="N",
                   help="then run N virtual tests of the plan (truth drawn from the prior) and "
                        "print predicted against empirical std")
    s.add_argument("--seed", type=seed, default=0, help="seed of the --validate trials")
    s.add_argument("--json", action="store_true")

    s = sub.add_parser("montecarlo", help="virtual tests of the study's plan: bias, std, coverage")
    s.add_argument("study")
    s.add_argument("--trials", type=count, required=True)
    s.add_argument("--truth", metavar="STUDY", help="study whose model holds the true values "
                   "(default: draw them from the priors)")
    s.add_argument("--seed", type=seed)
    s.add_argument("-o", "--output", metavar="DIR", help="write trials.csv, summary.json, plots")
    s.add_argument("--scheduler", metavar="tcp://HOST:PORT", type=scheduler,
                   help=f"existing Dask scheduler (or ${SCHEDULER_ENV}); default: a local "
                        f"cluster, one worker process per core")
    s.add_argument("--workers", type=workers, help="worker processes of the local cluster")
    s.add_argument("--in-process", action="store_true", help="no Dask: run here, one by one")
    s.add_argument("--force", action="store_true",
                   help="replace files in DIR that montecarlo did not write (never an input)")
    s.add_argument("--json", action="store_true")

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
    s.add_argument("--force", action="store_true", help=_FORCE)

    s = sub.add_parser("simulate-frf", help="synthetic noisy FRFs of every configuration (UFF 58)")
    s.add_argument("study")
    s.add_argument("-o", "--output", required=True, metavar="DIR")
    s.add_argument("--input", type=int, required=True, help="excitation coordinate")
    s.add_argument("--outputs", type=int, nargs="+", required=True, help="response coordinates")
    s.add_argument("--loss-factor", type=nonnegative, nargs="+", default=[0.01],
                   help="hysteretic loss factor, one value or one per elastic mode")
    s.add_argument("--noise", type=nonnegative, default=0.01,
                   help="complex noise std as a fraction of the largest peak")
    s.add_argument("--fmax", type=positive, required=True, help="highest frequency (Hz)")
    s.add_argument("--df", type=positive, default=0.5, help="frequency resolution (Hz)")
    s.add_argument("--binary", action="store_true", help="write binary UFF 58b")
    s.add_argument("--force", action="store_true",
                   help="replace files of the same names in DIR (never the study's inputs)")
    s.add_argument("--seed", type=seed)

    s = sub.add_parser("frf", help="plot predicted (and measured) receptance, paper Fig. 7")
    s.add_argument("study")
    s.add_argument("--input", type=int, required=True, help="excitation coordinate")
    s.add_argument("--output", type=int, required=True, help="response coordinate")
    s.add_argument("--configuration", help="configuration name (default: base)")
    s.add_argument("--measured", help="FRF file (UFF 58 or CSV) to compare with")
    s.add_argument("--updated", metavar="RESULT.json", help="result of 'update --save'")
    s.add_argument("--loss-factor", type=nonnegative, default=0.01,
                   help="hysteretic loss factor of every mode (default 0.01)")
    s.add_argument("--damping", metavar="UFF55",
                   help="per-mode loss factors from 'extract --uff55' (modes above the last "
                        "take its value)")
    s.add_argument("--fmax", type=positive, help="highest frequency without --measured (Hz)")
    s.add_argument("-o", required=True, metavar="FIG", help="figure file (.png, .svg, .pdf)")
    s.add_argument("--force", action="store_true", help=_FORCE)

    s = sub.add_parser("sweep", help="frequencies against added mass at a coordinate, Fig. 4")
    s.add_argument("study")
    s.add_argument("--coordinate", type=int, required=True)
    s.add_argument("--max-mass", type=positive, required=True, help="largest added mass (kg)")
    s.add_argument("--modes", type=int, help="number of elastic modes")
    s.add_argument("--configuration", help="configuration to add the mass to (default: base)")
    s.add_argument("-o", required=True, metavar="FIG")
    s.add_argument("--force", action="store_true", help=_FORCE)

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
    s.add_argument("--force", action="store_true", help=_FORCE)
    return p
