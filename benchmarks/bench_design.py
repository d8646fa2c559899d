"""Test design at scale: ``design_plan`` over 1,000 candidates (100 coordinates x 10
masses) of the benchmark frame against one base eigen-solve measured in the same run.

    .venv/bin/python benchmarks/bench_design.py [--size small|full] [--draws N] [--json PATH]

``--draws 0`` (default) designs at the prior mean (the screening of every candidate, then
the greedy and exchange search); ``--draws N`` also averages over N draws of the truth
from a 5 % prior on every parameter, each draw screening the shortlist again (the cost per
draw is printed). The goal of issue 22: at most 20 base eigen-solves at 100k coordinates
for the prior-mean design.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from dataclasses import replace
from pathlib import Path

for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(var, "1")  # as bench_update.py: BLAS threads off, package threads on
sys.path.insert(0, str(Path(__file__).resolve().parent))

import numpy as np  # noqa: E402
from _bench import N_MODES, SIZES, base_solve_time, build_frame, mass_sites  # noqa: E402

from eigenupdate.design.plan import design_plan  # noqa: E402
from eigenupdate.design.spec import DesignSpec  # noqa: E402
from eigenupdate.model.parametric import ParametricModel  # noqa: E402
from eigenupdate.solve.memory import keep_freed_memory  # noqa: E402


def with_prior(model: ParametricModel, rel: float) -> ParametricModel:
    params = tuple(replace(p, std=rel * p.value) for p in model.parameters)
    return replace(model, parameters=params)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", choices=("small", "full"), default="full")
    ap.add_argument("--draws", type=int, default=0)
    ap.add_argument("--json", metavar="PATH")
    a = ap.parse_args(argv)
    keep_freed_memory()
    frame = build_frame(*SIZES[a.size])
    model = with_prior(frame.model, 0.05)
    coords = mass_sites(frame, 100, seed=3)
    masses = frame.total_mass * np.geomspace(1e-3, 2e-2, 10)
    spec = DesignSpec(coordinates=tuple(int(c) for c in coords),
                      masses=tuple(float(m) for m in masses), configurations=10,
                      modes=tuple(range(1, N_MODES + 1)), frequency_std_hz=(0.002,),
                      prior_draws=a.draws, min_shift_in_std=1.0)
    t_base = base_solve_time(model)
    t = time.perf_counter()
    res = design_plan(model, spec, "bayesian")
    t_design = time.perf_counter() - t
    ratio = t_design / t_base
    admissible = sum(c.admissible for c in res.candidates)
    print(f"(design) {model.n} coordinates, {len(res.candidates)} candidates ({admissible} "
          f"admissible), {len(res.names)} parameters, {spec.configurations} configurations: "
          f"{t_design:.1f} s = {ratio:.1f} base eigen-solves (base solve {t_base:.2f} s; "
          f"goal <= 20 at the prior mean)")
    if a.draws:
        print(f"(design) of which {res.draws} draws of the prior: {res.draw_seconds:.1f} s = "
              f"{res.draw_seconds / res.draws / t_base:.1f} base eigen-solves per draw")
    out = {"design": {"coordinates": model.n, "candidates": len(res.candidates),
                      "base_solve_s": t_base, "design_s": t_design, "ratio": ratio,
                      "draws": res.draws, "draw_s": res.draw_seconds,
                      "chosen": [c.name for c in res.configurations]}}
    if a.json:
        Path(a.json).write_text(json.dumps(out, indent=2))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
