"""Fuzz the command line with seeded mutations of the shipped examples.

Every case copies one scenario (the paper's Fig. 2 system, the paper's beam, the FRF
example reduced to its bare structure with binary and ASCII UFF 58, the Fig. 2 system as
Matrix Market files) into a fresh directory, mutates one of its files (numbers replaced
by hostile values, lines deleted, swapped or repeated, huge fields, flipped bytes,
truncation), sometimes puts files where the outputs go, runs one command in-process
through ``eigenupdate.cli.main`` and checks the invariant:

* exit status 0, 1 or 2, never an exception (a traceback);
* exit 1 only for an update that did not converge;
* exit 2 with one error line on stderr that names the file or option (progress lines of
  ``extract`` aside), at most ``MAX_LINE`` characters;
* no NaN or inf in any output of a run with exit 0 (stdout and the files written);
* no file of the case changed, and none created, by a failed run (exit 1 may create its
  ``--save`` result); a successful run changes only its own outputs.

Usage: ``python tools/fuzz.py --cases 10000 [--seed 0] [--keep DIR]``; prints the count
of each class of outcome. ``tests/test_fuzz.py`` runs a few hundred cases.
"""

from __future__ import annotations

import argparse
import contextlib
import faulthandler
import hashlib
import io
import random
import re
import resource
import shutil
import signal
import struct
import sys
import tempfile
import time
import traceback
import warnings
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"
MAX_LINE = 500
TIMEOUT_S = 60

HOSTILE = ["0", "-1", "1e300", "-1e300", "5e-324", "nan", "inf", "-inf", "1e9", "100000",
           "true", "1_000", "\u0661\u0662", "0x10", '""', "1e-300", "2", "3", "1", "4",
           "999999999999", "0.0", "[]", "[true, 2]", "1e308", "-0", "1e15", "2.5"]
NUMBER = re.compile(rb"-?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?")
PROGRESS = re.compile(r"^(\[\d+/\d+\] |  warning: |wrote )")
ERROR = re.compile(r"^eigenupdate( [a-z-]+)?: error: ")  # subcommand usage errors name it
NAN = re.compile(r"\b(nan|inf|infinity)\b", re.IGNORECASE)


# ---------------------------------------------------------------- scenarios

def _fig2(d: Path) -> None:
    for name in ("study.toml", "truth.toml", "measured.csv"):
        shutil.copy(EXAMPLES / "paper_fig2" / name, d / name)


def _beam(d: Path) -> None:
    for name in ("study.toml", "measured.csv"):
        shutil.copy(EXAMPLES / "paper_beam" / name, d / name)


def _frf(d: Path) -> None:
    """The FRF example with only the bare structure: one binary and one ASCII UFF 58."""
    from eigenupdate.io.uff import read_frfs, write_frfs

    text = (EXAMPLES / "paper_beam_frf" / "study.toml").read_text(encoding="utf-8")
    text = re.sub(r"\[\[perturbation\]\].*?(?=\[measurement\])", "", text, flags=re.S)
    text = re.sub(r"\[measurement\.frf\].*", "", text, flags=re.S)
    text += '[measurement.frf]\n"base" = "base.uff"\n'
    (d / "study.toml").write_text(text, encoding="utf-8")
    (d / "ascii.toml").write_text(text.replace("base.uff", "ascii.uff"), encoding="utf-8")
    shutil.copy(EXAMPLES / "paper_beam_frf" / "frf" / "base.uff", d / "base.uff")
    write_frfs(d / "ascii.uff", read_frfs(d / "base.uff"), binary=False)


def _mtx(d: Path) -> None:
    """The Fig. 2 initial model as Matrix Market files (K0 as a dense array)."""
    import numpy as np
    import scipy.io
    import scipy.sparse as sp

    from eigenupdate.io.study import load_study

    study = load_study(EXAMPLES / "paper_fig2" / "study.toml")
    model = study.model
    scipy.io.mmwrite(d / "K0.mtx", np.zeros((model.n, model.n)))
    scipy.io.mmwrite(d / "M0.mtx", sp.coo_matrix((model.n, model.n)))
    text = ['title = "Fig. 2 from matrices"\n[model]\ntype = "matrices"\nK0 = "K0.mtx"\n'
            'M0 = "M0.mtx"\n']
    for p, kt, mt in zip(model.parameters, model.k_terms, model.m_terms, strict=True):
        key, mat = ("K", kt) if kt is not None else ("M", mt)
        scipy.io.mmwrite(d / f"{p.name}.mtx", sp.coo_matrix(mat))
        text.append(f'[[model.parameter]]\nname = "{p.name}"\nvalue = {p.value!r}\n'
                    f'{key} = "{p.name}.mtx"\n')
    fig2 = (EXAMPLES / "paper_fig2" / "study.toml").read_text(encoding="utf-8")
    text.append(fig2[fig2.index("[[perturbation]]"):])
    (d / "study.toml").write_text("".join(text), encoding="utf-8")
    shutil.copy(EXAMPLES / "paper_fig2" / "measured.csv", d / "measured.csv")


