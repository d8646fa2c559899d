# ruff: noqa: E501  (a table of cases, one per line)
"""Run hand-written hostile and wrong-data cases through every command of the CLI.

Each case copies a shipped example into a fresh temporary directory, mutates it, runs one
command as a subprocess (60 s, 2 GB address space) and records exit status, stderr line
count, "Traceback", and the files created or modified. Usage:

    python tools/hostile.py [-k SUBSTRING] [--nastran]

Prints one line per case: name, exit status, stderr lines, flags, the last stderr line.
Flags: TB (traceback), NEW/MOD (files created or changed by a failed run), HANG, >1L,
LONG (a line over 1000 characters), and a case's own check.
"""

from __future__ import annotations

import argparse
import csv
import hashlib
import io
import os
import re
import resource
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EX = ROOT / "examples"
CORE = "/work/main/.venv/bin/python"
NASTRAN = "/work/main/.venv-nastran/bin/python"


def _limit():
    resource.setrlimit(resource.RLIMIT_AS, (2 << 30, 2 << 30))


def snapshot(d: Path) -> dict:
    out = {}
    for p in d.rglob("*"):
        if p.is_file() and not p.is_symlink():
            out[str(p.relative_to(d))] = hashlib.sha256(p.read_bytes()).hexdigest()
    return out


def sub(path: Path, old: str, new: str, count: int = 1) -> None:
    text = path.read_text()
    assert old in text, (path, old)
    path.write_text(text.replace(old, new, count))


def csv_map(path: Path, fn) -> None:
    lines = [ln for ln in path.read_text().splitlines() if not ln.startswith("#")]
    path.write_text("\n".join([lines[0]] + [fn(ln) for ln in lines[1:]]) + "\n")


def scale_freq(factor):
    def fn(ln):
        f = next(csv.reader([ln]))
        f[2] = repr(float(f[2]) * factor)
        out = io.StringIO()
        csv.writer(out, lineterminator="").writerow(f)
        return out.getvalue()
    return fn


CASES: list[tuple] = []


def case(name, example, argv, mutate=None, python=CORE, env=None, check=None):
    """``check(code, stderr)``: a further flag (str) of this case, or None."""
    CASES.append((name, example, argv, mutate, python, env, check))


def run(name, example, argv, mutate, python, env_extra=None, check=None, keep=False):
    d = Path(tempfile.mkdtemp(prefix="hostile-"))
    try:
        shutil.copytree(EX / example, d / "ex")
        w = d / "ex"
        if mutate:
            mutate(w)
        before = snapshot(d)
        env = dict(os.environ, PYTHONPATH=str(ROOT / "src"), OPENBLAS_NUM_THREADS="1",
                   **(env_extra or {}))
        args = [a.replace("@", str(w) + "/") if isinstance(a, str) else str(a) for a in argv]
        try:
            p = subprocess.run([python, "-m", "eigenupdate", *args], cwd=w, env=env,
                               capture_output=True, text=True, timeout=60,
                               preexec_fn=_limit)
            code, err, out = p.returncode, p.stderr, p.stdout
        except subprocess.TimeoutExpired:
            code, err, out = "HANG", "", ""
        after = snapshot(d)
        flags = []
        if "Traceback" in err:
            flags.append("TB")
        new = sorted(set(after) - set(before))
        mod = sorted(k for k in before if k in after and before[k] != after[k])
        gone = sorted(set(before) - set(after))
        if code != 0 and (new or mod):
            flags.append(f"NEW{new}MOD{mod}")
        if code == 0 and mod:
            flags.append(f"MOD{mod}")
        if gone:
            flags.append(f"GONE{gone}")
        if code == "HANG":
            flags.append("HANG")
        elines = [ln for ln in err.strip().splitlines()
                  if not re.match(r"^(\[\d+/\d+\] |  warning: |eigenupdate: warning: |wrote )", ln)]
        if code == 2 and len(elines) != 1:
            flags.append(">1L")
        if code == 0 and re.search(r"\b(nan|inf)\b", out, re.I):
            flags.append("NAN")
        if any(len(ln) > 1000 for ln in elines):
            flags.append("LONG")
        if check is not None and (extra := check(code, err)):
            flags.append(extra)
        last = elines[-1] if elines else ""
        print(f"{name:45s} {code!s:4s} {len(err.strip().splitlines()):3d} "
              f"{' '.join(flags):10s} {last[:230]}", flush=True)
        if keep:
            print(out[-3000:])
            print(err[-3000:])
    finally:
        shutil.rmtree(d, ignore_errors=True)


# ----------------------------------------------------------------- the cases
F2 = "paper_fig2"
S = "@study.toml"
M = "@measured.csv"

case("fig2 baseline update", F2, ["update", S])
case("fig2 freq in rad/s", F2, ["update", S],
     lambda w: csv_map(w / "measured.csv", scale_freq(2 * 3.141592653589793)))
case("fig2 freq in kHz", F2, ["update", S],
     lambda w: csv_map(w / "measured.csv", scale_freq(1e-3)))
case("fig2 duplicate row", F2, ["update", S],
     lambda w: (w / "measured.csv").write_text((w / "measured.csv").read_text()
                                              + "base,1,42.86564108114408,\n"))
case("fig2 duplicate row diff value", F2, ["update", S],
     lambda w: (w / "measured.csv").write_text((w / "measured.csv").read_text()
                                              + "base,1,40.0,\n"))
case("fig2 extra config in csv", F2, ["update", S],
     lambda w: (w / "measured.csv").write_text((w / "measured.csv").read_text()
                                              + "1 kg at 3,1,40.0,\n"))
case("fig2 extra mode 4 in csv", F2, ["update", S],
     lambda w: (w / "measured.csv").write_text((w / "measured.csv").read_text()
                                              + "base,4,140.0,\n"))
case("fig2 mode 0 row", F2, ["update", S],
     lambda w: (w / "measured.csv").write_text((w / "measured.csv").read_text()
                                              + "base,0,10.0,\n"))
case("fig2 mode 1.0", F2, ["update", S],
     lambda w: sub(w / "measured.csv", "base,1,", "base,1.0,"))
case("fig2 missing row", F2, ["update", S],
     lambda w: sub(w / "measured.csv", "base,2,76.327754052682,\n", ""))
case("fig2 config name case", F2, ["update", S],
     lambda w: sub(w / "measured.csv", "0.35 kg at 1,", "0.35 KG at 1,", 3))
