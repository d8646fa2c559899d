"""Numbers in text files: plain ASCII decimal syntax only.

Python's ``float()`` and ``int()`` also accept ``1_000``, Unicode digits (``'١٢'``),
``nan``, ``inf`` and surrounding whitespace of any kind; a measurement file holding such
text is more likely corrupted than meant, so readers use these instead.
"""

from __future__ import annotations

import re
from decimal import Decimal

import numpy as np

_FLOAT = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?", re.ASCII)
_INT = re.compile(r"[+-]?\d+", re.ASCII)


def parse_float(text: str) -> float:
    """A finite float written as ``[+-]digits[.digits][e[+-]digits]``; ValueError otherwise.

    >>> parse_float(" 4.25e3 "), parse_float("-.5")
    (4250.0, -0.5)
    >>> parse_float("1_000")
    Traceback (most recent call last):
    ValueError: '1_000' is not a plain decimal number
    """
    s = text.strip(" \t")
    if not _FLOAT.fullmatch(s):
        raise ValueError(f"{s!r} is not a plain decimal number")
    value = float(s)
    if value in (float("inf"), float("-inf")):  # 1e999
        raise ValueError(f"{s!r} is beyond the floating-point range")
    return value


def parse_int(text: str) -> int:
    """An integer written as ``[+-]digits`` (ASCII); ValueError otherwise.

    >>> parse_int("12")
    12
    >>> parse_int("\\u0661\\u0662")
    Traceback (most recent call last):
    ValueError: '١٢' is not a plain integer
    """
    s = text.strip(" \t")
    if not _INT.fullmatch(s) or len(s) > 18:
        raise ValueError(f"{s!r} is not a plain integer")
    return int(s)


def printed_half_unit(value: float) -> float:
    """Half a unit in the last digit of ``value`` as written (its shortest decimal form,
    which is how it was written when it was read from text; ``5757.`` counts to units): the
    rounding a printed number carries.

    >>> printed_half_unit(8.7172e-6), printed_half_unit(5757.0), printed_half_unit(-1.5)
    (5e-11, 0.5, 0.05)
    """
    if value == 0:
        return 0.0
    text = repr(float(value))
    if text.endswith(".0"):
        text = text[:-2]
    return 0.5 * 10.0 ** int(Decimal(text).as_tuple().exponent)


def eigenvalues_with_slack(a: np.ndarray, half: np.ndarray | None = None
                           ) -> tuple[np.ndarray, float]:
    """Eigenvalues (ascending) of the symmetric matrix ``a`` and how far below zero the
    smallest may lie while ``a`` is still positive semi-definite: ``eigvalsh``'s own error
    m eps max|lambda|, plus ||half||_F when ``a``'s entries are printed values each within
    ``half`` (:func:`printed_half_unit`) of the true ones (Weyl's bound).

    >>> lam, slack = eigenvalues_with_slack(np.array([[1.0, 1.0], [1.0, 1.0]]),
    ...                                     np.full((2, 2), 0.05))
    >>> [round(float(x), 12) for x in lam], round(slack, 12)
    ([0.0, 2.0], 0.1)
    """
    lam = np.linalg.eigvalsh(a)
    slack = a.shape[0] * np.finfo(float).eps * np.abs(lam).max()
    return lam, float(slack + (0.0 if half is None else np.linalg.norm(half)))
