# ruff: noqa: E501  (a table of cases, one per line)
"""Third round of hostile and wrong-data cases (tools/hostile.py runs the first,
tools/hostile_round2.py the second): the newest features (DMIG matrices selected by
K2GG/M2GG, PCOMPG, CORD1R/C/S, ZOFFS, ANALYSIS = MODES subcases, --scheduler addresses,
the plan TOML of `design`) and the leftovers of round 2 (units, saved extractions,
--save-bdf and design -o onto other files, blank GRID ids, SciPy wording). Same harness
and output as tools/hostile.py:

    python tools/hostile_round3.py [-k SUBSTRING] [--keep]
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import hostile as h  # noqa: E402
from hostile import NASTRAN, case, sub  # noqa: E402

h.CASES.clear()
S = "@study.toml"
F2, BF, NF, SP = "paper_fig2", "paper_beam_frf", "nastran_frame", "stiffened_panel"
CASE_CONTROL = "SUBCASE 1\n  SPC = 1\n  METHOD = 10\n"
BULK = "BEGIN BULK\n"


def frame(*edits):
    """Edits (old, new) of the frame deck; the case control's and the bulk's."""
    def mutate(w):
        for old, new in edits:
            sub(w / "frame.bdf", old, new)
    return mutate


def nf(name, argv, mutate=None):
    case("nas3 " + name, NF, argv, mutate, NASTRAN)


def sp(name, argv, mutate=None):
    case("panel3 " + name, SP, argv, mutate, NASTRAN)


def k2gg(cards, selection="  K2GG = KX\n"):
    return frame((CASE_CONTROL, CASE_CONTROL + selection), (BULK, BULK + cards))


# ------------------------------------------------------------------ DMIG K2GG / M2GG
KX = "DMIG,KX,0,6,1,0\nDMIG,KX,3001,1,,3001,1,{}\n"
nf("dmig K2GG nan", ["check", S], k2gg(KX.format("nan")))
nf("dmig K2GG grid not in deck", ["check", S], k2gg(KX.replace("3001", "99999").format("1e5")))
nf("dmig K2GG component 7", ["check", S], k2gg(KX.replace("3001,1,,3001,1", "3001,7,,3001,7").format("1e5")))
nf("dmig K2GG on an SPC'd component", ["check", S], k2gg(KX.replace("3001", "1001").format("1e5")))
nf("dmig K2GG unsymmetric form 1 off-diagonal one side", ["check", S],
   k2gg("DMIG,KX,0,1,1,0\nDMIG,KX,3001,1,,3002,1,1e5\n"))
nf("dmig M2GG negative mass", ["frequencies", S], k2gg(KX.replace("KX", "MX").format("-1e9"), "  M2GG = MX\n"))
nf("dmig K2GG huge negative (indefinite K)", ["frequencies", S], k2gg(KX.format("-1e15")))
nf("dmig K2GG two names, one missing", ["check", S], k2gg(KX.format("1e5"), "  K2GG = KX, KY\n"))
nf("dmig K2GG CK2 = nan", ["check", S], k2gg(KX.format("1e5") + "PARAM,CK2,nan\n"))

# ------------------------------------------------------------------ CORD1R / CORD1C / CORD1S
CD = ("GRID        3001              0.      0.      6.", "GRID        3001              0.      0.      6.       7")
nf("cord1r collinear grids", ["check", S], frame(CD, (BULK, BULK + "CORD1R,7,1001,2001,3001\n")))
nf("cord1r grid missing", ["check", S], frame(CD, (BULK, BULK + "CORD1R,7,1001,2001,99999\n")))
nf("cord1r two grids the same", ["check", S], frame(CD, (BULK, BULK + "CORD1R,7,1001,1001,3002\n")))
nf("cord1s defined on its own grid's CP", ["check", S],
   frame(("GRID        1002              0.      3.      0.", "GRID        1002       7      0.      3.      0."),
         (BULK, BULK + "CORD1S,7,1002,2001,3002\n")))
nf("cord1c id reused by a CORD2R", ["check", S], frame(CD, (BULK, BULK + "CORD1C,7,1001,2001,3002\nCORD2R,7,0,0.,0.,0.,0.,0.,1.\n,1.,0.,0.\n")))

# ------------------------------------------------------------------ ANALYSIS = MODES subcases
nf("two MODES subcases, two SPC sets", ["check", S],
   frame((CASE_CONTROL, CASE_CONTROL + "  ANALYSIS = MODES\nSUBCASE 2\n  SPC = 2\n  ANALYSIS = MODES\n"),
         (BULK, BULK + "SPC1,2,123456,1001\n")))
nf("ANALYSIS = modes lower case", ["check", S], frame((CASE_CONTROL, CASE_CONTROL + "  analysis = modes\n")))
nf("MODES subcase without SPC", ["check", S],
   frame((CASE_CONTROL, "SUBCASE 1\n  METHOD = 10\n  ANALYSIS = MODES\nSUBCASE 2\n  SPC = 1\n  ANALYSIS = MFREQ\n")))
nf("ANALYSIS = BUCKLING only", ["check", S], frame((CASE_CONTROL, CASE_CONTROL + "  ANALYSIS = BUCK\n")))

# ------------------------------------------------------------------ PCOMPG and ZOFFS on the panel
PSHELL1 = "PSHELL,1,1,0.002,1,,1"


def panel(*edits, study_edits=()):
    def mutate(w):
        for old, new in edits:
            sub(w / "panel.bdf", old, new)
        text = (w / "study.toml").read_text()
        # the skin's PSHELL T parameter goes with PSHELL 1
        start = text.index('[[model.parameter]]\nname = "t_skin"')
        end = text.index("[[model.parameter]]", start + 1)
        (w / "study.toml").write_text(text[:start] + text[end:])
        for old, new in study_edits:
            sub(w / "study.toml", old, new)
    return mutate


sp("pcompg duplicate global ply ids", ["check", S], panel((PSHELL1, "PCOMPG,1\n,101,1,0.001,0.\n,101,1,0.001,90.")))
sp("pcompg ply material missing", ["check", S], panel((PSHELL1, "PCOMPG,1\n,101,9,0.001,0.\n,102,1,0.001,90.")))
sp("pcompg ply thickness negative", ["check", S], panel((PSHELL1, "PCOMPG,1\n,101,1,-0.001,0.\n,102,1,0.001,90.")))
sp("pcompg no plies", ["check", S], panel((PSHELL1, "PCOMPG,1,,,,,,,")))
sp("zoffs huge on every skin quad", ["frequencies", S],
   lambda w: (w / "mesh.bdf").write_text("\n".join(
       ln + ",,1e10" if ln.startswith("CQUAD4,") and ln.count(",") == 6 else ln
       for ln in (w / "mesh.bdf").read_text().splitlines()) + "\n"))
sp("zoffs nan", ["frequencies", S], lambda w: sub(w / "mesh.bdf", "CQUAD4,1,1,1,2,1002,1001", "CQUAD4,1,1,1,2,1002,1001,,nan"))
sp("grid blank id in the INCLUDEd mesh", ["check", S], lambda w: sub(w / "mesh.bdf", "GRID,2,,0.025000", "GRID,,,0.025000"))

# ------------------------------------------------------------------ --scheduler addresses
for label, address in [("port 0", "tcp://127.0.0.1:0"), ("two ports", "tcp://127.0.0.1:1:2"),
                       ("path after port", "tcp://127.0.0.1:1/x"), ("leading space", " tcp://127.0.0.1:1"),
                       ("ipv6 unreachable", "tcp://[::1]:1"), ("unicode host", "tcp://h\u00f6st:1"),
                       ("ucx scheme", "ucx://127.0.0.1:1"), ("newline", "tcp://127.0.0.1:1\nx")]:
    case("fig2 mc scheduler " + label, F2, ["montecarlo", S, "--trials", "3", "--scheduler", address])

# ------------------------------------------------------------------ the plan TOML of design, and its outputs
case("fig2 design -o over truth.toml", F2, ["design", S, "-o", "@truth.toml"])
case("fig2 design -o over truth.toml --force", F2, ["design", S, "-o", "@truth.toml", "--force"])
case("fig2 design -o plan then update the plan", F2, ["update", "@p.toml"],
     lambda w: h.subprocess.run([h.CORE, "-m", "eigenupdate", "design", str(w / "study.toml"), "-o", str(w / "p.toml")],
                                env=dict(h.os.environ, PYTHONPATH=str(h.ROOT / "src")), capture_output=True))
case("fig2 design masses negative", F2, ["design", S, "-o", "@p.toml"], lambda w: sub(w / "study.toml", "masses = [0.35, 1.0, 2.0]", "masses = [-0.35, 1.0]"))
case("fig2 design modes empty", F2, ["design", S, "-o", "@p.toml"], lambda w: sub(w / "study.toml", "modes = [1, 2, 3, 4]\nfrequency_std_hz", "modes = []\nfrequency_std_hz"))
case("fig2 unit g on a mass", F2, ["update", S], lambda w: sub(w / "study.toml", "value = 9.7  # kg", 'value = 9.7\nunit = "g"'))
case("fig2 unit kN/mm on a spring", F2, ["check", S], lambda w: sub(w / "study.toml", "value = 6.000e+05  # N/m", 'value = 6.000e+05\nunit = "kN/mm"'))
nf("save-bdf over truth.bdf (another deck)", ["update", S, "--save-bdf", "@truth.bdf"])
nf("save-bdf over the study's own measured.csv --force", ["update", S, "--save-bdf", "@measured.csv", "--force"])
case("frf report extraction over swapped files", BF, ["report", S, "--saved-only", "--extraction", "@x.json", "-o", "@r.html"],
     lambda w: (h.subprocess.run([h.CORE, "-m", "eigenupdate", "extract", str(w / "study.toml"), "-o", str(w / "x.csv"), "--save", str(w / "x.json")],
                                 env=dict(h.os.environ, PYTHONPATH=str(h.ROOT / "src")), capture_output=True),
                sub(w / "study.toml", '"0.2 kg at 1" = "frf/0.2_kg_at_1.uff"\n"0.2 kg at 3" = "frf/0.2_kg_at_3.uff"',
                    '"0.2 kg at 1" = "frf/0.2_kg_at_3.uff"\n"0.2 kg at 3" = "frf/0.2_kg_at_1.uff"')))


if __name__ == "__main__":
    sys.exit(h.main())
