"""The benchmark proper; run it through bench_update.py (which sets the BLAS threads)."""

from __future__ import annotations

import datetime as _dt
import json
import os
import platform
import resource
import sys
import time
from collections import defaultdict
from contextlib import contextmanager
from dataclasses import dataclass

import numpy as np
import scipy
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from frame import (
    COLUMN,
    E_STEEL,
    NU,
    RHO_STEEL,
    SIZES,
    Frame,
    build_frame,
    cantilever,
    mass_sites,
)
from scipy.optimize import least_squares

import eigenupdate.identify.pairing as pairing_mod
import eigenupdate.identify.updating as upd
import eigenupdate.solve.eigen as eig
import eigenupdate.solve.jacobian as jac
import eigenupdate.solve.krylov as kry
import eigenupdate.solve.perturbed as pert
from eigenupdate.identify.updating import update
from eigenupdate.measure.measurement import Measurement
from eigenupdate.model.configurations import BASE, Configuration, mass_at
from eigenupdate.model.parametric import ParametricModel
from eigenupdate.solve import parallel
from eigenupdate.solve.eigen import WarmStart, default_shift, solve_elastic
from eigenupdate.solve.jacobian import linearise, solve_configurations
from eigenupdate.solve.memory import keep_freed_memory
from eigenupdate.solve.restricted import RestrictedTerms
from eigenupdate.solve.screening import screen
from eigenupdate.solve.sensitivity import eigenvalue_derivatives

N_MODES = 10
N_PERTURBATIONS = 20
ADDED_MASS_FRACTION = 0.01  # each added mass: 1 % of the frame's total mass

# (a) size, (b) size, default cap on the baseline's iterations (least_squares max_nfev),
# scaling sizes
PLAN = {"full": ("full", "b-full", 20, ("mesh2", "mesh4", "full", "mesh16")),
        "small": ("small", "b-small", 3, ("small-mesh2", "small"))}
N_MANY = 80  # perturbations for the cost per added configuration
SCREEN_COORDINATES, SCREEN_MASSES = 100, 10
SAMPLE = (1, 7, 14, 20)  # configurations re-solved independently (accuracy)
REPEATS = 5  # (a): alternating base solves and iterations


# ----------------------------------------------------------------------------- timing


class Timers:
    """Accumulated wall time and call count per label."""

    def __init__(self):
        self.seconds = defaultdict(float)
        self.calls = defaultdict(int)

    @contextmanager
    def __call__(self, label):
        t = time.perf_counter()
        try:
            yield
        finally:
            self.seconds[label] += time.perf_counter() - t
            self.calls[label] += 1

    def as_dict(self):
        return {k: {"seconds": round(v, 4), "calls": self.calls[k]}
                for k, v in self.seconds.items()}


@contextmanager
def instrumented(timers: Timers):
    """Time the package's stages by wrapping its module attributes for the duration.

    Nothing in the package is changed on disk; the originals are restored on exit.
    Labels: factorisation (ShiftInvert: LU of K - sigma M), Woodbury set-up, LU solves
    (every A^-1 b; "LU solve columns" counts right-hand sides), eigsh
    (eigen.lowest_modes: ARPACK + mass normalisation + rigid-body test, including its LU
    solves), Krylov subspaces (krylov.Blocks.grow and .take and the projected matrices,
    including the LU solves),
    Rayleigh-Ritz (perturbed.ritz: projected eigenproblem, certificate, Ritz vectors),
    sensitivities (Fox-Kapoor), assembly (K(s), M(s)). A stage the package no longer has
    is skipped.
    """
    base_cls = eig.ShiftInvert

    class TimedShiftInvert(base_cls):
        last = None

        def __init__(self, K, M, sigma):
            with timers("factorisation"):
                super().__init__(K, M, sigma)
            TimedShiftInvert.last = self

        def solve(self, b):
            timers.seconds["LU solve columns"] += 0.0
            timers.calls["LU solve columns"] += 1 if np.ndim(b) == 1 else np.shape(b)[1]
            with timers("LU solves"):
                return super().solve(b)

        def updated(self, rows, dk, dm):
            with timers("Woodbury set-up"):
                return super().updated(rows, dk, dm)

    def timed(label, f):
        def g(*a, **kw):
            with timers(label):
                return f(*a, **kw)
        return g

    patches = [(eig, "ShiftInvert", lambda f: TimedShiftInvert),
               (eig, "lowest_modes", lambda f: timed("eigsh", f)),
               (jac, "eigenvalue_derivatives", lambda f: timed("sensitivities", f)),
               (RestrictedTerms, "derivatives", lambda f: timed("sensitivities", f)),
               (pert.Blocks, "grow", lambda f: timed("Krylov subspaces", f)),
               (pert.Blocks, "take", lambda f: timed("Krylov subspaces", f)),
               (pert, "_assemble", lambda f: timed("Krylov subspaces", f)),
               (kry, "_assemble", lambda f: timed("Krylov subspaces", f)),
               (pert, "ritz", lambda f: timed("Rayleigh-Ritz", f)),
               (ParametricModel, "stiffness", lambda f: timed("assembly", f)),
               (ParametricModel, "mass", lambda f: timed("assembly", f))]
    saved = []
    for obj, name, wrap in patches:
        if hasattr(obj, name):
            saved.append((obj, name, getattr(obj, name)))
            setattr(obj, name, wrap(getattr(obj, name)))
    try:
        yield TimedShiftInvert
    finally:
        for obj, name, value in saved:
            setattr(obj, name, value)


