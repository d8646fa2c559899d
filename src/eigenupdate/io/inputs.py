"""Input files are never read from a device, FIFO or socket.

/dev/zero, /dev/urandom or a FIFO fed by ``yes`` never end: read whole, they took memory
until the process died (a measurement CSV named /dev/zero: "out of memory", naming the
study). The size checks of the readers (``st_size``) see 0 for them. NASTRAN decks are
refused the same way (``io/nastran_deck.py``). A regular file is read whole, so one larger
than the ``input_mb`` budget (:mod:`eigenupdate.budget`) is refused before it is read.
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

from eigenupdate.budget import require
from eigenupdate.errors import InputError


def require_regular(path: str | os.PathLike, what: str = "file") -> None:
    """Raise InputError if ``path`` (after links) is a device, FIFO or socket, or a file
    beyond the ``input_mb`` budget; a missing file or a directory is left to the reader's
    own message."""
    try:
        st = Path(path).stat()
    except OSError:
        return
    if not (stat.S_ISREG(st.st_mode) or stat.S_ISDIR(st.st_mode)):
        raise InputError(f"is not a regular file (a device, FIFO or socket); a {what} is "
                         f"read from a regular file", source=str(path))
    if stat.S_ISREG(st.st_mode):
        require_size(path, st.st_size, what)


def require_size(path: str | os.PathLike, size: int, what: str = "file") -> None:
    """Raise InputError if ``size`` bytes (``path``'s) exceed the ``input_mb`` budget."""
    mb = size / 2**20
    require("input_mb", mb, f"the {what} is {mb:,.0f} MB, read whole into memory",
            source=str(path))
