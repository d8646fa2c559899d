"""Which model mode is each measured resonance? An ordered assignment that cannot drift.

Updating pairs measured mode k with the model's k-th elastic mode, so one spurious or
missed resonance would shift every number above it. Here each validated resonance of a
configuration is matched to a mode of the initial model of that configuration:

* the match keeps the order (resonance i below resonance j means model mode of i below
  that of j), matches as many resonances as possible, and among those minimises the sum
  of ``|ln(f_measured / f_model)|``;
* a resonance may match a model mode only within :data:`MODEL_TOLERANCE` of it (the
  initial model may be a few per cent off);
* under added mass only (``r`` masses), the perturbed eigenvalue of order k lies between
  the bare ones of orders ``k - r`` and k (eigenvalue interlacing); with added grounded
  springs only, between orders k and ``k + r``. The measured bare frequencies, once
  numbered, bound the perturbed resonances this way (slack :data:`INTERLACING_SLACK`);
* when another assignment with as many matches is nearly as good (cost within
  :data:`AMBIGUITY_MARGIN`), the numbering is ambiguous and the two candidates are named.

Model modes inside the measured frequency range that nothing matched are "expected but
not found"; resonances that match nothing are "found but not expected".
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

__all__ = ["AMBIGUITY_MARGIN", "INTERLACING_SLACK", "MODEL_TOLERANCE", "Numbering",
           "interlacing_bounds", "number_resonances"]

#: Largest relative distance of a resonance from the model mode it is matched to: an
#: initial model "a few per cent off" is covered twice over.
MODEL_TOLERANCE = 0.10
#: Relative slack on the interlacing bounds (measurement scatter of the bare frequencies).
INTERLACING_SLACK = 2e-3
#: Two assignments whose costs (sums of |ln ratio|) differ by less than this are equally
#: plausible: 1 %, well below the spacing of distinct modes of a model a few % off.
AMBIGUITY_MARGIN = 0.01


@dataclass(frozen=True)
class Numbering:
    """``numbers[i]``: model mode (1-based) of resonance i, or None if unexpected;
    ``missing``: model modes in range with no resonance; ``ambiguous``: one line each."""

    numbers: list[int | None]
    missing: list[int]
    ambiguous: list[str]


def number_resonances(
    measured_hz: Sequence[float],
    model_hz: Sequence[float],
    *,
    range_hz: tuple[float, float] | None = None,
    bounds_hz: Sequence[tuple[float, float] | None] | None = None,
    tolerance: float = MODEL_TOLERANCE,
) -> Numbering:
    """Number measured resonances (ascending) by the model modes (ascending) they match.

    Parameters
    ----------
    measured_hz : validated resonances of one configuration, ascending.
    model_hz : the initial model's elastic frequencies of that configuration, ascending.
    range_hz : the measured frequency range; model modes in it must be found.
    bounds_hz : per model mode, an interval its resonance must lie in (interlacing), or
        None.
    tolerance : see :data:`MODEL_TOLERANCE`.

    Examples
    --------
    The model is 4 % stiff; a spurious resonance and a missing mode cannot shift numbers:

    >>> r = number_resonances([48.0, 99.0, 290.0], [50.0, 150.0, 300.0])
    >>> r.numbers, r.missing
    ([1, None, 3], [2])
    """
    m = np.log(np.asarray(measured_hz, float))
    q = np.log(np.asarray(model_hz, float))
    allowed = np.abs(m[:, None] - q[None, :]) <= np.log1p(tolerance)
    if bounds_hz is not None:
        for k, b in enumerate(bounds_hz):
            if b is not None and k < q.size:
                lo, hi = b[0] * (1 - INTERLACING_SLACK), b[1] * (1 + INTERLACING_SLACK)
                allowed[:, k] &= (np.exp(m) >= lo) & (np.exp(m) <= hi)
    cost = np.abs(m[:, None] - q[None, :])
    best = _assign(allowed, cost)
    numbers: list[int | None] = [None] * m.size
    for i, k in best[1]:
        numbers[i] = k + 1
    ambiguous = []
    for i, k in best[1]:
        alt = allowed.copy()
        alt[i, k] = False
        other = _assign(alt, cost)
        if other[0][0] == best[0][0] and other[0][1] - best[0][1] < AMBIGUITY_MARGIN:
            ambiguous.append(_describe(i, k, dict(best[1]), dict(other[1]), measured_hz,
                                       model_hz))
    lo, hi = range_hz if range_hz is not None else (-np.inf, np.inf)
    found = {k for _, k in best[1]}
    missing = [k + 1 for k in range(q.size)
               if k not in found and lo <= model_hz[k] <= hi]
    return Numbering(numbers, missing, sorted(set(ambiguous)))


def _assign(allowed: np.ndarray, cost: np.ndarray
            ) -> tuple[tuple[int, float], list[tuple[int, int]]]:
    """Order-keeping matching: most pairs, then least cost (dynamic programming)."""
    p, q = allowed.shape
    # score[i][k]: best (pairs, -cost) using resonances < i and model modes < k
    score = np.zeros((p + 1, q + 1, 2))
    move = np.zeros((p + 1, q + 1), dtype=int)  # 0 skip resonance, 1 skip mode, 2 match
    for i in range(p + 1):
        for k in range(q + 1):
            if i == 0 or k == 0:
                continue
            options = [(tuple(score[i - 1, k]), 0), (tuple(score[i, k - 1]), 1)]
            if allowed[i - 1, k - 1]:
                s = score[i - 1, k - 1]
                options.append(((s[0] + 1, s[1] - cost[i - 1, k - 1]), 2))
            (a, b), mv = max(options, key=lambda o: (o[0][0], o[0][1] + 1e-15 * o[1]))
            score[i, k] = (a, b)
            move[i, k] = mv
    pairs = []
    i, k = p, q
    while i > 0 and k > 0:
        mv = move[i, k]
        if mv == 2:
            pairs.append((i - 1, k - 1))
            i, k = i - 1, k - 1
        elif mv == 0:
            i -= 1
        else:
            k -= 1
    return (int(score[p, q, 0]), float(-score[p, q, 1])), pairs[::-1]


def _describe(i: int, k: int, best: dict[int, int], other: dict[int, int],
              measured_hz: Sequence[float], model_hz: Sequence[float]) -> str:
    """Name the two candidates of an ambiguous assignment."""
    j = next((j for j, kk in other.items() if kk == k), None)
    if j is not None and j != i:  # another resonance could be this model mode
        a, b = sorted((i, j))
        return (f"model mode {k + 1} ({model_hz[k]:.5g} Hz): the resonance at "
                f"{measured_hz[a]:.5g} Hz or at {measured_hz[b]:.5g} Hz")
    kk = other.get(i)
    if kk is not None:  # this resonance could be another model mode
        a, b = sorted((k, kk))
        return (f"the resonance at {measured_hz[i]:.5g} Hz: model mode {a + 1} "
                f"({model_hz[a]:.5g} Hz) or {b + 1} ({model_hz[b]:.5g} Hz)")
    return f"the resonance at {measured_hz[i]:.5g} Hz: model mode {k + 1} or none"


def interlacing_bounds(
    bare_hz: dict[int, float], n_modes: int, masses: int, springs: int
) -> list[tuple[float, float] | None]:
    """Interval of each perturbed mode k (1-based) from the measured bare modes.

    ``masses`` added masses only: ``[f_bare(k - masses), f_bare(k)]``; ``springs``
    grounded springs only: ``[f_bare(k), f_bare(k + springs)]``; a mix: no bound. A
    bound whose bare mode was not measured is left open (0 or infinity).

    >>> interlacing_bounds({1: 50.0, 2: 140.0}, 3, masses=1, springs=0)
    [(0.0, 50.0), (50.0, 140.0), (140.0, inf)]
    """
    if (masses > 0) == (springs > 0):
        return [None] * n_modes
    out: list[tuple[float, float] | None] = []
    for k in range(1, n_modes + 1):
        lo_k, hi_k = (k - masses, k) if masses else (k, k + springs)
        lo = 0.0 if lo_k < 1 else bare_hz.get(lo_k, 0.0)
        out.append((lo, bare_hz.get(hi_k, np.inf)))
    return out
