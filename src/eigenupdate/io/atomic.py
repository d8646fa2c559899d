"""Outputs are written whole or not at all: a temporary file in the target's directory,
then a rename over the target.

Inside :func:`transaction` the renames are deferred: every output of a run is written to
its temporary file first and all are renamed only when the run has succeeded, so a run
that fails leaves every pre-existing file as it was. The renames of one transaction are
all or none: each replaced file is kept under a hard link until every rename has
succeeded, and put back if one fails.
"""

from __future__ import annotations

import contextlib
import contextvars
import errno
import os
import secrets
import shutil
from collections.abc import Callable, Iterator
from pathlib import Path

PathLike = str | os.PathLike

_PENDING: contextvars.ContextVar[list[tuple[Path, Path]] | None] = contextvars.ContextVar(
    "eigenupdate_pending_outputs", default=None)
_MADE: contextvars.ContextVar[list[Path] | None] = contextvars.ContextVar(
    "eigenupdate_made_directories", default=None)


def make_dir(path: PathLike) -> None:
    """``mkdir -p path``; inside a :func:`transaction` the directories it creates are
    removed again (if still empty) when the run fails."""
    target = Path(path)
    missing = [p for p in (target, *target.parents) if not p.exists()]
    try:
        target.mkdir(parents=True, exist_ok=True)
    finally:  # those made before a failure are removed too
        made = _MADE.get()
        if made is not None:
            made.extend(p for p in reversed(missing) if p.is_dir())  # parents first


def _unlink(path: Path) -> None:
    with contextlib.suppress(OSError):
        os.unlink(path)


def temporary_name(name: str) -> str:
    """A hidden, unique name in the directory of ``name``, no longer than the file
    system allows however long ``name`` is (the suffix is kept for writers that go by
    it)."""
    suffix = Path(name).suffix[:16]
    return f".{name[:40]}.{secrets.token_hex(6)}.tmp{suffix}"


def atomic_write(path: PathLike, write: Callable[[str], None]) -> None:
    """Create ``path`` atomically: ``write(tmp)`` fills a temporary file, then it is renamed.

    The temporary file is created empty (honouring the umask) in the directory of
    ``path`` with the same suffix (so writers that go by the extension work), passed to
    ``write`` by name, flushed to disk and moved over ``path`` with :func:`os.replace`,
    at once or, inside :func:`transaction`, when the transaction commits. On any error
    the temporary file is removed and ``path`` is left untouched.

    Parameters
    ----------
    path : str or path-like
        Destination file.
    write : callable
        Called with the temporary file name; must write the complete content.
    """
    # through a link, the file it leads to is replaced, never the link by a file
    target = Path(os.path.realpath(path)) if os.path.islink(path) else Path(path)
    if target.exists() and not target.is_file():  # the CLI refuses these before any work
        raise IsADirectoryError(errno.EISDIR if target.is_dir() else errno.EPERM,
                                "not a regular file; outputs are only regular files",
                                str(path))
    tmp = target.with_name(temporary_name(target.name))
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
    os.close(fd)
    try:
        write(str(tmp))
        with open(tmp, "rb+") as fh:
            os.fsync(fh.fileno())
        pending = _PENDING.get()
        if pending is None:
            os.replace(tmp, target)
        else:
            pending.append((tmp, target))
    except BaseException:
        _unlink(tmp)
        raise


@contextlib.contextmanager
def transaction() -> Iterator[None]:
    """Defer the renames of :func:`atomic_write` to the end of the block.

    If the block raises, every temporary file is removed and no target is touched;
    otherwise all targets are replaced, in the order they were written.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> write_text(d / "a.txt", "old")
    >>> try:
    ...     with transaction():
    ...         write_text(d / "a.txt", "new")
    ...         raise ValueError("the second output failed")
    ... except ValueError:
    ...     pass
    >>> (d / "a.txt").read_text(), sorted(p.name for p in d.iterdir())
    ('old', ['a.txt'])
    """
    outer, outer_made = _PENDING.get(), _MADE.get()
    pending: list[tuple[Path, Path]] = []
    made: list[Path] = []
    token, made_token = _PENDING.set(pending), _MADE.set(made)
    try:
        yield
    except BaseException:
        for tmp, _ in pending:
            _unlink(tmp)
        for d in reversed(made):  # children first; a directory with other files stays
            with contextlib.suppress(OSError):
                os.rmdir(d)
        raise
    finally:
        _PENDING.reset(token)
        _MADE.reset(made_token)
    if outer is not None:  # nested: the outermost transaction commits
        outer.extend(pending)
        if outer_made is not None:
            outer_made.extend(made)
        return
    _commit(pending)


def _commit(pending: list[tuple[Path, Path]]) -> None:
    """Rename every temporary file over its target, all or none."""
    kept: dict[Path, Path | None] = {}  # target -> hard link to its old content, or None
    done: list[Path] = []
    try:
        for _, target in pending:
            if target not in kept:
                old = None
                if target.exists():
                    old = target.with_name(temporary_name(target.name))
                    try:
                        os.link(target, old)
                    except OSError:  # a file system without hard links
                        shutil.copy2(target, old)
                kept[target] = old
        for tmp, target in pending:
            os.replace(tmp, target)
            done.append(target)
    except BaseException:
        for target in reversed(done):
            old = kept.get(target)
            with contextlib.suppress(OSError):
                if old is None:
                    os.unlink(target)
                else:
                    os.replace(old, target)
        for tmp, _ in pending:
            _unlink(tmp)
        for old in kept.values():
            if old is not None:
                _unlink(old)
        raise
    for old in kept.values():
        if old is not None:
            _unlink(old)


@contextlib.contextmanager
def scratch() -> Iterator[None]:
    """Write at once inside a :func:`transaction`: for scratch files the run reads back
    itself (a figure rendered to a temporary file), never for outputs."""
    token = _PENDING.set(None)
    try:
        yield
    finally:
        _PENDING.reset(token)


def write_text(path: PathLike, text: str) -> None:
    """Write a text file atomically."""

    def write(tmp: str) -> None:
        with open(tmp, "w", encoding="utf-8", newline="") as fh:
            fh.write(text)

    atomic_write(path, write)