@contextmanager
def one_thread():
    """The package's threads off for the duration (EIGENUPDATE_THREADS=1)."""
    saved = os.environ.get("EIGENUPDATE_THREADS")
    os.environ["EIGENUPDATE_THREADS"] = "1"
    try:
        yield
    finally:
        if saved is None:
            del os.environ["EIGENUPDATE_THREADS"]
        else:
            os.environ["EIGENUPDATE_THREADS"] = saved


@contextmanager
def counting(module, name, counter: list):
    """Count calls of module.name (e.g. updating.linearise) for the duration."""
    f = getattr(module, name)

    def g(*a, **kw):
        counter[0] += 1
        return f(*a, **kw)

    setattr(module, name, g)
    try:
        yield
    finally:
        setattr(module, name, f)


def peak_rss_gib() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20  # Linux: KiB


# ----------------------------------------------------------------------------- problem


@dataclass
class Problem:
    frame: Frame
    configurations: list
    modes: list
    measurements: dict
    lam_meas: np.ndarray  # measured eigenvalues in row order (configuration, mode)

    @property
    def model(self):
        return self.frame.model


def make_problem(size_key: str, simulate: bool = True) -> Problem:
    frame = build_frame(*SIZES[size_key])
    added = ADDED_MASS_FRACTION * frame.total_mass
    configs = [Configuration(BASE)] + [
        mass_at(c, added, name=f"m{i + 1:02d}@{c}")
        for i, c in enumerate(mass_sites(frame, N_PERTURBATIONS))
    ]
    modes = list(range(1, N_MODES + 1))
    meas, lam = {}, np.array([])
    if simulate:  # error-free data from the true model
        sols = solve_configurations(frame.model.with_values(frame.truth), configs, N_MODES)
        lam = np.concatenate([s.eigenvalues for s in sols])
        for c, s in zip(configs, sols, strict=True):
            for k in modes:
                meas[(c.name, k)] = Measurement(c.name, k, float(s.frequencies_hz[k - 1]))
    return Problem(frame, configs, modes, meas, lam)


def param_errors(values, truth) -> dict:
    rel = np.asarray(values) / truth - 1
    return {"max_rel": float(np.max(np.abs(rel))), "rms_rel": float(np.sqrt(np.mean(rel**2)))}


# ----------------------------------------------------------------------------- self-check


def self_check() -> dict:
    """Element and solver sanity checks (asserts); returns the figures."""
    out = {}
    # cantilever, 20 elements, along X and along Z: first bending frequency in both
    # planes against 1.8751^2 sqrt(EI / (rho A L^4)) / (2 pi)
    L, beta = 3.0, 1.87510407
    worst = 0.0
    for axis in ((1.0, 0.0, 0.0), (0.0, 0.0, 1.0), (1.0, 2.0, 0.5)):
        k, m = cantilever(20, L, COLUMN, axis)
        f = solve_elastic(E_STEEL * k, RHO_STEEL * m, 4, dense=True).frequencies_hz
        for inertia in (COLUMN.Iz, COLUMN.Iy):
            omega = beta**2 * np.sqrt(E_STEEL * inertia / (RHO_STEEL * COLUMN.A * L**4))
            err = float(np.min(np.abs(f / (omega / (2 * np.pi)) - 1)))
            worst = max(worst, err)
            assert err < 1e-6, f"cantilever bending: {f} vs {omega / (2 * np.pi)}"
        # first torsion mode: sqrt(G J / (rho Ip)) / (4 L); linear element, coarser
        g = E_STEEL / (2 * (1 + NU))
        exact_t = np.sqrt(g * COLUMN.J / (RHO_STEEL * (COLUMN.Iy + COLUMN.Iz))) / (4 * L)
        assert np.min(np.abs(f / exact_t - 1)) < 1e-3, "cantilever torsion"
    out["cantilever_bending_max_rel_error"] = worst
    print(f"self-check: cantilever (20 elements, 3 orientations) first bending frequency "
          f"vs 1.8751^2 sqrt(EI/(rho A L^4)): max rel. error {worst:.1e}")

    # free-free frame: exactly six rigid-body modes are found and excluded (sparse path)
    free = build_frame(*SIZES["b-small"], supports="free")
    K, M = free.model.stiffness(free.truth), free.model.mass(free.truth)
    sol = solve_elastic(K, M, N_MODES, dense=False)
    dense = solve_elastic(K, M, N_MODES, dense=True)
    assert sol.n_rigid == 6 == dense.n_rigid, (sol.n_rigid, dense.n_rigid)
    dif = float(np.max(np.abs(sol.eigenvalues / dense.eigenvalues - 1)))
    assert dif < 1e-7, dif  # ARPACK start vector is random; seen 2e-10..2e-9
    out["free_frame"] = {"n": free.model.n, "n_rigid": sol.n_rigid,
                         "sparse_vs_dense_max_rel": dif}
    print(f"self-check: free-free frame ({free.model.n} coordinates): {sol.n_rigid} rigid-body "
          f"modes excluded; sparse vs dense elastic eigenvalues agree to {dif:.1e}")
    return out


# ----------------------------------------------------------------------------- (a)