case("fig2 config name trailing space", F2, ["update", S],
     lambda w: sub(w / "measured.csv", "0.35 kg at 1,", "0.35 kg at 1 ,", 3))
case("fig2 config quoted", F2, ["update", S],
     lambda w: sub(w / "measured.csv", "0.35 kg at 1,", '"0.35 kg at 1",', 3))
case("fig2 csv BOM", F2, ["update", S],
     lambda w: (w / "measured.csv").write_bytes(b"\xef\xbb\xbf" + (w / "measured.csv").read_bytes()))
case("fig2 csv CRLF", F2, ["update", S],
     lambda w: (w / "measured.csv").write_bytes((w / "measured.csv").read_bytes().replace(b"\n", b"\r\n")))
case("fig2 study CRLF+BOM", F2, ["update", S],
     lambda w: (w / "study.toml").write_bytes(b"\xef\xbb\xbf" + (w / "study.toml").read_bytes().replace(b"\n", b"\r\n")))
case("fig2 csv columns reordered", F2, ["update", S],
     lambda w: (w / "measured.csv").write_text("mode,configuration,frequency_hz,std_hz\n" + "".join(
         f"{ln.split(',')[1]},{ln.split(',')[0]},{','.join(ln.split(',')[2:])}\n"
         for ln in (w / "measured.csv").read_text().splitlines()[1:])))
case("fig2 csv freq column renamed rad", F2, ["update", S],
     lambda w: sub(w / "measured.csv", "frequency_hz", "frequency_rad_s"))
case("fig2 csv extra column", F2, ["update", S],
     lambda w: csv_map(w / "measured.csv", lambda ln: ln + ",x"))
case("fig2 csv std 0", F2, ["update", S, "--method", "weighted-least-squares"],
     lambda w: csv_map(w / "measured.csv", lambda ln: ln + "0"))
case("fig2 csv std negative", F2, ["update", S, "--method", "weighted-least-squares"],
     lambda w: csv_map(w / "measured.csv", lambda ln: ln + "-0.01"))
case("fig2 csv std empty weighted", F2, ["update", S, "--method", "weighted-least-squares"])
case("fig2 csv std huge", F2, ["update", S, "--method", "weighted-least-squares"],
     lambda w: csv_map(w / "measured.csv", lambda ln: ln + "1e6"))
case("fig2 csv negative freq", F2, ["update", S],
     lambda w: sub(w / "measured.csv", "base,1,42.8", "base,1,-42.8"))
case("fig2 csv empty", F2, ["update", S], lambda w: (w / "measured.csv").write_text(""))
case("fig2 csv header only", F2, ["update", S],
     lambda w: (w / "measured.csv").write_text("configuration,mode,frequency_hz,std_hz\n"))
case("fig2 csv truncated mid-row", F2, ["update", S],
     lambda w: (w / "measured.csv").write_text((w / "measured.csv").read_text()[:-20]))
case("fig2 csv semicolon", F2, ["update", S],
     lambda w: (w / "measured.csv").write_text((w / "measured.csv").read_text().replace(",", ";")))
case("fig2 csv decimal comma", F2, ["update", S],
     lambda w: (w / "measured.csv").write_text((w / "measured.csv").read_text().replace(",", ";").replace(".", ",")))
case("fig2 csv utf16", F2, ["update", S],
     lambda w: (w / "measured.csv").write_bytes((w / "measured.csv").read_text().encode("utf-16")))
case("fig2 csv binary garbage", F2, ["update", S],
     lambda w: (w / "measured.csv").write_bytes(bytes(range(256)) * 10))
case("fig2 csv is directory", F2, ["update", S],
     lambda w: ((w / "measured.csv").unlink(), (w / "measured.csv").mkdir()))
case("fig2 csv is /dev/null", F2, ["update", S],
     lambda w: sub(w / "study.toml", '"measured.csv"', '"/dev/null"'))
case("fig2 csv is /dev/zero", F2, ["update", S],
     lambda w: sub(w / "study.toml", '"measured.csv"', '"/dev/zero"'))
case("fig2 csv is /dev/urandom", F2, ["update", S],
     lambda w: sub(w / "study.toml", '"measured.csv"', '"/dev/urandom"'))
case("fig2 study is /dev/zero", F2, ["check", "/dev/zero"])
case("fig2 csv is study", F2, ["update", S],
     lambda w: sub(w / "study.toml", '"measured.csv"', '"study.toml"'))
# study file semantics
case("fig2 pert coordinate 0", F2, ["update", S],
     lambda w: sub(w / "study.toml", "coordinate = 4\nmass = 0.35", "coordinate = 0\nmass = 0.35"))
case("fig2 pert mass 0", F2, ["check", S],
     lambda w: sub(w / "study.toml", "coordinate = 4\nmass = 0.35", "coordinate = 4\nmass = 0.0"))
case("fig2 pert mass negative", F2, ["check", S],
     lambda w: sub(w / "study.toml", "coordinate = 4\nmass = 0.35", "coordinate = 4\nmass = -0.35"))
case("fig2 pert mass huge", F2, ["update", S],
     lambda w: sub(w / "study.toml", "coordinate = 4\nmass = 0.35", "coordinate = 4\nmass = 1e30"))
case("fig2 pert stiffness negative", F2, ["check", S],
     lambda w: sub(w / "study.toml", "coordinate = 4\nmass = 0.35", "coordinate = 4\nstiffness = -1e5"))
case("fig2 pert duplicate name", F2, ["check", S],
     lambda w: sub(w / "study.toml", 'name = "0.35 kg at 2"', 'name = "0.35 kg at 1"'))
case("fig2 pert named base", F2, ["check", S],
     lambda w: sub(w / "study.toml", 'name = "0.35 kg at 2"', 'name = "base"'))
case("fig2 pert duplicate config content", F2, ["check", S],
     lambda w: sub(w / "study.toml", "coordinate = 2\nmass = 0.35", "coordinate = 1\nmass = 0.35"))
case("fig2 pert coordinate float", F2, ["check", S],
     lambda w: sub(w / "study.toml", "coordinate = 4\nmass = 0.35", "coordinate = 4.0\nmass = 0.35"))
case("fig2 pert coordinate and add", F2, ["check", S],
     lambda w: sub(w / "study.toml", "coordinate = 4\nmass = 0.35",
                   "coordinate = 4\nmass = 0.35\nadd = [{coordinate = 1, mass = 0.2}]"))