# (command arguments, outputs it may write); {d} is the case directory
SCENARIOS = {
    "fig2": (_fig2, ["study.toml", "truth.toml", "measured.csv"], [
        (["frequencies", "{d}/study.toml"], []),
        (["frequencies", "{d}/truth.toml", "--json"], []),
        (["frequencies", "{d}/study.toml", "--modes", "4"], []),
        (["check", "{d}/study.toml"], []),
        (["update", "{d}/study.toml", "--json"], []),
        (["update", "{d}/study.toml", "--save", "{d}/result.json"], ["result.json"]),
        (["update", "{d}/study.toml", "--save", "{d}/measured.csv"], ["measured.csv"]),
        (["simulate", "{d}/truth.toml", "-o", "{d}/sim.csv"], ["sim.csv"]),
        (["simulate", "{d}/study.toml", "-o", "{d}/study.toml"], ["study.toml"]),
        (["simulate", "{d}/truth.toml", "-o", "{d}/sim.csv", "--noise-hz", "{x}"], ["sim.csv"]),
    ]),
    "beam": (_beam, ["study.toml", "measured.csv"], [
        (["frequencies", "{d}/study.toml"], []),
        (["check", "{d}/study.toml"], []),
        (["update", "{d}/study.toml", "--save", "{d}/result.json"], ["result.json"]),
        (["simulate", "{d}/study.toml", "-o", "{d}/sim.csv"], ["sim.csv"]),
    ]),
    "frf": (_frf, ["study.toml", "base.uff", "ascii.uff"], [
        (["extract", "{d}/study.toml", "-o", "{d}/x.csv", "--uff55", "{d}/m.uff"],
         ["x.csv", "m.uff"]),
        (["extract", "{d}/ascii.toml", "-o", "{d}/x.csv"], ["x.csv"]),
    ]),
    "mtx": (_mtx, ["study.toml", "K0.mtx", "M0.mtx", "k1.mtx", "m2.mtx", "measured.csv"], [
        (["frequencies", "{d}/study.toml"], []),
        (["check", "{d}/study.toml"], []),
        (["update", "{d}/study.toml"], []),
    ]),
}


# ---------------------------------------------------------------- mutations

def _lines(data: bytes) -> list[bytes]:
    return data.splitlines(keepends=True) or [b""]


def mutate_text(data: bytes, rng: random.Random) -> bytes:
    kind = rng.choice(["number", "number", "number", "delete", "duplicate", "swap",
                       "swap_numbers", "long", "insert", "truncate"])
    if kind in ("number", "swap_numbers"):
        hits = list(NUMBER.finditer(data))
        if not hits:
            return data + b"\x00"
        a = rng.choice(hits)
        if kind == "number":
            new = rng.choice(HOSTILE).encode()
            return data[:a.start()] + new + data[a.end():]
        b = rng.choice(hits)
        if a.start() > b.start():
            a, b = b, a
        if a.end() > b.start():
            return data
        return (data[:a.start()] + b.group() + data[a.end():b.start()] + a.group()
                + data[b.end():])
    lines = _lines(data)
    i = rng.randrange(len(lines))
    if kind == "delete":
        del lines[i]
    elif kind == "duplicate":
        lines.insert(i, lines[i])
    elif kind == "swap":
        j = rng.randrange(len(lines))
        lines[i], lines[j] = lines[j], lines[i]
    elif kind == "long":
        pos = rng.randrange(len(data) + 1)
        filler = rng.choice([b"x", b"9", b"\n", b",", b"\xff"]) * rng.choice([200, 140_000])
        return data[:pos] + filler + data[pos:]
    elif kind == "insert":
        pos = rng.randrange(len(data) + 1)
        junk = bytes(rng.randrange(256) for _ in range(rng.randint(1, 8)))
        return data[:pos] + junk + data[pos:]
    else:
        return data[:rng.randrange(len(data) + 1)]
    return b"".join(lines)


