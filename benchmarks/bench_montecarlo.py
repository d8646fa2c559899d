"""Monte Carlo of the shipped beam study: wall time on a local Dask cluster against a single
process (the baseline, measured in the same run), and the check that both give the same
trials bit for bit.

    .venv/bin/python benchmarks/bench_montecarlo.py [--trials 500] [--workers N] [--seed S]
"""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

import numpy as np

from eigenupdate.design.executor import DaskExecutor, InProcess
from eigenupdate.design.montecarlo import montecarlo, study_setup
from eigenupdate.io.study import load_study

STUDY = Path(__file__).resolve().parents[1] / "examples" / "paper_beam" / "study.toml"


def _run(setup, trials, seed, executor):
    start = time.perf_counter()
    r = montecarlo(setup, trials, seed, executor)
    return r, time.perf_counter() - start


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--trials", type=int, default=500)
    ap.add_argument("--workers", type=int, default=os.cpu_count())
    ap.add_argument("--seed", type=int, default=2026)
    a = ap.parse_args()
    setup = study_setup(load_study(STUDY))
    one, t_one = _run(setup, a.trials, a.seed, InProcess())
    start = time.perf_counter()
    with DaskExecutor(n_workers=a.workers) as ex:
        t_start = time.perf_counter() - start
        many, t_many = _run(setup, a.trials, a.seed, ex)
    same = all(np.array_equal(x[k], y[k], equal_nan=True) and x["converged"] == y["converged"]
               for x, y in zip(one.trials, many.trials, strict=True)
               for k in ("truth", "estimate", "std"))
    print(f"beam study, {a.trials} trials, {os.cpu_count()} cores "
          f"(load average {os.getloadavg()[0]:.1f})")
    print(f"  single process:              {t_one:8.2f} s  (baseline)")
    print(f"  local cluster, {a.workers} workers:   {t_many:8.2f} s  ratio {t_one / t_many:.2f}x "
          f"(+ {t_start:.1f} s cluster start-up)")
    print(f"  same results bit for bit:    {same}")
    if not same:
        raise SystemExit(1)


if __name__ == "__main__":
    main()