def bench_a(size_key: str, colamd: bool = False) -> dict:
    t = time.perf_counter()
    prob = make_problem(size_key, simulate=False)
    model, configs, modes = prob.model, prob.configurations, prob.modes
    t_build = time.perf_counter() - t
    n = model.n
    print(f"(a) frame {SIZES[size_key]} (bays X, bays Y, storeys, elements/member): "
          f"{n} coordinates, {prob.frame.n_elements} elements, {len(model.parameters)} "
          f"parameters, {len(configs)} configurations x {len(modes)} modes; built in "
          f"{t_build:.1f} s")

    # one base eigen-solve, fresh factorisation (assembly of K, M not included)
    K, M = model.stiffness(), model.mass()
    base_timers = Timers()
    with instrumented(base_timers) as cls:
        t, c0 = time.perf_counter(), time.process_time()
        base = solve_elastic(K, M, N_MODES)
        t_base = time.perf_counter() - t
        cpu_base = time.process_time() - c0
        lu = cls.last._lu
    fill = int(lu.L.nnz + lu.U.nnz)
    t_fact = base_timers.seconds["factorisation"]
    n_solves_base = base_timers.calls["LU solves"]
    n_fact_base = base_timers.calls["factorisation"]
    print(f"(a) one base eigen-solve: {t_base:.2f} s = factorisation {t_fact:.2f} s "
          f"(x{n_fact_base}, nnz(L+U) = {fill:,}) + eigsh {base_timers.seconds['eigsh']:.2f} s "
          f"(x{base_timers.calls['eigsh']}, {n_solves_base} LU solves taking "
          f"{base_timers.seconds['LU solves']:.2f} s) + other "
          f"{t_base - t_fact - base_timers.seconds['eigsh']:.2f} s; "
          f"first frequencies {np.round(base.frequencies_hz[:4], 3).tolist()} Hz, "
          f"{base.n_rigid} rigid modes")

    # one update iteration: linearise (21 eigen-solves + sensitivities) + the GN step;
    # in one thread here, so that the stages add up (the repeated pairs below use them)
    timers = Timers()
    with instrumented(timers), one_thread():
        t, c0 = time.perf_counter(), time.process_time()
        lin = linearise(model, configs, modes)
        t_lin = time.perf_counter() - t
        cpu_lin = time.process_time() - c0
    # data for the step: the first-order prediction of the true eigenvalues (solving the
    # truth would double the run time; the least-squares step costs the same either way)
    scale = lin.scale
    dz_true = prob.frame.truth / scale - 1
    lam_meas = lin.eigenvalues + lin.normalised @ dz_true
    t = time.perf_counter()
    A, b = lin.normalised, lam_meas - lin.eigenvalues
    dz = np.linalg.lstsq(A, b, rcond=None)[0]
    t_step = time.perf_counter() - t
    t_iter = t_lin + t_step
    ratio = t_iter / t_base
    s = timers.seconds
    other = t_lin - (s["factorisation"] + s["Woodbury set-up"] + s["eigsh"]
                     + s["Krylov subspaces"] + s["Rayleigh-Ritz"] + s["sensitivities"]
                     + s["assembly"])
    c = timers.calls
    rep = lin.certificate.as_dict() if lin.certificate is not None else {}
    print(f"(a) one update iteration, one thread: {t_iter:.2f} s; one base eigen-solve: "
          f"{t_base:.2f} s; ratio {ratio:.2f} (before the fast path: 13-18); in CPU time "
          f"of this process "
          f"(less sensitive to other jobs on the machine): {cpu_lin:.2f} s vs "
          f"{cpu_base:.2f} s, ratio {cpu_lin / cpu_base:.2f}")
    print(f"(a) iteration split: assembly K(s),M(s) {s['assembly']:.2f} s; factorisation "
          f"{s['factorisation']:.2f} s (x{c['factorisation']}); base eigsh {s['eigsh']:.2f} s "
          f"(x{c['eigsh']}); Krylov subspaces {s['Krylov subspaces']:.2f} s "
          f"(x{c['Krylov subspaces']}); Rayleigh-Ritz + certificate {s['Rayleigh-Ritz']:.2f} s "
          f"(x{c['Rayleigh-Ritz']}); Woodbury set-up (fallback) {s['Woodbury set-up']:.2f} s "
          f"(x{c['Woodbury set-up']}); sensitivities {s['sensitivities']:.2f} s; "
          f"least-squares step {t_step * 1e3:.1f} ms; other {other:.2f} s; LU solves "
          f"{s['LU solves']:.2f} s ({c['LU solves']} calls, {c['LU solve columns']} "
          f"right-hand sides; base solve alone: {n_solves_base})")
    print(f"(a) fast path: {rep.get('certified')} of {rep.get('configurations')} perturbed "
          f"configurations certified ({rep.get('certified_with_extra_level')} with one more "
          f"Krylov level), {rep.get('fallback_lanczos')} by Lanczos; largest eigenvalue bound "
          f"{rep.get('max_eigenvalue_bound', 0):.1e}, mode-angle bound "
          f"{rep.get('max_mode_angle_bound', 0):.1e}")
    assert np.allclose(dz, dz_true, rtol=1e-6, atol=1e-8), "step does not recover the data"
    acc = accuracy_sample(model, configs, modes, lin, SAMPLE, "(a)")
    repeats = repeated_pairs(model, configs, modes, REPEATS, "(a)")
    warm = repeated_warm(model, configs, modes, scale * (1 + dz), REPEATS, "(a)")
    out = {
        "frame": SIZES[size_key], "n": n, "elements": prob.frame.n_elements,
        "nnz_K": int(K.nnz), "configurations": len(configs), "modes": len(modes),
        "parameters": len(model.parameters),
        "base_solve_s": t_base, "base_factorisation_s": t_fact, "base_lu_solves": n_solves_base,
        "base_lu_fill": fill, "base_frequencies_hz": base.frequencies_hz.tolist(),
        "iteration_s": t_iter, "linearise_s": t_lin, "step_s": t_step, "ratio": ratio,
        "cpu_base_solve_s": cpu_base, "cpu_linearise_s": cpu_lin,
        "cpu_ratio": cpu_lin / cpu_base,
        "iteration_split": timers.as_dict(), "iteration_other_s": other,
        "fast_path": rep, "accuracy_sample": acc, "repeated": repeats, "warm": warm,

        "threads": parallel.threads(), "peak_rss_gib": peak_rss_gib(),
    }
    if colamd:
        out["comparison_colamd_ordering"] = diagnose_ordering(model, configs, modes, K, M, lu,
                                                              t_base, t_iter, lin)
    return out


