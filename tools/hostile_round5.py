# ruff: noqa: E501  (a table of cases, one per line)
"""Fifth round of hostile and wrong-data cases (tools/hostile.py runs the first,
tools/hostile_round2..4.py the next): NASTRAN elements the earlier rounds left alone
(warped CQUAD4 between and above the warning levels, inside-out quadratic shells, solids
with negative Jacobians, MAT8, RBE3, CQUADR/CTRIAR, PCOMP plies of NaN), INCLUDE loops,
[model] subcase, study files of wrong types, NaN and duplicate tables, binary UFF 58b
headers declaring 0 or 10^9 points, files of 10 GB, and the leftovers of round 4
(simulate-frf -o DIR over files it did not write, a long refusal line from extract -o).
Same harness and output as tools/hostile.py, plus a case's own check (flag in capitals):

    python tools/hostile_round5.py [-k SUBSTRING] [--keep]
"""

from __future__ import annotations

import os
import re
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import hostile as h  # noqa: E402
import hostile_round4 as r4  # noqa: E402  (its quadratic plate and shear panel)
from hostile import NASTRAN, case, sub  # noqa: E402

h.CASES.clear()
S = "@study.toml"
F2, B, BF, NF, SP = "paper_fig2", "paper_beam", "paper_beam_frf", "nastran_frame", "stiffened_panel"
Q1 = r4.Q1


def nf(name, argv, mutate=None, check=None):
    case("nas5 " + name, NF, argv, mutate, NASTRAN, check=check)


def sp(name, argv, mutate=None, check=None):
    case("panel5 " + name, SP, argv, mutate, NASTRAN, check=check)


def both(*fns):
    def mutate(w):
        for f in fns:
            f(w)
    return mutate


def edit(file, old, new, count=1):
    return lambda w: sub(w / file, old, new, count)


def drop_param(name):
    """The study without its parameter ``name`` (a card the case replaces)."""
    def mutate(w):
        text = (w / "study.toml").read_text()
        start = text.index(f'[[model.parameter]]\nname = "{name}"')
        end = text.find("[[", start + 2)
        (w / "study.toml").write_text(text[:start] + text[end:])
    return mutate


# ------------------------------------------------------------------ warped CQUAD4 (panel skin: 25 mm squares)
def lift(*grids, dz):
    """Skin grids ``grids`` moved dz off the skin's plane: the four quads round each warp
    by about 10 dz (a corner dz / 4 off the mean plane, over sqrt(area) = 0.025)."""
    def mutate(w):
        text = (w / "mesh.bdf").read_text()
        for g in grids:
            text = re.sub(rf"^(GRID,{g},,[^,]*,[^,]*),0\.$", rf"\g<1>,{dz}", text, count=1, flags=re.M)
        (w / "mesh.bdf").write_text(text)
    return mutate


def warp_warnings(code, err):
    """Flag WARN if a warp warning repeats (one per element, not one per assembly slice)."""
    lines = [ln for ln in err.splitlines() if "warped" in ln and "warning" in ln]
    if code == 0 and not lines:
        return "NOWARN"
    if len(lines) != len(set(lines)) or len(lines) > 1:
        return f"WARN{len(lines)}x"
    return None


sp("cquad4 warp 0.5 (one grid 50 mm up)", ["check", S], lift(1002, dz=0.05))
sp("cquad4 warp 0.1 (one grid 10 mm up)", ["frequencies", S], lift(1002, dz=0.01), warp_warnings)
sp("cquad4 warp 0.1 at three grids far apart", ["frequencies", S], lift(1002, 5012, 10020, dz=0.01), warp_warnings)
sp("cquad4 warp 0.1 in the skin and in a blade (two properties)", ["frequencies", S],
   both(lift(1002, dz=0.01), edit("mesh.bdf", "GRID,104010,,0.225000,0.100000,", "GRID,104010,,0.225000,0.108000,")), warp_warnings)
sp("cquad4 warp 0.1 update (assembled at every step)", ["update", S], lift(1002, dz=0.01), warp_warnings)
sp("cquad4 warp 0.1 simulate truth", ["simulate", "@truth.toml", "-o", "@sim.csv"], both(lift(1002, dz=0.01), edit("truth.toml", 'bdf = "truth.bdf"', 'bdf = "panel.bdf"')), warp_warnings)


