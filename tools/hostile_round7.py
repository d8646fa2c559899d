# ruff: noqa: E501  (a table of cases, one per line)
"""Seventh round of hostile cases, on issue 20's newest NASTRAN reading: GENEL (K or Z,
UD, S given or computed), negative coupling CMASS, the ``*`` continuation marker of a
small-field line, the PBARL/PBEAML library shapes (T1 ... HAT) and parameters on their
DIMs, corner thicknesses T1-T4 with TFLAG, and the nested-INCLUDE fallback to the main
deck's folder. Same harness, table and judgement as tools/hostile_round6.py (whose
helpers it uses): a refusal must exit 2 with one line, a case that gives numbers may name
a hand-converted equivalent deck (EQ when the frequencies differ beyond 1e-5):

    python tools/hostile_round7.py [-k SUBSTRING] [--keep]
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import hostile as h  # noqa: E402
import hostile_round6 as r6  # noqa: E402

h.CASES.clear()  # round 6's cases registered on import: this round's only
S = "@study.toml"
NOP = {"param": None}


def eq(name, base, edits, equivalent, param=None):
    """``base`` with ``edits`` must give the frequencies of ``base`` with ``equivalent``."""
    state = {}
    mutate = r6.deck(base, *edits, param=param)

    def both(w):
        r6.deck(base, *equivalent, param=param, name="equiv.bdf")(w)
        (w / "equiv.toml").write_text((w / "study.toml").read_text())
        mutate(w)
        state["w"] = w

    def check(code, err):
        w = state["w"]
        got, want = r6._hz(h.NASTRAN, w, "study.toml"), r6._hz(h.NASTRAN, w, "equiv.toml")
        if got is None or want is None or len(got) != len(want) or any(
                abs(a / b - 1) > 1e-5 for a, b in zip(got, want, strict=True)):
            return f"EQ{got}!={want}"
        return None
    r6.case6("eq7 " + name, ["frequencies", S], both, 0, check)


def bad(name, base, *edits, param=None, argv=("frequencies", S), files=()):
    mutate = r6.deck(base, *edits, param=param)

    def with_files(w):
        mutate(w)
        for fname, make in files:
            make(w / fname)
    r6.case6("bad7 " + name, list(argv), with_files, 2)


def ok(name, base, *edits, param=None, files=(), argv=("frequencies", S)):
    """A case that must run (exit 0): a valid deck in an odd form."""
    mutate = r6.deck(base, *edits, param=param)

    def with_files(w):
        mutate(w)
        for fname, make in files:
            make(w / fname)
    r6.case6("ok7 " + name, list(argv), with_files, 0)


def either(name, base, *edits, param=None, argv=("update", S)):
    """A case that may run (0) or stop (exit 1 not converged, exit 2 one line), never a
    traceback: an update whose steps may leave a section's domain."""
    def check(w_code, err):
        lines = [ln for ln in err.strip().splitlines() if not ln.startswith("eigenupdate: warning")]
        if "Traceback" in err or w_code not in (0, 1, 2) or (w_code == 2 and len(lines) != 1):
            r6.FAILED.append("any7 " + name)
            return "ANY"
        return None
    h.case("any7 " + name, r6.NF, list(argv), r6.deck(base, *edits, param=param), h.NASTRAN, check=check)


def lines_of(fields: list[str], first: str) -> str:
    """Free-field lines of eight fields after the first (name, or blank continuation)."""
    rows = [fields[k:k + 8] for k in range(0, len(fields), 8)]
    return "\n".join((first if i == 0 else "") + "," + ",".join(r) for i, r in enumerate(rows))


def genel(eid, ui, ud=(), k=None, z=None, s=None) -> str:
    """A GENEL card, each of UD, K/Z and S starting a continuation line (QRG layout)."""
    def pad(f):
        return f + [""] * (-len(f) % 8)
    out = pad([str(eid), ""] + [str(x) for p in ui for x in p])
    if ud:
        out += pad(["UD", ""] + [str(x) for p in ud for x in p])
    word, vals = ("K", k) if k is not None else ("Z", z)
    out += pad([word] + [repr(float(v)) for v in vals])
    if s is not None:
        out += pad(["S"] + [repr(float(v)) for v in np.ravel(s)])
    return lines_of(out, "GENEL")


def small(*rows) -> str:
    """Small-field lines: each row's fields 8 columns wide (field 1 first)."""
    return "\n".join("".join(f"{x:>8}" if i else f"{x:<8}" for i, x in enumerate(r)) for r in rows)


def large(*rows) -> str:
    """Large-field lines: field 1 8 columns wide, the others 16."""
    return "\n".join("".join(f"{x:>16}" if i else f"{x:<8}" for i, x in enumerate(r)) for r in rows)


def lower_by_columns(a) -> list[float]:
    i, j = np.triu_indices(len(a))
    return [float(a[i_, j_]) for i_, j_ in zip(i, j, strict=True)]


# ------------------------------------------------------------------ GENEL on scalar points
# k1 = 3e4 from point 1 to ground, the GENEL the spring k2 = 1e4 between points 1 and 2
CH = ("SOL 103\nCEND\nMETHOD = 1\nBEGIN BULK\nEIGRL,1,,,2\nSPOINT,1,2\nCELAS4,1,3.e4,1\n"
      "CMASS4,3,2.,1\nCMASS4,4,5.,2\n@G\nENDDATA\n")
