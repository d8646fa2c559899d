"""Fuzz the command line with seeded mutations of the shipped examples.

Every case copies one scenario (the paper's Fig. 2 system with a saved result, the
paper's beam, the FRF example reduced to its bare structure with binary and ASCII UFF 58,
the Fig. 2 system as Matrix Market files, and the NASTRAN frame where pyNastran is
installed) into a fresh directory, mutates one of its files (numbers replaced by hostile
values, lines deleted, swapped or repeated, huge fields, flipped bytes, truncation, and
resource attacks: nesting thousands deep, a Matrix Market header of 3e6 x 3e6, a beam of
10,001 nodes, ``additions = 2000000000``), sometimes puts files where the outputs go or
attacks an output path (a FIFO, a socket, a link or hard link to an input, a dangling link,
a link loop, a directory, a 249- or 300-character name), sometimes breaks stdout, runs
one of the commands (all eleven) in-process through ``eigenupdate.cli.main`` and checks
the invariant:

* exit status 0, 1 or 2, never an exception (a traceback);
* exit 1 only for an update that did not converge, or a Monte Carlo with too few converged
  trials for statistics;
* exit 2 with one error line on stderr that names the file or option (progress lines of
  ``extract`` aside), at most ``MAX_LINE`` characters;
* no NaN or inf in any output of a run with exit 0 (stdout and the files written);
* no file of the case changed, and none created, by a failed run (exit 1 may create its
  ``--save`` result); a successful run changes only its own outputs (a special file or
  link replaced by a regular file counts as changed);
* with a broken stdout, exit 2 naming the standard output (the files still written) or
  the status the run would have had.

Usage: ``python tools/fuzz.py --cases 10000 [--seed 0] [--keep DIR]``; prints the count
of each class of outcome, overall and by command (inputs mutated, runs, tracebacks, bad
exits, hangs, NaN with exit 0, clobbered files). ``tests/cli/test_fuzz.py`` runs a short
seeded form in CI.
"""

from __future__ import annotations

import argparse
import contextlib
import faulthandler
import hashlib
import io
import os
import random
import re
import resource
import shutil
import signal
import socket
import stat
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
    """The Fig. 2 study, its truth and data, and the saved result of its update."""
    from eigenupdate.cli import main

    for name in ("study.toml", "truth.toml", "measured.csv"):
        shutil.copy(EXAMPLES / "paper_fig2" / name, d / name)
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        assert main(["update", str(d / "study.toml"), "--save", str(d / "result.json")]) == 0


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


def _nastran(d: Path) -> None:
    for name in ("study.toml", "frame.bdf", "measured.csv"):
        shutil.copy(EXAMPLES / "nastran_frame" / name, d / name)


MC = ["mc/trials.csv", "mc/summary.json", "mc/std.png", "mc/zscores.png"]

# (command arguments, outputs it may write); {d} is the case directory; an output ending
# in "/" is a directory whose files the command names itself
SCENARIOS = {
    "fig2": (_fig2, ["study.toml", "truth.toml", "measured.csv", "result.json"], [
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
        (["design", "{d}/study.toml", "-o", "{d}/plan.toml"], ["plan.toml"]),
        (["design", "{d}/study.toml", "-o", "{d}/plan.toml", "--scheduler", "{x}"],
         ["plan.toml"]),
        (["montecarlo", "{d}/study.toml", "--trials", "2", "--in-process", "--seed", "1",
          "--truth", "{d}/truth.toml", "-o", "{d}/mc"], MC),
        (["sweep", "{d}/study.toml", "--coordinate", "2", "--max-mass", "{x}", "-o",
          "{d}/sweep.png"], ["sweep.png"]),
        (["frf", "{d}/study.toml", "--input", "1", "--output", "2", "--updated",
          "{d}/result.json", "-o", "{d}/frf.png"], ["frf.png"]),
        (["report", "{d}/study.toml", "--result", "{d}/result.json", "-o", "{d}/report.html"],
         ["report.html"]),
        (["simulate-frf", "{d}/truth.toml", "-o", "{d}/frfs", "--input", "1", "--outputs",
          "1", "2", "--fmax", "120", "--df", "{x}"], ["frfs/"]),
        (["simulate-frf", "{d}/truth.toml", "-o", "{d}/frfs", "--input", "1", "--outputs",
          "2", "--fmax", "120", "--noise", "{x}", "--binary"], ["frfs/"]),
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
        (["extract", "{d}/ascii.uff", "-o", "{d}/x.csv", "--plots", "{d}/plots"],
         ["x.csv", "plots/"]),
        (["extract", "{d}/base.uff", "-o", "{d}/x.csv", "--kind", "receptance", "--json"],
         ["x.csv"]),
    ]),
    "mtx": (_mtx, ["study.toml", "K0.mtx", "M0.mtx", "k1.mtx", "m2.mtx", "measured.csv"], [
        (["frequencies", "{d}/study.toml"], []),
        (["check", "{d}/study.toml"], []),
        (["update", "{d}/study.toml"], []),
    ]),
}
try:  # the NASTRAN extra (numpy < 2) is another environment
    import pyNastran  # noqa: F401
