# ruff: noqa: E501  (a table of cases, one per line)
"""Fourth round of hostile and wrong-data cases (tools/hostile.py runs the first,
tools/hostile_round2.py and tools/hostile_round3.py the next): the newest features
(CSHEAR/PSHEAR, ZOFFS on CQUAD8/CTRIA6, PARAM SNORM, saved extractions of schema
extraction/2, the reduced-model step, --scheduler addresses), studies asking for more
modes than the model has, UFF files with NaN frequencies, EIGRL asking for nothing, and
the leftovers of round 3 (outputs over files a command did not write, blank ids on
cards other than GRID). Same harness and output as tools/hostile.py:

    python tools/hostile_round4.py [-k SUBSTRING] [--keep]
"""

from __future__ import annotations

import json
import struct
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import hostile as h  # noqa: E402
from hostile import NASTRAN, case, sub  # noqa: E402

h.CASES.clear()
S = "@study.toml"
F2, BF, NF, SP = "paper_fig2", "paper_beam_frf", "nastran_frame", "stiffened_panel"


def nf(name, argv, mutate=None):
    case("nas4 " + name, NF, argv, mutate, NASTRAN)


def sp(name, argv, mutate=None):
    case("panel4 " + name, SP, argv, mutate, NASTRAN)


def frame(old, new):
    return lambda w: sub(w / "frame.bdf", old, new)


# ------------------------------------------------------------------ CSHEAR / PSHEAR on the panel's first skin quad
Q1 = "CQUAD4,1,1,1,2,1002,1001"


def shear(card="CSHEAR,1,9,1,2,1002,1001", pshear="PSHEAR,9,1,0.002"):
    def mutate(w):
        sub(w / "mesh.bdf", Q1, card)
        sub(w / "panel.bdf", "MAT1,", pshear + "\nMAT1,")
    return mutate


sp("cshear baseline (one skin quad a shear panel)", ["frequencies", S], shear())
sp("pshear F1 = 1 (extensional effectiveness)", ["frequencies", S], shear(pshear="PSHEAR,9,1,0.002,,1.0"))
sp("pshear F2 = 0.5", ["frequencies", S], shear(pshear="PSHEAR,9,1,0.002,,,0.5"))
sp("pshear F1 text", ["frequencies", S], shear(pshear="PSHEAR,9,1,0.002,,abc"))
sp("pshear T = 0", ["frequencies", S], shear(pshear="PSHEAR,9,1,0."))
sp("cshear zero area (four collinear grids)", ["frequencies", S], shear(card="CSHEAR,1,9,1,2,3,4"))
sp("cshear inside-out (bow tie)", ["frequencies", S], shear(card="CSHEAR,1,9,1,2,1001,1002"))
sp("cshear clockwise (same panel, other order)", ["frequencies", S], shear(card="CSHEAR,1,9,1,1001,1002,2"))
sp("cshear a grid twice", ["frequencies", S], shear(card="CSHEAR,1,9,1,2,2,1001"))


