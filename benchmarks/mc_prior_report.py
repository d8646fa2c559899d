"""Summary of a run of ``mc_prior_long.py`` (issue 22): the Monte Carlo trials against
the checked virtual tests behind the design's prediction.

    .venv/bin/python benchmarks/mc_prior_report.py OUT.pkl [OUT2.pkl ...]

Prints the outcome counts of both sides, the gross-error fractions with their binomial
standard errors, per parameter empirical / predicted std with the design's 95 % interval
(delta method, :func:`eigenupdate.design.montecarlo.std_with_error`) and a bootstrap one,
the ratio at growing numbers of tests (the first k of each side: what ``design
--validate k`` would have printed), and where in the prior the gross errors fall.
"""

from __future__ import annotations

import pickle
import sys

import numpy as np

from eigenupdate.design.montecarlo import std_with_error

SIZES = (30, 60, 120, 250, 500, 1000, 2000)


def _errors(records):
    ok = [t for t in records if t["converged"]]
    return np.array([t["estimate"] - t["truth"] for t in ok]).reshape(len(ok), -1)


def _ratio(a, b):
    ea, sa = std_with_error(a)
    eb, sb = std_with_error(b)
    r = ea / eb
    se = r * np.hypot(sa / ea, sb / eb)
    return r, r - 1.96 * se, r + 1.96 * se


def _bootstrap(a, b, rng, reps=2000):
    ra = rng.integers(0, len(a), (reps, len(a)))
    rb = rng.integers(0, len(b), (reps, len(b)))
    r = np.array([a[i].std(axis=0, ddof=1) / b[j].std(axis=0, ddof=1)
                  for i, j in zip(ra, rb, strict=True)])
    return np.percentile(r, [2.5, 97.5], axis=0)


def report(doc) -> None:
    mc, vt, names = doc["trials"], doc["virtual"], doc["names"]
    n = min(len(mc), len(vt))
    mc, vt = mc[:n], vt[:n]
    print(f"== {doc['case']} prior {doc['prior']}: plan {doc['plan']}; {n} trials and {n} "
          f"virtual tests in {doc['seconds']:.0f} s")
    for side, rec in (("Monte Carlo", mc), ("virtual tests", vt)):
        kinds: dict[str, int] = {}
        for t in rec:
            kinds[t["outcome"]] = kinds.get(t["outcome"], 0) + 1
        g = 1 - sum(t["converged"] for t in rec) / n
        print(f"   {side:13s}: gross {g:.3f} +- {np.sqrt(g * (1 - g) / n):.3f}; {kinds}")
    a, b = _errors(mc), _errors(vt)
    r, lo, hi = _ratio(a, b)
    blo, bhi = _bootstrap(a, b, np.random.default_rng(0))
    ka = (((a - a.mean(0)) / a.std(0)) ** 4).mean(0)
    kb = (((b - b.mean(0)) / b.std(0)) ** 4).mean(0)
    print(f"   converged: {len(a)} trials, {len(b)} virtual tests")
    print("   param  emp/pred [95 % delta] [95 % bootstrap]  kurtosis emp / pred  "
          "robust (MAD) emp/pred")
    mad = 1.4826 * np.median(np.abs(a - np.median(a, 0)), 0) / (
        1.4826 * np.median(np.abs(b - np.median(b, 0)), 0))
    for i, name in enumerate(names):
        print(f"   {name:5s}  {r[i]:.2f} [{lo[i]:.2f}, {hi[i]:.2f}] [{blo[i]:.2f}, "
              f"{bhi[i]:.2f}]  {ka[i]:6.1f} / {kb[i]:6.1f}  {mad[i]:.2f}")
    print(f"   within 15 %: {np.mean(np.abs(r - 1) <= 0.15):.0%} of the parameters; "
          f"bootstrap interval inside [0.85, 1.15]: "
          f"{np.mean((blo >= 0.85) & (bhi <= 1.15)):.0%}; containing 1: "
          f"{np.mean((blo <= 1) & (bhi >= 1)):.0%}")
    for k in SIZES:
        if k > n:
            break
        rk = _ratio(_errors(mc[:k]), _errors(vt[:k]))[0]
        print(f"   first {k:4d} of each: emp/pred {rk.min():.2f}-{rk.max():.2f}, "
              f"within 15 %: {np.mean(np.abs(rk - 1) <= 0.15):.0%}")
    # sampling alone: the two halves of each side against each other (the same
    # estimator, the same prior, disjoint seeds) spread as far from 1 as the two sides
    h = n // 2
    for side, rec in (("Monte Carlo", mc), ("virtual tests", vt)):
        rh = _ratio(_errors(rec[:h]), _errors(rec[h:2 * h]))[0]
        print(f"   {side:13s}: first half / second half ({h} each): {rh.min():.2f}-"
              f"{rh.max():.2f}, within 15 %: {np.mean(np.abs(rh - 1) <= 0.15):.0%}")
    # the tails: share of the sum of squared errors from the largest 1 % of the errors,
    # and the ratio once both sides drop errors beyond 5 robust std (1.4826 MAD, pooled)
    for side, e in (("Monte Carlo", a), ("virtual tests", b)):
        top = max(1, len(e) // 100)
        sq = np.sort((e - e.mean(0)) ** 2, axis=0)[::-1]
        share = sq[:top].sum(0) / sq.sum(0)
        print(f"   {side:13s}: largest {top} errors carry {share.min():.0%}-{share.max():.0%} "
              f"of the variance (median {np.median(share):.0%})")
    pooled = np.vstack([a, b])
    centre = np.median(pooled, 0)
    scale = 1.4826 * np.median(np.abs(pooled - centre), 0)
    keep_a = np.all(np.abs(a - centre) <= 5 * scale, axis=1)
    keep_b = np.all(np.abs(b - centre) <= 5 * scale, axis=1)
    rt = _ratio(a[keep_a], b[keep_b])[0]
    print(f"   without errors beyond 5 robust std (kept {keep_a.sum()} / {keep_b.sum()}): "
          f"emp/pred {rt.min():.2f}-{rt.max():.2f}, within 15 %: "
          f"{np.mean(np.abs(rt - 1) <= 0.15):.0%}")
    # where the gross errors fall: distance of the truth from the prior mean, in prior
    # std (the same prior on both sides: a difference is sampling, not selection)
    for side, rec in (("Monte Carlo", mc), ("virtual tests", vt)):
        truth = np.array([t["truth"] for t in rec])
        z = np.sqrt(np.mean(((truth - truth.mean(0)) / truth.std(0)) ** 2, axis=1))
        conv = np.array([t["converged"] for t in rec])
        print(f"   {side:13s}: rms prior z of the truth, converged {z[conv].mean():.2f}, "
              f"gross {z[~conv].mean():.2f}; gross fraction by z quartile "
              + " ".join(f"{1 - conv[q].mean():.2f}" for q in np.array_split(np.argsort(z), 4)))


def main() -> None:
    for path in sys.argv[1:]:
        with open(path, "rb") as f:
            report(pickle.load(f))


if __name__ == "__main__":
    main()