case("fig2 pert add same coordinate twice", F2, ["check", S],
     lambda w: sub(w / "study.toml", "coordinate = 4\nmass = 0.35",
                   "add = [{coordinate = 1, mass = 0.2}, {coordinate = 1, mass = 0.15}]"))
case("fig2 pert add empty", F2, ["check", S],
     lambda w: sub(w / "study.toml", "coordinate = 4\nmass = 0.35", "add = []"))
case("fig2 spring self", F2, ["check", S],
     lambda w: sub(w / "study.toml", "coordinates = [2, 4]", "coordinates = [2, 2]"))
case("fig2 spring ground ground", F2, ["check", S],
     lambda w: sub(w / "study.toml", "coordinates = [2, 4]", "coordinates = [0, 0]"))
case("fig2 spring 3 coords", F2, ["check", S],
     lambda w: sub(w / "study.toml", "coordinates = [2, 4]", "coordinates = [2, 4, 1]"))
case("fig2 mass duplicated coordinate", F2, ["check", S],
     lambda w: sub(w / "study.toml", "coordinate = 2\nvalue = 9.7", "coordinate = 1\nvalue = 9.7"))
case("fig2 mass coordinate gap", F2, ["check", S],
     lambda w: sub(w / "study.toml", "coordinate = 4\nvalue = 4.7", "coordinate = 7\nvalue = 4.7"))
case("fig2 modes empty", F2, ["update", S], lambda w: sub(w / "study.toml", "modes = [1, 2, 3]", "modes = []"))
case("fig2 modes unsorted", F2, ["update", S], lambda w: sub(w / "study.toml", "modes = [1, 2, 3]", "modes = [3, 1, 2]"))
case("fig2 modes duplicate", F2, ["update", S], lambda w: sub(w / "study.toml", "modes = [1, 2, 3]", "modes = [1, 2, 2, 3]"))
case("fig2 modes 5 of 4-dof", F2, ["check", S], lambda w: sub(w / "study.toml", "modes = [1, 2, 3]", "modes = [1, 2, 5]"))
case("fig2 modes 0", F2, ["check", S], lambda w: sub(w / "study.toml", "modes = [1, 2, 3]", "modes = [0, 1, 2]"))
case("fig2 modes 1e9", F2, ["check", S], lambda w: sub(w / "study.toml", "modes = [1, 2, 3]", "modes = [1, 2, 1000000000]"))
case("fig2 max_iterations 0", F2, ["update", S], lambda w: sub(w / "study.toml", "max_iterations = 20", "max_iterations = 0"))
case("fig2 max_iterations 1e9", F2, ["update", S], lambda w: sub(w / "study.toml", "max_iterations = 20", "max_iterations = 1000000000"))
case("fig2 tolerance 0", F2, ["update", S], lambda w: sub(w / "study.toml", "max_iterations = 20", "max_iterations = 20\ntolerance = 0"))
case("fig2 tolerance nan", F2, ["update", S], lambda w: sub(w / "study.toml", "max_iterations = 20", "max_iterations = 20\ntolerance = nan"))
case("fig2 std on mass nan", F2, ["update", S, "--method", "bayesian"], lambda w: sub(w / "study.toml", "value = 9.7  # kg", "value = 9.7\nstd = nan"))
case("fig2 std 0 bayes", F2, ["update", S, "--method", "bayesian"], lambda w: sub(w / "study.toml", "value = 9.7  # kg", "value = 9.7\nstd = 0.0"))
case("fig2 update=false all", F2, ["update", S], lambda w: (w / "study.toml").write_text((w / "study.toml").read_text().replace("  # N/m\n", "\nupdate = false\n").replace("  # kg\n", "\nupdate = false\n")))
# frequencies/simulate options
case("fig2 frequencies modes 1e9", F2, ["frequencies", S, "--modes", "1000000000"])
case("fig2 frequencies modes 0", F2, ["frequencies", S, "--modes", "0"])
case("fig2 frequencies modes -1", F2, ["frequencies", S, "--modes", "-1"])
case("fig2 frequencies modes 5", F2, ["frequencies", S, "--modes", "5"])
case("fig2 simulate noise nan", F2, ["simulate", "@truth.toml", "-o", "@o.csv", "--noise-hz", "nan"])
case("fig2 simulate noise -1", F2, ["simulate", "@truth.toml", "-o", "@o.csv", "--noise-hz", "-1"])
case("fig2 simulate noise inf", F2, ["simulate", "@truth.toml", "-o", "@o.csv", "--noise-hz", "inf"])
case("fig2 simulate noise huge", F2, ["simulate", "@truth.toml", "-o", "@o.csv", "--noise-hz", "1e6", "--seed", "1"])
case("fig2 simulate rel noise 2", F2, ["simulate", "@truth.toml", "-o", "@o.csv", "--noise-relative", "2", "--seed", "1"])
case("fig2 simulate std nan", F2, ["simulate", "@truth.toml", "-o", "@o.csv", "--std-hz", "nan"])
case("fig2 simulate seed -1", F2, ["simulate", "@truth.toml", "-o", "@o.csv", "--seed", "-1"])
case("fig2 simulate seed huge", F2, ["simulate", "@truth.toml", "-o", "@o.csv", "--seed", "99999999999999999999999999999"])
case("fig2 simulate -o study", F2, ["simulate", "@truth.toml", "-o", "@truth.toml"])
case("fig2 simulate -o measured (not input)", F2, ["simulate", "@truth.toml", "-o", M])
case("fig2 simulate -o /dev/null", F2, ["simulate", "@truth.toml", "-o", "/dev/null"])
case("fig2 simulate -o /dev/stdout", F2, ["simulate", "@truth.toml", "-o", "/dev/stdout"])
case("fig2 simulate -o dir", F2, ["simulate", "@truth.toml", "-o", "@"])
case("fig2 simulate -o symlink to study", F2, ["simulate", "@truth.toml", "-o", "@ln.csv"],
     lambda w: os.symlink(w / "truth.toml", w / "ln.csv"))
