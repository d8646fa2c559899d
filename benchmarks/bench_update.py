"""Benchmark of mass-addition model updating on a large 3-D steel space frame.

(a) one update iteration (linearise over the bare structure + 20 mass perturbations at
    10 modes, plus the least-squares step) against one eigen-solve of the bare structure,
    at about 100k coordinates;
    with the split of the fast perturbed-configuration path and its accuracy against
    independent full re-solves of a sample;
(many) the cost per added configuration, 20 against 80 perturbations;
(screen) screening 1,000 single-mass candidates (100 coordinates x 10 masses);
(scaling) one iteration against one eigen-solve as the mesh is refined (25k-200k);
(whole) the whole update at about 100k coordinates (default optimiser, start 2.5-5 % off,
    error-free data) against one base eigen-solve, with the time of each phase;
(stop) whether the update stops promptly when done, at 13k coordinates, with error-free
    and with noisy (0.1 %) frequencies;
(b) the whole update (:func:`eigenupdate.identify.updating.update`) against
    ``scipy.optimize.least_squares`` with a finite-difference Jacobian whose every
    residual solves each configuration with SciPy's ``eigsh`` (shift-invert, its own
    factorisation), at a size where the baseline finishes in minutes.

Run ``python benchmarks/bench_update.py [--size small|full]
[--only a|many|screen|scaling|b|whole|stop] [--json PATH]``
(``--help`` for the other options).
See benchmarks/README.md.

This file only parses the options and sets the BLAS thread count: OpenBLAS reads it when
NumPy is first imported, so the benchmark proper (``_bench.py``) is imported afterwards.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

THREAD_VARS = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")


def parse(argv=None) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--size", choices=("small", "full"), default="full",
                   help="full: (a) at 103k coordinates, (b) at 2k (default, ~4 min); "
                        "small: a quick run (~20 s), (a) at 6k, (b) at 600")
    p.add_argument("--only", choices=("a", "many", "screen", "scaling", "b", "whole", "stop"),
                   help="run only one of the benchmarks")
    p.add_argument("--colamd", action="store_true",
                   help="(a) also repeat it with SuperLU's default COLAMD ordering (~1 min)")
    p.add_argument("--json", metavar="PATH", help="also write the results to this JSON file")
    p.add_argument("--blas-threads", type=int, default=1, metavar="N",
                   help="BLAS threads (default 1; 0 leaves the library default). On the "
                        "shared 2-core test machine OpenBLAS threading made ARPACK several "
                        "times slower, see README")
    p.add_argument("--baseline-max-nfev", type=int, default=None, metavar="N",
                   help="cap on the baseline's iterations (least_squares max_nfev, which "
                        "does not count finite-difference evaluations); default 20 (full), "
                        "3 (small); 0 = scipy's default (100 x parameters)")
    p.add_argument("--default-allocator", action="store_true",
                   help="leave glibc's malloc settings alone; by default the benchmark "
                        "keeps freed memory as the command line does "
                        "(eigenupdate.solve.memory)")
    p.add_argument("--reference", action="store_true",
                   help="(b) also run least_squares with the package's exact Jacobian, to "
                        "separate the Jacobian's accuracy from the optimiser (minutes)")
    return p.parse_args(argv)


def main(argv=None) -> int:
    args = parse(argv)
    if args.blas_threads > 0:
        for var in THREAD_VARS:
            os.environ[var] = str(args.blas_threads)
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    import _bench  # after the thread count is set

    return _bench.run(args)


if __name__ == "__main__":
    sys.exit(main())
