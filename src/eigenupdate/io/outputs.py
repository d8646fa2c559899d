"""Where a run may write, decided before the run does any work.

An output is a regular file (or, for ``-o DIR``, a directory) that is none of the run's
inputs, whatever links lead to it: a FIFO, a device such as /dev/null, a directory given
for a file, a symbolic link loop or a dangling link are refused, and so is an output that
is (after links, or as a hard link) the study, a model, measurement, FRF or result file
the run reads. The directory that will receive the file is probed by creating and
removing a file there, so a read-only directory or a name too long for the file system is
reported by its own name before the work starts, never by the temporary file's.
"""

from __future__ import annotations

import contextlib
import errno
import os
import stat
from collections.abc import Iterable, Mapping
from pathlib import Path

from eigenupdate.errors import InputError
from eigenupdate.io.atomic import temporary_name

PathLike = str | os.PathLike


def _error(path: PathLike, flag: str, message: str) -> InputError:
    return InputError(message, source=str(path), field=flag)


def _target(path: PathLike, flag: str) -> os.stat_result | None:
    """stat of what ``path`` leads to after links; None if nothing is there."""
    p = os.fspath(path)
    try:
        return os.stat(p)
    except FileNotFoundError:
        if os.path.islink(p):
            raise _error(path, flag, f"is a dangling symbolic link (to {os.readlink(p)!r}); "
                                     f"remove it or give another name") from None
        return None
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            raise _error(path, flag, "is a symbolic link loop") from None
        if exc.errno == errno.ENAMETOOLONG:
            raise _error(path, flag, "the name is too long for the file system") from None
        if exc.errno == errno.ENOTDIR:
            raise _error(path, flag, "a part of the path is not a directory") from None
        raise _error(path, flag, exc.strerror or str(exc)) from None


def _probe(directory: Path, name: str, flag: str, shown: PathLike) -> None:
    """Create and remove a file of the temporary name's length in ``directory``."""
    if not directory.is_dir():
        raise _error(shown, flag, f"directory {str(directory)!r} does not exist")
    tmp = directory / temporary_name(name)
    try:
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    except OSError as exc:
        if exc.errno == errno.ENAMETOOLONG:
            raise _error(shown, flag, "the file name is too long for the file system") from None
        raise _error(shown, flag, f"cannot create a file in directory {str(directory)!r}: "
                                  f"{exc.strerror or exc}") from None
    os.close(fd)
    os.unlink(tmp)
    try:
        limit = os.pathconf(directory, "PC_NAME_MAX")
    except (OSError, ValueError):
        limit = 255
    if len(os.fsencode(name)) > limit:
        raise _error(shown, flag, f"the file name has {len(os.fsencode(name))} bytes; this "
                                  f"file system allows {limit}")


def check_file(path: PathLike | None, flag: str) -> None:
    """Refuse an output file that cannot be written as a regular file (see the module)."""
    if path is None:
        return
    if not os.fspath(path):
        raise _error(path, flag, "is empty; give a file name")
    st = _target(path, flag)
    real = Path(os.path.realpath(path))
    if st is not None and stat.S_ISDIR(st.st_mode):
        raise _error(path, flag, "is a directory; give a file name")
    if st is not None and not stat.S_ISREG(st.st_mode):
        raise _error(path, flag, "is not a regular file (a FIFO, device or socket); outputs "
                                 "are written only to regular files")
    _probe(real.parent, real.name, flag, path)


def check_dir(path: PathLike | None, flag: str) -> None:
    """Refuse an output directory that is something else or cannot receive files."""
    if path is None:
        return
    if not os.fspath(path):
        raise _error(path, flag, "is empty; give a directory name")
    st = _target(path, flag)
    real = Path(os.path.realpath(path))
    if st is None:
        _probe(real.parent, real.name, flag, path)
    elif not stat.S_ISDIR(st.st_mode):
        raise _error(path, flag, "exists and is not a directory")
    else:
        _probe(real, "x", flag, path)


def _identity(path: PathLike) -> tuple[int, int] | str:
    try:
        st = os.stat(path)
        return (st.st_dev, st.st_ino)  # a hard link is the same file
    except OSError:
        return os.path.normcase(os.path.realpath(path))