def accuracy_sample(model, configs, modes, lin, sample, tag) -> dict:
    """Independent full re-solves of a sample of configurations: K + dK, M + dM assembled
    and solved by solve_elastic with a fresh factorisation (shift-invert Lanczos, no
    reuse of the base), Fox-Kapoor on those modes with the full K_j, M_j."""
    K, M = model.stiffness(), model.mass()
    upd_ = model.updated
    kt = [model.k_terms[j] for j in upd_]
    mt = [model.m_terms[j] for j in upd_]
    q = len(modes)
    eig_err, j_err = 0.0, 0.0
    for i in sample:
        if i >= len(configs):
            continue
        dk, dm = configs[i].delta(model)
        ref = solve_elastic(K + dk, M + dm, max(modes))
        J = eigenvalue_derivatives(ref, modes, kt, mt)
        rows = slice(q * i, q * (i + 1))
        lam = ref.eigenvalues[np.asarray(modes) - 1]
        eig_err = max(eig_err, float(np.max(np.abs(lin.eigenvalues[rows] / lam - 1))))
        j_err = max(j_err, float(np.max(np.abs(lin.J[rows] - J)
                                        / np.abs(J).max(axis=1, keepdims=True))))
    names = [configs[i].name for i in sample if i < len(configs)]
    print(f"{tag} accuracy against independent full re-solves (fresh factorisation, "
          f"Lanczos, full Fox-Kapoor) of {names}: eigenvalues max rel. error {eig_err:.1e} "
          f"(goal 1e-10), sensitivities max error {j_err:.1e} relative to the row's largest "
          f"(goal 1e-7)")
    return {"configurations": names, "eigenvalue_max_rel_error": eig_err,
            "sensitivity_max_rel_error": j_err}


def repeated_pairs(model, configs, modes, repeats: int, tag: str) -> dict:
    """One base eigen-solve then one iteration, ``repeats`` times, not instrumented:
    single timings on a shared machine vary by tens of per cent, so the median of the
    per-pair ratios is the figure to quote."""
    pairs = []
    for _ in range(repeats):
        cpu: list = []
        t_base = base_solve_time(model, cpu)
        t_iter = one_iteration(model, configs, modes, cpu)[0]
        pairs.append((t_base, t_iter, cpu[0], cpu[1]))
    a = np.array(pairs)
    ratios = a[:, 1] / a[:, 0]
    out = {"base_solve_s": a[:, 0].tolist(), "iteration_s": a[:, 1].tolist(),
           "ratios": ratios.tolist(), "median_ratio": float(np.median(ratios)),
           "ratio_of_fastest": float(a[:, 1].min() / a[:, 0].min()),
           "median_cpu_ratio": float(np.median(a[:, 3] / a[:, 2]))}
    print(f"{tag} repeated {repeats} x (base solve, iteration), {parallel.threads()} threads: "
          f"ratios {np.round(ratios, 2).tolist()}, median {out['median_ratio']:.2f}; fastest "
          f"iteration / fastest base solve {a[:, 1].min():.2f} s / {a[:, 0].min():.2f} s = "
          f"{out['ratio_of_fastest']:.2f}; median CPU-time ratio {out['median_cpu_ratio']:.2f} "
          f"(the threads' CPU time counted)")
    return out


def repeated_warm(model, configs, modes, stepped, repeats: int, tag: str) -> dict:
    """Iterations as an update makes them after the first: each linearisation warm-started
    by the previous one (:class:`eigenupdate.solve.eigen.WarmStart`), the parameters
    moving by one Gauss-Newton step (initial values <-> ``stepped``), each against a
    base eigen-solve (cold, as in (a)) in the same pair."""
    points = [model.values.copy(), np.asarray(stepped, float)]
    warm = WarmStart()
    lin0 = linearise(model, configs, modes, points[0], warm=warm)
    pairs = []
    for i in range(repeats):
        t_base = base_solve_time(model)
        values = points[(i + 1) % 2]
        t = time.perf_counter()
        lin = linearise(model, configs, modes, values, warm=warm)
        np.linalg.lstsq(lin.normalised, lin.eigenvalues, rcond=None)
        pairs.append((t_base, time.perf_counter() - t))
    a = np.array(pairs)
    ratios = a[:, 1] / a[:, 0]
    cold = linearise(model, configs, modes, points[repeats % 2])
    diff = float(np.max(np.abs(lin.eigenvalues / cold.eigenvalues - 1)))
    out = {"base_solve_s": a[:, 0].tolist(), "iteration_s": a[:, 1].tolist(),
           "ratios": ratios.tolist(), "median_ratio": float(np.median(ratios)),
           "step_max_rel": float(np.max(np.abs(points[1] / points[0] - 1))),
           "warm_vs_cold_eigenvalues_max_rel": diff}
    print(f"{tag} warm iterations (each started from the previous one, parameters moving "
          f"by up to {out['step_max_rel']:.1%}): ratios {np.round(ratios, 2).tolist()}, median "
          f"{out['median_ratio']:.2f}; eigenvalues against a cold linearisation: {diff:.1e}")
    del lin0
    return out