case("fig2 simulate -o nonexistent dir", F2, ["simulate", "@truth.toml", "-o", "@no/o.csv"])
case("fig2 update --save over csv", F2, ["update", S, "--save", M])
case("fig2 update --save over study", F2, ["update", S, "--save", S])
case("fig2 update --save /proc", F2, ["update", S, "--save", "/proc/self/status"])
# sweep / frf / design / montecarlo
case("fig2 sweep coord 0", F2, ["sweep", S, "--coordinate", "0", "--max-mass", "1", "-o", "@s.png"])
case("fig2 sweep coord 9", F2, ["sweep", S, "--coordinate", "9", "--max-mass", "1", "-o", "@s.png"])
case("fig2 sweep mass -1", F2, ["sweep", S, "--coordinate", "1", "--max-mass", "-1", "-o", "@s.png"])
case("fig2 sweep mass nan", F2, ["sweep", S, "--coordinate", "1", "--max-mass", "nan", "-o", "@s.png"])
case("fig2 sweep mass 1e308", F2, ["sweep", S, "--coordinate", "1", "--max-mass", "1e308", "-o", "@s.png"])
case("fig2 sweep -o .txt", F2, ["sweep", S, "--coordinate", "1", "--max-mass", "1", "-o", "@s.txt"])
case("fig2 sweep -o noext", F2, ["sweep", S, "--coordinate", "1", "--max-mass", "1", "-o", "@s"])
case("fig2 frf input 9", F2, ["frf", S, "--input", "9", "--output", "1", "-o", "@f.png"])
case("fig2 frf input 0", F2, ["frf", S, "--input", "0", "--output", "1", "-o", "@f.png"])
case("fig2 design configurations 0", F2, ["design", S, "-o", "@p.toml"],
     lambda w: sub(w / "study.toml", "configurations = 3", "configurations = 0"))
case("fig2 design configurations 1e9", F2, ["design", S, "-o", "@p.toml"],
     lambda w: sub(w / "study.toml", "configurations = 3", "configurations = 1000000000"))
case("fig2 design masses negative", F2, ["design", S, "-o", "@p.toml"],
     lambda w: sub(w / "study.toml", "masses = [0.35, 1.0, 2.0]", "masses = [-0.35, 1.0, 2.0]"))
case("fig2 design masses dup", F2, ["design", S, "-o", "@p.toml"],
     lambda w: sub(w / "study.toml", "masses = [0.35, 1.0, 2.0]", "masses = [1.0, 1.0, 2.0]"))
case("fig2 design coords 99", F2, ["design", S, "-o", "@p.toml"],
     lambda w: sub(w / "study.toml", "coordinates = [1, 2, 3, 4]", "coordinates = [1, 2, 3, 99]"))
case("fig2 design coords 0", F2, ["design", S, "-o", "@p.toml"],
     lambda w: sub(w / "study.toml", "coordinates = [1, 2, 3, 4]", "coordinates = [0, 1, 2, 3, 4]"))
case("fig2 design std 0", F2, ["design", S, "-o", "@p.toml"],
     lambda w: sub(w / "study.toml", "frequency_std_hz = 0.01", "frequency_std_hz = 0.0"))
case("fig2 design modes 9", F2, ["design", S, "-o", "@p.toml"],
     lambda w: sub(w / "study.toml", "modes = [1, 2, 3, 4]", "modes = [1, 2, 3, 9]"))
case("fig2 design -o study", F2, ["design", S, "-o", S])
case("fig2 design -o csv input", F2, ["design", S, "-o", M])
case("fig2 design validate 1e9", F2, ["design", S, "-o", "@p.toml", "--validate", "1000000000"])
case("fig2 mc trials 1e9", F2, ["montecarlo", S, "--trials", "1000000000", "--in-process", "-o", "@mc"])
case("fig2 mc trials 2", F2, ["montecarlo", S, "--trials", "2", "--in-process"])
case("fig2 mc -o is file", F2, ["montecarlo", S, "--trials", "3", "--in-process", "-o", M])
case("fig2 mc truth other model", F2, ["montecarlo", S, "--trials", "3", "--in-process", "--truth", str(EX / "paper_beam" / "study.toml")])
case("fig2 mc workers 0", F2, ["montecarlo", S, "--trials", "3", "--workers", "0"])
case("fig2 mc workers 1e6", F2, ["montecarlo", S, "--trials", "3", "--workers", "1000000"])
case("fig2 mc scheduler bogus", F2, ["montecarlo", S, "--trials", "3", "--scheduler", "tcp://127.0.0.1:1"])
case("fig2 report -o csv", F2, ["report", S, "--saved-only", "-o", M])
case("fig2 report result other study", F2, ["report", S, "--saved-only", "--result", "@r.json", "-o", "@r.html"],
     lambda w: subprocess.run([CORE, "-m", "eigenupdate", "update", str(EX / "paper_beam" / "study.toml"),
                               "--save", str(w / "r.json")], env=dict(os.environ, PYTHONPATH=str(ROOT / "src")),
                              capture_output=True))
case("fig2 frf updated other study", F2, ["frf", S, "--input", "1", "--output", "1", "--updated", "@r.json", "-o", "@f.png"],
     lambda w: subprocess.run([CORE, "-m", "eigenupdate", "update", str(EX / "paper_beam" / "study.toml"),
                               "--save", str(w / "r.json")], env=dict(os.environ, PYTHONPATH=str(ROOT / "src")),
                              capture_output=True))

# ------------------------------------------------------------ beam, matrices, FRF, NASTRAN
B = "paper_beam"
BF = "paper_beam_frf"
case("beam restrained pert coordinate", B, ["update", S],
     lambda w: sub(w / "study.toml", "mass_per_length_std = 0.1", "mass_per_length_std = 0.1\nrestrained = [1]"))
case("beam restrained pert frequencies", B, ["frequencies", S],
     lambda w: sub(w / "study.toml", "mass_per_length_std = 0.1", "mass_per_length_std = 0.1\nrestrained = [1]"))
case("beam restrained twice", B, ["check", S],
     lambda w: sub(w / "study.toml", "mass_per_length_std = 0.1", "mass_per_length_std = 0.1\nrestrained = [2, 2]"))
case("beam restrained 0", B, ["check", S],
     lambda w: sub(w / "study.toml", "mass_per_length_std = 0.1", "mass_per_length_std = 0.1\nrestrained = [0]"))
case("beam point mass at restrained", B, ["check", S],
     lambda w: sub(w / "study.toml", "mass_per_length_std = 0.1", "mass_per_length_std = 0.1\nrestrained = [11]"))
case("beam nodes unsorted", B, ["check", S],
     lambda w: sub(w / "study.toml", "[0.0, 0.09, 0.19", "[0.0, 0.19, 0.09"))
case("beam nodes duplicated", B, ["check", S],
     lambda w: sub(w / "study.toml", "[0.0, 0.09, 0.19", "[0.0, 0.09, 0.09"))