except ImportError:
    pass
else:
    SCENARIOS["nastran"] = (_nastran, ["study.toml", "frame.bdf", "measured.csv"], [
        (["frequencies", "{d}/study.toml"], []),
        (["check", "{d}/study.toml"], []),
        (["update", "{d}/study.toml", "--save-bdf", "{d}/updated.bdf"], ["updated.bdf"]),
    ])


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


def mutate_resource(path: Path, data: bytes, rng: random.Random) -> bytes:
    """An input that asks for more than a run may build (see eigenupdate/budget.py)."""
    depth = rng.choice([100, 3000, 50_000])
    if path.suffix == ".json":
        return b'{"parameters": ' + b"[" * depth + b"]" * depth + b"}"
    if path.suffix == ".mtx":
        lines = data.split(b"\n")
        i = next((k for k, ln in enumerate(lines) if ln and not ln.startswith(b"%")), 1)
        size = rng.choice([b"3000000", b"100000000", b"2147483648"])
        lines[i] = size + b" " + size + b" " + (lines[i].split() or [b"1"])[-1]
        return b"\n".join(lines)
    if path.suffix == ".toml":
        kind = rng.choice(["deep", "additions", "nodes", "design"])
        if kind == "deep":
            return b"x = " + b"[" * depth + b"]" * depth + b"\n" + data
        if kind == "additions" and b"[design]" in data:
            return data.replace(b"[design]", b"[design]\nadditions = 2000000000")
        if kind == "design" and b"[design]" in data:
            coords = ", ".join(str(i) for i in range(1, 5)).encode()
            masses = ", ".join(f"{0.01 * (i + 1):.2f}" for i in range(400)).encode()
            return re.sub(rb"\[design\][^\[]*", b"[design]\ncoordinates = [" + coords +
                          b"]\nmasses = [" + masses + b"]\nconfigurations = 3\nadditions = 4\n"
                          b"modes = [1, 2]\nfrequency_std_hz = 0.01\n\n", data)
        if b"nodes = [" in data:
            nodes = ", ".join(f"{0.001 * i:.3f}" for i in range(10_001)).encode()
            return re.sub(rb"nodes = \[[^\]]*\]", b"nodes = [" + nodes + b"]", data)
        return b"x = " + b"{a = " * depth + b"1" + b"}" * depth + b"\n" + data
    return data + b"9" * 1_000_000


def mutate(path: Path, rng: random.Random) -> str:
    data = path.read_bytes()
    if rng.random() < 0.1:
        path.write_bytes(mutate_resource(path, data, rng))
        return f"{path.name} (resource)"
    for _ in range(rng.choice([1, 1, 1, 2, 3])):
        binary = path.suffix == ".uff" and path.name == "base.uff"
        data = mutate_binary(data, rng) if binary else mutate_text(data, rng)
    path.write_bytes(data)
    return path.name


ATTACKS = ("fifo", "socket", "link to input", "hard link to input", "dangling link",
           "link loop", "directory", "name of 249", "name of 300")


def attack_output(d: Path, argv: list[str], files: list[str], outputs: list[str],
                  rng: random.Random) -> tuple[str, list[str], socket.socket | None]:
    """Put something hostile where one output goes; returns (attack, outputs, socket)."""
    flags = [i for i, a in enumerate(argv[:-1]) if a in ("-o", "--save", "--save-bdf",
                                                          "--uff55", "--plots")
             and argv[i + 1].startswith(str(d))]
    if not flags:
        return "(none)", outputs, None
    i = rng.choice(flags) + 1
    target = Path(argv[i])
    if target.name in files:  # the output is itself an input: already an attack
        return "(none)", outputs, None
    if target.is_file():  # a pre-existing output gives way to the attack
        target.unlink()
    kind = rng.choice(ATTACKS)
    sock = None
    if kind == "fifo":
        os.mkfifo(target)
    elif kind == "socket":
        sock = socket.socket(socket.AF_UNIX)
        sock.bind(str(target))
    elif kind in ("link to input", "hard link to input"):
        # a file the command line names is an input for sure (a study's model or data
        # file is one too, but the fuzzer does not parse the study to know)
        named = [Path(a) for a in argv if a.startswith(str(d)) and Path(a).is_file()
                 and Path(a) != target]
        if not named:
            return "(none)", outputs, None
        source = rng.choice(named)
        if kind == "link to input":
            target.symlink_to(source)
        else:
            os.link(source, target)
    elif kind == "dangling link":
        target.symlink_to(d / "nowhere" / "x")
    elif kind == "link loop":
        target.symlink_to(d / "loop")
        (d / "loop").symlink_to(target)
    elif kind == "directory":
        target.mkdir()
        (target / "keep").write_text("kept\n")
    else:
        name = "n" * (249 if kind == "name of 249" else 300 - len(target.suffix)) + target.suffix
        slash = "/" if f"{target.name}/" in outputs else ""  # an output directory
        outputs = [o for o in outputs if o.rstrip("/") != target.name] + [name + slash]
        argv[i] = str(target.with_name(name))
    return kind, outputs, sock


