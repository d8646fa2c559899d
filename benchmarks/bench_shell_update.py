"""One update iteration on a ~200k-coordinate stiffened shell panel against one base
eigen-solve (issue 20, item 3), measured in the same run.

The model: a flat aluminium skin of NX x NY CQUAD4 (PSHELL 1, 2 mm) with four blade
stiffeners along x, 3 CQUAD4 high (PSHELL 2, 3 mm), both short edges clamped, written as a
BDF (GRID, CQUAD4, PSHELL, MAT1, SPC1, PARAM COUPMASS) and read through
:func:`eigenupdate.io.nastran.read_nastran` with the two PSHELL T as parameters (they
enter K nonlinearly: E T membrane and shear, E T^3 bending). 10 configurations each add
1 % of the panel's mass normal to the skin at one grid; 10 elastic modes.

Timed (wall and this process's CPU time), alternately, ``--repeats`` times (the least
of each kept, as the machine is shared):

* base: :func:`eigenupdate.solve.eigen.solve_elastic` of the bare panel (10 modes);
* iteration: :func:`eigenupdate.solve.jacobian.linearise` over the bare panel and the 10
  perturbed configurations (base + perturbed solves + sensitivities, K_j and M_j of the
  nonlinear parameters re-formed at the values) plus the least-squares step.

``--pivot-threshold X`` (a comparison, not package code): every SuperLU factorisation of
the run is made with ``diag_pivot_thresh=X`` instead of the package's 0.1. A shell's
drilling diagonal is ~1e-9 of the largest, so 0.1 rejects those diagonal pivots even where
K - sigma M is positive definite (sigma < 0), and the off-diagonal pivots spoil the
symmetric fill ordering (benchmarks/README.md: 13x the fill, 37x the time at 5.7k
coordinates).

Run: ``.venv-nastran/bin/python benchmarks/bench_shell_update.py`` (``--size small`` for a
quick run, ``--json PATH`` to write the figures).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import tempfile
import time
import warnings
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from eigenupdate.errors import EigenupdateWarning  # noqa: E402
from eigenupdate.model.configurations import Configuration, mass_at  # noqa: E402
from eigenupdate.model.parameters import Parameter  # noqa: E402
from eigenupdate.solve.eigen import solve_elastic  # noqa: E402
from eigenupdate.solve.jacobian import linearise  # noqa: E402

SIZES = {"full": (200, 150), "small": (60, 40)}  # skin cells along x, y
LX, LY, BLADE_H, NZ, N_BLADES = 2.0, 1.5, 0.06, 3, 4
N_MODES, N_MASSES = 10, 10
E, NU, RHO, T_SKIN, T_BLADE = 7.0e10, 0.33, 2700.0, 0.002, 0.003


def write_deck(path: Path, nx: int, ny: int) -> list[int]:
    """The panel's BDF; returns the skin grids that receive the masses."""
    gid = np.arange((nx + 1) * (ny + 1)).reshape(ny + 1, nx + 1) + 1  # [j, i]
    x, y = np.meshgrid(LX * np.arange(nx + 1) / nx, LY * np.arange(ny + 1) / ny)
    lines = ["PARAM,COUPMASS,1", f"PSHELL,1,1,{T_SKIN},1,,1", f"PSHELL,2,1,{T_BLADE},1,,1",
             f"MAT1,1,{E},,{NU},{RHO}"]
    lines += [f"GRID,{g},,{a:.8f},{b:.8f},0." for g, a, b in zip(gid.ravel(), x.ravel(),
                                                                 y.ravel(), strict=True)]
    quads = np.column_stack([gid[:-1, :-1].ravel(), gid[:-1, 1:].ravel(),
                             gid[1:, 1:].ravel(), gid[1:, :-1].ravel()])
    lines += [f"CQUAD4,{e + 1},1,{a},{b},{c},{d}" for e, (a, b, c, d) in enumerate(quads)]
    eid, nxt = quads.shape[0], gid.size
    clamped = [*gid[:, 0], *gid[:, -1]]
    rows = np.linspace(0, ny, N_BLADES + 2).round().astype(int)[1:-1]
    for j in rows:
        levels = [gid[j]]
        for k in range(1, NZ + 1):
            ids = nxt + 1 + np.arange(nx + 1)
            nxt += nx + 1
            lines += [f"GRID,{g},,{a:.8f},{y[j, 0]:.8f},{BLADE_H * k / NZ:.8f}"
                      for g, a in zip(ids, x[0], strict=True)]
            levels.append(ids)
            clamped += [ids[0], ids[-1]]
        for lo, hi in zip(levels[:-1], levels[1:], strict=True):
            for i in range(nx):
                eid += 1
                lines.append(f"CQUAD4,{eid},2,{lo[i]},{lo[i + 1]},{hi[i + 1]},{hi[i]}")
    lines += [f"SPC1,1,123456,{g}" for g in clamped]
    path.write_text("\n".join(["BEGIN BULK", *lines, "ENDDATA", ""]))
    # masses at skin grids spread over the panel, off the stiffeners
    rng = np.random.default_rng(20)
    i = rng.integers(1, nx, N_MASSES)
    j = rng.choice(np.setdiff1d(np.arange(1, ny), rows), N_MASSES)
    return [int(g) for g in gid[j, i]]


