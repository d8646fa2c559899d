"""Input files are never read from a device, FIFO or socket.

/dev/zero, /dev/urandom or a FIFO fed by ``yes`` never end: read whole, they took memory
until the process died (a measurement CSV named /dev/zero: "out of memory", naming the
study). The size checks of the readers (``st_size``) see 0 for them. NASTRAN decks are
refused the same way (``io/nastran_deck.py``).
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

from eigenupdate.errors import InputError


def require_regular(path: str | os.PathLike, what: str = "file") -> None:
    """Raise InputError if ``path`` (after links) is a device, FIFO or socket; a missing
    file or a directory is left to the reader's own message."""
    try:
        mode = Path(path).stat().st_mode
    except OSError:
        return
    if not (stat.S_ISREG(mode) or stat.S_ISDIR(mode)):
        raise InputError(f"is not a regular file (a device, FIFO or socket); a {what} is "
                         f"read from a regular file", source=str(path))