# ------------------------------------------------------------------ inside-out quadratic shells (round 4's plate)
def first_element(fn, triangles=False):
    """The quadratic plate with its first element's grid list (8 or 6 ids) rewritten by ``fn``."""
    def mutate(w):
        r4.quadratic_plate(triangles)(w)
        text = (w / "plate.bdf").read_text()
        if triangles:
            m = re.search(r"^CTRIA6,1,1,([\d,]+)$", text, re.M)
            g = m.group(1).split(",")
            text = text.replace(m.group(0), "CTRIA6,1,1," + ",".join(fn(g)), 1)
        else:
            m = re.search(r"^CQUAD8,1,1,([\d,]+)\n,([\d,]+)$", text, re.M)
            g = (m.group(1) + "," + m.group(2)).split(",")
            g = fn(g)
            text = text.replace(m.group(0), f"CQUAD8,1,1,{','.join(g[:6])}\n,{g[6]},{g[7]}", 1)
        (w / "plate.bdf").write_text(text)
    return mutate


sp("cquad8 bow tie (corners 1 2 4 3)", ["frequencies", S], first_element(lambda g: [g[0], g[1], g[3], g[2], g[4], g[5], g[6], g[7]]))
sp("cquad8 mid-side node on a corner", ["frequencies", S], first_element(lambda g: g[:4] + [g[0]] + g[5:]))
sp("cquad8 mid-sides rotated (each on the wrong edge)", ["frequencies", S], first_element(lambda g: g[:4] + [g[5], g[6], g[7], g[4]]))
sp("ctria6 corners twice (zero area)", ["frequencies", S], first_element(lambda g: [g[0], g[1], g[0], g[3], g[4], g[5]], True))
sp("ctria6 mid-sides swapped (inside out)", ["frequencies", S], first_element(lambda g: g[:3] + [g[5], g[3], g[4]], True))


# ------------------------------------------------------------------ solids: a 4 x 1 x 1 steel bar, clamped at x = 0
def solid_bar(tet10=False, first=None):
    """CHEXA (or CTETRA10, six per cube) bar 0.4 x 0.1 x 0.1 m; ``first`` rewrites the
    first element's grid list."""
    def mutate(w):
        gid = {(i, j, k): 1 + i + 5 * (j + 2 * k) for i in range(5) for j in range(2) for k in range(2)}
        lines = ["SOL 103", "CEND", "SPC = 1", "BEGIN BULK", "PSOLID,1,1", "MAT1,1,2.0e11,,0.3,7850."]
        lines += [f"GRID,{g},,{0.1 * i},{0.1 * j},{0.1 * k}" for (i, j, k), g in gid.items()]
        mid: dict = {}
        elements = []
        for i in range(4):
            c = [gid[i + a, b, z] for z in (0, 1) for (a, b) in ((0, 0), (1, 0), (1, 1), (0, 1))]
            if not tet10:
                elements.append(("CHEXA", c))
                continue
            for t in ((0, 1, 2, 6), (0, 2, 3, 6), (0, 3, 7, 6), (0, 7, 4, 6), (0, 4, 5, 6), (0, 5, 1, 6)):
                v = [c[n] for n in t]
                edges = [(v[0], v[1]), (v[1], v[2]), (v[2], v[0]), (v[0], v[3]), (v[1], v[3]), (v[2], v[3])]
                elements.append(("CTETRA", v + [mid.setdefault(tuple(sorted(e)), 1000 + len(mid)) for e in edges]))
        xyz = {g: (0.1 * i, 0.1 * j, 0.1 * k) for (i, j, k), g in gid.items()}
        for (a, b), g in mid.items():
            lines.append("GRID,{},,{},{},{}".format(g, *((p + q) / 2 for p, q in zip(xyz[a], xyz[b], strict=True))))
        for n, (card, g) in enumerate(elements, 1):
            if n == 1 and first:
                g = first(g)
            lines.append(f"{card},{n},1,{','.join(map(str, g[:6]))}\n,{','.join(map(str, g[6:]))}")
        lines += [f"SPC1,1,123456,{g}" for (i, j, k), g in gid.items() if i == 0] + ["ENDDATA"]
        (w / "bar.bdf").write_text("\n".join(lines) + "\n")
        (w / "study.toml").write_text(
            'title = "solid bar"\n[model]\ntype = "nastran"\nbdf = "bar.bdf"\n'
            '[[model.parameter]]\nname = "E"\ncard = "MAT1"\nid = 1\nfield = "E"\nstd = 1e10\n'
            '[[perturbation]]\nname = "m"\ngrid = 5\ncomponent = 3\nmass = 0.5\n'
            '[measurement]\nfrequencies = "p.csv"\nmodes = [1, 2]\n')
        (w / "p.csv").write_text("configuration,mode,frequency_hz,std_hz\n" + "".join(
            f"{c},{k},{f},1.0\n" for c in ("base", "m") for k, f in ((1, 500.0), (2, 510.0))))
    return mutate


