"""Monte Carlo of the shipped beam study: wall time on a local Dask cluster against a single
process (the baseline, measured in the same run), and the check that both give the same
trials bit for bit.

    .venv/bin/python benchmarks/bench_montecarlo.py [--trials N | --seconds S] [--workers N]
        [--seed S] [--json PATH]

Without ``--trials`` the study is sized from pilot runs of 2 and 20 trials in this process
(a study's fixed set-up and its cost per trial) to take about ``--seconds`` (default 70,
so that it takes at least a minute) in one process. ``--json`` writes {"speedup",
"workers", "t_inprocess", "identical", ...}. The cluster's start-up is timed apart from the study.

Both sides are single-threaded per process: this process sets the BLAS and the package's
thread counts to 1 before NumPy is imported, and Dask's nannies start their workers with
OPENBLAS/OMP/MKL_NUM_THREADS=1 (``distributed.nanny.pre-spawn-environ``, read back from the
workers and written to the JSON), so the speed-up compares one core with ``--workers``.
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

THREAD_VARS = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS",
               "EIGENUPDATE_THREADS")
for _var in THREAD_VARS:  # before NumPy is imported: OpenBLAS reads it once
    os.environ[_var] = "1"

import numpy as np  # noqa: E402

from eigenupdate.design.executor import Automatic, DaskExecutor, InProcess  # noqa: E402
from eigenupdate.design.montecarlo import montecarlo, study_setup  # noqa: E402
from eigenupdate.io.study import load_study  # noqa: E402

STUDY = Path(__file__).resolve().parents[1] / "examples" / "paper_beam" / "study.toml"
PILOT = 20


def _run(setup, trials, seed, executor):
    start = time.perf_counter()
    r = montecarlo(setup, trials, seed, executor)
    return r, time.perf_counter() - start


def _cpu() -> float:
    """CPU seconds of this process, all threads (also run on each worker)."""
    return time.process_time()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--trials", type=int, help="default: sized by --seconds")
    ap.add_argument("--seconds", type=float, default=70.0,
                    help="size the study to take about this long in one process (default "
                         "70: pilots misjudge it by up to ~20 %%, and the study should take "
                         "at least a minute)")
    ap.add_argument("--workers", type=int, default=os.cpu_count())
    ap.add_argument("--seed", type=int, default=2026)
    ap.add_argument("--json", metavar="PATH", help="also write the results to this JSON file")
    a = ap.parse_args()
    setup = study_setup(load_study(STUDY))
    # a study costs a fixed set-up (~6 s here) plus its trials: sized from 20 trials
    # alone, "60 s" ran 30 s; two pilots give both
    _, t_two = _run(setup, 2, a.seed + 2, InProcess())
    _, t_pilot = _run(setup, PILOT, a.seed + 1, InProcess())
    per_trial = max(t_pilot - t_two, t_pilot / 4) / (PILOT - 2)
    fixed = max(t_two - 2 * per_trial, 0.0)
    trials = a.trials or max(PILOT, int(round((a.seconds - fixed) / per_trial)))
    with Automatic(n_workers=a.workers) as auto:  # what the command line does by default
        _, t_auto = _run(setup, PILOT, a.seed + 1, auto)
        auto_choice = str(auto)
    c0 = _cpu()
    one, t_one = _run(setup, trials, a.seed, InProcess())
    c_one = _cpu() - c0
    start = time.perf_counter()
    with DaskExecutor(n_workers=a.workers) as ex:
        t_start = time.perf_counter() - start
        before = ex.client.run(_cpu)
        many, t_many = _run(setup, trials, a.seed, ex)
        after = ex.client.run(_cpu)
        worker_env = ex.client.run(lambda: {v: os.environ.get(v) for v in THREAD_VARS})
    # the machine is shared: CPU time says whether the workers did the same work as this
    # process (then a shortfall in wall time is the load, not Dask)
    c_many = sum(after[w] - before[w] for w in after)
    same = all(np.array_equal(x[k], y[k], equal_nan=True) and x["converged"] == y["converged"]
               for x, y in zip(one.trials, many.trials, strict=True)
               for k in ("truth", "estimate", "std"))
    load = os.getloadavg()[0]
    print(f"beam study, {trials} trials (sized from pilots: {fixed:.1f} s set-up + "
          f"{per_trial:.3f} s a trial), {os.cpu_count()} cores (load average {load:.1f})")
    print(f"  single process:              {t_one:8.2f} s  (baseline)")
    if not a.trials and t_one < 60:  # the pilots' trials can cost more than the study's
        print(f"  note: {t_one:.0f} s, not the minute the issue asks for: rerun with "
              f"--trials {int(trials * 65 / max(t_one - fixed, 1.0))}")
    print(f"  local cluster, {a.workers} workers:   {t_many:8.2f} s  speed-up "
          f"{t_one / t_many:.2f}x = {t_one / t_many / a.workers:.2f} x workers "
          f"(+ {t_start:.1f} s cluster start-up)")
    print(f"  same results bit for bit:    {same}")
    print(f"  CPU time: {c_one:.1f} s in one process, {c_many:.1f} s on the workers together "
          f"({c_many / c_one:.2f}x)")
    envs = sorted({tuple(sorted(e.items())) for e in worker_env.values()})
    print(f"  thread settings here: {{{', '.join(f'{v}={os.environ[v]}' for v in THREAD_VARS)}}}"
          f"; on the workers: {[dict(e) for e in envs]}")
    print(f"  automatic choice, {PILOT} trials: {auto_choice}, {t_auto:.2f} s")
    if a.json:
        doc = {"speedup": t_one / t_many, "workers": a.workers, "t_inprocess": t_one,
               "identical": bool(same), "trials": trials, "t_cluster": t_many,
               "t_cluster_start": t_start, "cores": os.cpu_count(), "load_average": load,
               "automatic_20_trials": {"choice": auto_choice, "seconds": t_auto},
               "cpu_inprocess": c_one, "cpu_workers": c_many,
               "threads_here": {v: os.environ[v] for v in THREAD_VARS},
               "threads_on_workers": [dict(e) for e in envs]}
        Path(a.json).write_text(json.dumps(doc, indent=2) + "\n", encoding="utf-8")
        print(f"results written to {a.json}")
    if not same:
        raise SystemExit(1)


if __name__ == "__main__":
    main()