# ------------------------------------------------------------------ ZOFFS on CQUAD8 / CTRIA6: a 4 x 4 clamped plate
def quadratic_plate(triangles=False, zoffs="", pshell="PSHELL,1,1,0.005,1,,1", component=3, theta=""):
    """A 0.4 m steel plate clamped at x = 0, 4 x 4 CQUAD8 (or 32 CTRIA6), its study."""
    def mutate(w):
        n = 9  # 2 nx + 1 grid lines
        ids = {}
        lines = ["SOL 103", "CEND", "SPC = 1", "BEGIN BULK", pshell, "MAT1,1,2.0e11,,0.3,7850."]
        for i in range(n):
            for j in range(n):
                if triangles or not (i % 2 and j % 2):
                    ids[i, j] = len(ids) + 1
                    lines.append(f"GRID,{ids[i, j]},,{0.05 * i},{0.05 * j},0.")
        eid = 0
        for i in range(0, n - 1, 2):
            for j in range(0, n - 1, 2):
                c = {(a, b): ids.get((i + a, j + b)) for a in range(3) for b in range(3)}
                if triangles:
                    for g in ([c[0, 0], c[2, 0], c[2, 2], c[1, 0], c[2, 1], c[1, 1]],
                              [c[0, 0], c[2, 2], c[0, 2], c[1, 1], c[1, 2], c[0, 1]]):
                        eid += 1
                        lines.append(f"CTRIA6,{eid},1,{','.join(map(str, g))}" + (f"\n,{theta},{zoffs}" if zoffs or theta else ""))  # continuation: THETA, ZOFFS
                else:
                    eid += 1
                    g = [c[0, 0], c[2, 0], c[2, 2], c[0, 2], c[1, 0], c[2, 1], c[1, 2], c[0, 1]]
                    lines.append(f"CQUAD8,{eid},1,{','.join(map(str, g[:6]))}\n,{g[6]},{g[7]}" + (f",,,,,,{zoffs}" if zoffs else ""))  # T1-T4, THETA
        lines += [f"SPC1,1,123456,{ids[0, j]}" for j in range(n)] + ["ENDDATA"]
        (w / "plate.bdf").write_text("\n".join(lines) + "\n")
        (w / "study.toml").write_text(
            'title = "quadratic plate"\n[model]\ntype = "nastran"\nbdf = "plate.bdf"\n'
            '[[model.parameter]]\nname = "t"\ncard = "PSHELL"\nid = 1\nfield = "T"\nstd = 5e-4\n'
            f'[[perturbation]]\nname = "m"\ngrid = {ids[n - 1, n - 1]}\ncomponent = {component}\nmass = 0.5\n'
            '[measurement]\nfrequencies = "p.csv"\nmodes = [1, 2, 3]\n')
        (w / "p.csv").write_text("configuration,mode,frequency_hz,std_hz\n" + "".join(
            f"{c},{k},{f},0.1\n" for c in ("base", "m") for k, f in ((1, 25.0), (2, 61.0), (3, 153.0))))
    return mutate


sp("cquad8 plate baseline", ["frequencies", S], quadratic_plate())
sp("cquad8 zoffs nan", ["frequencies", S], quadratic_plate(zoffs="nan"))
sp("cquad8 zoffs 1e10", ["frequencies", S], quadratic_plate(zoffs="1e10"))
sp("cquad8 zoffs text", ["frequencies", S], quadratic_plate(zoffs="up"))
sp("ctria6 zoffs without MID2", ["frequencies", S], quadratic_plate(True, "0.001", "PSHELL,1,1,0.005", component=1))
sp("ctria6 zoffs -inf", ["frequencies", S], quadratic_plate(True, "-inf"))
sp("ctria6 THETA -inf (MAT1: no material axes)", ["frequencies", S], quadratic_plate(True, theta="-inf"))



def pcomp_theta(theta):
    """The panel's skin a [0/90] PCOMP (its t_skin parameter dropped), quad 1 at THETA."""
    def mutate(w):
        sub(w / "panel.bdf", "PSHELL,1,1,0.002,1,,1", "PCOMP,1\n,1,0.001,0.\n,1,0.001,90.")
        sub(w / "mesh.bdf", Q1, Q1 + f",{theta}")
        text = (w / "study.toml").read_text()
        start = text.index('[[model.parameter]]\nname = "t_skin"')
        (w / "study.toml").write_text(text[:start] + text[text.index("[[model.parameter]]", start + 1):])
    return mutate


sp("pcomp skin quad THETA inf", ["frequencies", S], pcomp_theta("inf"))
sp("pcomp skin quad THETA nan", ["frequencies", S], pcomp_theta("nan"))
sp("pcomp skin quad THETA 1e300", ["frequencies", S], pcomp_theta("1e300"))

# ------------------------------------------------------------------ PARAM SNORM (the panel: flat, so normals change nothing)
for label, value in [("negative", "-5."), ("text", "YES"), ("huge", "1e300"), ("nan", "nan"), ("integer 20", "20")]:
    sp("param snorm " + label, ["frequencies", S], lambda w, v=value: sub(w / "panel.bdf", "PARAM,COUPMASS,1", f"PARAM,COUPMASS,1\nPARAM,SNORM,{v}"))