class _BrokenStdout(io.StringIO):
    def write(self, s: str) -> int:
        raise BrokenPipeError(32, "Broken pipe")


# ---------------------------------------------------------------- one case

class _Timeout(Exception):
    pass


def _alarm(signum, frame):
    raise _Timeout


def _snapshot(d: Path) -> dict[str, str]:
    """Every entry of ``d``: content hash of a regular file, else what it is (a link by
    its target, a FIFO, a socket), so replacing one by a file is a change."""
    out = {}
    for p in sorted(d.rglob("*")):
        st = os.lstat(p)
        if stat.S_ISLNK(st.st_mode):
            out[str(p.relative_to(d))] = "link to " + os.readlink(p)
        elif stat.S_ISREG(st.st_mode):
            out[str(p.relative_to(d))] = hashlib.sha256(p.read_bytes()).hexdigest()
        elif not stat.S_ISDIR(st.st_mode):
            out[str(p.relative_to(d))] = f"special {stat.S_IFMT(st.st_mode):o}"
    return out


def _allowed(name: str, outputs: list[str]) -> bool:
    return any(name == o or (o.endswith("/") and name.startswith(o)) for o in outputs)


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
        if (rng.random() < 0.5 and not out.endswith("/") and not (d / out).exists()
                and (d / out).parent.is_dir()):
            (d / out).write_text("pre-existing\n", encoding="utf-8")
    attack, sock = "(none)", None
    if rng.random() < 0.25:
        attack, outputs, sock = attack_output(d, argv, files, outputs, rng)
    broken = rng.random() < 0.1
    before = _snapshot(d)
    stdout = _BrokenStdout() if broken else io.StringIO()
    stderr = io.StringIO()
    what = (f"seed {seed} case {index}: {name}, mutated {target}, output {attack}"
            f"{', stdout broken' if broken else ''}, eigenupdate {' '.join(argv)}")
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
    except KeyboardInterrupt:  # the campaign is stopped, not the case failed
        raise
    except BaseException:
        return "traceback", what + "\n" + traceback.format_exc(limit=-3)
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)
        if sock is not None:
            sock.close()
    after = _snapshot(d)
    changed = sorted(k for k in set(before) | set(after) if before.get(k) != after.get(k))
    out, err = ("" if broken else stdout.getvalue()), stderr.getvalue()
    err_lines = [ln for ln in err.splitlines() if not PROGRESS.match(ln)]
    if code not in (0, 1, 2):
        return "bad exit status", f"{what}: {code!r}"
    if broken and STDOUT_ERROR in err:  # the run's own outcome, then the stdout error
        if len(err_lines) > 2 or not err_lines[-1].startswith("eigenupdate: error: "):
            return "exit 2 not one line", f"{what}\n{err[:2000]}"
        changed = sorted(k for k in set(before) | set(_snapshot(d))
                         if before.get(k) != _snapshot(d).get(k))
        if any(not _allowed(c, outputs) for c in changed):
            return "clobbered", f"{what}: {changed}"
        return "exit 2 (stdout broken)", what
    if code == 2:
        if len(err_lines) != 1 or not ERROR.match(err_lines[0]):
            return "exit 2 not one line", f"{what}\n{err[:2000]}"
        line = err_lines[0]
        if len(line) > MAX_LINE:
            return "exit 2 line too long", f"{what}: {len(line)} characters"
        if str(d) not in line and not re.search(r"(^|\s)-", line):
            return "exit 2 names no file", f"{what}\n{line}"
    if code == 1:  # an update that did not converge, or a Monte Carlo too few of whose
        # trials converged to give statistics (README: exit 1)
        if not ((argv[0] == "update" and "not converged" in err)
                or (argv[0] == "montecarlo" and "no statistics" in err)):
            return "exit 1 not non-convergence", f"{what}\n{err[:2000]}"
        allowed = [o for o in outputs if o not in before]  # only a new --save result
        if any(not _allowed(c, allowed) for c in changed):
            return "clobbered", f"{what}: {changed}"
        return "exit 1 (not converged)", what
    if code == 2:
        if changed:
            return "clobbered", f"{what}: {changed}"
        return "exit 2 (input error)", what
    if any(not _allowed(c, outputs) for c in changed):
        return "clobbered", f"{what}: {changed}"
    texts = [out] + [(d / c).read_text(encoding="utf-8", errors="replace") for c in changed
                     if (d / c).is_file() and (d / c).suffix not in (".png", ".uff")]
    # a mutated title or configuration name may itself say "inf": echoed, not computed
    for s in _strings(Path(argv[1])) if len(argv) > 1 else []:
        texts = [t.replace(s, "") for t in texts]
    if any(NAN.search(t) for t in texts):
        return "NaN in output", what
    if err_lines and argv[0] not in ("simulate", "montecarlo", "design"):
        return "exit 0 with messages", f"{what}\n{err[:2000]}"
    return "exit 0", what


