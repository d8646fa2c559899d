"""Errors the command line turns into a one-line message and exit status."""

from __future__ import annotations


class InputError(ValueError):
    """Bad input: the message names the file, the field and what is wrong.

    The CLI prints ``eigenupdate: error: <message>`` and exits with status 2.
    """

    def __init__(self, message: str, *, source: str | None = None, field: str | None = None):
        parts = [p for p in (source, field) if p]
        prefix = ": ".join(parts)
        super().__init__(f"{prefix}: {message}" if prefix else message)
        self.source = source
        self.field = field


class ConvergenceError(RuntimeError):
    """An iteration failed to converge (CLI exit status 1)."""
