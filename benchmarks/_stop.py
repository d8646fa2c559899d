"""(stop) of bench_update.py: does the update stop promptly when it is done (issue 21
item 5)? Run it through bench_update.py (which sets the BLAS threads)."""

from __future__ import annotations

import time

import numpy as np
from _bench import make_problem, param_errors
from frame import SIZES

from eigenupdate.identify.updating import update
from eigenupdate.measure.measurement import Measurement

STOP_SIZE = {"full": "stop", "small": "small"}
STOP_NOISE = 1e-3  # relative std of the noisy frequencies
STOP_SEED = 7


def bench_stop(size_key: str) -> dict:
    """Does the update stop promptly when it is done (issue 21 item 5)? The frame of
    ``size_key`` with error-free data (least squares) and with frequencies carrying
    ``STOP_NOISE`` relative Gaussian noise and that std (weighted least squares), from the
    benchmark's start; a progress line per iteration, the time of each."""
    prob = make_problem(size_key)
    model, truth = prob.model, prob.frame.truth
    n_eq, n_par = len(prob.measurements), int(model.updated.size)
    print(f"(stop) frame {SIZES[size_key]}: {model.n} coordinates, {n_par} parameters, "
          f"{n_eq} frequencies; start max {param_errors(model.values, truth)['max_rel']:.2%} "
          f"off")
    out = {"coordinates": model.n, "parameters": n_par, "equations": n_eq}
    for label, noise in (("error_free", 0.0), ("noisy", STOP_NOISE)):
        rng = np.random.default_rng(STOP_SEED)
        meas = {key: Measurement(m.configuration, m.mode,
                                 m.frequency_hz * (1 + noise * rng.standard_normal()),
                                 noise * m.frequency_hz if noise else None)
                for key, m in prob.measurements.items()}
        method = "weighted-least-squares" if noise else "least-squares"
        lines: list = []

        def say(line, label=label, lines=lines):
            lines.append((time.perf_counter(), line))
            print(f"(stop) {label}: {line}", flush=True)

        t = time.perf_counter()
        res = update(model, prob.configurations, prob.modes, meas, method=method, progress=say)
        sec = time.perf_counter() - t
        x = np.array([res.parameters[n] for n in model.names])
        err = param_errors(x, truth)
        r = {"method": method, "converged": bool(res.success), "status": res.status,
             "message": res.message, "iterations": res.nit, "seconds": sec,
             "progress_lines": len(lines), "max_rel_error": err["max_rel"],
             "objective": 2 * res.cost}
        if noise:
            std = np.array([res.std[n] or np.nan for n in res.names])
            idx = [model.names.index(n) for n in res.names]
            r["max_error_in_posterior_std"] = float(np.nanmax(np.abs(x[idx] - truth[idx]) / std))
            r["expected_objective"] = n_eq - n_par  # chi-square degrees of freedom
        out[label] = r
        print(f"(stop) {label}: {method}, converged {res.success} (status {res.status}), "
              f"{res.nit} iterations, {sec:.1f} s, max parameter error {err['max_rel']:.1e}"
              + (f" = {r['max_error_in_posterior_std']:.2f} posterior std; objective "
                 f"{r['objective']:.1f} against {r['expected_objective']} degrees of freedom"
                 if noise else "") + f"; {res.message}")
    return out