G = "@G"
GK = "GENEL,2,,1,0,2,0\n,K,1.e4,-1.e4,1.e4"
SPRING = [(G, "CELAS4,2,1.e4,1,2")]
eq("genel K as the CELAS4 it replaces", CH, [(G, GK)], SPRING)
eq("genel UD and S as the CELAS4", CH, [(G, "GENEL,2,,2,0\n,UD,,1,0\n,K,1.e4\n,S,1.")], SPRING)
eq("genel Z UD S as the CELAS4", CH, [(G, "GENEL,2,,2,0\n,UD,,1,0\n,Z,1.e-4\n,S,1.")], SPRING)
eq("genel lowercase genel, ud, k, s", CH, [(G, "genel,2,,2,0\n,ud,,1,0\n,k,1.e4\n,s,1.")], SPRING)
eq("genel tabs", CH, [(G, "GENEL\t2\t\t1\t0\t2\t0\n\tK\t1.e4\t-1.e4\t1.e4")], SPRING)
eq("genel small fixed fields", CH, [(G, small(["GENEL", 2, "", 1, 0, 2, 0], ["", "K", "1.e4", "-1.e4", "1.e4"]))], SPRING)
eq("genel large fields", CH, [(G, large(["GENEL*", 2, "", 1, 0], ["*", 2, 0], ["*", "K", "1.e4", "-1.e4", "1.e4"]))], SPRING)
eq("genel small line, * in columns 73-80, large continuation", CH, [(G, small(["GENEL", 2, "", 1, 0, 2, 0, "", "", "*G1"]) + "\n" + large(["*G1", "K", "1.e4", "-1.e4", "1.e4"]))], SPRING)
eq("genel small line, * in columns 73-80, small continuation +G1", CH, [(G, small(["GENEL", 2, "", 1, 0, 2, 0, "", "", "*G1"], ["+G1", "K", "1.e4", "-1.e4", "1.e4"]))], SPRING)
eq("genel K written 1.+4 (NASTRAN exponent)", CH, [(G, "GENEL,2,,1,0,2,0\n,K,1.+4,-1.+4,1.+4")], SPRING)
eq("genel Z 1.-4 with S -1. on a sign-flipped point", CH, [(G, "GENEL,2,,2,0\n,UD,,1,0\n,Z,1.-4\n,S,1.")], SPRING)
for label, kk in [("K nan", "nan,-1.e4,1.e4"), ("K inf", "1.e4,-inf,1.e4"), ("K 1e308", "1e308,-1.e4,1.e4"),
                  ("K 1e200", "1e200,-1.e200,1.e200"), ("K 1e-300", "1e-300,0.,1.e4"),
                  ("K not positive semi-definite", "1.e4,-2.e4,1.e4"), ("K negative diagonal", "-1.e4,0.,1.e4"),
                  ("K 2 values for 2 UI", "1.e4,-1.e4"), ("K full square (4 values)", "1.e4,-1.e4,-1.e4,1.e4"),
                  ("K a blank inside", "1.e4,,-1.e4,1.e4"), ("K integer 10000", "10000,-10000,10000"),
                  ("K text", "1.e4,abc,1.e4")]:
    bad("genel " + label, CH, (G, f"GENEL,2,,1,0,2,0\n,K,{kk}"))
for label, zz in [("Z nan", "nan"), ("Z 0", "0."), ("Z negative", "-1.e-4"), ("Z 1e308", "1e308"), ("Z 1e-300", "1e-300")]:
    bad("genel " + label, CH, (G, f"GENEL,2,,2,0\n,UD,,1,0\n,Z,{zz}\n,S,1."))
# Z = [[1e-4, b], [b, 1e-4]] nearly singular: K = Z^-1 exactly (rationals), printed to 17 digits
def _z_inverse(b: float) -> str:
    from fractions import Fraction
    a, fb = Fraction(1e-4), Fraction(b)
    det = a * a - fb * fb
    return ",".join(repr(float(x)) for x in (a / det, -fb / det, a / det))