def mutate_binary(data: bytes, rng: random.Random) -> bytes:
    kind = rng.choice(["flip", "flip", "double", "double", "truncate", "header"])
    buf = bytearray(data)
    if kind == "flip":
        for _ in range(rng.randint(1, 20)):
            buf[rng.randrange(len(buf))] = rng.randrange(256)
    elif kind == "double":
        value = rng.choice([1e308, -1e308, float("nan"), float("inf"), 5e-324, 0.0, 1e300])
        for _ in range(rng.randint(1, 50)):
            pos = rng.randrange(0, len(buf) - 8)
            buf[pos:pos + 8] = struct.pack("<d", value)
    elif kind == "header":  # the text records before the binary block
        head = bytes(buf[:800])
        return mutate_text(head, rng) + bytes(buf[800:])
    else:
        del buf[rng.randrange(len(buf)):]
    return bytes(buf)


def mutate(path: Path, rng: random.Random) -> str:
    data = path.read_bytes()
    for _ in range(rng.choice([1, 1, 1, 2, 3])):
        binary = path.suffix == ".uff" and path.name == "base.uff"
        data = mutate_binary(data, rng) if binary else mutate_text(data, rng)
    path.write_bytes(data)
    return path.name


# ---------------------------------------------------------------- one case

class _Timeout(Exception):
    pass


def _alarm(signum, frame):
    raise _Timeout


def _snapshot(d: Path) -> dict[str, str]:
    return {str(p.relative_to(d)): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(d.rglob("*")) if p.is_file()}


def _strings(path: Path) -> list[str]:
    """The strings of a TOML file that contain 'nan' or 'inf', longest first: a run
    echoes them (titles, configuration names), it did not compute them."""
    import tomllib

    try:
        data = tomllib.loads(path.read_text(encoding="utf-8-sig"))
    except (OSError, ValueError):
        return []
    out, todo = [], [data]
    while todo:
        x = todo.pop()
        if isinstance(x, dict):
            todo += list(x.values())
        elif isinstance(x, list):
            todo += x
        elif isinstance(x, str) and NAN.search(x):  # only these could look like a NaN
            out.append(x)
    return sorted(set(out), key=len, reverse=True)


def run_case(seed: int, index: int, base: Path, cache: dict[str, Path]) -> tuple[str, str]:
    """Run case ``index`` of ``seed`` in a fresh directory under ``base``.

    Returns (class, detail): class is ``exit 0``, ``exit 1 (not converged)``,
    ``exit 2 (input error)`` or a violation of the invariant.
    """
    from eigenupdate.cli import main

    rng = random.Random(f"{seed}:{index}")
    name = rng.choice(sorted(SCENARIOS))
    make, files, commands = SCENARIOS[name]
    if name not in cache:
        cache[name] = base / f"seed_{name}"
        cache[name].mkdir()
        make(cache[name])
    d = base / f"case_{index}"
    shutil.copytree(cache[name], d)
    target = mutate(d / rng.choice(files), rng) if rng.random() < 0.9 else "(none)"
    args, outputs = rng.choice(commands)
    x = rng.choice(HOSTILE)
    argv = [a.replace("{d}", str(d)).replace("{x}", x) for a in args]
    for out in outputs:
        if rng.random() < 0.5 and not (d / out).exists():
            (d / out).write_text("pre-existing\n", encoding="utf-8")
    before = _snapshot(d)
    stdout, stderr = io.StringIO(), io.StringIO()
    what = f"seed {seed} case {index}: {name}, mutated {target}, eigenupdate {' '.join(argv)}"
    old = signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(TIMEOUT_S)
    try:
        with (contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr),
              warnings.catch_warnings()):
            warnings.simplefilter("always")
            try:
                code = main(argv)
            except SystemExit as exc:  # argparse usage errors
                code = exc.code
    except _Timeout:
        return "timeout", what
    except BaseException:
        return "traceback", what + "\n" + traceback.format_exc(limit=-3)
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)
    after = _snapshot(d)
    changed = sorted(k for k in set(before) | set(after) if before.get(k) != after.get(k))
    out, err = stdout.getvalue(), stderr.getvalue()
    err_lines = [ln for ln in err.splitlines() if not PROGRESS.match(ln)]
    if code not in (0, 1, 2):
        return "bad exit status", f"{what}: {code!r}"
    if code == 2:
        if len(err_lines) != 1 or not ERROR.match(err_lines[0]):
            return "exit 2 not one line", f"{what}\n{err[:2000]}"
        line = err_lines[0]
        if len(line) > MAX_LINE:
            return "exit 2 line too long", f"{what}: {len(line)} characters"
        if str(d) not in line and not re.search(r"(^|\s)-", line):
            return "exit 2 names no file", f"{what}\n{line}"
    if code == 1:
        if argv[0] != "update" or "not converged" not in err:
            return "exit 1 not non-convergence", f"{what}\n{err[:2000]}"
        allowed = [o for o in outputs if o not in before]  # only a new --save result
        if any(c not in allowed for c in changed):
            return "clobbered", f"{what}: {changed}"
        return "exit 1 (not converged)", what
    if code == 2:
        if changed:
            return "clobbered", f"{what}: {changed}"
        return "exit 2 (input error)", what
    if any(c not in outputs for c in changed):
        return "clobbered", f"{what}: {changed}"
    texts = [out] + [(d / c).read_text(encoding="utf-8", errors="replace") for c in changed
                     if (d / c).exists()]
    # a mutated title or configuration name may itself say "inf": echoed, not computed
    for s in _strings(Path(argv[1])) if len(argv) > 1 else []:
        texts = [t.replace(s, "") for t in texts]
    if any(NAN.search(t) for t in texts):
        return "NaN in output", what
    if err_lines and argv[0] not in ("simulate",):
        return "exit 0 with messages", f"{what}\n{err[:2000]}"
    return "exit 0", what