sp("chexa bar baseline", ["frequencies", S], solid_bar())
sp("chexa faces swapped (negative Jacobian)", ["frequencies", S], solid_bar(first=lambda g: g[4:] + g[:4]))
sp("chexa two corners swapped (twisted)", ["frequencies", S], solid_bar(first=lambda g: [g[1], g[0]] + g[2:]))
sp("ctetra10 bar baseline", ["frequencies", S], solid_bar(True))
sp("ctetra10 two corners swapped (negative volume)", ["frequencies", S], solid_bar(True, lambda g: [g[1], g[0]] + g[2:]))
sp("ctetra10 mid-edge node on a corner", ["frequencies", S], solid_bar(True, lambda g: g[:4] + [g[0]] + g[5:]))


# ------------------------------------------------------------------ PCOMP / MAT8 on the panel's skin
def skin(pcomp, mat=""):
    return both(drop_param("t_skin"), edit("panel.bdf", "PSHELL,1,1,0.002,1,,1", pcomp + ("\n" + mat if mat else "")))


MAT8 = "MAT8,8,1.4e11,1.0e10,0.3,5.0e9,5.0e9,5.0e9,1600."
CROSS8 = "PCOMP,1\n,8,0.001,0.\n,8,0.001,90."
sp("pcomp ply T nan", ["frequencies", S], skin("PCOMP,1\n,1,nan,0.\n,1,0.001,90."))
sp("pcomp ply angle nan", ["frequencies", S], skin("PCOMP,1\n,1,0.001,nan\n,1,0.001,90."))
sp("pcomp ply T 1e300", ["frequencies", S], skin("PCOMP,1\n,1,1e300,0.\n,1,0.001,90."))
sp("mat8 baseline [0/90]", ["frequencies", S], skin(CROSS8, MAT8))
sp("mat8 E1 = 0", ["frequencies", S], skin(CROSS8, MAT8.replace("1.4e11", "0.")))
sp("mat8 E1 negative", ["frequencies", S], skin(CROSS8, MAT8.replace("1.4e11", "-1.4e11")))
sp("mat8 nu12^2 > E1/E2 (nu12 = 4)", ["frequencies", S], skin(CROSS8, MAT8.replace(",0.3,", ",4.0,")))
sp("mat8 G12 = 0", ["frequencies", S], skin(CROSS8, MAT8.replace("5.0e9,5.0e9,5.0e9", "0.,5.0e9,5.0e9")))

# ------------------------------------------------------------------ RBE3: a grid 20 mm above the skin centre
RBE3_GRID = "GRID,99001,,0.3,0.2,0.02\nCONM2,99002,99001,,1.0"


def rbe3(card):
    return edit("panel.bdf", "MAT1,", RBE3_GRID + "\n" + card + "\nMAT1,")


sp("rbe3 baseline (four skin grids round it)", ["frequencies", S], rbe3("RBE3,99003,,99001,123456,1.0,123,8012,8014\n,7013,9013"))
sp("rbe3 weight 0", ["frequencies", S], rbe3("RBE3,99003,,99001,123456,0.0,123,8012,8014\n,7013,9013"))
sp("rbe3 weight negative", ["frequencies", S], rbe3("RBE3,99003,,99001,123456,-1.0,123,8012,8014\n,7013,9013"))
sp("rbe3 weight nan", ["frequencies", S], rbe3("RBE3,99003,,99001,123456,nan,123,8012,8014\n,7013,9013"))
sp("rbe3 independent grids collinear", ["frequencies", S], rbe3("RBE3,99003,,99001,123456,1.0,123,8012,8013,8014"))
sp("rbe3 one independent grid", ["frequencies", S], rbe3("RBE3,99003,,99001,123456,1.0,123,8013"))

