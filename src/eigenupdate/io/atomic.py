"""Outputs are written whole or not at all: a temporary file in the target's directory,
then a rename over the target."""

from __future__ import annotations

import os
import secrets
from collections.abc import Callable
from pathlib import Path

PathLike = str | os.PathLike


def atomic_write(path: PathLike, write: Callable[[str], None]) -> None:
    """Create ``path`` atomically: ``write(tmp)`` fills a temporary file, then it is renamed.

    The temporary file is created empty (honouring the umask) in the directory of
    ``path``, passed to ``write`` by name, flushed to disk and moved over ``path`` with
    :func:`os.replace`.  On any error the temporary file is removed and ``path`` is left
    untouched.

    Parameters
    ----------
    path : str or path-like
        Destination file.
    write : callable
        Called with the temporary file name; must write the complete content.
    """
    target = Path(path)
    tmp = target.with_name(f".{target.name}.{secrets.token_hex(6)}.tmp")
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
    os.close(fd)
    try:
        write(str(tmp))
        with open(tmp, "rb+") as fh:
            os.fsync(fh.fileno())
        os.replace(tmp, target)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def write_text(path: PathLike, text: str) -> None:
    """Write a text file atomically."""

    def write(tmp: str) -> None:
        with open(tmp, "w", encoding="utf-8", newline="") as fh:
            fh.write(text)

    atomic_write(path, write)
