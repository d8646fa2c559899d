"""Does the update converge on frames it was not tuned on? The benchmark's problem (30
parameters, 20 added masses of 1 % of the frame's mass, modes 1-10, error-free data,
start 2.5-5 % off) on 10 frame sizes x 2 seeds of ``frame.py``'s family, with the
defaults of :func:`eigenupdate.identify.updating.update`.

``.venv/bin/python benchmarks/bench_family.py [--free] [--max-iterations N] [--json PATH]``

Prints one line per frame (converged, iterations, largest relative parameter error,
clusters, cut groups) and the count that converged to the truth (error <= 1e-6). About
2 minutes for the clamped frames on 2 cores; ``--free`` adds the free-free ones (about 15
more: they run to the limit).
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np
from frame import build_frame, mass_sites

from eigenupdate.identify.updating import update
from eigenupdate.measure.measurement import Measurement
from eigenupdate.model.configurations import BASE, Configuration, mass_at
from eigenupdate.solve.jacobian import solve_configurations

SIZES = [(2, 2, 5, 4), (1, 1, 5, 3), (2, 1, 5, 3), (3, 2, 6, 3), (3, 3, 6, 2), (4, 2, 8, 2),
         (4, 3, 6, 4), (5, 3, 10, 2), (2, 3, 12, 2), (3, 1, 9, 3)]
SEEDS = (1, 3)


def problem(dims, seed: int, supports: str = "clamped"):
    """The benchmark's problem on a frame of ``dims`` (bays X, bays Y, storeys, elements
    per member): (model at its start, configurations, modes, error-free data, truth)."""
    fr = build_frame(*dims, seed=seed, supports=supports)
    added = 0.01 * fr.total_mass
    configs = [Configuration(BASE)] + [
        mass_at(c, added, name=f"m{i + 1:02d}@{c}")
        for i, c in enumerate(mass_sites(fr, 20, seed=seed + 1))]
    modes = list(range(1, 11))
    sols = solve_configurations(fr.model.with_values(fr.truth), configs, 10)
    data = {(c.name, k): Measurement(c.name, k, float(s.frequencies_hz[k - 1]))
            for c, s in zip(configs, sols, strict=True) for k in modes}
    return fr.model, configs, modes, data, fr.truth


def one(dims, seed: int, supports: str, max_iterations: int) -> dict:
    model, configs, modes, data, truth = problem(dims, seed, supports)
    t = time.perf_counter()
    res = update(model, configs, modes, data, max_iterations=max_iterations)
    got = np.array([res.parameters[n] for n in model.names])
    err = float(np.max(np.abs(got / truth - 1)))
    notes = res.pairing["notes"]
    return {"frame": list(dims), "seed": seed, "supports": supports, "coordinates": model.n,
            "converged": bool(res.success), "iterations": res.nit, "max_rel_error": err,
            "truth": bool(res.success and err <= 1e-6), "seconds": time.perf_counter() - t,
            "clusters": len(res.pairing["clusters"]),
            "cut_groups": sum(n["kind"] == "cut group" for n in notes),
            "message": res.message}


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--free", action="store_true", help="also the free-free frames")
    p.add_argument("--max-iterations", type=int, default=20)
    p.add_argument("--json", help="write the results here")
    args = p.parse_args()
    out = []
    for supports in ("clamped", "free") if args.free else ("clamped",):
        for dims in SIZES:
            for seed in SEEDS:
                r = one(dims, seed, supports, args.max_iterations)
                out.append(r)
                print(f"{'truth' if r['truth'] else 'FAILED'} {tuple(dims)} seed {seed} "
                      f"{supports} ({r['coordinates']} coordinates): converged "
                      f"{r['converged']} in {r['iterations']}, error {r['max_rel_error']:.1e}, "
                      f"{r['clusters']} clusters, {r['cut_groups']} cut groups, "
                      f"{r['seconds']:.0f} s", flush=True)
    print(f"converged to the truth: {sum(r['truth'] for r in out)} of {len(out)}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"family": out}, f, indent=1)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