def check_not_inputs(outputs: Mapping[str, PathLike | None],
                     inputs: Iterable[PathLike]) -> None:
    """Refuse an output that is an input of the same run, or two outputs in one file.

    ``outputs`` maps the option (``-o``) to its path; links, hard links and relative
    spellings of one file are recognised.
    """
    seen = {_identity(p): "an input of this run" for p in inputs}
    for flag, path in outputs.items():
        if path is None:
            continue
        key = _identity(path)
        what = seen.get(key)
        if what is not None:
            raise _error(path, flag, f"is {what}; choose another output file")
        seen[key] = f"also the output of {flag}"
        # a new file is recognised by name only: two outputs with one new name
        seen.setdefault(os.path.normcase(os.path.realpath(path)), f"also the output of {flag}")


def check_files_in(directory: PathLike, names: Iterable[str], flag: str,
                   inputs: Iterable[PathLike], own: Mapping[str, str | bytes] | None = None,
                   force: bool = False) -> None:
    """The files a run writes into an output directory: regular files, none an input,
    and, if ``own`` (by name) is given, each replaced only as :func:`check_outputs` says."""
    paths = {f"{flag} {n}": Path(directory) / n for n in names}
    if Path(directory).is_dir():
        for f, p in paths.items():
            check_file(p, f)
    check_not_inputs(paths, inputs)
    for n in names if own is not None else ():
        check_replaceable(Path(directory) / n, f"{flag} {n}", own[n], force)


def check_no_replaced(directory: PathLike, names: Iterable[str], flag: str) -> None:
    """Refuse an output directory that already holds files of these names."""
    there = [n for n in names if os.path.lexists(Path(directory) / n)]
    if there:
        shown = ", ".join(there[:3]) + (f" and {len(there) - 3} more" if len(there) > 3 else "")
        raise _error(directory, flag, f"already holds {shown}, which this run would replace "
                                      f"(measured FRFs of a test?); give a new or empty "
                                      f"directory, or --force to replace them")


def schema_marker(schema: str) -> bytes:
    """What a JSON document of ``schema`` (e.g. ``eigenupdate.update/2``) holds whatever
    its version: the marker of its writer's earlier output (:func:`check_replaceable`)."""
    return f'"schema": "{schema.rsplit("/", 1)[0]}/'.encode()


def _is_own(path: PathLike, own: str | bytes) -> bool:
    try:
        with open(path, "rb") as f:
            head = f.read(_SEEN)
            if isinstance(own, str):
                return head.decode("utf-8", "replace").startswith(own)
            f.seek(max(0, os.fstat(f.fileno()).st_size - _SEEN))
            return own in head or own in f.read(_SEEN)
    except OSError:
        return False


_SEEN = 8192  # bytes read at each end: a PDF's Creator is in its trailer


def check_replaceable(path: PathLike | None, flag: str, own: str | bytes, force: bool) -> None:
    """Refuse an existing ``path`` that is not an earlier output of ``flag`` unless
    ``force``: its first line starts with ``own`` (a str: a signature line) or its first or
    last 8 KiB hold ``own`` (bytes: a JSON schema, a figure's Creator). An earlier output
    of the option is replaced; another study's deck, plan or measurements are not."""
    if path is None or force or not os.path.lexists(path) or _is_own(path, own):
        return
    what = (f"its first line is not {own!r}..." if isinstance(own, str)
            else f"it holds no {own.decode()!r}")
    raise _error(path, flag, f"exists and is not an earlier output of {flag} ({what}): give "
                             f"a new name, or --force to replace it")


def write_stdout(text: str, out) -> str | None:
    """Write a command's held standard output to ``out`` (``sys.stdout`` as it was);
    None if written, else why not (closed, broken pipe), after pointing the descriptor at
    /dev/null so that the interpreter's own flush at exit raises nothing more."""
    if not text:
        return None
    try:
        if out is None:  # started with stdout closed
            raise BrokenPipeError(errno.EBADF, "standard output is closed")
        out.write(text)
        out.flush()
    except (OSError, ValueError) as exc:
        with contextlib.suppress(OSError, ValueError, AttributeError):  # none at exit
            os.dup2(os.open(os.devnull, os.O_WRONLY), out.fileno())
        return exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
    return None


def check_outputs(outputs: Mapping[str, PathLike | None], inputs: Iterable[PathLike],
                  own: Mapping[str, str | bytes], force: bool = False) -> None:
    """The rule of every command's output files, checked before any work: each (by flag)
    is a regular file that can be written, none is among the run's ``inputs`` (--force
    or not), and one that exists is replaced only if it is the flag's own earlier output
    (``own[flag]``, see :func:`check_replaceable`) or with ``force``."""
    for flag, path in outputs.items():
        check_file(path, flag)
    check_not_inputs(outputs, inputs)
    for flag, path in outputs.items():
        check_replaceable(path, flag, own[flag], force)
