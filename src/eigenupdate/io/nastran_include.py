"""A deck's files as pre-processors write them, and their INCLUDEs as NASTRAN reads them.

:func:`expand` reads a deck file and every file its INCLUDE statements name, in place, one
list of lines. A file is text: UTF-8 (a byte-order mark dropped, as Notepad and some
exporters write it) or, where it is not valid UTF-8, the one-byte Windows code page Femap
and Patran write (read as Latin-1: each byte one character, so a fixed-field column is the
byte NASTRAN counts; the accents live in comments and titles). A UTF-16 file or one with a
NUL byte is refused; DOS's end-of-file mark (Ctrl-Z, byte 0x1A) ending a file is dropped
(it was an unknown card). Lines end at LF or CRLF only (``str.splitlines`` also split at
form feeds and Latin-1's NEL, byte 0x85, shifting every later line number).

INCLUDE (MSC and Autodesk QRG, INCLUDE): anywhere in the deck, nested; ``include`` in any
case; the file name quoted with apostrophes (the quotes optional: a name without blanks or
commas), a quoted name continued over several lines (each line's leading and trailing
blanks dropped: the QRG's ``INCLUDE '/dir123`` / ``/dir456`` / ``/dir789/filename.dat'``).
A relative name is looked up beside the file that holds the INCLUDE, then beside the main
deck (the job's directory: SimXpert nests INCLUDEs relative to it). Written on Windows,
its separators are backslashes (NASTRAN_CoFE's ``INCLUDE '..\\se0.dat'``; the QRG's own
example ``C:\\NASA\\RLV\\...``): they are read as ``/``. Refused, each in one line naming
the file and line: a Windows absolute name (``C:\\proj\\mesh.bdf``, ``\\\\server\\share``,
``\\proj``), which cannot exist here; MSC's logical symbols (``MESHDIR:mesh.bdf``, defined
in the nastran command or its rc file, not in the deck); double quotes; text after the
closing quote (MSC's names pieced from quoted and unquoted parts); a quote never closed;
and a name that exists only in another case (Windows ignores case, this system may not).
"""

from __future__ import annotations

import filecmp
import os
import re
import warnings
from pathlib import Path

from eigenupdate.errors import EigenupdateWarning, InputError
from eigenupdate.io.inputs import require_size

MAX_INCLUDE_DEPTH = 100
"""Deepest INCLUDE nesting read (each level is a frame of :func:`expand`'s recursion)."""
_INCLUDE = re.compile(r"^\s*INCLUDE(?=[\s'\"]|$)\s*(.*)$", re.IGNORECASE)
_DRIVE = re.compile(r"^[A-Za-z]:")
_SYMBOL = re.compile(r"^([A-Za-z_][A-Za-z0-9_]+):")
_PATH_MAX = 4096  # Linux's longest path: a quoted name running past it lost its quote


def read_lines(path: Path) -> list[str]:
    """The lines of a deck file (UTF-8, else Latin-1; CRLF or LF)."""
    try:
        require_size(path, path.stat().st_size, "NASTRAN file")
        raw = path.read_bytes()
    except OSError as exc:
        raise InputError(f"cannot read {path}: {exc.strerror or exc}") from None
    if raw.startswith((b"\xff\xfe", b"\xfe\xff")):
        raise InputError(f"{path.name}: the file is UTF-16 text (Windows' \"Unicode\"); "
                         f"NASTRAN reads one byte per character: save it as ANSI or UTF-8")
    if b"\x00" in raw:
        line = raw[:raw.index(b"\x00")].count(b"\n") + 1
        raise InputError(f"{path.name}:{line}: a NUL byte: not a text file (UTF-16 without "
                         f"its mark, or binary)")
    raw = raw.rstrip(b"\x1a")  # DOS's end-of-file mark (Ctrl-Z), not a card
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError:  # a Windows code page: its accents in comments and titles
        text = raw.decode("latin-1")
    lines = text.split("\n")
    if lines and lines[-1] == "":
        lines.pop()
    return [x[:-1] if x.endswith("\r") else x for x in lines]


def include_name(lines: list[str], i: int, where: str) -> tuple[str, int] | None:
    """The file name of the INCLUDE statement starting at ``lines[i]`` (None if it is
    no INCLUDE) and the index of the line after it; ``where`` is ``file:line``."""
    if lines[i].lstrip().startswith("$"):
        return None
    m = _INCLUDE.match(lines[i])
    if m is None:
        return None
    rest = m.group(1).strip()
    if rest.startswith('"'):
        raise InputError(f"{where}: INCLUDE {rest.split('$')[0].strip()}: a file name in "
                         f"double quotes; NASTRAN quotes it with apostrophes ('...')")
    if not rest.startswith("'"):  # unquoted: the QRG's quotes are optional
        name = rest.split("$")[0].strip()
        if re.search(r"[\s,]", name):
            raise InputError(f"{where}: INCLUDE {name}: an unquoted file name holding a "
                             f"blank or comma; quote it ('...')")
        return name, i + 1
    # quoted: the name may continue over the next lines until its closing quote
    name, j = rest[1:], i
    while "'" not in name:
        j += 1
        if j >= len(lines) or len(name) > _PATH_MAX:
            raise InputError(f"{where}: INCLUDE '{_short(name)}: the file name's quote is "
                             f"never closed (no second ' "
                             + ("before the end of the file)" if j >= len(lines) else
                                f"within {_PATH_MAX} characters)"))
        if not lines[j].lstrip().startswith("$"):  # a comment line between the parts
            name += lines[j].strip()
    name, after = name.split("'", 1)
    if after.split("$")[0].strip():
        raise InputError(f"{where}: INCLUDE '{_short(name)}' is followed by "
                         f"{_short(after.strip())!r}: a name pieced from several quoted and "
                         f"unquoted parts is not read; write it in one pair of quotes")
    return name.strip(), j + 1