# ------------------------------------------------------------------ CQUADR / CTRIAR with bad properties
QR = "CQUADR,1,{pid},1,2,1002,1001"
TR = "CTRIAR,1,{pid},1,2,1002\nCTRIAR,99004,{pid},1,1002,1001"
sp("cquadr baseline", ["frequencies", S], edit("mesh.bdf", Q1, QR.format(pid=1)))
sp("cquadr property a PSHEAR", ["frequencies", S], both(edit("mesh.bdf", Q1, QR.format(pid=9)), edit("panel.bdf", "MAT1,", "PSHEAR,9,1,0.002\nMAT1,")))
sp("cquadr PSHELL material missing", ["frequencies", S], both(edit("mesh.bdf", Q1, QR.format(pid=9)), edit("panel.bdf", "MAT1,", "PSHELL,9,77,0.002,77,,77\nMAT1,")))
sp("ctriar PSHELL T = 0", ["frequencies", S], both(edit("mesh.bdf", Q1, TR.format(pid=9)), edit("panel.bdf", "MAT1,", "PSHELL,9,1,0.,1,,1\nMAT1,")))
sp("ctriar PSHELL bending only (MID1 blank)", ["frequencies", S], both(edit("mesh.bdf", Q1, TR.format(pid=9)), edit("panel.bdf", "MAT1,", "PSHELL,9,,0.002,1,,1\nMAT1,")))
sp("ctriar property missing", ["frequencies", S], edit("mesh.bdf", Q1, TR.format(pid=55)))

# ------------------------------------------------------------------ PSHEAR F1 / F2 negative
sp("pshear F1 negative", ["frequencies", S], r4.shear(pshear="PSHEAR,9,1,0.002,,-1.0"))
sp("pshear F2 negative", ["frequencies", S], r4.shear(pshear="PSHEAR,9,1,0.002,,,-0.5"))

# ------------------------------------------------------------------ INCLUDE
sp("include itself (loop)", ["check", S], edit("mesh.bdf", "$ stiffened panel", "INCLUDE 'mesh.bdf'\n$ stiffened panel"))
sp("include loop through panel.bdf", ["check", S], edit("mesh.bdf", "$ stiffened panel", "INCLUDE 'panel.bdf'\n$ stiffened panel"))
sp("include missing file", ["check", S], edit("panel.bdf", "INCLUDE 'mesh.bdf'", "INCLUDE 'mesh2.bdf'"))
sp("include a directory", ["check", S], edit("panel.bdf", "INCLUDE 'mesh.bdf'", "INCLUDE 'mesh.bdf'\nINCLUDE '.'"))
sp("include /dev/zero", ["check", S], edit("panel.bdf", "INCLUDE 'mesh.bdf'", "INCLUDE 'mesh.bdf'\nINCLUDE '/dev/zero'"))
sp("include the study.toml", ["check", S], edit("panel.bdf", "INCLUDE 'mesh.bdf'", "INCLUDE 'mesh.bdf'\nINCLUDE 'study.toml'"))

# ------------------------------------------------------------------ parameters on fields that do not exist, subcases
sp("param PSHELL field T5", ["check", S], edit("study.toml", 'id = 1\nfield = "T"', 'id = 1\nfield = "T5"'))
sp("param PSHELL field E (a MAT1 field)", ["check", S], edit("study.toml", 'id = 1\nfield = "T"', 'id = 1\nfield = "E"'))
sp("param PSHELL field 3 (a number)", ["check", S], edit("study.toml", 'id = 1\nfield = "T"', 'id = 1\nfield = 3'))
nf("model subcase 7 (deck has 1)", ["check", S], edit("study.toml", 'bdf = "frame.bdf"', 'bdf = "frame.bdf"\nsubcase = 7'))
nf("model subcase 0", ["check", S], edit("study.toml", 'bdf = "frame.bdf"', 'bdf = "frame.bdf"\nsubcase = 0'))
nf("model subcase -1", ["check", S], edit("study.toml", 'bdf = "frame.bdf"', 'bdf = "frame.bdf"\nsubcase = -1'))
nf("model subcase \"1\"", ["check", S], edit("study.toml", 'bdf = "frame.bdf"', 'bdf = "frame.bdf"\nsubcase = "1"'))
nf("model subcase 1e999", ["check", S], edit("study.toml", 'bdf = "frame.bdf"', 'bdf = "frame.bdf"\nsubcase = 1e999'))
case("fig2 subcase on a spring-mass study", F2, ["check", S], edit("study.toml", 'type = "spring-mass"', 'type = "spring-mass"\nsubcase = 1'))

