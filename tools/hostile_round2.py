# ruff: noqa: E501  (a table of cases, one per line)
"""Second round of hostile and wrong-data cases (tools/hostile.py runs the first): the
newer features (parameter units, NASTRAN shell/ply/section parameters, products of
parameters, --save-bdf targets), saved results that do not match, absurd sizes and
schedulers, FRF files with wrong axes, CSV number spellings, additions at restrained
coordinates. Same harness and output as tools/hostile.py:

    python tools/hostile_round2.py [-k SUBSTRING] [--keep]
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import hostile as h  # noqa: E402
from hostile import CORE, EX, NASTRAN, ROOT, case, csv_map, sub  # noqa: E402

h.CASES.clear()
S, M = "@study.toml", "@measured.csv"
F2, B, BF, NF, SP = "paper_fig2", "paper_beam", "paper_beam_frf", "nastran_frame", "stiffened_panel"
ENV = dict(os.environ, PYTHONPATH=str(ROOT / "src"))


def cli(python, *args):
    return subprocess.run([python, "-m", "eigenupdate", *map(str, args)], env=ENV,
                          capture_output=True, text=True)


def after(*fns):
    def mutate(w):
        for f in fns:
            f(w)
    return mutate


def study(old, new, count=1):
    return lambda w: sub(w / "study.toml", old, new, count)


# ------------------------------------------------------------------ parameter units
UNIT = "value = 9.7  # kg"
for label, text in [("empty", 'unit = ""'), ("number", "unit = 5"), ("newline", 'unit = "k\\ng"'),
                    ("long", f'unit = "{"m" * 41}"'), ("bidi", 'unit = "kg\\u202e"'),
                    ("html", 'unit = "<script>x</script>"'), ("spaces", 'unit = "   "'),
                    ("grams on kg", 'unit = "g"')]:
    case("fig2 unit " + label, F2, ["update", S], study(UNIT, UNIT + "\n" + text))
case("fig2 unit on perturbation", F2, ["check", S], study("mass = 0.35", 'mass = 0.35\nunit = "g"'))
case("fig2 unit report html", F2, ["report", S, "--saved-only", "-o", "@r.html"],
     study(UNIT, UNIT + '\nunit = "<b>kg</b>"'))
case("beam unit on EI", B, ["check", S], study("EI_std = 150.0", 'EI_std = 150.0\nEI_unit = "N m^2"'))
case("beam unit on point mass", B, ["update", S], study('name = "m_L"', 'name = "m_L"\nunit = "g"'))
case("fig2 unit mc table", F2, ["montecarlo", S, "--trials", "3", "--in-process", "--seed", "1"],
     study(UNIT, UNIT + '\nunit = "t"'))


# ------------------------------------------------------------------ measurement CSV spellings
def edit_csv(fn):
    return lambda w: csv_map(w / "measured.csv", fn)


def first_row(old, new):
    return lambda w: sub(w / "measured.csv", old, new)


R1 = "base,1,42.86564108114408,"
case("fig2 csv unicode minus freq", F2, ["update", S], first_row(R1, "base,1,\u221242.86564108114408,"))
case("fig2 csv unicode minus exponent", F2, ["update", S], first_row(R1, "base,1,4.286564108114408e\u22121,"))
case("fig2 csv decimal comma quoted", F2, ["update", S], first_row(R1, 'base,1,"42,86564108114408",'))
case("fig2 csv thousands separator quoted", F2, ["update", S], first_row(R1, 'base,1,"4,286.564108114408",'))
case("fig2 csv thousands apostrophe", F2, ["update", S], first_row(R1, "base,1,4'286.56,"))
case("fig2 csv nbsp in number", F2, ["update", S], first_row(R1, "base,1,42.8656\u00a04108114408,"))
case("fig2 csv narrow nbsp thousands", F2, ["update", S], first_row(R1, "base,1,4\u202f286.5,"))
case("fig2 csv std decimal comma", F2, ["update", S, "--method", "weighted-least-squares"],
     edit_csv(lambda ln: ln + '"0,01"'))
case("fig2 csv hex float", F2, ["update", S], first_row(R1, "base,1,0x1.56ep5,"))
case("fig2 csv inf", F2, ["update", S], first_row(R1, "base,1,infinity,"))
case("fig2 csv underflow 1e-400", F2, ["update", S, "--method", "weighted-least-squares"],
     edit_csv(lambda ln: ln + "1e-400"))
case("fig2 csv freq with unit", F2, ["update", S], first_row(R1, "base,1,42.86564108114408 Hz,"))
case("fig2 csv freq plus sign", F2, ["update", S], first_row(R1, "base,1,+42.86564108114408,"))
case("fig2 csv duplicated header col", F2, ["update", S],
     lambda w: sub(w / "measured.csv", "configuration,mode,frequency_hz,std_hz", "configuration,mode,frequency_hz,frequency_hz"))
case("fig2 csv duplicated header freq first", F2, ["update", S],
     lambda w: (w / "measured.csv").write_text("configuration,mode,frequency_hz,frequency_hz,std_hz\n" + "".join(
         f"{ln.split(',')[0]},{ln.split(',')[1]},1.0,{ln.split(',')[2]},\n"
         for ln in (w / "measured.csv").read_text().splitlines()[1:] if not ln.startswith("#"))))
case("fig2 csv header twice (concatenated files)", F2, ["update", S],
     lambda w: (w / "measured.csv").write_text((w / "measured.csv").read_text() + "configuration,mode,frequency_hz,std_hz\n"))
case("fig2 csv header upper case", F2, ["update", S],
     lambda w: sub(w / "measured.csv", "configuration,mode,frequency_hz,std_hz", "CONFIGURATION,MODE,FREQUENCY_HZ,STD_HZ"))
case("fig2 csv header spaces", F2, ["update", S],
     lambda w: sub(w / "measured.csv", "configuration,mode,frequency_hz,std_hz", "configuration, mode, frequency_hz, std_hz"))
case("fig2 csv no header", F2, ["update", S],
     lambda w: sub(w / "measured.csv", "configuration,mode,frequency_hz,std_hz\n", ""))
case("fig2 csv std column missing", F2, ["update", S],
     lambda w: (w / "measured.csv").write_text("\n".join(ln.rsplit(",", 1)[0] for ln in (w / "measured.csv").read_text().splitlines()) + "\n"))
case("fig2 csv std in percent", F2, ["update", S, "--method", "weighted-least-squares"],
     edit_csv(lambda ln: ln + "0.01%"))
case("fig2 csv mode unicode digit", F2, ["update", S], first_row(R1, "base,\u0661,42.86564108114408,"))
case("fig2 csv mode 01", F2, ["update", S], first_row(R1, "base,01,42.86564108114408,"))
case("fig2 csv mode +1", F2, ["update", S], first_row(R1, "base,+1,42.86564108114408,"))
case("fig2 csv mode 1e0", F2, ["update", S], first_row(R1, "base,1e0,42.86564108114408,"))
case("fig2 csv latin1 name", F2, ["update", S],
     lambda w: (sub(w / "study.toml", '"0.35 kg at 1"', '"0.35 kg à 1"'),
                (w / "measured.csv").write_bytes((w / "measured.csv").read_text().replace("0.35 kg at 1", "0.35 kg à 1").encode("latin-1"))))
case("fig2 csv NFD name", F2, ["update", S],
     lambda w: (sub(w / "study.toml", '"0.35 kg at 1"', '"0.35 kg \u00e0 1"'),
                sub(w / "measured.csv", "0.35 kg at 1", "0.35 kg a\u0300 1", 3)))

# ------------------------------------------------------------------ additions
case("fig2 add mass 0 among others", F2, ["check", S],
     study("coordinate = 4\nmass = 0.35", "add = [{coordinate = 4, mass = 0.35}, {coordinate = 1, mass = 0.0}]"))
case("fig2 add mass -0.0", F2, ["check", S], study("coordinate = 4\nmass = 0.35", "coordinate = 4\nmass = -0.0"))
case("fig2 add mass 1e-100", F2, ["update", S], study("coordinate = 4\nmass = 0.35", "coordinate = 4\nmass = 1e-100"))
case("fig2 add mass and negative stiffness", F2, ["check", S], study("coordinate = 4\nmass = 0.35", "coordinate = 4\nmass = 0.35\nstiffness = -1e3"))
case("fig2 simulate negative stiffness", F2, ["simulate", "@truth.toml", "-o", "@o.csv"],
     lambda w: sub(w / "truth.toml", "coordinate = 4\nmass = 0.35", "coordinate = 4\nstiffness = -1e5"))
case("fig2 add mass string", F2, ["check", S], study("coordinate = 4\nmass = 0.35", 'coordinate = 4\nmass = "0.35"'))
case("fig2 add mass inf", F2, ["check", S], study("coordinate = 4\nmass = 0.35", "coordinate = 4\nmass = inf"))
case("fig2 add stiffness 1e100", F2, ["update", S], study("coordinate = 4\nmass = 0.35", "coordinate = 4\nstiffness = 1e100"))
case("fig2 model mass 0 (massless coordinate)", F2, ["frequencies", S], study("value = 4.7  # kg", "value = 0.0", 1))
case("fig2 model mass negative", F2, ["frequencies", S], study("value = 4.7  # kg", "value = -4.7", 1))
case("fig2 model spring negative", F2, ["frequencies", S], study("value = 6.000e+05  # N/m", "value = -6.0e5"))
case("fig2 model spring 0", F2, ["update", S], study("value = 6.000e+05  # N/m", "value = 0.0"))
case("fig2 pert mass at massless coordinate", F2, ["update", S],
     study("value = 4.7  # kg", "value = 0.0\nupdate = false", 2))
case("beam pert restrained rotation", B, ["check", S],
     after(study("mass_per_length_std = 0.1", "mass_per_length_std = 0.1\nrestrained = [2]"),
           study("coordinate = 1\nmass = 0.2", "coordinate = 2\nmass = 0.001")))
case("beam pert stiffness at restrained", B, ["check", S],
     after(study("mass_per_length_std = 0.1", "mass_per_length_std = 0.1\nrestrained = [1]"),
           study("coordinate = 1\nmass = 0.2", "coordinate = 1\nstiffness = 1e4")))
case("beam design at restrained", B, ["design", S, "-o", "@p.toml"],
     after(study("mass_per_length_std = 0.1", "mass_per_length_std = 0.1\nrestrained = [1, 2]"),
           study("coordinate = 1\nmass = 0.2", "coordinate = 3\nmass = 0.2"),
           study('coordinates = "translational"', "coordinates = [1, 3, 5]")))
case("beam sweep restrained", B, ["sweep", S, "--coordinate", "1", "--max-mass", "1", "-o", "@s.png"],
     after(study("mass_per_length_std = 0.1", "mass_per_length_std = 0.1\nrestrained = [1, 2]"),
           study("coordinate = 1\nmass = 0.2", "coordinate = 3\nmass = 0.2")))
case("beam frf input restrained", B, ["frf", S, "--input", "1", "--output", "3", "-o", "@f.png"],
     after(study("mass_per_length_std = 0.1", "mass_per_length_std = 0.1\nrestrained = [1, 2]"),
           study("coordinate = 1\nmass = 0.2", "coordinate = 3\nmass = 0.2")))
case("beam mc truth restrained differently", B, ["montecarlo", S, "--trials", "3", "--in-process", "--truth", "@t.toml"],
     lambda w: (w / "t.toml").write_text((w / "study.toml").read_text().replace("mass_per_length_std = 0.1", "mass_per_length_std = 0.1\nrestrained = [17]")))

# ------------------------------------------------------------------ design / montecarlo sizes and schedulers
for label, sched in [("nohost", "tcp://nohost:1"), ("no scheme", "nohost:8786"), ("empty host", "tcp://:8786"),
                     ("port 99999", "tcp://127.0.0.1:99999"), ("inproc", "inproc://x"), ("http", "http://127.0.0.1:8786"),
                     ("bracket", "tcp://[::1"), ("10.255.255.1 blackhole", "tcp://10.255.255.1:8786")]:
    case("fig2 mc scheduler " + label, F2, ["montecarlo", S, "--trials", "3", "--scheduler", sched])
case("fig2 design scheduler nohost", F2, ["design", S, "-o", "@p.toml", "--scheduler", "tcp://nohost:1"])
case("fig2 design validate scheduler blackhole", F2, ["design", S, "-o", "@p.toml", "--validate", "3", "--scheduler", "tcp://10.255.255.1:8786"])
case("fig2 mc env scheduler garbage", F2, ["montecarlo", S, "--trials", "3"], env={"EIGENUPDATE_SCHEDULER": "tcp://nohost:1"})
case("fig2 mc env scheduler + in-process", F2, ["montecarlo", S, "--trials", "3", "--in-process"], env={"EIGENUPDATE_SCHEDULER": "garbage"})
case("fig2 design env scheduler garbage", F2, ["design", S, "-o", "@p.toml"], env={"EIGENUPDATE_SCHEDULER": "tcp://nohost:1"})
for w_ in ["-1", "abc", "1.5"]:  # "0": tools/hostile.py
    case("fig2 mc workers " + w_, F2, ["montecarlo", S, "--trials", "3", "--workers", w_])
case("fig2 mc workers + scheduler", F2, ["montecarlo", S, "--trials", "3", "--workers", "2", "--scheduler", "tcp://127.0.0.1:1"])
case("fig2 mc workers + in-process", F2, ["montecarlo", S, "--trials", "3", "--workers", "2", "--in-process"])
case("fig2 mc trials 100001", F2, ["montecarlo", S, "--trials", "100001", "--in-process"])
case("fig2 mc trials env limit garbage", F2, ["montecarlo", S, "--trials", "3", "--in-process"], env={"EIGENUPDATE_MAX_TRIALS": "-5"})
case("fig2 mc trials env limit huge", F2, ["montecarlo", S, "--trials", "3", "--in-process"], env={"EIGENUPDATE_MAX_TRIALS": "1e30"})
case("fig2 design masses 25000 values", F2, ["design", S, "-o", "@p.toml"],
     study("masses = [0.35, 1.0, 2.0]", "masses = [" + ", ".join(f"{0.001 * (i + 1):.3f}" for i in range(6000)) + "]"))
case("fig2 design configurations 4 of 12", F2, ["design", S, "-o", "@p.toml"], study("configurations = 3", "configurations = 12"))
case("fig2 design configurations 13 of 12", F2, ["design", S, "-o", "@p.toml"], study("configurations = 3", "configurations = 13"))
case("fig2 design additions 4 configurations 3", F2, ["design", S, "-o", "@p.toml"], study("configurations = 3", "configurations = 3\nadditions = 4"))
case("fig2 design additions 3", F2, ["design", S, "-o", "@p.toml"], study("configurations = 3", "configurations = 3\nadditions = 3"))
case("beam design all coords 10 masses additions 3", B, ["design", S, "-o", "@p.toml"],
     study("masses = [0.1, 0.2, 0.5]", "masses = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0]\nadditions = 3"))
case("beam design all coordinates", B, ["design", S, "-o", "@p.toml"], study('coordinates = "translational"', 'coordinates = "all"'))
case("beam design coordinates bogus word", B, ["design", S, "-o", "@p.toml"], study('coordinates = "translational"', 'coordinates = "rotational"'))
case("beam design validate 3 workers 2", B, ["design", S, "-o", "@p.toml", "--validate", "3", "--workers", "2"])
case("fig2 mc -o over the measurement file's dir (trials.csv input)", F2,
     ["montecarlo", S, "--trials", "3", "--in-process", "--truth", "@truth.toml", "-o", "@"],
     lambda w: ((w / "measured.csv").rename(w / "trials.csv"), sub(w / "study.toml", 'frequencies = "measured.csv"', 'frequencies = "trials.csv"')))
case("panel design translational 3 masses", SP, ["design", S, "-o", "@p.toml"],
     lambda w: (w / "study.toml").write_text((w / "study.toml").read_text() + '\n[design]\ncoordinates = "translational"\nmasses = [0.1, 3.0]\nconfigurations = 4\nmodes = [1, 2, 3]\nfrequency_std_hz = 0.01\n'),
     python=NASTRAN)


# ------------------------------------------------------------------ report with saved results that do not match
case("fig2 report --result other method", F2, ["report", S, "--saved-only", "--result", "@r.json", "-o", "@r.html"],
     lambda w: (csv_map(w / "measured.csv", lambda ln: ln + "0.01"),
                cli(CORE, "update", w / "study.toml", "--method", "weighted-least-squares", "--save", w / "r.json")))
case("fig2 report --result model spring moved, saved-only", F2, ["report", S, "--saved-only", "--result", "@r.json", "-o", "@r.html"],
     lambda w: (cli(CORE, "update", w / "study.toml", "--save", w / "r.json"), sub(w / "study.toml", "coordinates = [2, 4]", "coordinates = [1, 4]")))
case("fig2 report --result other modes", F2, ["report", S, "--saved-only", "--result", "@r.json", "-o", "@r.html"],
     lambda w: (cli(CORE, "update", w / "study.toml", "--save", w / "r.json"), sub(w / "study.toml", "modes = [1, 2, 3]", "modes = [1, 2]")))
case("fig2 report --result param renamed", F2, ["report", S, "--saved-only", "--result", "@r.json", "-o", "@r.html"],
     lambda w: (cli(CORE, "update", w / "study.toml", "--save", w / "r.json"), sub(w / "study.toml", 'name = "k6"', 'name = "k7"')))
case("fig2 report --result param fixed now", F2, ["report", S, "--saved-only", "--result", "@r.json", "-o", "@r.html"],
     lambda w: (cli(CORE, "update", w / "study.toml", "--save", w / "r.json"), sub(w / "study.toml", "value = 6.000e+05  # N/m", "value = 6.0e5\nupdate = false")))
case("fig2 report --result perturbation removed", F2, ["report", S, "--saved-only", "--result", "@r.json", "-o", "@r.html"],
     lambda w: (cli(CORE, "update", w / "study.toml", "--save", w / "r.json"),
                sub(w / "study.toml", '[[perturbation]]\nname = "0.35 kg at 4"\ncoordinate = 4\nmass = 0.35\n', "")))
case("fig2 report --result perturbation renamed", F2, ["report", S, "--saved-only", "--result", "@r.json", "-o", "@r.html"],
     lambda w: (cli(CORE, "update", w / "study.toml", "--save", w / "r.json"), sub(w / "study.toml", '"0.35 kg at 4"', '"heavy at 4"'),
                sub(w / "measured.csv", "0.35 kg at 4", "heavy at 4", 3)))
case("fig2 report --result model spring moved", F2, ["report", S, "--result", "@r.json", "-o", "@r.html"],
     lambda w: (cli(CORE, "update", w / "study.toml", "--save", w / "r.json"), sub(w / "study.toml", "coordinates = [2, 4]", "coordinates = [1, 4]")))
case("fig2 report --result std added", F2, ["report", S, "--saved-only", "--result", "@r.json", "-o", "@r.html"],
     lambda w: (cli(CORE, "update", w / "study.toml", "--save", w / "r.json"), csv_map(w / "measured.csv", lambda ln: ln + "0.01")))
case("fig2 report --result edited x", F2, ["report", S, "--saved-only", "--result", "@r.json", "-o", "@r.html"],
     lambda w: (cli(CORE, "update", w / "study.toml", "--save", w / "r.json"),
                (w / "r.json").write_text(re.sub(r'"x": \[\s*[0-9.e+-]+', '"x": [ 1e9', (w / "r.json").read_text(), count=1))))
case("fig2 report --result unconverged", F2, ["report", S, "--saved-only", "--result", "@r.json", "-o", "@r.html"],
     lambda w: (sub(w / "study.toml", "max_iterations = 20", "max_iterations = 1"), cli(CORE, "update", w / "study.toml", "--save", w / "r.json"),
                sub(w / "study.toml", "max_iterations = 1", "max_iterations = 20")))
case("fig2 report --result solve (not saved-only) other", F2, ["report", S, "--result", "@r.json", "-o", "@r.html"],
     lambda w: (cli(CORE, "update", w / "study.toml", "--save", w / "r.json"), sub(w / "study.toml", 'name = "k6"', 'name = "k7"')))
case("fig2 report --montecarlo other study", F2, ["report", S, "--saved-only", "--montecarlo", "@mc/summary.json", "-o", "@r.html"],
     lambda w: cli(CORE, "montecarlo", EX / B / "study.toml", "--trials", "3", "--in-process", "--seed", "1", "-o", w / "mc"))
case("fig2 report --design other study", F2, ["report", S, "--saved-only", "--design", "@d.json", "-o", "@r.html"],
     lambda w: (w / "d.json").write_text(cli(CORE, "design", EX / B / "study.toml", "-o", w / "p.toml", "--json").stdout))
case("fig2 report --extracted other study", F2, ["report", S, "--saved-only", "--extracted", "@e.csv", "-o", "@r.html"],
     lambda w: (w / "e.csv").write_text((EX / BF / "extracted.csv").read_text()))
# two FRF files swapped after `extract --save`: tools/hostile_round3.py
case("frf report --extraction from truth frfs regenerated", BF, ["report", S, "--saved-only", "--extraction", "@x.json", "-o", "@r.html"],
     lambda w: (cli(CORE, "extract", w / "study.toml", "-o", w / "x.csv", "--save", w / "x.json"),
                cli(CORE, "simulate-frf", w / "truth.toml", "-o", w / "frf", "--input", "11", "--outputs", "1", "15", "--fmax", "1600", "--seed", "7", "--binary", "--force")))
case("frf report --extracted while csv differs", BF, ["report", S, "--saved-only", "--extracted", "@e.csv", "-o", "@r.html"],
     lambda w: (w / "e.csv").write_text((w / "extracted.csv").read_text().replace("199.877", "205.877")))
case("fig2 frf --updated other modes", F2, ["frf", S, "--input", "1", "--output", "1", "--updated", "@r.json", "-o", "@f.png"],
     lambda w: (cli(CORE, "update", w / "study.toml", "--save", w / "r.json"), sub(w / "study.toml", 'name = "k6"', 'name = "k7"')))


case("fig2 sim-frf two names one file", F2, ["simulate-frf", "@truth.toml", "-o", "@o", "--input", "1", "--outputs", "2", "--fmax", "200"],
     lambda w: sub(w / "truth.toml", 'name = "0.35 kg at 2"', 'name = "0.35 kg at 1!"'))
case("frf extract plots two names one file", BF, ["extract", "@x.uff", "@x!.uff", "-o", "@e.csv", "--plots", "@plots"],
     lambda w: ((w / "frf" / "base.uff").rename(w / "x.uff"), (w / "frf" / "0.2_kg_at_1.uff").rename(w / "x!.uff")))


# ------------------------------------------------------------------ UFF 58 with wrong axes
def ascii_frfs(edit=None, which="base.uff"):
    """the truth's FRFs as ASCII UFF 58 in a/, the study pointing at them; ``edit`` the
    text of one of them"""
    def mutate(w):
        p = cli(CORE, "simulate-frf", w / "truth.toml", "-o", w / "a", "--input", "11", "--outputs", "1", "15",
                "--fmax", "1600", "--df", "0.5", "--seed", "1")
        assert p.returncode == 0, p.stderr
        sub(w / "study.toml", '"frf/', '"a/', 20)
        if edit:
            f = w / "a" / which
            f.write_text(edit(f.read_text()))
    return mutate


REC7 = "         6      3200         1  5.00000e-01  5.00000e-01  0.00000e+00"
case("uff baseline ascii", BF, ["extract", S, "-o", "@e.csv"], ascii_frfs())
case("uff increment 0", BF, ["extract", S, "-o", "@e.csv"], ascii_frfs(lambda t: t.replace(REC7, REC7.replace("5.00000e-01  0.0", "0.00000e+00  0.0"), 1)))
case("uff increment negative", BF, ["extract", S, "-o", "@e.csv"], ascii_frfs(lambda t: t.replace(REC7, REC7.replace("5.00000e-01  0.0", "-5.0000e-01  0.0"), 1)))
case("uff increment nan", BF, ["extract", S, "-o", "@e.csv"], ascii_frfs(lambda t: t.replace(REC7, REC7.replace("5.00000e-01  0.0", "        nan  0.0"), 1)))
case("uff increment 1.0 (twice)", BF, ["extract", S, "-o", "@e.csv"], ascii_frfs(lambda t: t.replace(REC7, REC7.replace("5.00000e-01  0.0", "1.00000e+00  0.0"), 2)))
case("uff increment 0.5 vs others 1.0 one FRF", BF, ["extract", S, "-o", "@e.csv"], ascii_frfs(lambda t: t.replace(REC7, REC7.replace("5.00000e-01  0.0", "1.00000e+00  0.0"), 1)))
case("uff start 1e6", BF, ["extract", S, "-o", "@e.csv"], ascii_frfs(lambda t: t.replace(REC7, REC7.replace("5.00000e-01  5.0", "1.00000e+06  5.0"), 2)))
case("uff npoints 3300", BF, ["extract", S, "-o", "@e.csv"], ascii_frfs(lambda t: t.replace(REC7, REC7.replace("3200", "3300"), 1)))
case("uff npoints 3100", BF, ["extract", S, "-o", "@e.csv"], ascii_frfs(lambda t: t.replace(REC7, REC7.replace("3200", "3100"), 1)))
case("uff npoints 0", BF, ["extract", S, "-o", "@e.csv"], ascii_frfs(lambda t: t.replace(REC7, REC7.replace("3200", "   0"), 1)))
case("uff npoints 2e9", BF, ["extract", S, "-o", "@e.csv"], ascii_frfs(lambda t: t.replace(REC7, REC7.replace("      3200", "2000000000"), 1)))
case("uff uneven flag", BF, ["extract", S, "-o", "@e.csv"], ascii_frfs(lambda t: t.replace(REC7, REC7.replace("3200         1", "3200         0"), 2)))
case("uff ordinate type real", BF, ["extract", S, "-o", "@e.csv"], ascii_frfs(lambda t: t.replace(REC7, REC7.replace("         6      3200", "         2      3200"), 1)))
case("uff abscissa rad/s label", BF, ["extract", S, "-o", "@e.csv"], ascii_frfs(lambda t: t.replace("18    0    0    0 Frequency            Hz    ", "18    0    0    0 Frequency            rad/s ", 2)))
case("uff abscissa rpm label", BF, ["extract", S, "-o", "@e.csv"], ascii_frfs(lambda t: t.replace("18    0    0    0 Frequency            Hz    ", "18    0    0    0 Frequency            RPM   ", 2)))
case("uff abscissa kHz label", BF, ["extract", S, "-o", "@e.csv"], ascii_frfs(lambda t: t.replace("18    0    0    0 Frequency            Hz    ", "18    0    0    0 Frequency            kHz   ", 2)))
case("uff abscissa type time", BF, ["extract", S, "-o", "@e.csv"], ascii_frfs(lambda t: t.replace("        18    0    0    0 Frequency            Hz  ", "        17    0    0    0 Time                 s   ", 2)))
case("uff ordinate label mm/N", BF, ["extract", S, "-o", "@e.csv"], ascii_frfs(lambda t: t.replace("Displacement         m    ", "Displacement         mm   ", 2)))
case("uff ordinate type 12 accel label m", BF, ["extract", S, "-o", "@e.csv"], ascii_frfs(lambda t: t.replace("         8    0    0    0 Displacement", "        12    0    0    0 Displacement", 2)))
case("uff nan ordinate", BF, ["extract", S, "-o", "@e.csv"], ascii_frfs(lambda t: t.replace("-1.14621974207e-02", "               nan", 1)))
case("uff inf ordinate", BF, ["extract", S, "-o", "@e.csv"], ascii_frfs(lambda t: t.replace("-1.14621974207e-02", "               inf", 1)))
case("uff 1e300 ordinate", BF, ["extract", S, "-o", "@e.csv"], ascii_frfs(lambda t: t.replace("-1.14621974207e-02", "  1.0000000000e300", 1)))
case("uff fortran D exponent", BF, ["extract", S, "-o", "@e.csv"], ascii_frfs(lambda t: t.replace("-1.14621974207e-02", "-1.14621974207D-02", 1)))
case("uff response node 99", BF, ["extract", S, "-o", "@e.csv"], ascii_frfs(lambda t: t.replace("receptance 1+Z/6+Z", "receptance 99+Z/6+Z").replace("NONE         1   3       NONE         6   3", "NONE        99   3       NONE         6   3", 1)))
case("uff response direction 1 (x)", BF, ["extract", S, "-o", "@e.csv"], ascii_frfs(lambda t: t.replace("NONE         1   3       NONE         6   3", "NONE         1   1       NONE         6   3", 1)))
case("uff response direction 5 (rotation)", BF, ["extract", S, "-o", "@e.csv"], ascii_frfs(lambda t: t.replace("NONE         1   3       NONE         6   3", "NONE         1   5       NONE         6   3", 1)))
case("uff reference differs", BF, ["extract", S, "-o", "@e.csv"], ascii_frfs(lambda t: t.replace("NONE         1   3       NONE         6   3", "NONE         1   3       NONE         5   3", 1)))
case("uff response = reference twice", BF, ["extract", S, "-o", "@e.csv"], ascii_frfs(lambda t: t.replace("NONE         8   3       NONE         6   3", "NONE         1   3       NONE         6   3", 1)))
case("uff frf --measured rad/s label", BF, ["frf", S, "--input", "11", "--output", "1", "--measured", "@a/base.uff", "-o", "@f.png"],
     ascii_frfs(lambda t: t.replace("18    0    0    0 Frequency            Hz    ", "18    0    0    0 Frequency            rad/s ", 2)))
case("uff extract files inc 0", BF, ["extract", "@a/base.uff", "-o", "@e.csv"], ascii_frfs(lambda t: t.replace(REC7, REC7.replace("5.00000e-01  0.0", "0.00000e+00  0.0"), 2)))


# ------------------------------------------------------------------ NASTRAN: shells, plies, sections, save-bdf
def panel(old, new, count=1, f="panel.bdf"):
    return lambda w: sub(w / f, old, new, count)


def sp(name, argv, mutate=None, env=None):
    case("panel " + name, SP, argv, mutate, NASTRAN, env)


def nf(name, argv, mutate=None):
    case("nas2 " + name, NF, argv, mutate, NASTRAN)


TSKIN = 'card = "PSHELL"\nid = 1\nfield = "T"'
sp("baseline check", ["check", S])
sp("T blank in deck", ["check", S], panel("PSHELL,1,1,0.002,1,,1", "PSHELL,1,1,,1,,1"))
sp("T zero in deck", ["check", S], panel("PSHELL,1,1,0.002,1,,1", "PSHELL,1,1,0.,1,,1"))
sp("T negative in deck", ["check", S], panel("PSHELL,1,1,0.002,1,,1", "PSHELL,1,1,-0.002,1,,1"))
sp("T with MID2 blank", ["check", S], panel("PSHELL,1,1,0.002,1,,1", "PSHELL,1,1,0.002,,,1"))
sp("T with 12I/T3 given", ["check", S], panel("PSHELL,1,1,0.002,1,,1", "PSHELL,1,1,0.002,1,2.0,1"))
sp("T with TS/T given", ["check", S], panel("PSHELL,1,1,0.002,1,,1", "PSHELL,1,1,0.002,1,,1,0.5"))
sp("T with NSM", ["check", S], panel("PSHELL,1,1,0.002,1,,1", "PSHELL,1,1,0.002,1,,1,,5.0"))
sp("T with MID3 other material", ["check", S], after(panel("MAT1,1,7.0e10,,0.33,2700.", "MAT1,1,7.0e10,,0.33,2700.\nMAT1,7,2.0e11,,0.3,7800."), panel("PSHELL,1,1,0.002,1,,1", "PSHELL,1,1,0.002,1,,7")))
sp("T field lowercase", ["check", S], study(TSKIN, 'card = "PSHELL"\nid = 1\nfield = "t"'))
sp("T field T1 (corner)", ["check", S], study(TSKIN, 'card = "PSHELL"\nid = 1\nfield = "T1"'))
sp("field MID1", ["check", S], study(TSKIN, 'card = "PSHELL"\nid = 1\nfield = "MID1"'))
sp("field 12I/T**3", ["check", S], study(TSKIN, 'card = "PSHELL"\nid = 1\nfield = "12I/T**3"'))
sp("field NSM", ["check", S], study(TSKIN, 'card = "PSHELL"\nid = 1\nfield = "NSM"'))
sp("T twice", ["check", S], study('card = "PSHELL"\nid = 2\nfield = "T"', TSKIN))
sp("PSHELL id unused", ["check", S], after(panel("PSHELL,2,1,0.003,1,,1", "PSHELL,2,1,0.003,1,,1\nPSHELL,5,1,0.003,1,,1"), study('card = "PSHELL"\nid = 2', 'card = "PSHELL"\nid = 5')))
sp("unit T mm", ["update", S], study('std = 2.0e-4\nunit = "m"', 'std = 2.0e-4\nunit = "mm"'))
sp("unit E force/length^2 given", ["check", S], study('unit = "Pa"', 'unit = "force/length^2"'))
sp("unit on non-nastran key", ["check", S], study('unit = "Pa"', 'unit = "Pa"\nunits = "Pa"'))
sp("mass at SPC'd grid (included SPC1)", ["check", S], study("grid = 8013\ncomponent = 3", "grid = 8001\ncomponent = 3"))
sp("spring at SPC'd grid", ["check", S], study("grid = 8013\ncomponent = 3\nmass = 0.1", "grid = 8001\ncomponent = 3\nstiffness = 1e4"))
sp("mass on drilling dof K6ROT 0", ["check", S], after(panel("PARAM,COUPMASS,1", "PARAM,COUPMASS,1\nPARAM,K6ROT,0."), study("grid = 8013\ncomponent = 3", "grid = 8013\ncomponent = 6")))
sp("mass on drilling dof (K6ROT default)", ["check", S], study("grid = 8013\ncomponent = 3", "grid = 8013\ncomponent = 6"))
sp("mass 0 at grid", ["check", S], study("grid = 8013\ncomponent = 3\nmass = 0.1", "grid = 8013\ncomponent = 3\nmass = 0.0"))
sp("stiffness negative", ["check", S], study("grid = 8013\ncomponent = 3\nmass = 0.1", "grid = 8013\ncomponent = 3\nstiffness = -10.0"))
sp("mass at GRID PS", ["check", S], lambda w: (w / "mesh.bdf").write_text(re.sub(r"(?m)^(GRID,8013,[^\n]*)$", lambda m: m.group(1) + ("," * (7 - m.group(1).count(","))) + "3", (w / "mesh.bdf").read_text())))
sp("mass at grid not in deck", ["check", S], study("grid = 8013", "grid = 8014000"))
sp("save-bdf included mesh", ["update", S, "--save-bdf", "@mesh.bdf"])
sp("save-bdf panel itself", ["update", S, "--save-bdf", "@panel.bdf"])
sp("save-bdf symlink to panel", ["update", S, "--save-bdf", "@ln.bdf"], lambda w: os.symlink(w / "panel.bdf", w / "ln.bdf"))
sp("save-bdf hardlink to mesh", ["update", S, "--save-bdf", "@hl.bdf"], lambda w: os.link(w / "mesh.bdf", w / "hl.bdf"))
sp("save-bdf directory", ["update", S, "--save-bdf", "@"])
sp("save-bdf /dev/full", ["update", S, "--save-bdf", "/dev/full"])
sp("save-bdf measured.csv", ["update", S, "--save-bdf", M])
sp("save-bdf truth.bdf (not an input)", ["update", S, "--save-bdf", "@truth.bdf"])
sp("save-bdf = --save", ["update", S, "--save-bdf", "@o.bdf", "--save", "@o.bdf"])
sp("save-bdf fails to converge", ["update", S, "--save-bdf", "@o.bdf"], study("[measurement]", "[updating]\nmax_iterations = 1\n\n[measurement]"))
case("fig2 save-bdf on a spring-mass study", F2, ["update", S, "--save-bdf", "@o.bdf"])


NO_E = ('[[model.parameter]]\nname = "E"\ncard = "MAT1"\nid = 1\nfield = "E"\nstd = 5.0e9\nunit = "Pa"\n', "")


def pcomp(card, field="T1", keep_e=False):
    return after(panel("PSHELL,1,1,0.002,1,,1", card), study(TSKIN, f'card = "PCOMP"\nid = 1\nfield = "{field}"'),
                 *([] if keep_e else [study(*NO_E)]))


SYM = "PCOMP,1,,,,,,,SYM\n,1,0.001,0.\n"
for f in ["T1", "T2", "T0", "T", "THICK1", "T01", "t1", "T1 ", "THETA1", "MID1", "T+1"]:
    sp("pcomp field " + f, ["check", S], pcomp(SYM, f))
sp("pcomp ply T blank first", ["check", S], pcomp("PCOMP,1,,,,,,,SYM\n,1,,0.\n"))
sp("pcomp ply T zero", ["check", S], pcomp("PCOMP,1,,,,,,,SYM\n,1,0.,0.\n"))
sp("pcomp ply T negative", ["check", S], pcomp("PCOMP,1,,,,,,,SYM\n,1,-0.001,0.\n"))
sp("pcomp 2 plies T2 blank inherits", ["check", S], pcomp("PCOMP,1,,,,,,,SYM\n,1,0.0005,0.,,1,,90.\n", "T2"))
sp("pcomp 2 plies T1 with T2 blank", ["update", S, "--save-bdf", "@o.bdf"], pcomp("PCOMP,1,,,,,,,SYM\n,1,0.0005,0.,,1,,90.\n", "T1"))
sp("pcomp two params same ply", ["check", S], after(pcomp(SYM), study('card = "PSHELL"\nid = 2\nfield = "T"', 'card = "PCOMP"\nid = 1\nfield = "T1"')))
sp("pcomp ply param and MAT1 E", ["check", S], pcomp(SYM, keep_e=True))
sp("pcomp ply update save-bdf", ["update", S, "--save-bdf", "@o.bdf"], pcomp(SYM))
sp("pcomp lam BLEND", ["check", S], pcomp("PCOMP,1,,,,,,,BLEND\n,1,0.001,0.\n"))
sp("pcomp 1e6 plies", ["check", S], pcomp("PCOMP,1,,,,,,,SYM\n" + ",1,0.000001,0.,,1,0.000001,0.\n" * 2000))


def frame(old, new, count=1):
    return lambda w: sub(w / "frame.bdf", old, new, count)


PB1 = "PBAR           1       1  .00543.0000249  8.89-6  3.12-7"
PBARL_I = "PBARL,1,1,,I\n,0.2,0.1,0.1,0.0056,0.0085,0.0085"


def pbarl(card=PBARL_I, field="DIM1", extra=None):
    mut = [frame(PB1, card), study('name = "E_columns"\ncard = "MAT1"\nid = 1\nfield = "E"',
                                   f'name = "d"\ncard = "PBARL"\nid = 1\nfield = "{field}"')]
    return after(*mut, *(extra or []))


nf("pbarl baseline", ["check", S], frame(PB1, PBARL_I))
for f in ["DIM1", "DIM6", "DIM7", "DIM0", "DIM", "dim1", "DIM01", "NSM", "A"]:
    nf("pbarl field " + f, ["check", S], pbarl(field=f))
nf("pbarl DIM1 and E product", ["check", S], after(frame(PB1, PBARL_I), study('name = "E_beams"\ncard = "MAT1"\nid = 2', 'name = "d"\ncard = "PBARL"\nid = 1\nfield = "DIM1"\n\n[[model.parameter]]\nname = "E_beams"\ncard = "MAT1"\nid = 2')))
nf("pbarl DIM4 (web) update save-bdf", ["update", S, "--save-bdf", "@o.bdf"], pbarl(field="DIM4"))
nf("pbarl ROD DIM1 0", ["check", S], pbarl("PBARL,1,1,,ROD\n,0.", "DIM1"))
nf("pbarl ROD DIM1 negative", ["check", S], pbarl("PBARL,1,1,,ROD\n,-0.05", "DIM1"))
nf("pbarl BOX wall = half", ["check", S], pbarl("PBARL,1,1,,BOX\n,0.2,0.2,0.1,0.01", "DIM3"))
nf("pbarl BOX wall near half update", ["update", S], pbarl("PBARL,1,1,,BOX\n,0.2,0.2,0.0999,0.01", "DIM3"))
nf("pbarl I used by no element", ["check", S], after(frame(PB1, PB1 + "\n" + PBARL_I.replace("PBARL,1", "PBARL,7")), study('name = "E_columns"\ncard = "MAT1"\nid = 1\nfield = "E"', 'name = "d"\ncard = "PBARL"\nid = 7\nfield = "DIM1"')))
nf("pbarl TUBE inner > outer", ["check", S], pbarl("PBARL,1,1,,TUBE\n,0.05,0.06", "DIM1"))
nf("pbarl dim std huge", ["check", S], pbarl(extra=[study("std = 1.5e10", "std = 1e10", 1)]))
nf("pbar A and E product", ["check", S], study('name = "E_beams"\ncard = "MAT1"\nid = 2', 'name = "A"\ncard = "PBAR"\nid = 1\nfield = "A"\nstd = 1e-4\n\n[[model.parameter]]\nname = "E_beams"\ncard = "MAT1"\nid = 2'))
nf("celas2 K unit label", ["check", S], study('field = "K"\nstd = 2.0e6', 'field = "K"\nstd = 2.0e6\nunit = "N/mm"'))
nf("save-bdf /dev/full", ["update", S, "--save-bdf", "/dev/full"])
nf("save-bdf dir", ["update", S, "--save-bdf", "@"])
nf("save-bdf into measured.csv via symlink", ["update", S, "--save-bdf", "@o.bdf"], lambda w: os.symlink(w / "measured.csv", w / "o.bdf"))
nf("save-bdf truth.toml (another study)", ["update", S, "--save-bdf", "@truth.toml"])
nf("mass at celas scalar grid 1006 comp 3", ["check", S], study("grid = 3001\ncomponent = 1", "grid = 1006\ncomponent = 3"))
nf("mass at 1006 comp 6 (SPC'd 12456)", ["check", S], study("grid = 3001\ncomponent = 1", "grid = 1006\ncomponent = 6"))
nf("negative grounded spring huge", ["frequencies", S], study("grid = 3001\ncomponent = 1\nmass = 40.0", "grid = 3001\ncomponent = 1\nstiffness = -1e12"))


# ------------------------------------------------------------------ products of parameters (matrices model terms)
def mtx_terms(text_edit):
    def mutate(w):
        sys.path.insert(0, str(ROOT / "tools"))
        import fuzz
        fuzz._mtx(w)
        s = (w / "study.toml").read_text()
        (w / "study.toml").write_text(text_edit(s))
    return mutate


def term(extra):
    # k2's own K file becomes a term k1 * k2 (a product)
    return mtx_terms(lambda s: s.replace('K = "k2.mtx"\n', "", 1) + "\n[[model.term]]\nK = \"k2.mtx\"\n" + extra + "\n")


for label, extra in [("product", "powers = { k1 = 1, k2 = 1 }"), ("power 0.5 param zero", "powers = { k2 = 0.5 }\ncoefficient = 1.0"),
                     ("power -1", "powers = { k2 = -1 }"), ("power 1e100", "powers = { k2 = 1e100 }"), ("power nan", "powers = { k2 = nan }"),
                     ("power inf", "powers = { k2 = inf }"), ("power 1e-100", "powers = { k2 = 1e-100 }"), ("coefficient 0", "powers = { k2 = 1 }\ncoefficient = 0.0"),
                     ("coefficient negative", "powers = { k2 = 1 }\ncoefficient = -1.0"), ("coefficient nan", "powers = { k2 = 1 }\ncoefficient = nan"),
                     ("power on fixed param", "powers = { k2 = 2 }"), ("same term twice", "powers = { k2 = 1 }\n\n[[model.term]]\nK = \"k2.mtx\"\npowers = { k2 = 1 }"),
                     ("powers list", "powers = [1, 2]"), ("power bool", "powers = { k2 = true }"), ("unknown key", "powers = { k2 = 1 }\nfoo = 1"),
                     ("power 3 update", "powers = { k2 = 3 }")]:
    case("terms " + label, F2, ["update", S], term(extra))


if __name__ == "__main__":
    sys.exit(h.main())