case("beam nodes tiny element", B, ["check", S],
     lambda w: sub(w / "study.toml", "[0.0, 0.09, 0.19", "[0.0, 0.09, 0.0900000001"))
case("beam EI list wrong length", B, ["check", S],
     lambda w: sub(w / "study.toml", "EI = 4557.0", "EI = [4557.0, 4557.0]"))
case("beam mc trials 1e9", B, ["montecarlo", S, "--trials", "1000000000", "--in-process", "-o", "@mc"])
case("beam design validate 1e9", B, ["design", S, "-o", "@p.toml", "--validate", "1000000000"])
case("beam design prior_draws 1e9", B, ["design", S, "-o", "@p.toml"],
     lambda w: sub(w / "study.toml", "[design]", "[design]\nprior_draws = 1000000000"))
case("beam csv rad/s", B, ["update", S],
     lambda w: csv_map(w / "measured.csv", scale_freq(2 * 3.141592653589793)))
case("beam mode 3 not in model order", B, ["update", S],
     lambda w: sub(w / "study.toml", "modes = [1, 2]", "modes = [2, 1]"))
case("frf extract baseline", BF, ["extract", S, "-o", "@e.csv"])
case("frf extract -o extracted", BF, ["extract", S, "-o", "@extracted.csv"])
case("frf extract uff as study", BF, ["extract", "@frf/base.uff", "-o", "@e.csv"])
case("frf extract uff truncated", BF, ["extract", "@frf/base.uff", "-o", "@e.csv"],
     lambda w: (w / "frf/base.uff").write_bytes((w / "frf/base.uff").read_bytes()[:5000]))
case("frf extract uff empty", BF, ["extract", "@frf/base.uff", "-o", "@e.csv"],
     lambda w: (w / "frf/base.uff").write_bytes(b""))
case("frf extract uff garbage", BF, ["extract", "@frf/base.uff", "-o", "@e.csv"],
     lambda w: (w / "frf/base.uff").write_bytes(bytes(range(256)) * 100))
case("frf extract uff /dev/zero", BF, ["extract", "/dev/zero", "-o", "@e.csv"])
case("frf extract same file twice", BF, ["extract", "@frf/base.uff", "@frf/base.uff", "-o", "@e.csv"])
case("frf extract -o = input uff", BF, ["extract", "@frf/base.uff", "-o", "@frf/base.uff"])
case("frf extract --uff55 = input", BF, ["extract", S, "-o", "@e.csv", "--uff55", "@frf/base.uff"])
case("frf extract --plots = frf dir", BF, ["extract", S, "-o", "@e.csv", "--plots", "@frf"])
case("frf csv frf reversed", BF, ["extract", "@a.csv", "-o", "@e.csv"],
     lambda w: (w / "a.csv").write_text("frequency_hz,real,imag\n" + "".join(
         f"{f},{(1e-6/(1-(f/100)**2+0.02j)).real},{(1e-6/(1-(f/100)**2+0.02j)).imag}\n" for f in range(400, 0, -1))))
case("frf csv frf duplicated freq", BF, ["extract", "@a.csv", "-o", "@e.csv"],
     lambda w: (w / "a.csv").write_text("frequency_hz,real,imag\n" + "".join(
         f"{f//2},{(1e-6/(1-(f/200)**2+0.02j)).real},{(1e-6/(1-(f/200)**2+0.02j)).imag}\n" for f in range(2, 800))))
case("frf csv frf nan", BF, ["extract", "@a.csv", "-o", "@e.csv"],
     lambda w: (w / "a.csv").write_text("frequency_hz,real,imag\n" + "".join(
         f"{f},{'nan' if f == 100 else (1e-6/(1-(f/100)**2+0.02j)).real},{(1e-6/(1-(f/100)**2+0.02j)).imag}\n" for f in range(1, 400))))
case("frf sim-frf fmax huge", BF, ["simulate-frf", "@truth.toml", "-o", "@o", "--input", "11", "--outputs", "1", "--fmax", "1e12", "--df", "1e-6"])
case("frf sim-frf df 0", BF, ["simulate-frf", "@truth.toml", "-o", "@o", "--input", "11", "--outputs", "1", "--fmax", "100", "--df", "0"])
case("frf sim-frf loss negative", BF, ["simulate-frf", "@truth.toml", "-o", "@o", "--input", "11", "--outputs", "1", "--fmax", "1600", "--loss-factor", "-0.01"])
case("frf sim-frf outputs 1e6 list", BF, ["simulate-frf", "@truth.toml", "-o", "@o", "--input", "11", "--outputs", *(["1"] * 3000), "--fmax", "1600"])
case("frf sim-frf -o = frf dir", BF, ["simulate-frf", "@truth.toml", "-o", "@frf", "--input", "11", "--outputs", "1", "--fmax", "1600"])
case("frf frf --measured study", BF, ["frf", S, "--input", "11", "--output", "1", "--measured", S, "-o", "@f.png"])
case("frf frf --measured wrong pair", BF, ["frf", S, "--input", "1", "--output", "3", "--measured", "@frf/base.uff", "-o", "@f.png"])
case("frf frf --damping csv", BF, ["frf", S, "--input", "11", "--output", "1", "--damping", "@extracted.csv", "-o", "@f.png"])
case("frf report -o uff", BF, ["report", S, "--saved-only", "-o", "@frf/base.uff"])
case("frf report extracted rad", BF, ["report", S, "--saved-only", "--extracted", "@extracted.csv", "-o", "@r.html"],
     lambda w: sub(w / "extracted.csv", "configuration,mode", "configuration,mode"))

NF = "nastran_frame"
NP = NASTRAN


def bdf(w, old, new, count=1):
    sub(w / "frame.bdf", old, new, count)


def nas(name, argv, mutate=None):
    case("nas " + name, NF, argv, mutate, NP)


nas("baseline check", ["check", S])
nas("pert at SPC'd grid 1001 comp 1", ["check", S],
    lambda w: sub(w / "study.toml", "grid = 3001\ncomponent = 1", "grid = 1001\ncomponent = 1"))
nas("pert at SPC'd grid 1006 comp 1", ["check", S],
    lambda w: sub(w / "study.toml", "grid = 3001\ncomponent = 1", "grid = 1006\ncomponent = 1"))
nas("pert at grid missing", ["check", S],
    lambda w: sub(w / "study.toml", "grid = 3001\ncomponent = 1", "grid = 9999\ncomponent = 1"))