def base_solve_time(model, cpu: list | None = None) -> float:
    """Wall time of one base eigen-solve (its CPU time appended to ``cpu``)."""
    K, M = model.stiffness(), model.mass()
    t, c0 = time.perf_counter(), time.process_time()
    solve_elastic(K, M, N_MODES)
    if cpu is not None:
        cpu.append(time.process_time() - c0)
    return time.perf_counter() - t


def one_iteration(model, configs, modes, cpu: list | None = None):
    t, c0 = time.perf_counter(), time.process_time()
    lin = linearise(model, configs, modes)
    np.linalg.lstsq(lin.normalised, lin.eigenvalues, rcond=None)
    if cpu is not None:
        cpu.append(time.process_time() - c0)
    return time.perf_counter() - t, lin


def bench_many(size_key: str) -> dict:
    """Cost per added configuration: one iteration with 20 and with 80 perturbations."""
    frame = build_frame(*SIZES[size_key])
    model, added = frame.model, ADDED_MASS_FRACTION * frame.total_mass
    sites = mass_sites(frame, N_MANY)
    modes = list(range(1, N_MODES + 1))
    t_base = base_solve_time(model)
    times = {}
    for count in (N_PERTURBATIONS, N_MANY):
        configs = [Configuration(BASE)] + [mass_at(c, added, name=f"m{i + 1:02d}@{c}")
                                           for i, c in enumerate(sites[:count])]
        times[count], lin = one_iteration(model, configs, modes)
        rep = lin.certificate.as_dict()
        print(f"(many) {count} perturbations: one iteration {times[count]:.2f} s "
              f"({times[count] / t_base:.2f} base solves); certified {rep['certified']}, "
              f"Lanczos {rep['fallback_lanczos']}")
    per = (times[N_MANY] - times[N_PERTURBATIONS]) / (N_MANY - N_PERTURBATIONS)
    print(f"(many) cost per added configuration: {per:.3f} s = {per / t_base:.3f} base "
          f"eigen-solves (base solve {t_base:.2f} s; before the fast path ~0.8)")
    return {"n": model.n, "base_solve_s": t_base, "iteration_s": times,
            "per_configuration_s": per, "per_configuration_base_solves": per / t_base}


def bench_screen(size_key: str) -> dict:
    """Screening 100 coordinates x 10 masses against one base eigen-solve."""
    frame = build_frame(*SIZES[size_key])
    model = frame.model
    modes = list(range(1, N_MODES + 1))
    coords = mass_sites(frame, SCREEN_COORDINATES, seed=3)
    masses = frame.total_mass * np.geomspace(1e-3, 2e-2, SCREEN_MASSES)
    candidates = [(c, float(m)) for c in coords for m in masses]
    t_base = base_solve_time(model)
    t = time.perf_counter()
    res = screen(model, candidates, modes)
    t_screen = time.perf_counter() - t
    print(f"(screen) {len(candidates)} candidates ({len(coords)} coordinates x {len(masses)} "
          f"masses, {masses[0]:.0f}-{masses[-1]:.0f} kg), {len(modes)} modes, "
          f"{len(res.names)} parameters: {t_screen:.1f} s = {t_screen / t_base:.1f} base "
          f"eigen-solves (goal <= 20); certified {int(res.certified.sum())}, largest bound "
          f"{np.nanmax(res.bound):.1e}")
    # accuracy: a few candidates re-solved independently
    sample = [0, 9, 505, len(candidates) - 1]
    configs = [Configuration(BASE)] + [mass_at(*candidates[i], name=f"cand{i}")
                                       for i in sample]

    class _Lin:  # the screening rows laid out like a Linearisation
        eigenvalues = np.concatenate([res.base_eigenvalues] + [res.eigenvalues[i]
                                                                 for i in sample])
        J = np.vstack([res.base_J] + [res.J[i] for i in sample])

    acc = accuracy_sample(model, configs, modes, _Lin, range(1, len(configs)), "(screen)")
    return {"n": model.n, "candidates": len(candidates), "base_solve_s": t_base,
            "screen_s": t_screen, "ratio": t_screen / t_base,
            "certified": int(res.certified.sum()), "max_bound": float(np.nanmax(res.bound)),
            "accuracy_sample": acc}


def bench_scaling(keys) -> dict:
    """One iteration (20 perturbations, 10 modes) against one base solve, mesh refined."""
    rows = []
    for key in keys:
        prob = make_problem(key, simulate=False)
        cpu = []
        t_base = base_solve_time(prob.model, cpu)
        t_iter, lin = one_iteration(prob.model, prob.configurations, prob.modes, cpu)
        rep = lin.certificate.as_dict()
        rows.append({"size": key, "n": prob.model.n, "base_solve_s": t_base,
                     "iteration_s": t_iter, "ratio": t_iter / t_base,
                     "cpu_ratio": cpu[1] / cpu[0],
                     "certified": rep["certified"], "fallback": rep["fallback_lanczos"]})
        print(f"(scaling) {key}: {prob.model.n} coordinates: base solve {t_base:.2f} s, one "
              f"iteration {t_iter:.2f} s, ratio {t_iter / t_base:.2f} (CPU time: "
              f"{cpu[1]:.2f} s vs {cpu[0]:.2f} s, {cpu[1] / cpu[0]:.2f}); certified "
              f"{rep['certified']}/{rep['configurations']}")
    return {"rows": rows}


def _colamd_splu(A):
    return spla.splu(sp.csc_matrix(A))  # SuperLU's defaults: COLAMD, partial pivoting