def _short(text: str, n: int = 60) -> str:
    """``text`` cut to ``n`` characters for a message."""
    return text if len(text) <= n else text[:n] + "..."


def _refuse_foreign(name: str, where: str) -> None:
    """A name that cannot be opened here whatever the folder: refused, saying why."""
    symbol = _SYMBOL.match(name)
    if symbol:
        raise InputError(f"{where}: INCLUDE {name}: {symbol.group(1)} is a logical symbol "
                         f"(MSC's SYMBOL:filename, set in the nastran command or its rc "
                         f"file, not in the deck); write the path instead")
    why = None
    if os.name == "nt":  # Windows names: they may exist here
        return
    if name.startswith("\\\\"):
        why = "a Windows network path"
    elif _DRIVE.match(name):
        why = f"a Windows absolute path (drive {name[:2]})"
    elif name.startswith("\\"):
        why = "a Windows path from the root of the current drive"
    if why:
        raise InputError(f"{where}: INCLUDE {name}: {why}, which does not exist on this "
                         f"system; copy the file beside the deck and name it relatively")


def local_name(name: str) -> str:
    r"""An INCLUDE name with Windows' separators (``..\se0.dat``) as this system's ``/``.

    >>> local_name("..\\mesh\\se0.dat")
    '../mesh/se0.dat'
    """
    return name.replace("\\", "/")


def _case_twin(folder: Path, name: str) -> Path | None:
    """A file that ``folder / name`` names up to letter case, if one exists."""
    here = folder
    for part in Path(name).parts:
        if part in (".", ".."):
            here = here / part
            continue
        try:
            match = [e for e in os.scandir(here) if e.name.lower() == part.lower()]
        except OSError:
            return None
        if len(match) != 1:
            return None
        here = here / match[0].name
    return here if here.is_file() else None


def expand(path: Path, out: list[str], origin: list[tuple[str, int]], stack: tuple,
           included: list | None = None) -> None:
    """Append ``path``'s lines to ``out`` with every INCLUDE replaced by its file's lines
    (relative to ``path``'s directory, else to the main deck's, ``stack[0]``);
    ``origin[i]`` is where ``out[i]`` came from, and ``included`` collects the files included."""
    if path.exists() and not path.is_file():  # a directory, /dev/zero, a pipe: unbounded
        raise InputError(f"cannot read {path}: not a regular file")
    lines = read_lines(path)
    i = 0
    while i < len(lines):
        # the main deck's own lines as "line N" (the reader prefixes its name), as cards
        where = f"line {i + 1}" if path == stack[0] else f"{path.name}:{i + 1}"
        found_name = include_name(lines, i, where)
        if found_name is None:
            out.append(lines[i])
            origin.append((path.name, i + 1))
            i += 1
            continue
        name, i = found_name
        if not name:
            raise InputError(f"{where}: INCLUDE without a file name")
        _refuse_foreign(name, where)
        target = _resolve(name, path, stack, where)
        if included is not None:
            included.append(target)
        expand(target, out, origin, (*stack, target), included)


def _resolve(name: str, path: Path, stack: tuple, where: str) -> Path:
    """The file an INCLUDE ``name`` in ``path`` reads, checked."""
    local = local_name(name)  # written on Windows
    folders = list(dict.fromkeys((path.parent, stack[0].parent)))
    try:
        found = list(dict.fromkeys((f / local).resolve() for f in folders
                                   if (f / local).is_file()))
        target = found[0] if found else (path.parent / local).resolve()
    except (OSError, RuntimeError, ValueError) as exc:  # a symlink loop, a NUL byte
        raise InputError(f"{where}: INCLUDE {name!r} cannot be opened: {exc}") from None
    if len(found) > 1 and not _same_content(found[0], found[1]):
        # two different files answer the name: which one NASTRAN takes depends on
        # its version (the including file's folder, or the job's), so say which
        warnings.warn(f"{where}: INCLUDE {name} names two different files, {found[0]} "
                      f"(beside {path.name}: read) and {found[1]} (beside the main deck)",
                      EigenupdateWarning, stacklevel=3)
    if target in stack:
        raise InputError(f"{where}: INCLUDE {name} includes itself")
    if len(stack) > MAX_INCLUDE_DEPTH:
        raise InputError(f"{where}: INCLUDE {name}: more than {MAX_INCLUDE_DEPTH} nested "
                         f"INCLUDE levels")
    if target.exists() and not target.is_file():  # was "not found" for /dev/zero
        raise InputError(f"{where}: INCLUDE {name} is not a regular file (a directory, "
                         f"device or FIFO)")
    if not target.is_file():
        twins = [t for t in (_case_twin(f, local) for f in folders) if t is not None]
        if twins:
            raise InputError(f"{where}: INCLUDE file {name} not found; {twins[0]} differs "
                             f"from it in letter case only (Windows ignores case, this "
                             f"system does not): make the names agree")
        raise InputError(f"{where}: INCLUDE file {name} not found (looked in "
                         f"{' and '.join(str(f) for f in folders)})")
    return target


def _same_content(a: Path, b: Path) -> bool:
    """Whether two files hold the same bytes: sizes first, then in chunks (bounded
    memory: the second file is never read whole)."""
    try:
        return filecmp.cmp(a, b, shallow=False)
    except OSError:
        return False
