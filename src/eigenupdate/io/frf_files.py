"""FRFs of several files, each read by the reader of its format."""

from __future__ import annotations

import hashlib
from collections.abc import Mapping, Sequence
from pathlib import Path

from eigenupdate.errors import InputError
from eigenupdate.io.frf_csv import read_frf_csv
from eigenupdate.io.inputs import require_regular
from eigenupdate.io.uff import read_frfs
from eigenupdate.io.uff._pyuff import PathLike
from eigenupdate.measure.frf import FRF, dof_label
from eigenupdate.model.configurations import Configuration


def read_frf_files(
    paths: Sequence[PathLike], kinds: Sequence[str | None] | None = None
) -> list[FRF]:
    """FRFs of several files: ``.csv`` files by :func:`eigenupdate.io.frf_csv.read_frf_csv`
    (one receptance each), anything else as a universal file (:func:`read_frfs`, with
    ``kinds[i]`` as the ``default_kind`` of file ``i``)."""
    out: list[FRF] = []
    for i, p in enumerate(paths):
        kind = None if kinds is None else kinds[i]
        if str(p).lower().endswith(".csv"):
            if kind not in (None, "receptance"):  # the CSV format holds receptance only
                raise InputError(f"an FRF CSV holds receptance (m/N); kind {kind!r} applies "
                                 f"to universal files", source=str(p), field="kind")
            out.append(read_frf_csv(p))
        else:
            out += read_frfs(p, default_kind=kind)
    seen: dict[bytes, FRF] = {}
    for f in out:  # a file concatenated to itself: the std shrank by sqrt(2), silently
        key = hashlib.sha256(f.frequency_hz.tobytes() + f.receptance.tobytes()).digest()
        first = seen.setdefault(key, f)
        if first is not f:
            raise InputError(f"FRF {dof_label(f.response)}/{dof_label(f.reference)} is given "
                             f"twice with the same "
                             f"values (also in {Path(first.source).name}): a copied "
                             f"dataset would count as two measurements", source=f.source)
    return out


def require_distinct(files: Mapping[str, Sequence[PathLike]], source: str | None = None
                     ) -> None:
    """InputError if one file's bytes are given twice (two configurations, or twice in
    one): the study's '0.2 kg at 1' named the bare structure's file by a slip, and
    `extract` gave it the bare structure's frequencies, numbered and accepted (a
    configuration that adds mass may equal the bare structure within interlacing); twice in
    one configuration its FRFs count double and its std shrinks by sqrt(2). Measured files
    of two tests never agree to the byte (their noise differs)."""
    seen: dict[bytes, tuple[str, PathLike]] = {}
    for config, paths in files.items():
        for p in paths:
            if not Path(p).is_file():  # /dev/zero, a directory: the reader refuses it unread
                continue
            require_regular(p, "FRF file")  # read whole to be hashed: a 10 GB one is not
            try:
                digest = hashlib.sha256(Path(p).read_bytes()).digest()
            except OSError:
                continue  # the reader names it
            first = seen.setdefault(digest, (config, p))
            if first != (config, p):
                where = ("twice for" if first[0] == config
                         else f"for {first[0]!r} (as {Path(first[1]).name}) and for")
                slip = " (a slip in [measurement.frf]?)" if source else ""
                raise InputError(f"{Path(p).name} holds the same FRFs {where} {config!r}: "
                                 f"one file per test{slip}",
                                 source=source or str(p),
                                 field=f"measurement.frf.{config}" if source else "inputs")


def frf_set_names(configurations: Sequence[Configuration], source: str | None = None
                  ) -> list[str]:
    """The file name of each configuration's FRFs in ``write_frf_sets``'s directory; two
    names that make one file ('0.35 kg at 1' and '0.35 kg at 1!') are refused: the second
    replaced the first's file in the same run."""
    from eigenupdate.io.extraction import safe_name

    out: dict[str, str] = {}
    for c in configurations:
        name = f"{safe_name(c.name)}.uff"
        if name in out:
            raise InputError(f"configurations {out[name]!r} and {c.name!r} would both be "
                             f"written to {name}; rename one", source=source,
                             field="-o")
        out[name] = c.name
    return list(out)


def write_frf_sets(directory: PathLike, sets: Sequence[tuple[Configuration, list[FRF]]],
                   binary: bool = False) -> list[str]:
    """Each configuration's FRFs as ``directory/<name>.uff`` (UFF 58, ``binary``: 58b);
    returns the study's ``[measurement.frf]`` table naming them."""
    from eigenupdate.io.atomic import make_dir
    from eigenupdate.io.extraction import safe_name
    from eigenupdate.io.uff import write_frfs

    out = Path(directory)
    make_dir(out)
    lines = ["[measurement.frf]"]
    for c, frfs in sets:
        name = f"{safe_name(c.name)}.uff"
        write_frfs(out / name, frfs, binary=binary)
        lines.append(f'"{c.name}" = "{out.name}/{name}"')
    return lines