def diagnose_ordering(model, configs, modes, K, M, lu, t_base, t_iter, lin) -> dict:
    """Comparison, not package code: the same base solve and iteration with K - sigma M
    factorised by SuperLU's defaults (COLAMD column ordering, partial pivoting), which
    the package used before it switched to a symmetric ordering. The package's
    ShiftInvert is replaced in memory for the duration only."""
    A = sp.csc_matrix(K - default_shift(K, M) * M)
    t = time.perf_counter()
    lu2 = _colamd_splu(A)
    t_fact2 = time.perf_counter() - t
    fill, fill2 = int(lu.L.nnz + lu.U.nnz), int(lu2.L.nnz + lu2.U.nnz)
    rhs = np.random.default_rng(0).standard_normal(A.shape[0])
    t_solve, t_solve2 = _time_solves(lu.solve, rhs), _time_solves(lu2.solve, rhs)
    out = {"factorisation_s": t_fact2, "fill": fill2, "solve_s": t_solve2,
           "package_fill": fill, "package_solve_s": t_solve}
    print(f"(a) comparison: splu with SuperLU's default COLAMD ordering factorises in "
          f"{t_fact2:.2f} s, nnz(L+U) {fill2:,} (package's symmetric ordering: {fill:,}), "
          f"one solve {t_solve2 * 1e3:.2f} ms vs {t_solve * 1e3:.2f} ms")

    original = eig.ShiftInvert

    class ColamdShiftInvert(original):
        def __init__(self, K, M, sigma):
            self.sigma = float(sigma)
            self._lu = _colamd_splu(K - self.sigma * M)

    eig.ShiftInvert = ColamdShiftInvert
    try:
        t = time.perf_counter()
        base2 = solve_elastic(K, M, N_MODES)
        t_base2 = time.perf_counter() - t
        t = time.perf_counter()
        lin2 = linearise(model, configs, modes)
        np.linalg.lstsq(lin2.normalised, lin2.eigenvalues, rcond=None)
        t_iter2 = time.perf_counter() - t
    except Exception as exc:  # the package's internals changed: report, don't fail
        print(f"(a) comparison skipped: {type(exc).__name__}: {exc}")
        return out
    finally:
        eig.ShiftInvert = original
    dif = float(np.max(np.abs(lin2.eigenvalues / lin.eigenvalues - 1)))
    dJ = float(np.max(np.abs(lin2.J - lin.J)) / np.max(np.abs(lin.J)))
    out.update(base_solve_s=t_base2, iteration_s=t_iter2, ratio=t_iter2 / t_base2,
               eigenvalue_max_rel_diff=dif, J_max_rel_diff=dJ,
               base_frequencies_hz=base2.frequencies_hz.tolist(),
               speedup_iteration=t_iter2 / t_iter, speedup_base=t_base2 / t_base)
    print(f"(a) comparison, same with COLAMD: one update iteration {t_iter2:.1f} s "
          f"(package: {t_iter:.1f} s, {t_iter2 / t_iter:.1f}x faster); one base eigen-solve "
          f"{t_base2:.2f} s (package: {t_base:.2f} s, {t_base2 / t_base:.1f}x faster); "
          f"eigenvalues agree to {dif:.1e}, J to {dJ:.1e}")
    return out


def _time_solves(solve, rhs, repeat=5) -> float:
    solve(rhs)
    t = time.perf_counter()
    for _ in range(repeat):
        solve(rhs)
    return (time.perf_counter() - t) / repeat


# ----------------------------------------------------------------------------- (b)