nas("pert component 0", ["check", S],
    lambda w: sub(w / "study.toml", "grid = 3001\ncomponent = 1", "grid = 3001\ncomponent = 0"))
nas("pert component 7", ["check", S],
    lambda w: sub(w / "study.toml", "grid = 3001\ncomponent = 1", "grid = 3001\ncomponent = 7"))
nas("pert component 12", ["check", S],
    lambda w: sub(w / "study.toml", "grid = 3001\ncomponent = 1", "grid = 3001\ncomponent = 12"))
nas("param card id missing", ["check", S],
    lambda w: sub(w / "study.toml", 'card = "CONM2"\nid = 901', 'card = "CONM2"\nid = 999'))
nas("param field missing", ["check", S],
    lambda w: sub(w / "study.toml", 'field = "M"', 'field = "X1"'))
nas("param field lowercase", ["check", S],
    lambda w: sub(w / "study.toml", 'field = "M"', 'field = "m"'))
nas("param same field twice", ["check", S],
    lambda w: sub(w / "study.toml", 'card = "CONM2"\nid = 901\nfield = "M"', 'card = "MAT1"\nid = 2\nfield = "RHO"'))
nas("param nu", ["check", S],
    lambda w: sub(w / "study.toml", 'card = "CONM2"\nid = 901\nfield = "M"', 'card = "MAT1"\nid = 2\nfield = "NU"'))
nas("conm2 negative", ["check", S], lambda w: bdf(w, "CONM2        902    3002            150.", "CONM2        902    3002           -150."))
nas("mat1 E nan", ["check", S], lambda w: bdf(w, "MAT1           1  2.1+11", "MAT1           1     nan"))
nas("mat1 E 1e308", ["check", S], lambda w: bdf(w, "MAT1           1  2.1+11", "MAT1           1  1.+308"))
nas("mat1 rho 0", ["check", S], lambda w: bdf(w, "2.1+11              .3   7850.", "2.1+11              .3      0.", 2))
nas("pbar A 0", ["check", S], lambda w: bdf(w, "PBAR           1       1  .00543", "PBAR           1       1      0."))
nas("duplicate GRID", ["check", S], lambda w: bdf(w, "GRID        1002              0.      3.      0.", "GRID        1001              0.      3.      0."))
nas("duplicate GRID same", ["check", S], lambda w: bdf(w, "GRID        1002              0.      3.      0.", "GRID        1002              0.      3.      0.\nGRID        1002              0.      3.      0."))
nas("duplicate GRID diff coords", ["check", S], lambda w: bdf(w, "GRID        1002              0.      3.      0.", "GRID        1002              0.      3.      0.\nGRID        1002              0.      4.      0."))
nas("duplicate CONM2 id", ["check", S], lambda w: bdf(w, "CONM2        902    3002", "CONM2        901    3002"))
nas("duplicate MAT1 id", ["check", S], lambda w: bdf(w, "MAT1           2  2.1+11", "MAT1           1  2.1+11"))
nas("INCLUDE self", ["check", S], lambda w: bdf(w, "$PARAMS", "INCLUDE 'frame.bdf'"))
nas("INCLUDE missing", ["check", S], lambda w: bdf(w, "$PARAMS", "INCLUDE 'nope.bdf'"))
nas("INCLUDE dev zero", ["check", S], lambda w: bdf(w, "$PARAMS", "INCLUDE '/dev/zero'"))
nas("INCLUDE dir", ["check", S], lambda w: bdf(w, "$PARAMS", "INCLUDE '/tmp'"))
nas("bdf CRLF BOM", ["check", S], lambda w: (w / "frame.bdf").write_bytes(b"\xef\xbb\xbf" + (w / "frame.bdf").read_bytes().replace(b"\n", b"\r\n")))
nas("bdf tabs", ["check", S], lambda w: bdf(w, "GRID        1001              0.", "GRID\t1001\t\t0."))
nas("bdf truncated", ["check", S], lambda w: (w / "frame.bdf").write_text((w / "frame.bdf").read_text()[:5000]))
nas("bdf empty", ["check", S], lambda w: (w / "frame.bdf").write_text(""))
nas("bdf binary", ["check", S], lambda w: (w / "frame.bdf").write_bytes(bytes(range(256)) * 40))
nas("bdf no SPC (free)", ["check", S], lambda w: bdf(w, "  SPC = 1\n", ""))
nas("bdf SPC set 2 selected", ["check", S], lambda w: bdf(w, "  SPC = 1\n", "  SPC = 2\n"))
nas("bdf unicode comment", ["check", S], lambda w: bdf(w, "$PARAMS", "$ paramètres ✓ 日本"))
nas("bdf grid huge id", ["check", S], lambda w: bdf(w, "GRID        1001", "GRID    99999999"))
nas("csv rad/s", ["update", S], lambda w: csv_map(w / "measured.csv", scale_freq(2 * 3.141592653589793)))
nas("save-bdf over frame", ["update", S, "--save-bdf", "@frame.bdf"])
nas("save-bdf over study", ["update", S, "--save-bdf", S])
nas("save-bdf /dev/null", ["update", S, "--save-bdf", "/dev/null"])
nas("frf coord bad component", ["frf", S, "--input", "60117", "--output", "60112", "-o", "@f.png"])
nas("frf coord SPC'd", ["frf", S, "--input", "10011", "--output", "60112", "-o", "@f.png"])
nas("sweep SPC'd", ["sweep", S, "--coordinate", "10011", "--max-mass", "10", "-o", "@s.png"])
nas("sweep coord 6011 (grid only)", ["sweep", S, "--coordinate", "6011", "--max-mass", "10", "-o", "@s.png"])


def rename(new):
    return lambda w: sub(w / "study.toml", 'name = "0.35 kg at 2"', f'name = {new}')


def roundtrip(name, new):
    """simulate the truth with a renamed configuration, then update from what it wrote"""
    def mutate(w):
        for f in ("study.toml", "truth.toml"):
            sub(w / f, 'name = "0.35 kg at 2"', f'name = {new}')
    case("fig2 roundtrip name " + name, F2, ["simulate", "@truth.toml", "-o", M], mutate)
    case("fig2 roundtrip+update name " + name, F2, ["update", S], lambda w: (mutate(w), subprocess.run(
        [CORE, "-m", "eigenupdate", "simulate", str(w / "truth.toml"), "-o", str(w / "measured.csv")],
        env=dict(os.environ, PYTHONPATH=str(ROOT / "src")), capture_output=True)))