EXPECTED = ("exit 0", "exit 1 (not converged)", "exit 2 (input error)")


def run(cases: int, seed: int = 0, keep: Path | None = None, progress: bool = False,
        first: int = 0) -> tuple[Counter, dict[str, list[str]]]:
    """Run cases ``first`` to ``first + cases - 1``; returns the count of each class and
    the details of violations."""
    counts: Counter = Counter()
    examples: dict[str, list[str]] = {}
    with tempfile.TemporaryDirectory(prefix="eigenupdate-fuzz-") as tmp:
        base, cache = Path(tmp), {}
        start = time.monotonic()
        for i in range(first, first + cases):
            if progress == "each":
                print(f"case {i}", file=sys.stderr, flush=True)
            cls, detail = run_case(seed, i, base, cache)
            counts[cls] += 1
            if cls not in EXPECTED:
                examples.setdefault(cls, []).append(detail)
                if keep is not None:
                    shutil.copytree(base / f"case_{i}", keep / f"case_{i}", dirs_exist_ok=True)
            shutil.rmtree(base / f"case_{i}")
            if progress and (i + 1 - first) % 100 == 0:
                print(f"{i + 1 - first} cases, {time.monotonic() - start:.0f} s: {dict(counts)}",
                      file=sys.stderr, flush=True)
    return counts, examples


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--cases", type=int, default=1000)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--keep", type=Path, help="copy the directory of every violating case here")
    p.add_argument("--first", type=int, default=0, help="number of the first case")
    p.add_argument("--verbose", action="store_true", help="print every case number first")
    args = p.parse_args(argv)
    faulthandler.enable()  # a crash in compiled code still says where
    # a case that tries to allocate tens of GiB fails here instead of swapping the machine
    resource.setrlimit(resource.RLIMIT_AS, (8 << 30, resource.RLIM_INFINITY))
    if args.keep:
        args.keep.mkdir(parents=True, exist_ok=True)
    start = time.monotonic()
    counts, examples = run(args.cases, args.seed, args.keep,
                           progress="each" if args.verbose else True, first=args.first)
    print(f"{args.cases} cases from {args.first}, seed {args.seed}, "
          f"{time.monotonic() - start:.0f} s")
    for cls in (*EXPECTED, *sorted(set(counts) - set(EXPECTED))):
        print(f"  {cls:28s} {counts.get(cls, 0)}")
    for cls, details in examples.items():
        print(f"\n{cls}: {len(details)} case(s), first ones:")
        for detail in details[:3]:
            print("  " + detail.replace("\n", "\n    "))
    return 1 if examples else 0


if __name__ == "__main__":
    sys.exit(main())