# ------------------------------------------------------------------ study files: types, NaN, duplicate tables, units
case("fig2 modes a string", F2, ["check", S], edit("study.toml", "modes = [1, 2, 3]", 'modes = "1,2,3"'))
case("fig2 pert coordinate true", F2, ["check", S], edit("study.toml", "coordinate = 1\nmass = 0.35", "coordinate = true\nmass = 0.35"))
case("fig2 pert mass true", F2, ["check", S], edit("study.toml", "coordinate = 1\nmass = 0.35", "coordinate = 1\nmass = true"))
case("fig2 pert mass nan", F2, ["check", S], edit("study.toml", "coordinate = 1\nmass = 0.35", "coordinate = 1\nmass = nan"))
case("fig2 model mass nan", F2, ["check", S], edit("study.toml", "value = 9.7  # kg", "value = nan"))
case("fig2 model spring inf", F2, ["check", S], edit("study.toml", "value = 6.000e+05  # N/m", "value = inf"))
case("fig2 model mass a date", F2, ["check", S], edit("study.toml", "value = 9.7  # kg", "value = 1979-05-27"))
case("fig2 title a table", F2, ["check", S], edit("study.toml", 'title = "Paper Fig. 2 system, initial model (Table 4)"', "title = {a = 1}"))
case("fig2 measurement table twice", F2, ["check", S], lambda w: (w / "study.toml").write_text((w / "study.toml").read_text() + '\n[measurement]\nmodes = [1]\n'))
case("fig2 modes key twice", F2, ["check", S], edit("study.toml", "modes = [1, 2, 3]", "modes = [1, 2, 3]\nmodes = [1, 2]"))
case("fig2 model.mass an inline table and an array", F2, ["check", S], edit("study.toml", "[model]", "[model]\nmass = 3"))
case("fig2 two masses named m1", F2, ["check", S], edit("study.toml", 'name = "m2"', 'name = "m1"'))
case("fig2 unit N/m on a mass", F2, ["check", S], edit("study.toml", "value = 9.7  # kg", 'value = 9.7\nunit = "N/m"'))
sp("unit Pa on PSHELL T", ["check", S], edit("study.toml", 'unit = "m"', 'unit = "Pa"'))
sp("unit m on MAT1 E", ["check", S], edit("study.toml", 'unit = "Pa"', 'unit = "m"'))
case("beam point mass negative", B, ["check", S], edit("study.toml", 'name = "m_L"\ncoordinate = 11\nvalue = 0.0', 'name = "m_L"\ncoordinate = 11\nvalue = -0.1'))
case("beam mass_per_length negative", B, ["check", S], edit("study.toml", "mass_per_length = 3.4", "mass_per_length = -3.4"))
sp("pert mass negative at a grid", ["check", S], edit("study.toml", "component = 3\nmass = 0.1", "component = 3\nmass = -0.1"))
case("fig2 pert coordinate 5 of 4", F2, ["check", S], edit("study.toml", "coordinate = 4\nmass = 0.35", "coordinate = 5\nmass = 0.35"))
case("beam pert coordinate 19 of 18", B, ["check", S], edit("study.toml", "coordinate = 17\nmass = 0.2", "coordinate = 19\nmass = 0.2"))
case("fig2 mc truth with other parameter names", F2, ["montecarlo", S, "--trials", "3", "--in-process", "--truth", "@truth.toml"],
     edit("truth.toml", 'name = "m1"', 'name = "mass1"'))
