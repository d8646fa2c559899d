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

from scipy.stats import norm

from eigenupdate.errors import InputError
from eigenupdate.identify.consistency import ALPHA
from eigenupdate.measure.measurement import Measurement
from eigenupdate.model.configurations import BASE, Configuration

RTOL = 1e-3


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