def override_pivot_threshold(threshold: float) -> None:
    """Replace scipy's ``splu`` in memory, for this run only, by one that uses
    ``diag_pivot_thresh=threshold``."""
    import scipy.sparse.linalg as spla

    splu = spla.splu

    def patched(A, *args, **kw):
        kw["diag_pivot_thresh"] = threshold
        return splu(A, *args, **kw)

    spla.splu = patched


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", choices=sorted(SIZES), default="full")
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--json", type=Path, help="write the figures to this file")
    ap.add_argument("--pivot-threshold", type=float,
                    help="SuperLU diag_pivot_thresh for every factorisation (comparison)")
    args = ap.parse_args()
    if args.pivot_threshold is not None:
        override_pivot_threshold(args.pivot_threshold)
    from eigenupdate.io.nastran import CardField, dof_number, read_nastran

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "panel.bdf"
        grids = write_deck(path, *SIZES[args.size])
        specs = [(Parameter(f"t{p}", 0.0), CardField("PSHELL", p, "T")) for p in (1, 2)]
        t0 = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", EigenupdateWarning)
            model = read_nastran(path, specs).model
        t_read = time.perf_counter() - t0
    panel_mass = RHO * (LX * LY * T_SKIN + N_BLADES * LX * BLADE_H * T_BLADE)
    configs = [Configuration("base")] + [mass_at(dof_number(g, 3), 0.01 * panel_mass, f"g{g}")
                                         for g in grids]
    modes = list(range(1, N_MODES + 1))
    print(f"panel: {model.n} coordinates, 2 PSHELL T parameters, read and assembled in "
          f"{t_read:.1f} s; {N_MASSES} masses of {0.01 * panel_mass:.3f} kg, {N_MODES} modes")
    base, iteration, cpu_base, cpu_iteration = [], [], [], []
    for _ in range(args.repeats):
        t0, c0 = time.perf_counter(), time.process_time()
        solve_elastic(model.stiffness(), model.mass(), N_MODES)
        base.append(time.perf_counter() - t0)
        cpu_base.append(time.process_time() - c0)
        t0, c0 = time.perf_counter(), time.process_time()
        lin = linearise(model, configs, modes)
        np.linalg.lstsq(lin.normalised, lin.eigenvalues, rcond=None)
        iteration.append(time.perf_counter() - t0)
        cpu_iteration.append(time.process_time() - c0)
        print(f"  base solve {base[-1]:.2f} s (CPU {cpu_base[-1]:.2f} s), one iteration "
              f"{iteration[-1]:.2f} s (CPU {cpu_iteration[-1]:.2f} s)")
    rep = lin.certificate.as_dict() if lin.certificate is not None else {}
    ratio = min(iteration) / min(base)
    pivot = "package's" if args.pivot_threshold is None else args.pivot_threshold
    print(f"SuperLU diag_pivot_thresh: {pivot}")
    print(f"one iteration / one base eigen-solve: {ratio:.2f} (least of {args.repeats}: "
          f"{min(iteration):.2f} s / {min(base):.2f} s; CPU time "
          f"{min(cpu_iteration) / min(cpu_base):.2f}); perturbed configurations certified "
          f"{rep.get('certified')}/{rep.get('configurations')}, Lanczos fallback "
          f"{rep.get('fallback_lanczos')}; load average {os.getloadavg()[0]:.1f} on "
          f"{os.cpu_count()} cores")
    if args.json:
        args.json.write_text(json.dumps({
            "n": model.n, "parameters": 2, "masses": N_MASSES, "modes": N_MODES,
            "read_s": t_read, "base_solve_s": base, "iteration_s": iteration,
            "cpu_base_solve_s": cpu_base, "cpu_iteration_s": cpu_iteration,
            "ratio": ratio, "cpu_ratio": min(cpu_iteration) / min(cpu_base),
            "certificate": rep, "pivot_threshold": args.pivot_threshold,
            "load_average": os.getloadavg(),
            "machine": platform.platform()}, indent=2))


if __name__ == "__main__":
    main()
