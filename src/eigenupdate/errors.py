"""Errors the command line turns into a one-line message and exit status."""

from __future__ import annotations

import re

MAX_NAME = 120
"""File and field names longer than this are cut in the middle."""

MAX_MESSAGE = 300
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


class InputError(ValueError):
    """Bad input: the message names the file, the field and what is wrong.

    The CLI prints ``eigenupdate: error: <message>`` and exits with status 2.
    """

    def __init__(self, message: str, *, source: str | None = None, field: str | None = None):
        parts = [shorten(p) for p in (source, field) if p]
        prefix = ": ".join(parts)
        message = shorten(message, max(80, MAX_MESSAGE - len(prefix) - 2))
        super().__init__(f"{prefix}: {message}" if prefix else message)
        self.source = source
        self.field = field


class ConvergenceError(RuntimeError):
    """An iteration failed to converge (CLI exit status 1)."""