# ------------------------------------------------------------------ extraction/2 files edited by hand
def saved_extraction(edit):
    def mutate(w):
        h.subprocess.run([h.CORE, "-m", "eigenupdate", "extract", str(w / "study.toml"), "-o", str(w / "x.csv"), "--save", str(w / "x.json")],
                         env=dict(h.os.environ, PYTHONPATH=str(h.ROOT / "src")), capture_output=True)
        doc = json.loads((w / "x.json").read_text())
        edit(doc)
        (w / "x.json").write_text(json.dumps(doc, indent=2))
    return mutate


def drop_hashes(doc):
    for files in doc["frfs"].values():
        for f in files:
            f.pop("sha256", None)


def set_key(key, value):
    return lambda doc: doc.__setitem__(key, value)


REP = ["report", S, "--saved-only", "--extraction", "@x.json", "-o", "@r.html"]
case("frf4 extraction hash field removed", BF, REP, saved_extraction(drop_hashes))
case("frf4 extraction schema /1", BF, REP, saved_extraction(set_key("schema", "eigenupdate.extraction/1")))
case("frf4 extraction schema /3", BF, REP, saved_extraction(set_key("schema", "eigenupdate.extraction/3")))
case("frf4 extraction schema of an update", BF, REP, saved_extraction(set_key("schema", "eigenupdate.update/2")))
case("frf4 extraction frfs table removed", BF, REP, saved_extraction(lambda d: d.pop("frfs")))

# ------------------------------------------------------------------ the reduced-model step (the panel: > 400 coordinates)
sp("reduced step: update with a mass of 1e6 kg", ["update", S], lambda w: sub(w / "study.toml", "mass = 0.1", "mass = 1e6"))
sp("reduced step: update from a start 50x off", ["update", S], lambda w: sub(w / "panel.bdf", "MAT1,1,7.0e10", "MAT1,1,3.5e12"))
sp("reduced step: update with every frequency of 'base' 100 Hz", ["update", S],
   lambda w: h.csv_map(w / "measured.csv", lambda ln: ln.replace(ln.split(",")[2], "100.0", 1) if ln.startswith("base,") else ln))

# ------------------------------------------------------------------ --scheduler addresses
for label, address in [("port leading zero", "tcp://127.0.0.1:01"), ("port plus sign", "tcp://127.0.0.1:+1"),
                       ("port with space", "tcp://127.0.0.1: 1"), ("query", "tcp://127.0.0.1:1?x=1"), ("fragment", "tcp://127.0.0.1:1#x"),
                       ("upper-case scheme", "TCP://127.0.0.1:1"), ("percent-encoded host", "tcp://%31%32%37.0.0.1:1"),
                       ("ipv6 port 99999", "tcp://[::1]:99999"), ("tls scheme", "tls://127.0.0.1:1"),
                       ("control character", "tcp://127.0.0.1:1\x01"), ("10000 characters", "tcp://" + "a" * 10000 + ":1")]:
    case("fig2 mc4 scheduler " + label, F2, ["montecarlo", S, "--trials", "3", "--scheduler", address])
case("fig2 mc4 env scheduler user info", F2, ["montecarlo", S, "--trials", "3"], env={"EIGENUPDATE_SCHEDULER": "tcp://u@127.0.0.1:1"})  # '@' is the harness's

# ------------------------------------------------------------------ more modes than the model has
case("fig2 modes 1..5 of a 4-coordinate model", F2, ["update", S],
     lambda w: (sub(w / "study.toml", "modes = [1, 2, 3]", "modes = [1, 2, 3, 5]"),
                (w / "measured.csv").write_text((w / "measured.csv").read_text() + "".join(
                    f"{c},5,200.0,\n" for c in dict.fromkeys(ln.split(",")[0] for ln in (w / "measured.csv").read_text().splitlines()[1:])))))