case("fig2 mc truth without a parameter", F2, ["montecarlo", S, "--trials", "3", "--in-process", "--truth", "@truth.toml"],
     edit("truth.toml", '[[model.spring]]\nname = "k6"\ncoordinates = [0, 4]\nvalue = 5.000e+05  # N/m\n', ""))

# ------------------------------------------------------------------ empty files and garbage
GARBAGE = bytes(range(256)) * 8
case("fig2 study empty", F2, ["check", S], lambda w: (w / "study.toml").write_text(""))
case("fig2 study binary garbage", F2, ["check", S], lambda w: (w / "study.toml").write_bytes(GARBAGE))
case("fig2 simulate truth empty", F2, ["simulate", "@truth.toml", "-o", "@s.csv"], lambda w: (w / "truth.toml").write_text(""))
nf("deck binary garbage", ["check", S], lambda w: (w / "frame.bdf").write_bytes(GARBAGE))
sp("included mesh binary garbage", ["check", S], lambda w: (w / "mesh.bdf").write_bytes(GARBAGE))
sp("included mesh empty", ["check", S], lambda w: (w / "mesh.bdf").write_text(""))


# ------------------------------------------------------------------ measured data
def swap_first_two(w):
    lines = (w / "measured.csv").read_text().splitlines()
    a, b = lines[1].split(","), lines[2].split(",")
    a[2], b[2] = b[2], a[2]
    lines[1], lines[2] = ",".join(a), ",".join(b)
    (w / "measured.csv").write_text("\n".join(lines) + "\n")


case("fig2 csv modes 1 and 2 swapped (unsorted frequencies)", F2, ["update", S], swap_first_two)
case("fig2 csv mode 2 twice, mode 1 missing", F2, ["update", S], edit("measured.csv", "base,1,", "base,2,"))
case("frf uff second file in mm", BF, ["extract", S, "-o", "@x.csv"],
     lambda w: (w / "frf" / "0.2_kg_at_1.uff").write_bytes((w / "frf" / "0.2_kg_at_1.uff").read_bytes().replace(b"Displacement         m   ", b"Displacement         mm  ", 1)))
case("frf uff second FRF of base in rad/s", BF, ["extract", S, "-o", "@x.csv"],
     lambda w: (w / "frf" / "base.uff").write_bytes(re.sub(rb"(Frequency            )Hz   ", rb"\1rad/s", (w / "frf" / "base.uff").read_bytes(), count=2).replace(b"Frequency            rad/s", b"Frequency            Hz   ", 1)))
for label, n in [("0", "         0"), ("1e9", "1000000000"), ("3199", "      3199"), ("-1", "        -1")]:
    case(f"frf uff58b declares {label} points", BF, ["extract", S, "-o", "@x.csv"],
         lambda w, n=n: (w / "frf" / "base.uff").write_bytes((w / "frf" / "base.uff").read_bytes().replace(b"         6      3200         1", b"         6" + n.encode() + b"         1", 1)))
case("frf uff58b byte count 10^12", BF, ["extract", S, "-o", "@x.csv"],
     lambda w: (w / "frf" / "base.uff").write_bytes((w / "frf" / "base.uff").read_bytes().replace(b"       25600", b"999999999999", 1)))


# ------------------------------------------------------------------ resources
def sparse(name, size=10 << 30):
    def mutate(w):
        with open(w / name, "r+b" if (w / name).exists() else "wb") as f:
            f.truncate(size)
    return mutate