def bench_b(size_key: str, max_nfev: int | None, reference: bool = False) -> dict:
    t = time.perf_counter()
    prob = make_problem(size_key)
    model, configs, modes, truth = prob.model, prob.configurations, prob.modes, prob.frame.truth
    nconf = len(configs)
    print(f"(b) frame {SIZES[size_key]}: {model.n} coordinates, {len(model.parameters)} "
          f"parameters, {nconf} configurations x {len(modes)} modes = {prob.lam_meas.size} "
          f"equations; truth simulated in {time.perf_counter() - t:.1f} s; initial parameter "
          f"error max {param_errors(model.values, truth)['max_rel']:.3f}")

    # ours
    calls, ours_t = [0], Timers()
    with counting(upd, "linearise", calls), instrumented(ours_t):
        t = time.perf_counter()
        res = update(model, configs, modes, prob.measurements)
        t_ours = time.perf_counter() - t
    ours_values = np.array([res.parameters[nm] for nm in model.names])
    ours_err = param_errors(ours_values, truth)
    ours_solves = ours_t.calls["eigsh"]
    print(f"(b) ours: update() {t_ours:.1f} s, {res.nit} iterations, converged "
          f"{res.success}, {calls[0]} linearisations = {ours_solves} eigsh calls and "
          f"{ours_t.calls['factorisation']} factorisations; parameter error vs truth max "
          f"{ours_err['max_rel']:.1e}, rms {ours_err['rms_rel']:.1e}; fast path {res.solver}")

    # baseline: least_squares, 2-point finite differences, normalised parameters; every
    # residual solves each configuration as a user would by hand: SciPy's eigsh in
    # shift-invert mode about 0 (the frame is clamped), its own factorisation each time
    scale = model.values
    evaluated = []  # (evaluation, seconds, x, cost)
    eigsh_calls = [0]

    def residual(x):
        K, M = model.stiffness(x * scale), model.mass(x * scale)
        lam = []
        for c in configs:
            dk, dm = c.delta(model)
            vals = spla.eigsh(sp.csc_matrix(K + dk), k=N_MODES, M=sp.csc_matrix(M + dm),
                              sigma=0.0, which="LM", return_eigenvectors=False)
            eigsh_calls[0] += 1
            lam.append(np.sort(vals))
        r = np.concatenate(lam) - prob.lam_meas
        evaluated.append((len(evaluated) + 1, time.perf_counter() - t, x.copy(),
                          0.5 * float(r @ r)))
        return r

    base_t = Timers()
    with instrumented(base_t):
        t = time.perf_counter()
        ls = least_squares(residual, np.ones(len(scale)), jac="2-point", max_nfev=max_nfev)
        t_base = time.perf_counter() - t
    n_evals = len(evaluated)
    base_solves = eigsh_calls[0]
    # the optimiser's own points, not the finite-difference ones (which differ from the
    # last optimiser point in a single component)
    trial, last = [], None
    for e, sec, x, cost in evaluated:
        if last is None or np.count_nonzero(x != last) > 1:
            trial.append((e, sec, cost, param_errors(x * scale, truth)["max_rel"]))
            last = x
    # accuracy of its finite-difference Jacobian: against Fox-Kapoor at the final point
    exact = linearise(model, configs, modes, ls.x * scale).normalised
    fd_err = np.linalg.norm(ls.jac - exact, axis=0) / np.linalg.norm(exact, axis=0)
    base_err = param_errors(ls.x * scale, truth)
    print(f"(b) baseline: scipy least_squares(trf, 2-point, max_nfev={max_nfev}) "
          f"{t_base:.1f} s, {ls.nfev} residuals at its iterates + {ls.njev} FD Jacobians = "
          f"{n_evals} residual evaluations = {base_solves} eigsh calls (shift-invert, "
          f"each its own factorisation); status {ls.status} "
          f"({ls.message}); parameter error vs truth max {base_err['max_rel']:.1e}, "
          f"rms {base_err['rms_rel']:.1e}")
    print("(b) baseline iterates (evaluation: cost 0.5|r|^2, max parameter error): "
          + ", ".join(f"{e}: {c:.2g}, {er:.2g}" for e, _, c, er in trial))
    print(f"(b) baseline's 2-point Jacobian vs the exact (Fox-Kapoor) one at its final point: "
          f"column relative error median {np.median(fd_err):.1e}, max {fd_err.max():.1e}; "
          f"condition number of the exact normalised J {np.linalg.cond(exact):.1e}")
    print(f"(b) baseline/ours: time {t_base / t_ours:.1f}x (goal >= 50), factorisations "
          f"{base_solves / ours_t.calls['factorisation']:.1f}x"
          + ("" if ls.status > 0 else " (baseline stopped at its evaluation cap, unconverged)"))
    ref = _reference(prob, residual, scale) if reference else None
    return {
        "reference_exact_jacobian": ref,
        "frame": SIZES[size_key], "n": model.n, "configurations": nconf, "modes": len(modes),
        "parameters": len(model.parameters),
        "initial_error": param_errors(model.values, truth),
        "ours": {"seconds": t_ours, "iterations": res.nit, "converged": res.success,
                 "message": res.message, "linearisations": calls[0],
                 "eigsh_calls": ours_solves, "split": ours_t.as_dict(), "error": ours_err,
                 "objective": [h.objective for h in res.history]},
        "baseline": {"seconds": t_base, "nfev": int(ls.nfev), "njev": int(ls.njev or 0),
                     "residual_evaluations": n_evals, "eigsh_calls": base_solves,
                     "split": base_t.as_dict(), "status": int(ls.status),
                     "message": ls.message, "error": base_err, "max_nfev": max_nfev,
                     "iterates": [{"evaluation": e, "seconds": sec, "cost": c, "max_error": er}
                                  for e, sec, c, er in trial],
                     "fd_jacobian_rel_error": {"median": float(np.median(fd_err)),
                                               "max": float(fd_err.max())},
                     "condition_J": float(np.linalg.cond(exact))},
        "time_ratio": t_base / t_ours, "ours_solver": res.solver,
        "peak_rss_gib": peak_rss_gib(),
    }


def _reference(prob, residual, scale) -> dict:
    """least_squares (trf) with the package's exact Jacobian instead of finite differences:
    separates the effect of the Jacobian's accuracy from that of the optimiser."""
    model, configs, modes = prob.model, prob.configurations, prob.modes
    njac = [0]

    def jacobian(x):
        njac[0] += 1
        return linearise(model, configs, modes, x * scale).normalised

    t = time.perf_counter()
    ls = least_squares(residual, np.ones(len(scale)), jac=jacobian, max_nfev=300)
    sec = time.perf_counter() - t
    err = param_errors(ls.x * scale, prob.frame.truth)
    print(f"(b) reference: least_squares(trf) with the exact Fox-Kapoor Jacobian {sec:.1f} s, "
          f"{ls.nfev} residual evaluations + {njac[0]} Jacobians (linearisations); status "
          f"{ls.status}; parameter error vs truth max {err['max_rel']:.1e}")
    return {"seconds": sec, "nfev": int(ls.nfev), "njev": njac[0], "status": int(ls.status),
            "error": err}


# ----------------------------------------------------------------------------- whole