eq("genel Z condition 2e5 as its exact inverse K", CH, [(G, "GENEL,2,,1,0,2,0\n,Z,1.e-4,.99999e-4,1.e-4")], [(G, "GENEL,2,,1,0,2,0\n,K," + _z_inverse(.99999e-4))])
bad("genel Z condition 2e13 (K was 7e-4 off, f 1.2e-4)", CH, (G, "GENEL,2,,1,0,2,0\n,Z,1.e-4,.9999999999999e-4,1.e-4"))
bad("genel Z condition 2e9", CH, (G, "GENEL,2,,1,0,2,0\n,Z,1.e-4,.999999999e-4,1.e-4"))
bad("genel Z singular 2x2", CH, (G, "GENEL,2,,1,0,2,0\n,Z,1.e-4,1.e-4,1.e-4"))
bad("genel Z indefinite 2x2", CH, (G, "GENEL,2,,1,0,2,0\n,Z,1.e-4,2.e-4,1.e-4"))
bad("genel Z lowercase z", CH, (G, "GENEL,2,,1,0,2,0\n,z,1.e-4,0.,1.e-4"))
bad("genel K and Z both", CH, (G, "GENEL,2,,1,0,2,0\n,K,1.e4,-1.e4,1.e4\n,Z,1.e-4,0.,1.e-4"))
bad("genel K twice", CH, (G, "GENEL,2,,1,0,2,0\n,K,1.e4,-1.e4,1.e4\n,K,1.e4,-1.e4,1.e4"))
bad("genel neither K nor Z", CH, (G, "GENEL,2,,1,0,2,0"))
bad("genel no UI", CH, (G, "GENEL,2\n,K,1.e4"))
bad("genel UI without component", CH, (G, "GENEL,2,,1,0,2\n,K,1.e4,-1.e4,1.e4"))
bad("genel UI a component blank, then more", CH, (G, "GENEL,2,,1,,2,0\n,K,1.e4,-1.e4,1.e4"))
eq("genel UI component 1 on a SPOINT (as every scalar card here)", CH, [(G, "GENEL,2,,1,1,2,0\n,K,1.e4,-1.e4,1.e4")], SPRING)
bad("genel UI component -1", CH, (G, "GENEL,2,,1,-1,2,0\n,K,1.e4,-1.e4,1.e4"))
bad("genel UI an undefined point", CH, (G, "GENEL,2,,1,0,7,0\n,K,1.e4,-1.e4,1.e4"))
bad("genel UI point 0", CH, (G, "GENEL,2,,1,0,0,0\n,K,1.e4,-1.e4,1.e4"))
bad("genel UI point -2", CH, (G, "GENEL,2,,1,0,-2,0\n,K,1.e4,-1.e4,1.e4"))
bad("genel UI point 10^12", CH, (G, "GENEL,2,,1,0,999999999999,0\n,K,1.e4,-1.e4,1.e4"))
bad("genel UI point 2.", CH, (G, "GENEL,2,,1,0,2.,0\n,K,1.e4,-1.e4,1.e4"))
bad("genel UI twice", CH, (G, "GENEL,2,,1,0,1,0\n,K,1.e4,-1.e4,1.e4"))
bad("genel UI also in UD", CH, (G, "GENEL,2,,2,0\n,UD,,2,0\n,K,1.e4\n,S,1."))
bad("genel UI blank pair then more (dropped by pyNastran)", CH, (G, "GENEL,2,,1,0,,,2,0\n,K,1.e4"))
bad("genel field 3 not blank (ignored by pyNastran)", CH, (G, "GENEL,2,9,1,0,2,0\n,K,1.e4,-1.e4,1.e4"))
bad("genel UD field 3 not blank (ignored by pyNastran)", CH, (G, "GENEL,2,,2,0\n,UD,7,1,0\n,K,1.e4\n,S,1."))
bad("genel UD blank pair then more", CH, (G, "GENEL,2,,2,0\n,UD,,1,0,,,3,0\n,K,1.e4\n,S,1."), ("SPOINT,1,2", "SPOINT,1,2,3"))
bad("genel S without UD", CH, (G, "GENEL,2,,1,0,2,0\n,K,1.e4,-1.e4,1.e4\n,S,1.,1."))
bad("genel S count wrong", CH, (G, "GENEL,2,,2,0\n,UD,,1,0\n,K,1.e4\n,S,1.,1."))
bad("genel S nan", CH, (G, "GENEL,2,,2,0\n,UD,,1,0\n,K,1.e4\n,S,nan"))
bad("genel S 1e308", CH, (G, "GENEL,2,,2,0\n,UD,,1,0\n,K,1.e4\n,S,1e308"))
bad("genel S omitted with one UD", CH, (G, "GENEL,2,,2,0\n,UD,,1,0\n,K,1.e4"))
bad("genel S omitted, six UD on SPOINTs", CH, (G, "GENEL,2,,2,0\n,UD,,1,0,11,0,12,0\n,13,0,14,0,15,0\n,K,1.e4"), ("SPOINT,1,2", "SPOINT,1,2,11,THRU,15"))
bad("genel S twice", CH, (G, "GENEL,2,,2,0\n,UD,,1,0\n,K,1.e4\n,S,1.\n,S,1."))
bad("genel UD twice", CH, (G, "GENEL,2,,2,0\n,UD,,1,0\n,UD,,1,0\n,K,1.e4\n,S,1."))
bad("genel EID 0", CH, (G, GK.replace("GENEL,2,", "GENEL,0,")))
bad("genel EID -2", CH, (G, GK.replace("GENEL,2,", "GENEL,-2,")))
bad("genel EID blank", CH, (G, GK.replace("GENEL,2,", "GENEL,,")))
ok("genel EID 10^12 (no number depends on an element id: accepted as any element's)", CH, (G, GK.replace("GENEL,2,", "GENEL,999999999999,")))
bad("genel EID shared with the CELAS4", CH, (G, GK.replace("GENEL,2,", "GENEL,1,")))
ok("genel small field, a value past column 80 (warned, not read)", CH, (G, small(["GENEL", 2, "", 1, 0, 2, 0, "", "", "", "9"], ["", "K", "1.e4", "-1.e4", "1.e4"])))
bad("genel small field, * in columns 73-80 of a line with * in field 2", CH, (G, small(["GENEL", 2, "", 1, 0, 2, 0, "", "", "*G1"], ["+G1", "*K", "1.e4", "-1.e4", "1.e4"])))
# a huge UI list: 1000 points whose K lists one value too few (the count is checked before
# the 1000 x 1000 matrix is made), one with no K at all, and one read
HUGE_UI = [(p, 0) for p in range(101, 1101)]
bad("genel 1000 UI, K one value short", CH, ("SPOINT,1,2", "SPOINT,1,2,101,THRU,1100"), (G, genel(2, HUGE_UI, k=[1.0] * (1000 * 1001 // 2 - 1))))
bad("genel 1000 UI, no K", CH, ("SPOINT,1,2", "SPOINT,1,2,101,THRU,1100"), (G, genel(2, HUGE_UI, k=[]).replace(",K", ",")))
bad("genel 1000 UI, K diagonal 1. (500,500 values read; massless points refused)", CH, ("SPOINT,1,2", "SPOINT,1,2,101,THRU,1100"), (G, genel(2, HUGE_UI, k=lower_by_columns(np.eye(1000)))))

# ------------------------------------------------------------------ GENEL on grids, S computed
# two free bodies on grids 1 (origin) and 2 (x = 1), the GENEL a cantilever's tip stiffness
# (EA 1e6, 12 EI 1.2e5, 4 EI 4e4, 6 EI 6e4, GJ 5e3) on grid 2 with grid 1 as UD
KC = np.diag([1e6, 1.2e5, 1.2e5, 5e3, 4e4, 4e4])
KC[1, 5] = KC[5, 1] = -6e4
KC[2, 4] = KC[4, 2] = 6e4
# rigid motion of grid 1 carried to grid 2 (r = (1, 0, 0)): u2 = u1 + theta1 x r
S_BASIC = np.eye(6)
S_BASIC[1, 5], S_BASIC[2, 4] = 1.0, -1.0
ROT = np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # CORD2R 5 from basic
R6 = np.kron(np.eye(2), ROT)
UI2 = [(2, c) for c in range(1, 7)]
UD1 = [(1, c) for c in range(1, 7)]
GR = ("SOL 103\nCEND\nMETHOD = 1\nBEGIN BULK\nEIGRL,1,,,12\n"
      "CORD2R,5,,0.,0.,0.,0.,0.,1.,+C\n+C,0.,1.,0.\n"
      "GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\n"
      "CONM2,11,1,,10.,,,,,+A\n+A,1.,,1.,,,1.\nCONM2,12,2,,5.,,,,,+B\n+B,.5,,.5,,,.5\n@G\nENDDATA\n")
GS = genel(7, UI2, UD1, k=lower_by_columns(KC))
eq("genel grids S computed as S written out", GR, [(G, GS)], [(G, genel(7, UI2, UD1, k=lower_by_columns(KC), s=S_BASIC))])
eq("genel grids UI in CD 5, S computed as written out", GR, [("GRID,2,,1.,0.,0.", "GRID,2,,1.,0.,0.,5"), (G, GS)],
   [("GRID,2,,1.,0.,0.", "GRID,2,,1.,0.,0.,5"), (G, genel(7, UI2, UD1, k=lower_by_columns(KC), s=R6 @ S_BASIC))])
eq("genel grids UD in CD 5, S computed as written out", GR, [("GRID,1,,0.,0.,0.", "GRID,1,,0.,0.,0.,5"), (G, GS)],
   [("GRID,1,,0.,0.,0.", "GRID,1,,0.,0.,0.,5"), (G, genel(7, UI2, UD1, k=lower_by_columns(KC), s=S_BASIC @ R6.T))])
eq("genel grids UD listed out of order, S computed", GR, [(G, genel(7, UI2, UD1[::-1], k=lower_by_columns(KC)))],
   [(G, genel(7, UI2, UD1[::-1], k=lower_by_columns(KC), s=S_BASIC[:, ::-1]))])
eq("genel grids as the K of a rotated UI written out in basic", GR, [("GRID,2,,1.,0.,0.", "GRID,2,,1.,0.,0.,5"), (G, genel(7, UI2, UD1, k=lower_by_columns(R6 @ KC @ R6.T)))], [(G, GS)])
bad("genel grids S omitted, UD two components of one direction", GR, (G, genel(7, UI2, [(1, 1), (1, 1), (1, 3), (1, 4), (1, 5), (1, 6)], k=lower_by_columns(KC))))
# UD grid 1's 1-5 and grid 2's rotation 6 (which is the body's): u2y = u1y + theta2z
S_MIXED = [[1, 0, 0, 0, 0, 0], [0, 1, 0, 0, 0, 1], [0, 0, 1, 0, -1, 0], [0, 0, 0, 1, 0, 0], [0, 0, 0, 0, 1, 0]]
UD_MIXED = [(1, 1), (1, 2), (1, 3), (1, 4), (1, 5), (2, 6)]
eq("genel grids S omitted, UD grid 1's 1-5 and grid 2's 6", GR, [(G, genel(7, UI2[:5], UD_MIXED, k=lower_by_columns(KC[:5, :5])))],
   [(G, genel(7, UI2[:5], UD_MIXED, k=lower_by_columns(KC[:5, :5]), s=S_MIXED))])
bad("genel grids S omitted, UD grid 1's 1-5 and grid 2's 1 (rotation z free)", GR, (G, genel(7, UI2[1:], UD_MIXED[:5] + [(2, 1)], k=lower_by_columns(KC[1:, 1:]))))
bad("genel grids S omitted, UD component 0 on a grid", GR, (G, genel(7, UI2, [(1, 0)] + UD1[1:], k=lower_by_columns(KC))))
bad("genel grids S omitted, UD component 7", GR, (G, genel(7, UI2, [(1, 7)] + UD1[1:], k=lower_by_columns(KC))))
bad("genel grids UD on a grid with CD undefined", GR, ("GRID,1,,0.,0.,0.", "GRID,1,,0.,0.,0.,9"), (G, GS))
bad("genel grids S omitted, seven UD", GR, ("GRID,2,,1.,0.,0.", "GRID,2,,1.,0.,0.\nGRID,3,,2.,0.,0."), (G, genel(7, UI2, UD1 + [(3, 1)], k=lower_by_columns(KC))))
bad("genel grids S omitted, UD grids coincident and free rotation", GR, ("GRID,2,,1.,0.,0.", "GRID,2,,1.,0.,0.\nGRID,3,,0.,0.,0."), (G, genel(7, UI2, [(1, 1), (1, 2), (1, 3), (3, 1), (3, 2), (3, 3)], k=lower_by_columns(KC))))

# ------------------------------------------------------------------ negative coupling CMASS
CM = CH.replace(G, "CELAS4,2,1.e4,1,2\nCMASS2,9,-1.,1,,2")
ok("cmass2 -1 between points of 2 and 5 kg (semi-definite)", CM)
bad("cmass2 -3 between points of 2 and 5 kg (indefinite)", CM, ("CMASS2,9,-1.,", "CMASS2,9,-3.,"))
bad("cmass2 -1.5 (semi-definite needs M >= -10/7)", CM, ("CMASS2,9,-1.,", "CMASS2,9,-1.5,"))
bad("cmass2 -1.5 on 2.000 and 5.000 kg", CM, ("CMASS2,9,-1.,", "CMASS2,9,-1.5,"), ("CMASS4,3,2.,1", "CMASS4,3,2.000,1"), ("CMASS4,4,5.,2", "CMASS4,4,5.000,2"))
bad("cmass2 coupling nan", CM, ("CMASS2,9,-1.,", "CMASS2,9,nan,"))
bad("cmass2 coupling -1e308", CM, ("CMASS2,9,-1.,", "CMASS2,9,-1e308,"))
bad("cmass2 negative grounded", CM, ("CMASS2,9,-1.,1,,2", "CMASS2,9,-1.,1"))
bad("cmass2 negative from a point to itself", CM, ("CMASS2,9,-1.,1,,2", "CMASS2,9,-1.,1,,1"))
bad("cmass2 positive from a point to itself", CM, ("CMASS2,9,-1.,1,,2", "CMASS2,9,1.,1,,1"))
bad("cmass1 PMASS negative coupling indefinite", CM, ("CMASS2,9,-1.,1,,2", "CMASS1,9,8,1,,2\nPMASS,8,-3."))

# ------------------------------------------------------------------ PBARL library shapes
BARD = ("SOL 103\nCEND\nSPC = 1\nMETHOD = 1\nBEGIN BULK\nEIGRL,1,,,4\nGRID,1,,0.,0.,0.\n"
        "GRID,2,,0.4,0.,0.\nGRID,3,,0.8,0.,0.\nCBAR,1,1,1,2,0.,1.,0.\nCBAR,2,1,2,3,0.,1.,0.\n"
        "@P\nMAT1,1,7.e10,,0.3,2700.\nSPC1,1,123456,1\nENDDATA\n")
P = "@P"
VALID = {"T1": [.03, .02, .003, .002], "T2": [.02, .03, .002, .0025], "I1": [.01, .002, .04, .05],
         "CHAN1": [.015, .002, .04, .05], "CHAN2": [.002, .003, .03, .05], "H": [.03, .004, .05, .002],
         "Z": [.03, .004, .08, .1], "CROSS": [.04, .005, .05, .004], "TUBE2": [.03, .004],
         "BOX1": [.1, .06, .004, .004, .005, .006], "HEXA": [.01, .05, .03], "HAT": [.03, .002, .04, .01]}


def pbarl(shape, dims, pid=1, card="PBARL") -> str:
    return f"{card},{pid},1,,{shape}\n," + ",".join(str(d) for d in dims)


for shape, dims in VALID.items():
    ok(f"pbarl {shape} valid", BARD, (P, pbarl(shape, dims)))
    for label, value in [("0", "0."), ("negative", "-.001"), ("nan", "nan"), ("inf", "inf"), ("1e308", "1e308"), ("blank", "")]:
        k = len(dims) - 1
        d = list(dims)
        d[k] = value
        bad(f"pbarl {shape} DIM{k + 1} {label}", BARD, (P, pbarl(shape, d)))
    bad(f"pbarl {shape} one DIM short", BARD, (P, pbarl(shape, dims[:-1])))
    ok(f"pbarl {shape} a value after the DIMs (its NSM)", BARD, (P, pbarl(shape, [*dims, .01])))
    bad(f"pbarl {shape} DIM1 1e-300", BARD, (P, pbarl(shape, ["1e-300", *dims[1:]])))
for label, shape, dims in [("T1 web as thick as the flange is high", "T1", [.002, .02, .003, .002]),
                           ("T2 flange thicker than the height", "T2", [.02, .002, .003, .0025]),
                           ("T2 web as thick as the flange", "T2", [.02, .03, .002, .02]),
                           ("I1 clear web as high as the section", "I1", [.01, .002, .05, .05]),
                           ("CHAN1 clear web higher than the section", "CHAN1", [.015, .002, .06, .05]),
                           ("CHAN2 legs shorter than the base is thick", "CHAN2", [.002, .03, .03, .05]),
                           ("CHAN2 legs wider than the base", "CHAN2", [.03, .003, .03, .05]),
                           ("H web thicker than the plates are high", "H", [.03, .004, .05, .06]),
                           ("Z web as high as the section", "Z", [.03, .004, .1, .1]),
                           ("CROSS arm thicker than the bar is high", "CROSS", [.04, .005, .004, .005]),
                           ("TUBE2 wall thicker than the radius", "TUBE2", [.03, .031]),
                           ("BOX1 side walls wider than the box", "BOX1", [.01, .06, .004, .004, .005, .006]),
                           ("BOX1 top and bottom higher than the box", "BOX1", [.1, .006, .004, .004, .005, .006]),
                           ("BOX1 both pairs unequal", "BOX1", [.1, .06, .004, .003, .005, .006]),
                           ("HEXA points deeper than half the width", "HEXA", [.03, .05, .03]),
                           ("HAT wall half the height", "HAT", [.004, .002, .04, .01]),
                           ("HAT wall half the crown", "HAT", [.03, .002, .004, .01])]:
    bad("pbarl " + label, BARD, (P, pbarl(shape, dims)))
eq("pbarl TUBE2 as the TUBE of its radii", BARD, [(P, pbarl("TUBE2", [.03, .004]))], [(P, pbarl("TUBE", [.03, .026]))])
eq("pbarl TUBE2 wall = radius as the TUBE of inner radius 0", BARD, [(P, pbarl("TUBE2", [.03, .03]))], [(P, pbarl("TUBE", [.03, 0.]))])
# a wall 1e-9 of the radius: A = pi t (2 r - t), I = A (r^2 + (r - t)^2) / 4 (hand, no cancellation)
_r, _t = .03, 3e-11
_a = np.pi * _t * (2 * _r - _t)
_i = _a * (_r**2 + (_r - _t) ** 2) / 4
eq("pbarl TUBE2 wall 1e-9 of the radius as the hand PBAR", BARD, [(P, pbarl("TUBE2", [_r, _t]))], [(P, f"PBAR,1,1,{_a!r},{_i!r},{_i!r},{2 * _i!r}\n,,,,,,,,\n,.5,.5")])
_t = 3e-14  # 1e-12 of the radius: TUBE's r^2 - (r - t)^2 would keep 4 digits
_a = np.pi * _t * (2 * _r - _t)
_i = _a * (_r**2 + (_r - _t) ** 2) / 4
eq("pbarl TUBE2 wall 1e-12 of the radius as the hand PBAR", BARD, [(P, pbarl("TUBE2", [_r, _t]))], [(P, f"PBAR,1,1,{_a!r},{_i!r},{_i!r},{2 * _i!r}\n,,,,,,,,\n,.5,.5")])
eq("pbarl T2 as the T of its dims (I12 = 0, same A, I)", BARD, [(P, pbarl("T2", VALID["T2"]))], [(P, pbarl("T", VALID["T2"]))])
eq("pbarl lowercase pbarl, t2", BARD, [(P, pbarl("t2", VALID["T2"]).replace("PBARL", "pbarl"))], [(P, pbarl("T2", VALID["T2"]))])
eq("pbarl I1 as the I of its dims", BARD, [(P, pbarl("I1", [.01, .002, .04, .05]))], [(P, pbarl("I", [.05, .012, .012, .002, .005, .005]))])
eq("pbarl CHAN1 as the CHAN of its dims", BARD, [(P, pbarl("CHAN1", [.015, .002, .04, .05]))], [(P, pbarl("CHAN", [.017, .05, .002, .005]))])
eq("pbarl H as the I of its dims turned (v rotated)", BARD, [(P, pbarl("H", [.03, .004, .05, .002]))],
   [(P, pbarl("I", [.034, .05, .05, .002, .002, .002])), ("0.,1.,0.", "0.,0.,1."), ("0.,1.,0.", "0.,0.,1.")])
eq("pbarl large fields", BARD, [(P, large(["PBARL*", 1, 1, "", "TUBE2"], ["*", "", "", "", ""], ["*", ".03", ".004"]))], [(P, pbarl("TUBE2", [.03, .004]))])
eq("pbeaml TUBE2 on a CBEAM as PBARL on the CBAR", BARD, [(P, pbarl("TUBE2", [.03, .004], card="PBEAML")), ("CBAR", "CBEAM"), ("CBAR", "CBEAM")], [(P, pbarl("TUBE2", [.03, .004]))])
BEAMD = BARD.replace("CBAR", "CBEAM")
eq("pbeaml TUBE2 tapered as the TUBE of its radii", BEAMD, [(P, "PBEAML,1,1,,TUBE2\n,.03,.004,0.,NO,1.,.02,.004")], [(P, "PBEAML,1,1,,TUBE\n,.03,.026,0.,NO,1.,.02,.016")])
eq("pbeaml T2 tapered as the T of its dims", BEAMD, [(P, "PBEAML,1,1,,T2\n,.02,.03,.002,.0025,0.,NO,1.,.02\n,.02,.002,.0025")], [(P, "PBEAML,1,1,,T\n,.02,.03,.002,.0025,0.,NO,1.,.02\n,.02,.002,.0025")])
bad("pbeaml Z tapered (I12)", BEAMD, (P, "PBEAML,1,1,,Z\n,.03,.004,.08,.1,0.,NO,1.,.03\n,.004,.08,.09"))
bad("pbeaml CHAN2 tapered out of its domain at end B", BEAMD, (P, "PBEAML,1,1,,CHAN2\n,.002,.003,.03,.05,0.,NO,1.,.002\n,.003,.03,.003"))
bad("genel a parameter on GENEL K", CH, (G, GK), param=("GENEL", "K"))
# parameters on the DIMs (the study): the update's steps must stay in the section's domain
for shape, k in [("T1", 4), ("CHAN2", 1), ("H", 4), ("CROSS", 4), ("TUBE2", 2), ("HEXA", 1), ("HAT", 2), ("BOX1", 5)]:
    either(f"pbarl {shape} DIM{k} a parameter, update to data out of reach", BARD, (P, pbarl(shape, VALID[shape])),
           param=("PBARL", f"DIM{k}"))
either("pbarl BOX1 DIM3 a parameter (DIM3 = DIM4, DIM5 != DIM6)", BARD, (P, pbarl("BOX1", VALID["BOX1"])), param=("PBARL", "DIM3"))
bad("pbarl Z DIM1 a parameter (I12)", BARD, (P, pbarl("Z", VALID["Z"])), param=("PBARL", "DIM1"))
bad("pbarl T1 DIM5 a parameter (no such DIM)", BARD, (P, pbarl("T1", VALID["T1"])), param=("PBARL", "DIM5"))
bad("pbarl HAT DIM0 a parameter", BARD, (P, pbarl("HAT", VALID["HAT"])), param=("PBARL", "DIM0"))
bad("pbarl HAT1 (refused shape)", BARD, (P, pbarl("HAT1", [.03, .04, .002, .002, .002])))
bad("pbarl DBOX (refused shape)", BARD, (P, pbarl("DBOX", [.1, .06, .05, .004, .004, .004, .004, .004, .004, .004])))
bad("pbarl L (refused shape)", BARD, (P, pbarl("L", [.03, .03, .003, .003])))

# ------------------------------------------------------------------ corner thicknesses T1-T4
PL = r6.PLATE_CQUAD4
Q1, Q2 = "CQUAD4,1,1,1,2,5,4", "CQUAD4,2,1,2,3,6,5"
PS = "PSHELL,1,1,.05,1,.96,1,.8,.3"
HALF = [(PS, "PSHELL,1,1,.025,1,.96,1,.8,.3")]


def corners(q, tflag, *t):
    return q + ",,\n,," + str(tflag) + "," + ",".join(str(x) for x in t)


eq("corners all .05 TFLAG 0 as none", PL, [(Q1, corners(Q1, 0, .05, .05, .05, .05))], [])
eq("corners all 1. TFLAG 1 as none", PL, [(Q1, corners(Q1, 1, 1., 1., 1., 1.))], [])
eq("corners TFLAG 0 only T1 given .05 (the rest T)", PL, [(Q1, corners(Q1, 0, .05))], [])
eq("corners TFLAG 0 .025 everywhere as PSHELL T .025", PL, [(Q1, corners(Q1, 0, .025, .025, .025, .025)), (Q2, corners(Q2, "", .025, .025, .025, .025))], HALF)
eq("corners TFLAG 1 .5 everywhere as PSHELL T .025", PL, [(Q1, corners(Q1, 1, .5, .5, .5, .5)), (Q2, corners(Q2, 1, .5, .5, .5, .5))], HALF)
eq("corners TFLAG 0 and TFLAG 1 mixed as PSHELL T .025", PL, [(Q1, corners(Q1, 0, .025, .025, .025, .025)), (Q2, corners(Q2, 1, .5, .5, .5, .5))], HALF)
eq("corners TFLAG 1 with T a parameter (T .025)", PL, [(Q1, corners(Q1, 1, .5, .5, .5, .5)), (Q2, corners(Q2, 1, .5, .5, .5, .5))], HALF, param=("PSHELL", "T"))
eq("corners cquadr all .05 TFLAG 0 as none", PL, [(Q1, corners(Q1, 0, .05, .05, .05, .05).replace("CQUAD4", "CQUADR")), (Q2, Q2.replace("CQUAD4", "CQUADR"))], [(Q1, Q1.replace("CQUAD4", "CQUADR")), (Q2, Q2.replace("CQUAD4", "CQUADR"))])
eq("corners lowercase cquad4", PL, [(Q1, corners(Q1, 0, .05, .05, .05, .05).replace("CQUAD4", "cquad4"))], [])
eq("corners large field", PL, [(Q1, large(["CQUAD4*", 1, 1, 1, 2], ["*", 5, 4, "", ""], ["*", "", 0, ".05", ".05"], ["*", ".05", ".05"]))], [])
eq("corners small field", PL, [(Q1, small(["CQUAD4", 1, 1, 1, 2, 5, 4, "", ""], ["", "", 0, ".05", ".05", ".05", ".05"]))], [])
eq("corners tabs", PL, [(Q1, "CQUAD4\t1\t1\t1\t2\t5\t4\n\t\t0\t.05\t.05\t.05\t.05")], [])
bad("corners PSHELL T blank, every Ti .05 (refused: not supported)", PL, (PS, "PSHELL,1,1,,1,.96,1,.8,.3"), (Q1, corners(Q1, 0, .05, .05, .05, .05)), (Q2, corners(Q2, 0, .05, .05, .05, .05)))
for label, t in [("T1 negative", (-.05, .05, .05, .05)), ("T2 nan", (.05, "nan", .05, .05)), ("T3 inf", (.05, .05, "inf", .05)),
                 ("T4 1e308", (.05, .05, .05, "1e308")), ("T1 1e-300", ("1e-300", .05, .05, .05)), ("all zero", (0., 0., 0., 0.)),
                 ("T1 text", ("abc", .05, .05, .05))]:
    bad("corners TFLAG 0 " + label, PL, (Q1, corners(Q1, 0, *t)))
    bad("corners TFLAG 1 " + label, PL, (Q1, corners(Q1, 1, *t)))
# a plate thick beyond reason is shear-governed, its frequencies independent of T: the same
# at 1e50 and 1e99 (no overflow, no lost digits); only a thickness out of range is refused
eq("corners TFLAG 1 Ti 1e99 as 1e50 (thick limit)", PL, [(Q1, corners(Q1, 1, "1e99", "1e99", "1e99", "1e99"))], [(Q1, corners(Q1, 1, "1e50", "1e50", "1e50", "1e50"))])
bad("corners TFLAG 1 Ti 1e60 on PSHELL T 1e60 (thickness 1e120)", PL, (PS, "PSHELL,1,1,1e60,1,.96,1,.8,.3"), (Q1, corners(Q1, 1, "1e60", "1e60", "1e60", "1e60")))
eq("pshell T 1e99 as 1e50 (thick limit, no corners)", PL, [(PS, "PSHELL,1,1,1e99,1,.96,1,.8,.3")], [(PS, "PSHELL,1,1,1e50,1,.96,1,.8,.3")])
for label, flag in [("2", "2"), ("-1", "-1"), ("1.", "1."), ("nan", "nan"), ("A", "A"), ("10^12", "999999999999")]:
    bad(f"corners TFLAG {label}", PL, (Q1, corners(Q1, flag, .5, .5, .5, .5)))
bad("corners TFLAG 2 with all Ti blank", PL, (Q1, corners(Q1, 2)))
bad("corners TFLAG 0 partly blank with T a parameter", PL, (Q1, corners(Q1, 0, .03, .04)), param=("PSHELL", "T"))
bad("corners differing on a PCOMP", PL, (PS, "PCOMP,1\n,1,.025,0.,YES,1,.025,90.,YES"), (Q1, corners(Q1, 0, .03, .04, .05, .05)))
ok("corners on CQUAD8 differing (read: io/nastran_corners.py)", PL, ("GRID,6,,2.,1.,0.", "GRID,6,,2.,1.,0.\nGRID,7,,.5,0.,0.\nGRID,8,,1.,.5,0.\nGRID,9,,.5,1.,0.\nGRID,10,,0.,.5,0."),
    (Q1, "CQUAD8,1,1,1,2,5,4,7,8\n,9,10,.03,.04,.05,.05"))
bad("ctria3 a value in T4's place", PL, (Q1, "CTRIA3,1,1,1,2,5,,,\n,,0,.05,.05,.05,.05"))

# ------------------------------------------------------------------ INCLUDE fallback to the main deck's folder
INC = PL.replace(PS + "\n", "INCLUDE 'sub/a.dat'\n")


def text(t):
    return lambda p: (p.parent.mkdir(exist_ok=True), p.write_text(t))


def link(to):
    return lambda p: (p.parent.mkdir(exist_ok=True), os.symlink(to, p))


def folder(p):
    p.mkdir(parents=True, exist_ok=True)


A_INC = ("sub/a.dat", text("INCLUDE 'b.dat'\n"))
ok("include nested b.dat found beside the main deck", INC, files=[A_INC, ("b.dat", text(PS + "\n"))])
ok("include nested found beside the including file first", INC, files=[A_INC, ("sub/b.dat", text(PS + "\n")), ("b.dat", text("PSHELL,1,1,nan\n"))])
bad("include nested name a directory in the main folder", INC, files=[A_INC, ("b.dat", folder)])
ok("include nested name a directory beside it, file in main (read: the lookup takes files)", INC, files=[A_INC, ("sub/b.dat", folder), ("b.dat", text(PS + "\n"))])
bad("include nested two different files answer (warned), the one beside read", INC, files=[A_INC, ("sub/b.dat", text("PSHELL,1,1,nan\n")), ("b.dat", text(PS + "\n"))])
bad("include nested self symlink loop (both folders)", INC, files=[A_INC, ("sub/b.dat", link("b.dat")), ("b.dat", link("b.dat"))])
bad("include nested symlink loop in the main folder", INC, files=[A_INC, ("b.dat", link("c.dat")), ("c.dat", link("b.dat"))])
bad("include nested symlink to a missing file", INC, files=[A_INC, ("b.dat", link("nowhere.dat"))])
bad("include nested found nowhere", INC, files=[A_INC])
bad("include nested names the main deck (fallback)", INC, files=[("sub/a.dat", text("INCLUDE 'frame.bdf'\n"))])
bad("include nested cycle through the fallback", INC, files=[A_INC, ("b.dat", text("INCLUDE 'sub/a.dat'\n"))])
bad("include nested ../ back to the main deck", INC, files=[("sub/a.dat", text("INCLUDE '../frame.bdf'\n"))])
ok("include nested ../ escape to a file beside the main folder", INC, files=[("sub/a.dat", text("INCLUDE '../../out.dat'\n")), ("../out.dat", text(PS + "\n"))])
bad("include nested /dev/zero", INC, files=[("sub/a.dat", text("INCLUDE '/dev/zero'\n"))])
bad("include nested b.dat a symlink to /dev/zero", INC, files=[A_INC, ("b.dat", link("/dev/zero"))])
bad("include nested b.dat a FIFO", INC, files=[A_INC, ("b.dat", lambda p: os.mkfifo(p))])
bad("include nested empty name", INC, files=[("sub/a.dat", text("INCLUDE ''\n"))])
bad("include nested name with a NUL", INC, files=[("sub/a.dat", text("INCLUDE 'b\x00.dat'\n"))])
bad("include nested, the main folder's file has a bad card", INC, files=[A_INC, ("b.dat", text("PSHELL,1,1,nan\n"))])


if __name__ == "__main__":
    sys.stdout = r6._Watch(sys.stdout)
    h.main()
    sys.stdout = sys.stdout.out
    print(f"{len(h.CASES)} cases; {len(r6.FAILED)} failed" + (": " + "; ".join(r6.FAILED) if r6.FAILED else ""))
    sys.exit(1 if r6.FAILED else 0)