case("fig2 csv 10 GB (sparse)", F2, ["check", S], sparse("measured.csv"))
case("fig2 study 10 GB (sparse)", F2, ["check", S], sparse("study.toml"))
nf("deck 10 GB (sparse)", ["check", S], sparse("frame.bdf"))
case("frf uff 10 GB (sparse)", BF, ["extract", S, "-o", "@x.csv"], lambda w: sparse("frf/base.uff")(w))
nf("eigrl ND = 10^9", ["frequencies", S], edit("frame.bdf", "EIGRL         10                      12", "EIGRL         10                1000000000"))
nf("spc1 1 THRU 10^8", ["check", S], edit("frame.bdf", "SPC1           1   12456    1006", "SPC1           1   12456    1006\nSPC1,1,3,1,THRU,100000000"))
nf("set1 1 THRU 10^8 (a card not assembled)", ["check", S], edit("frame.bdf", "SPC1           1   12456    1006", "SPC1           1   12456    1006\nSET1,77,1,THRU,100000000"))
nf("spc1 THRU reversed (3001 THRU 1001)", ["check", S], edit("frame.bdf", "SPC1           1   12456    1006", "SPC1           1   12456    1006\nSPC1,1,3,3001,THRU,1001"))
nf("grid id 99999999 (unconnected, its own SPC)", ["check", S], edit("frame.bdf", "GRID        1001", "GRID,99999999,,9.,9.,9.\nSPC1,1,123456,99999999\nGRID        1001"))
case("beam with 10^6 nodes", B, ["check", S],
     lambda w: (w / "study.toml").write_text(re.sub(r"^nodes = \[.*\]", "nodes = [" + ", ".join(f"{i * 1e-6:.6f}" for i in range(10**6)) + "]",
                                                   (w / "study.toml").read_text(), count=1, flags=re.M)))


# ------------------------------------------------------------------ leftovers: simulate-frf -o DIR, extract -o's refusal line
SIMFRF = ["simulate-frf", "@truth.toml", "-o", "@o", "--input", "11", "--outputs", "1", "--fmax", "800", "--df", "1"]


def in_o(name, content=None, link=None, fifo=False):
    def mutate(w):
        (w / "o").mkdir()
        if link:
            (w / "o" / name).symlink_to(w / link)
        elif fifo:
            os.mkfifo(w / "o" / name)
        else:
            (w / "o" / name).write_bytes(content)
    return mutate


case("frf sim-frf -o DIR holds a hand-written base.uff", BF, SIMFRF, in_o("base.uff", b"my measured FRF\n"))
case("frf sim-frf -o DIR holds a hand-written base.uff --force", BF, SIMFRF + ["--force"], in_o("base.uff", b"my measured FRF\n"))
case("frf sim-frf -o DIR base.uff a symlink to the study --force", BF, SIMFRF + ["--force"], in_o("base.uff", link="study.toml"))
case("frf sim-frf -o DIR base.uff a symlink to truth.toml --force", BF, SIMFRF + ["--force"], in_o("base.uff", link="truth.toml"))
case("frf sim-frf -o DIR base.uff a FIFO --force", BF, SIMFRF + ["--force"], in_o("base.uff", fifo=True))
case("frf sim-frf -o DIR base.uff a directory --force", BF, SIMFRF + ["--force"], lambda w: (w / "o" / "base.uff").mkdir(parents=True))
case("frf sim-frf -o DIR a symlink to frf (the inputs) --force", BF, SIMFRF + ["--force"], lambda w: (w / "o").symlink_to(w / "frf"))
case("frf sim-frf -o /dev/null", BF, SIMFRF[:3] + ["/dev/null"] + SIMFRF[4:])
case("frf extract --uff55 /dev/null", BF, ["extract", S, "-o", "@x.csv", "--uff55", "/dev/null"])
case("fig2 report -o a FIFO", F2, ["report", S, "--saved-only", "-o", "@r.html"], lambda w: os.mkfifo(w / "r.html"))
case("fig2 design -o a symlink to the study", F2, ["design", S, "-o", "@p.toml"], lambda w: (w / "p.toml").symlink_to(w / "study.toml"))
case("fig2 design -o a symlink to the study --force", F2, ["design", S, "-o", "@p.toml", "--force"], lambda w: (w / "p.toml").symlink_to(w / "study.toml"))
LONG = "configuration,mode," + "x" * 20000 + "\n"
case("frf extract -o over a file with a 20000-character first line", BF, ["extract", S, "-o", "@x.csv"], lambda w: (w / "x.csv").write_text(LONG))
case("frf extract -o a 4000-character name", BF, ["extract", S, "-o", "@" + "x" * 4000 + ".csv"])
case("frf extract -o over a file with a binary first line", BF, ["extract", S, "-o", "@x.csv"], lambda w: (w / "x.csv").write_bytes(GARBAGE))
case("frf extract -o over a file of one 10 MB line", BF, ["extract", S, "-o", "@x.csv"], lambda w: (w / "x.csv").write_text("a" * 10_000_000))


if __name__ == "__main__":
    sys.exit(h.main())