def bench_whole(size_key: str) -> dict:
    """The whole update (default optimiser, pairing) from the benchmark's start, error-free
    data, against one base eigen-solve of the same run (median of three, before and after)."""
    t = time.perf_counter()
    prob = make_problem(size_key)
    model, configs, modes, truth = prob.model, prob.configurations, prob.modes, prob.frame.truth
    t_build = time.perf_counter() - t
    initial = param_errors(model.values, truth)["max_rel"]
    print(f"(whole) frame {SIZES[size_key]}: {model.n} coordinates, {len(model.parameters)} "
          f"parameters, {len(configs)} configurations x {len(modes)} modes; truth simulated "
          f"in {t_build:.1f} s; start max {initial:.2%} off")
    cpu: list = []  # CPU seconds (all threads): less at the mercy of the machine's load
    bases = [base_solve_time(model, cpu)]
    calls = [0]
    timers = Timers()
    with counting(upd, "linearise", calls), phases(timers):
        t, c0 = time.perf_counter(), time.process_time()
        res = update(model, configs, modes, prob.measurements,
                     progress=lambda line: print(f"(whole)   {line}", flush=True))
        t_upd, c_upd = time.perf_counter() - t, time.process_time() - c0
    bases += [base_solve_time(model, cpu), base_solve_time(model, cpu)]
    base = float(np.median(bases))
    cpu_ratio = c_upd / float(np.median(cpu))
    err = param_errors(np.array([res.parameters[n] for n in model.names]), truth)
    out = {"ratio": t_upd / base, "coordinates": model.n, "iterations": res.nit,
           "max_rel_error": err["max_rel"], "converged": bool(res.success),
           "seconds": t_upd, "base_solve_s": bases, "linearisations": calls[0],
           "initial_max_rel_error": initial, "optimizer": res.optimizer,
           "status": res.status, "message": res.message, "pairing": res.pairing,
           "solver": res.solver, "peak_rss_gib": peak_rss_gib(), "cpu_ratio": cpu_ratio,
           "cpu_s": c_upd, "base_solve_cpu_s": cpu, "load_average": os.getloadavg()[0],
           "phases": timers.as_dict()}
    print(f"(whole) update() {t_upd:.1f} s = {out['ratio']:.2f} base eigen-solves (base solve "
          f"median {base:.2f} s of {np.round(bases, 2).tolist()}; CPU time {c_upd:.1f} s = "
          f"{cpu_ratio:.2f} base solves' CPU time, load {os.getloadavg()[0]:.1f}); "
          f"{res.nit} iterations, "
          f"{calls[0]} linearisations; converged {res.success} ({res.message}); "
          f"parameter error max {err['max_rel']:.1e}, rms {err['rms_rel']:.1e}; clusters "
          f"{res.pairing['clusters']}")
    print("(whole) phases (seconds summed over threads; 'LU solves' is part of eigsh and the "
          "Krylov subspaces): " + ", ".join(
              f"{k} {v['seconds']:.2f} s ({v['calls']})" for k, v in sorted(
                  out["phases"].items(), key=lambda kv: -kv[1]["seconds"])
              if k != "LU solve columns"))
    return out


@contextmanager
def phases(timers: Timers):
    """:func:`instrumented`, plus the missed-mode check's inertia counts (Sturm) and the
    mode tracking (pairing)."""
    def timed(label, f):
        def g(*a, **kw):
            with timers(label):
                return f(*a, **kw)
        return g

    count, match = eig.negative_count, pairing_mod.Pairing.match
    with instrumented(timers):
        eig.negative_count = jac.negative_count = timed("Sturm counts", count)
        pairing_mod.Pairing.match = timed("pairing", match)
        try:
            yield
        finally:
            eig.negative_count = jac.negative_count = count
            pairing_mod.Pairing.match = match


# ----------------------------------------------------------------------------- main


def run(args) -> int:
    kept = False if args.default_allocator else keep_freed_memory()
    t0 = time.perf_counter()
    a_size, b_size, cap, scaling = PLAN[args.size]
    if args.baseline_max_nfev is not None:
        cap = args.baseline_max_nfev or None
    meta = {
        "date": _dt.datetime.now().isoformat(timespec="seconds"),
        "size": args.size, "cores": os.cpu_count(), "blas_threads": args.blas_threads,
        "python": platform.python_version(), "numpy": np.__version__,
        "scipy": scipy.__version__, "machine": platform.machine(),
        "threads": parallel.threads(), "keep_freed_memory": kept,
    }
    print(f"eigenupdate benchmark, --size {args.size}, {meta['date']}, {meta['cores']} cores, "
          f"BLAS threads {args.blas_threads or 'library default'}, Python {meta['python']}, "
          f"NumPy {meta['numpy']}, SciPy {meta['scipy']}, {meta['threads']} threads, freed "
          f"memory {'kept (as the command line does)' if kept else 'returned (glibc default)'}")
    out = {"meta": meta, "self_check": self_check()}
    if args.only in (None, "a"):
        out["a"] = bench_a(a_size, args.colamd)
    if args.only in (None, "many"):
        out["many"] = bench_many(a_size)
    if args.only in (None, "screen"):
        out["screen"] = bench_screen(a_size)
    if args.only in (None, "scaling"):
        out["scaling"] = bench_scaling(scaling)
    if args.only in (None, "b"):
        out["b"] = bench_b(b_size, cap, args.reference)
    if args.only in (None, "whole"):
        out["whole"] = bench_whole(a_size)
    if args.only in (None, "stop"):
        from _stop import STOP_SIZE, bench_stop  # imports this module

        out["stop"] = bench_stop(STOP_SIZE[args.size])
    out["total_s"] = time.perf_counter() - t0
    print(f"total {out['total_s']:.0f} s, peak memory {peak_rss_gib():.2f} GiB")
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump(out, fh, indent=2, default=_jsonable)
        print(f"results written to {args.json}")
    sys.stdout.flush()
    return 0


def _jsonable(x):
    if isinstance(x, np.generic):
        return x.item()
    if isinstance(x, np.ndarray):
        return x.tolist()
    raise TypeError(type(x))