EXPECTED = ("exit 0", "exit 1 (not converged)", "exit 2 (input error)", "exit 2 (stdout broken)")
STDOUT_ERROR = "eigenupdate: error: standard output:"
BAD_EXITS = ("bad exit status", "exit 1 not non-convergence", "exit 2 not one line",
             "exit 2 line too long", "exit 2 names no file", "exit 0 with messages")
COLUMNS = {"tracebacks": ("traceback",), "bad exits": BAD_EXITS, "hangs": ("timeout",),
           "NaN exit 0": ("NaN in output",), "clobbered": ("clobbered",)}


def run(cases: int, seed: int = 0, keep: Path | None = None, progress: bool = False,
        first: int = 0) -> tuple[Counter, dict[str, list[str]], dict[str, Counter]]:
    """Run cases ``first`` to ``first + cases - 1``; returns the count of each class, the
    details of violations and the count of each class by command."""
    counts: Counter = Counter()
    by_command: dict[str, Counter] = {}
    examples: dict[str, list[str]] = {}
    with tempfile.TemporaryDirectory(prefix="eigenupdate-fuzz-") as tmp:
        base, cache = Path(tmp), {}
        start = time.monotonic()
        for i in range(first, first + cases):
            if progress == "each":
                print(f"case {i}", file=sys.stderr, flush=True)
            try:
                cls, detail = run_case(seed, i, base, cache)
            except KeyboardInterrupt:  # a bounded campaign stopped: report what it reached
                print(f"stopped before case {i}", file=sys.stderr, flush=True)
                break
            counts[cls] += 1
            command = re.search(r", eigenupdate (\S+)", detail).group(1)
            by_command.setdefault(command, Counter())[cls] += 1
            if cls not in EXPECTED:
                examples.setdefault(cls, []).append(detail)
                if keep is not None:
                    shutil.copytree(base / f"case_{i}", keep / f"case_{i}", dirs_exist_ok=True)
            shutil.rmtree(base / f"case_{i}")
            if progress and (i + 1 - first) % 100 == 0:
                print(f"{i + 1 - first} cases, {time.monotonic() - start:.0f} s: {dict(counts)}",
                      file=sys.stderr, flush=True)
    return counts, examples, by_command


def command_table(by_command: dict[str, Counter]) -> str:
    """Counts by command: inputs mutated (= runs, one per case) and the violations."""
    head = ["command", "inputs", "runs", *COLUMNS]
    rows = [head]
    for cmd in sorted(by_command):
        c = by_command[cmd]
        n = sum(c.values())
        rows.append([cmd, str(n), str(n), *(str(sum(c[k] for k in v)) for v in COLUMNS.values())])
    widths = [max(len(r[i]) for r in rows) for i in range(len(head))]
    return "\n".join("  ".join(x.rjust(w) for x, w in zip(r, widths, strict=True)) for r in rows)


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
    signal.signal(signal.SIGTERM, signal.default_int_handler)  # `timeout` still reports
    if args.keep:
        args.keep.mkdir(parents=True, exist_ok=True)
    start = time.monotonic()
    counts, examples, by_command = run(args.cases, args.seed, args.keep,
                                       progress="each" if args.verbose else True,
                                       first=args.first)
    print(f"{sum(counts.values())} cases from {args.first}, seed {args.seed}, "
          f"{time.monotonic() - start:.0f} s")
    for cls in (*EXPECTED, *sorted(set(counts) - set(EXPECTED))):
        print(f"  {cls:28s} {counts.get(cls, 0)}")
    print("\nby command:\n" + command_table(by_command))
    for cls, details in examples.items():
        print(f"\n{cls}: {len(details)} case(s), first ones:")
        for detail in details[:3]:
            print("  " + detail.replace("\n", "\n    "))
    return 1 if examples else 0


if __name__ == "__main__":
    sys.exit(main())
