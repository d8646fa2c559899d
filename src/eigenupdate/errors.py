"""Errors and warnings of eigenupdate, and the exit status the command line gives each.

Two families, kept apart so that a caller can tell "your input is wrong" from "the
numbers cannot be computed":

* :class:`InputError`: bad input (a file, a field, an option). Exit status 2.
* :class:`NumericalError`: the core cannot compute a trustworthy number from valid
  input: :class:`SingularMatrixError`, :class:`RepeatedEigenvalueError` (exit status 2:
  the model or plan must change) and :class:`NotConvergedError` (exit status 1).

Soft trouble (a result that is computed but deserves a look) is a warning of class
:class:`EigenupdateWarning`, issued with :func:`warnings.warn`.

>>> try:
...     raise RepeatedEigenvalueError("modes 1 and 2 coincide", field="configuration 'base'")
... except NumericalError as exc:
...     print(exc, "-> exit", exc.exit_status)
configuration 'base': modes 1 and 2 coincide -> exit 2
"""

from __future__ import annotations

import re

MAX_NAME = 120
"""File and field names longer than this are cut in the middle."""

MAX_MESSAGE = 400
"""Messages longer than this are cut (the CLI prints one readable line)."""


def shorten(text: str, limit: int = MAX_NAME) -> str:
    """One printable line of at most ``limit`` characters: control characters escaped,
    the middle of a longer text replaced by '...'.

    >>> shorten("a\\nb")
    'a\\\\nb'
    >>> shorten("x" * 200, 20)
    'xxxxxxxx...xxxxxxxxx'
    """
    text = re.sub(r"[\x00-\x1f\x7f-\x9f\u2028\u2029]",
                  lambda m: repr(m.group())[1:-1], str(text))
    if len(text) <= limit:
        return text
    head = (limit - 3) // 2
    return f"{text[:head]}...{text[len(text) - (limit - 3 - head):]}"


class _Located(Exception):
    """One-line message ``source: field: message``; ``exit_status`` is the CLI's."""

    exit_status = 2

    def __init__(self, message: str, *, source: str | None = None, field: str | None = None):
        parts = [shorten(p) for p in (source, field) if p]
        prefix = ": ".join(parts)
        message = shorten(message, max(80, MAX_MESSAGE - len(prefix) - 2))
        super().__init__(f"{prefix}: {message}" if prefix else message)
        self.message = message  # without the prefix: for a caller that adds the source
        self.source = source
        self.field = field

    def located(self, study: str | None) -> str:
        """The message, prefixed by the ``study`` file when it names no file: errors found
        deep in the numerics (too few elastic modes, an indefinite mass matrix) come from
        the study's model all the same; options (``--x``) name themselves."""
        if self.source is None and study and not (self.field or "").startswith("-"):
            return f"{shorten(study)}: {self}"
        return str(self)


class InputError(_Located, ValueError):
    """Bad input: the message names the file, the field and what is wrong.

    The CLI prints ``eigenupdate: error: <message>`` and exits with status 2.
    """


class NumericalError(_Located, ArithmeticError):
    """Valid input whose numbers cannot be computed reliably (base class)."""


class SingularMatrixError(NumericalError):
    """A matrix that must be factorised is exactly singular."""


class RepeatedEigenvalueError(NumericalError):
    """A mode used for updating has a repeated eigenvalue (e.g. a symmetric structure):
    its derivative is not defined."""


class NotConvergedError(NumericalError):
    """An iterative solver stopped before it converged (CLI exit status 1)."""

    exit_status = 1


class EigenupdateWarning(UserWarning):
    """Soft trouble: a result was computed but deserves a look (e.g. two estimates of a
    natural frequency disagree)."""
