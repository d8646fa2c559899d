"""Physics checks of measured natural frequencies, before any update.

Two facts hold for every structure, whatever its parameters:

* in one configuration, natural frequencies do not decrease with the mode number;
* adding a positive semi-definite term of rank r interlaces the eigenvalues (Cauchy,
  Weyl): adding masses at r coordinates gives lambda_{k-r} <= lambda'_k <= lambda_k,
  adding grounded springs at r coordinates lambda_{k-r} <= lambda'_k <= lambda_{k+r}
  (elastic numbering; a grounded spring on a free structure can turn a rigid-body mode
  into elastic mode 1, which moves the numbering by up to r, hence the wider bounds).
  Configurations that add masses and springs together are not checked against the bare
  structure. When the number of rigid-body modes of the bare structure is known
  (``n_rigid``), the springs' lower bound is lambda_{k - min(r, n_rigid)}: on a grounded
  structure added stiffness can only raise each eigenvalue, as added mass can only
  lower it.

Measured frequencies that break them are not a poor model but a labelling error (two
modes swapped, one missed) and would drive the update far from the truth (a swapped pair
in the paper's Fig. 2 data takes m3 to 418,384 kg). Each comparison allows ``n_std``
combined standard deviations, or ``rtol`` of the frequency where no std is given. By
default ``n_std`` is the one-sided normal quantile at ALPHA divided by the number of
comparisons (Bonferroni): correct data with Gaussian noise are refused with probability
at most ALPHA over the whole file, as by the chi-square test
(:data:`eigenupdate.identify.consistency.ALPHA`). A fixed 3 std refused 0.13 % of the
comparisons whose true difference is nil (a mode with a node at the added mass): on a
PBARL frame with 0.1 % noise 1 of 40 simulated tests, on a frame of Matrix Market files
1 of 100.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np
from scipy.stats import norm

from eigenupdate.errors import InputError
from eigenupdate.identify.consistency import ALPHA
from eigenupdate.measure.measurement import Measurement
from eigenupdate.model.configurations import BASE, Configuration

RTOL = 1e-3

SCALE_LIMIT = 4.0
"""Measured frequencies all this many times the initial model's (or all below its
inverse) are refused (:func:`check_frequency_scale`)."""


def n_std_for(comparisons: int) -> float:
    """The allowance in combined std that refuses correct data with probability at most
    ALPHA over ``comparisons`` one-sided tests.

    >>> round(n_std_for(1), 2), round(n_std_for(200), 2)
    (3.72, 4.89)
    """
    return float(norm.isf(ALPHA / max(comparisons, 1)))


def _tolerance(a: Measurement, b: Measurement, n_std: float, rtol: float) -> float:
    if a.std_hz is not None and b.std_hz is not None:
        return n_std * math.hypot(a.std_hz, b.std_hz)
    return rtol * max(a.frequency_hz, b.frequency_hz)


def check_measured_frequencies(
    configurations: Sequence[Configuration],
    measurements: Mapping[tuple[str, int], Measurement],
    *,
    n_std: float | None = None,
    rtol: float = RTOL,
    source: str | None = None,
    n_rigid: int | None = None,
) -> None:
    """Raise InputError if measured frequencies break ordering or interlacing.

    Parameters
    ----------
    configurations : the bare structure (named ``base``) and the perturbed ones.
    measurements : {(configuration name, elastic mode): Measurement}.
    n_std, rtol : allowance, in combined standard deviations (default: ALPHA over all
        comparisons, :func:`n_std_for`) or (without std) relative.
    source : the measurement file, for the message.
    n_rigid : rigid-body modes of the bare structure, if known (tightens the bound of
        added springs, see the module).

    Examples
    --------
    The paper's Fig. 2 data with modes 2 and 3 of the bare structure swapped:

    >>> m = {("base", 1): Measurement("base", 1, 42.87),
    ...      ("base", 2): Measurement("base", 2, 94.29),
    ...      ("base", 3): Measurement("base", 3, 76.33)}
    >>> try:
    ...     check_measured_frequencies([Configuration("base")], m)
    ... except InputError as exc:
    ...     print(str(exc)[:59])
    configuration 'base': mode 2 at 94.29 Hz is above mode 3 at
    """
    by_config: dict[str, dict[int, Measurement]] = {}
    for (name, mode), m in measurements.items():
        by_config.setdefault(name, {})[mode] = m
    if n_std is None:  # ordering pairs, and up to two bounds per perturbed frequency
        n_std = n_std_for(sum(max(len(v) - 1, 0) for v in by_config.values())
                          + 2 * sum(len(v) for k, v in by_config.items() if k != BASE))
    for c in configurations:
        got = by_config.get(c.name, {})
        modes = sorted(got)
        for lo, hi in zip(modes, modes[1:], strict=False):
            a, b = got[lo], got[hi]
            if a.frequency_hz > b.frequency_hz + _tolerance(a, b, n_std, rtol):
                raise InputError(
                    f"configuration {c.name!r}: mode {lo} at {a.frequency_hz:.6g} Hz is above "
                    f"mode {hi} at {b.frequency_hz:.6g} Hz; frequencies must increase with the "
                    f"mode number (modes {lo} and {hi} swapped, or one missed?)", source=source)
    base = by_config.get(BASE, {})
    for c in configurations:
        if not c.additions or c.name == BASE:
            continue
        masses = all(a.stiffness == 0 for a in c.additions)
        springs = all(a.mass == 0 for a in c.additions)
        if not (masses or springs):
            continue
        r = len({a.coordinate for a in c.additions})
        what = "adds mass" if masses else "adds grounded springs"
        # springs can make up to min(r, n_rigid) rigid-body modes elastic
        low = r if masses or n_rigid is None else min(r, n_rigid)
        for k, m in sorted(by_config.get(c.name, {}).items()):
            bounds = ((base.get(k if masses else k + r), 1.0, "above"),
                      (base.get(k - low), -1.0, "below"))
            for b, sign, word in bounds:
                if b is not None and sign * (m.frequency_hz - b.frequency_hz) > _tolerance(
                        m, b, n_std, rtol):
                    raise InputError(
                        f"configuration {c.name!r} {what} at {r} coordinate(s), yet its mode "
                        f"{k} at {m.frequency_hz:.6g} Hz is {word} mode {b.mode} of the bare "
                        f"structure at {b.frequency_hz:.6g} Hz ({_law(masses, sign, low, r)}); "
                        f"a swapped or missed mode in one of them?", source=source)


def _law(masses: bool, sign: float, low: int, r: int) -> str:
    if low == 0:
        return "added stiffness cannot lower an eigenvalue"
    if masses and sign > 0:
        return "added mass cannot raise an eigenvalue"
    return "interlacing"


def check_frequency_scale(rows: Sequence[tuple[str, int]], measured_hz: np.ndarray,
                          model_hz: np.ndarray, *, source: str | None = None) -> None:
    """Raise InputError if every measured frequency is at least :data:`SCALE_LIMIT` times
    the initial model's, or every one at most its inverse.

    Data in rad/s (2 pi = 6.28 times the Hz), kHz or cycles per minute pass the ordering
    laws, and so does a deck in mm with E in Pa: scaled alike, every frequency fits a
    model scaled alike. The Fig. 2 data in rad/s converged, exit status 0, to springs
    39.5 (4 pi^2) times the truth. A factor 4 in every frequency is a factor 16 in every
    eigenvalue: not an initial model an update can start from, whatever the cause.

    >>> check_frequency_scale([("base", 1)], np.array([120.0]), np.array([100.0]))
    >>> try:
    ...     check_frequency_scale([("base", 1)], np.array([628.3]), np.array([100.0]))
    ... except InputError as exc:
    ...     print(str(exc)[:62])
    every measured frequency is 6.28 to 6.28 times the initial mod
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.asarray(measured_hz, float) / np.asarray(model_hz, float)
    ratio = ratio[np.isfinite(ratio) & (ratio > 0)]
    if ratio.size == 0:
        return
    lo, hi = float(ratio.min()), float(ratio.max())
    if lo < SCALE_LIMIT and hi > 1 / SCALE_LIMIT:
        return
    mean = math.exp(float(np.mean(np.log(ratio))))
    if abs(mean / (2 * math.pi) - 1) < 0.3:
        hint = "rad/s given as Hz (2 pi = 6.28)?"
    elif mean < 2e-3:
        hint = "kHz given as Hz?"
    elif abs(mean / 60 - 1) < 0.3:
        hint = "cycles per minute given as Hz?"
    else:
        hint = "units of the model (mm with E in Pa?) or of the frequencies?"
    raise InputError(
        f"every measured frequency is {lo:.3g} to {hi:.3g} times the initial model's "
        f"({len(ratio)} of them, e.g. {rows[0][0]!r} mode {rows[0][1]}): {hint} frequency_hz "
        f"is in Hz, and an update starts within a factor {SCALE_LIMIT:g} of the data",
        source=source)
