"""Scalar optimality criteria of a posterior covariance (normalised parameters).

``A``: sum of the variances; ``D``: log-determinant; ``E``: largest eigenvalue (the variance
of the worst-determined combination); a list of parameter names: the sum of their variances.
A singular plan scores ``inf``.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np


def criterion_value(cov: np.ndarray, criterion: str | Sequence[str], names: Sequence[str]) -> float:
    """Value of ``criterion`` (smaller is better).

    >>> import numpy as np
    >>> c = np.diag([4.0, 1.0])
    >>> [criterion_value(c, k, ["a", "b"]) for k in ("A", "E")], criterion_value(c, ["b"], "ab")
    ([5.0, 4.0], 1.0)
    >>> round(criterion_value(c, "D", ["a", "b"]), 6)    # log 4
    1.386294
    """
    if not np.all(np.isfinite(cov)):
        return float("inf")
    if criterion == "A":
        return float(np.trace(cov))
    if criterion == "D":
        sign, logdet = np.linalg.slogdet(cov)
        return float(logdet) if sign > 0 else float("inf")
    if criterion == "E":
        return float(np.linalg.eigvalsh(cov)[-1])
    idx = [list(names).index(n) for n in criterion]
    return float(np.sum(np.diag(cov)[idx]))