case("fig2 check modes [4] only", F2, ["check", S], lambda w: sub(w / "study.toml", "modes = [1, 2, 3]", "modes = [4]"))
sp("panel modes up to 100000", ["check", S], lambda w: sub(w / "study.toml", "modes = [1, 2, 3, 4, 5, 6]", "modes = [1, 2, 100000]"))
case("fig2 frequencies --modes 1000000", F2, ["frequencies", S, "--modes", "1000000"])

# ------------------------------------------------------------------ UFF with NaN frequencies (record 7: abscissa start, increment)
UFF_AXIS = "  5.00000e-01  5.00000e-01"
for label, axis in [("start nan", "          nan  5.00000e-01"), ("increment nan", "  5.00000e-01          nan"),
                    ("increment inf", "  5.00000e-01          inf"), ("increment negative", "  5.00000e-01 -5.00000e-01")]:
    case("frf4 uff abscissa " + label, BF, ["extract", S, "-o", "@x.csv"],
         lambda w, a=axis: (w / "frf" / "base.uff").write_bytes((w / "frf" / "base.uff").read_bytes().replace(UFF_AXIS.encode(), a.encode(), 1)))



def uff_value(value):
    """One ordinate of the last FRF of base.uff (binary 58b, 25600 data bytes before the
    closing '    -1' line) replaced by a little-endian double ``value``."""
    def mutate(w):
        f = w / "frf" / "base.uff"
        b = bytearray(f.read_bytes())
        at = len(b) - 7 - 25600 + 800
        b[at:at + 8] = struct.pack("<d", value)
        f.write_bytes(bytes(b))
    return mutate


case("frf4 uff ordinate nan", BF, ["extract", S, "-o", "@x.csv"], uff_value(float("nan")))
case("frf4 uff ordinate inf", BF, ["extract", S, "-o", "@x.csv"], uff_value(float("inf")))
case("frf4 uff ordinate 1e300", BF, ["extract", S, "-o", "@x.csv"], uff_value(1e300))

# ------------------------------------------------------------------ EIGRL asking for nothing
EIGRL = "EIGRL         10                      12"
nf("eigrl ND = 0", ["frequencies", S], frame(EIGRL, "EIGRL         10                       0"))
nf("eigrl negative range", ["frequencies", S], frame(EIGRL, "EIGRL         10   -100.    -10."))
nf("eigrl ND = -5", ["frequencies", S], frame(EIGRL, "EIGRL         10                      -5"))

# ------------------------------------------------------------------ leftovers: outputs, blank ids
case("fig2 simulate -o over it --force", F2, ["simulate", "@truth.toml", "-o", "@measured.csv", "--force"])
case("fig2 sweep -o over truth.toml", F2, ["sweep", S, "--coordinate", "1", "--max-mass", "1", "-o", "@truth.png"],
     lambda w: (w / "truth.toml").rename(w / "truth.png"))
case("frf4 extract -o over the study's own measurement file written by hand", BF, ["extract", S, "-o", "@extracted.csv"],
     lambda w: (w / "extracted.csv").write_text("configuration,mode,frequency_hz,std_hz\nbase,1,200.0,0.1\n"))
case("frf4 extract --plots over a foreign extract_base_1.png", BF, ["extract", S, "-o", "@x.csv", "--plots", "@plots"],
     lambda w: ((w / "plots").mkdir(), (w / "plots" / "extract_base_1.png").write_bytes(b"\x89PNG\r\n\x1a\n photo")))
nf("cbar blank EID", ["check", S], frame("CBAR         101       1    1001", "CBAR                 1    1001"))
nf("mat1 blank MID", ["check", S], frame("MAT1           1  2.1+11", "MAT1              2.1+11"))
sp("cquad4 blank EID in the INCLUDEd mesh", ["check", S], lambda w: sub(w / "mesh.bdf", Q1, "CQUAD4,,1,1,2,1002,1001"))
sp("cquad4 blank PID (NASTRAN: PID = EID)", ["check", S], lambda w: sub(w / "mesh.bdf", Q1, "CQUAD4,1,,1,2,1002,1001"))


if __name__ == "__main__":
    sys.exit(h.main())