for label, new in [("hash", '"#2"'), ("lead space", '" 0.35 kg at 2"'), ("newline", '"a\\nb"'),
                   ("quote", "'a\"b'"), ("comma", '"a,b"'), ("base space", '"base "'),
                   ("empty", '""'), ("tab", '"a\\tb"'), ("unicode", '"0,35 kg à 2 ✓"'),
                   ("cr", '"a\\rb"'), ("nul", '"a\\u0000b"'), ("bidi", '"a\\u202eb"')]:
    roundtrip(label, new)


# negative and singular physics
nas("pbar I1 negative", ["frequencies", S], lambda w: bdf(w, "PBAR           2       2  .00285.0000194", "PBAR           2       2  .00285-.000019"))
nas("pbar A negative", ["frequencies", S], lambda w: bdf(w, "PBAR           2       2  .00285", "PBAR           2       2 -.00285"))
nas("celas2 stays but param removed, K negative", ["frequencies", S],
    lambda w: (bdf(w, "CELAS2       8015000000.", "CELAS2       801-5000000."),
               sub(w / "study.toml", 'name = "k_support"\ncard = "CELAS2"\nid = 801\nfield = "K"\nstd = 2.0e6\n', 'name = "k_support"\ncard = "CONM2"\nid = 902\nfield = "M"\nstd = 2.0e6\n')))
nas("conm2 inertia negative", ["frequencies", S], lambda w: bdf(w, "CONM2        902    3002            150.", "CONM2        902    3002            150.                        \n         -10.      0.     10.      0.      0.     10."))
nas("mat1 rho negative (beams param)", ["frequencies", S], lambda w: bdf(w, "MAT1           1  2.1+11              .3   7850.", "MAT1           1  2.1+11              .3  -7850."))
nas("mat1 nu 0.5", ["frequencies", S], lambda w: bdf(w, "MAT1           1  2.1+11              .3", "MAT1           1  2.1+11              .5"))
nas("mat1 nu -1", ["frequencies", S], lambda w: bdf(w, "MAT1           1  2.1+11              .3", "MAT1           1  2.1+11             -1."))
nas("mat1 E negative non-param", ["frequencies", S],
    lambda w: (bdf(w, "MAT1           1  2.1+11", "MAT1           1 -2.1+11"),
               sub(w / "study.toml", 'name = "E_columns"\ncard = "MAT1"\nid = 1\nfield = "E"', 'name = "E_columns"\ncard = "CONM2"\nid = 903\nfield = "M"')))
nas("wtmass 0", ["frequencies", S], lambda w: bdf(w, "PARAM   COUPMASS       1", "PARAM   COUPMASS       1\nPARAM   WTMASS        0."))
nas("wtmass negative", ["frequencies", S], lambda w: bdf(w, "PARAM   COUPMASS       1", "PARAM   COUPMASS       1\nPARAM   WTMASS      -1.0"))
nas("grid coords nan", ["frequencies", S], lambda w: bdf(w, "GRID        1002              0.      3.      0.", "GRID        1002              0.     nan      0."))
nas("two grids same place", ["frequencies", S], lambda w: bdf(w, "GRID        1002              0.      3.      0.", "GRID        1002              0.      0.      0."))
MX = "mtx"


def mtx_setup(w, edit=None):
    sys.path.insert(0, str(ROOT / "tools"))
    import fuzz
    sys.path.insert(0, str(ROOT / "src"))
    fuzz._mtx(w)
    if edit:
        edit(w)


def mx(name, argv, edit=None):
    case("mtx " + name, F2, argv, lambda w: mtx_setup(w, edit))


mx("baseline", ["update", S])
mx("M param negative diag", ["frequencies", S], lambda w: (w / "m1.mtx").write_text((w / "m1.mtx").read_text().replace("1 1 1", "1 1 -1")))
mx("K param nonsymmetric general", ["frequencies", S], lambda w: (w / "k2.mtx").write_text("%%MatrixMarket matrix coordinate real general\n4 4 3\n1 1 1\n1 2 -1\n2 2 1\n"))
mx("K param nonsym 1e-12", ["frequencies", S], lambda w: (w / "k2.mtx").write_text("%%MatrixMarket matrix coordinate real general\n4 4 4\n1 1 1\n1 2 -1\n2 1 -1.000000000001\n2 2 1\n"))
mx("K param complex", ["frequencies", S], lambda w: (w / "k2.mtx").write_text("%%MatrixMarket matrix coordinate complex symmetric\n4 4 1\n1 1 1 0\n"))
mx("K param pattern", ["frequencies", S], lambda w: (w / "k2.mtx").write_text("%%MatrixMarket matrix coordinate pattern symmetric\n4 4 1\n1 1\n"))
mx("K param integer", ["frequencies", S], lambda w: (w / "k2.mtx").write_text("%%MatrixMarket matrix coordinate integer symmetric\n4 4 3\n1 1 1\n2 1 -1\n2 2 1\n"))
mx("K param skew", ["frequencies", S], lambda w: (w / "k2.mtx").write_text("%%MatrixMarket matrix coordinate real skew-symmetric\n4 4 1\n2 1 1\n"))
mx("K param upper triangle only symmetric", ["frequencies", S], lambda w: (w / "k2.mtx").write_text("%%MatrixMarket matrix coordinate real symmetric\n4 4 3\n1 1 1\n1 2 -1\n2 2 1\n"))
mx("K param wrong size", ["frequencies", S], lambda w: (w / "k2.mtx").write_text("%%MatrixMarket matrix coordinate real symmetric\n5 5 1\n1 1 1\n"))
mx("K param index 0", ["frequencies", S], lambda w: (w / "k2.mtx").write_text("%%MatrixMarket matrix coordinate real symmetric\n4 4 1\n0 0 1\n"))
mx("K param index 5", ["frequencies", S], lambda w: (w / "k2.mtx").write_text("%%MatrixMarket matrix coordinate real symmetric\n4 4 1\n5 5 1\n"))
mx("K param fewer entries", ["frequencies", S], lambda w: (w / "k2.mtx").write_text("%%MatrixMarket matrix coordinate real symmetric\n4 4 3\n1 1 1\n"))
mx("K param more entries", ["frequencies", S], lambda w: (w / "k2.mtx").write_text("%%MatrixMarket matrix coordinate real symmetric\n4 4 1\n1 1 1\n2 2 1\n3 3 1\n"))
mx("K param nan", ["frequencies", S], lambda w: (w / "k2.mtx").write_text("%%MatrixMarket matrix coordinate real symmetric\n4 4 1\n1 1 nan\n"))
mx("K param header 1e10 entries", ["frequencies", S], lambda w: (w / "k2.mtx").write_text("%%MatrixMarket matrix coordinate real symmetric\n4 4 10000000000\n1 1 1\n"))
mx("K param CRLF", ["frequencies", S], lambda w: (w / "k2.mtx").write_bytes((w / "k2.mtx").read_bytes().replace(b"\n", b"\r\n")))
mx("K param BOM", ["frequencies", S], lambda w: (w / "k2.mtx").write_bytes(b"\xef\xbb\xbf" + (w / "k2.mtx").read_bytes()))
mx("K param indefinite (negative stiffness)", ["frequencies", S], lambda w: (w / "k2.mtx").write_text("%%MatrixMarket matrix coordinate real symmetric\n4 4 3\n1 1 -1\n2 1 1\n2 2 -1\n"))
mx("K0 = study.toml", ["frequencies", S], lambda w: sub(w / "study.toml", 'K0 = "K0.mtx"', 'K0 = "study.toml"'))
mx("same mtx for two params", ["frequencies", S], lambda w: sub(w / "study.toml", 'K = "k2.mtx"', 'K = "k1.mtx"'))



def frf_opt(text):
    return lambda w: sub(w / "study.toml", "[measurement.frf]", "[measurement.frf_options]\n" + text + "\n\n[measurement.frf]")


case("frf extract exclude negative", BF, ["extract", S, "-o", "@e.csv"], frf_opt("exclude_below_hz = -5.0"))
case("frf extract exclude huge", BF, ["extract", S, "-o", "@e.csv"], frf_opt("exclude_below_hz = 1e9"))
case("frf extract bands reversed", BF, ["extract", S, "-o", "@e.csv"], frf_opt("bands_hz = [[215, 190], [530, 575]]"))
case("frf extract bands overlapping", BF, ["extract", S, "-o", "@e.csv"], frf_opt("bands_hz = [[150, 600], [500, 700]]"))
case("frf extract bands one", BF, ["extract", S, "-o", "@e.csv"], frf_opt("bands_hz = [[190, 215]]"))
case("frf extract bands outside data", BF, ["extract", S, "-o", "@e.csv"], frf_opt("bands_hz = [[1e6, 2e6], [3e6, 4e6]]"))
case("frf extract kind bogus", BF, ["extract", S, "-o", "@e.csv"], frf_opt('kind = "velocity"'))
case("frf extract kind accelerance wrong", BF, ["extract", S, "-o", "@e.csv"], frf_opt('kind = "accelerance"'))
case("frf extract frf file missing", BF, ["extract", S, "-o", "@e.csv"], lambda w: (w / "frf/base.uff").unlink())
case("frf extract frf key unknown config", BF, ["extract", S, "-o", "@e.csv"], lambda w: sub(w / "study.toml", '"base" = "frf/base.uff"', '"base" = "frf/base.uff"\n"bogus" = "frf/base.uff"'))
case("frf extract same frf for two configs", BF, ["extract", S, "-o", "@e.csv"], lambda w: sub(w / "study.toml", '"0.2 kg at 1" = "frf/0.2_kg_at_1.uff"', '"0.2 kg at 1" = "frf/base.uff"'))
case("frf update extracted other study", BF, ["update", S], lambda w: shutil.copy(EX / "paper_beam" / "measured.csv", w / "extracted.csv"))
case("frf frf --damping from other run", BF, ["frf", S, "--input", "11", "--output", "1", "--damping", "@m55.uff", "-o", "@f.png"],
     lambda w: subprocess.run([CORE, "-m", "eigenupdate", "extract", str(w / "frf/base.uff"), "-o", str(w / "x.csv"), "--uff55", str(w / "m55.uff")],
                              env=dict(os.environ, PYTHONPATH=str(ROOT / "src")), capture_output=True))
case("frf report --extraction garbage json", BF, ["report", S, "--saved-only", "--extraction", "@x.json", "-o", "@r.html"],
     lambda w: (w / "x.json").write_text('{"schema": "eigenupdate.extraction/2", "configurations": 5}'))
case("frf report --result nested json", BF, ["report", S, "--saved-only", "--result", "@x.json", "-o", "@r.html"],
     lambda w: (w / "x.json").write_text("[" * 100000 + "]" * 100000))
case("frf report --design huge number", BF, ["report", S, "--saved-only", "--design", "@x.json", "-o", "@r.html"],
     lambda w: (w / "x.json").write_text('{"a": 1e999, "b": NaN, "c": "x"}'))



def des(text, old="criterion = \"A\""):
    return lambda w: sub(w / "study.toml", old, old + "\n" + text)


for label, text in [("prior_draws 1e9", "prior_draws = 1000000000"), ("prior_draws -1", "prior_draws = -1"),
                    ("max_added_mass 0", "max_added_mass = 0.0"), ("min_shift 1e9", "min_shift_in_std = 1e9"),
                    ("gap 2", "min_relative_gap = 2.0"), ("risk -1", "max_exchange_risk = -1.0"),
                    ("additions 1e9", "additions = 1000000000"), ("rel std 10", "frequency_std_relative = 10.0"),
                    ("stiffnesses neg", "stiffnesses = [-1e5]"), ("unknown key", "bogus = 1"),
                    ("criterion unknown param", "criterion = [\"nope\"]")]:
    case("fig2 design " + label, F2, ["design", S, "-o", "@p.toml"], des(text))
case("beam design prior_draws 1e6", "paper_beam", ["design", S, "-o", "@p.toml"],
     lambda w: sub(w / "study.toml", "[design]", "[design]\nprior_draws = 1000000"))
case("fig2 design masses 1e-90", F2, ["design", S, "-o", "@p.toml"],
     lambda w: sub(w / "study.toml", "masses = [0.35, 1.0, 2.0]", "masses = [1e-90]"))
case("fig2 design masses 1e90", F2, ["design", S, "-o", "@p.toml"],
     lambda w: sub(w / "study.toml", "masses = [0.35, 1.0, 2.0]", "masses = [1e90]"))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("-k", default="")
    ap.add_argument("--start", type=int, default=0, help="skip the first cases")
    ap.add_argument("--keep", action="store_true", help="print stdout and stderr")
    a = ap.parse_args()
    for c in CASES[a.start:]:
        if a.k in c[0]:
            run(*c, keep=a.keep)


if __name__ == "__main__":
    sys.exit(main())
