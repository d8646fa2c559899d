"""A deck whose solution sequence computes the modes of another stiffness than its K and M
is refused, naming the line (io/nastran_solution.py, issue 20).

Found by tools/deck_sweep.py: NASTRAN-95's demonstration D13-01-1A (rigid format 13,
"normal modes analysis with differential stiffness", nasa/NASTRAN-95 inp/d13011a.inp) read
as an unloaded beam, 41 % off the frequencies NASTRAN-95 printed for it. Sources for the
sequences refused: NASTRAN-95 User's Manual section 3 (rigid formats 13, 14, 15; APP
HEAT), MSC Nastran Quick Reference Guide (STATSUB: "selects the static solution to use
in forming the differential stiffness for buckling analysis, normal modes, complex
eigenvalue..."; PARAM NMLOOP; SOL 114-118 cyclic symmetry; SOL 153/159 heat transfer).

Independent check: the same cantilever accepted under SOL 103 gives the Euler-Bernoulli
frequencies of its discrete model; each refusal is one line with the deck's line number,
exit 2 through the CLI. Run for real in .venv-nastran (``make test``)."""

from __future__ import annotations

import pytest
from nastran_frames import need

pytestmark = [pytest.mark.nastran,
              pytest.mark.filterwarnings("ignore::eigenupdate.errors.EigenupdateWarning")]
need("pyNastran")
from eigenupdate.errors import InputError  # noqa: E402
from eigenupdate.io.nastran import read_nastran  # noqa: E402

BULK = ("BEGIN BULK\nGRID,1,,0.,0.,0.\nGRID,2,,.5,0.,0.\nGRID,3,,1.,0.,0.\n"
        "CBAR,1,1,1,2,0.,0.,1.\nCBAR,2,1,2,3,0.,0.,1.\n"
        "PBAR,1,1,1.e-3,2.e-7,8.e-7,5.e-7\nMAT1,1,2.e11,,0.3,7800.\n"
        "CONM2,10,3,,2.\nSPC1,1,123456,1\nEIGRL,1,,,4\nENDDATA\n")


def _deck(tmp_path, executive: str, case: str = "", bulk_extra: str = ""):
    path = tmp_path / "deck.bdf"
    bulk = BULK.replace("ENDDATA", bulk_extra + "ENDDATA")
    path.write_text(f"{executive}\nCEND\nSPC = 1\nMETHOD = 1\n{case}{bulk}")
    return path


@pytest.mark.parametrize("executive,case,extra,line,words", [
    ("ID D13\nAPP DISPLACEMENT\nSOL   13,0", "", "", 3, "differential stiffness"),
    ("SOL 103", "STATSUB = 2\n", "", 5, "STATSUB"),
    ("SOL 106", "", "PARAM,NMLOOP,10\n", 16, "NMLOOP"),
    ("SOL CYCMODE", "", "", 1, "cyclic symmetry"),
    ("SOL 15", "", "", 1, "cyclic symmetry"),
    ("SOL 101\nAPP HEAT", "", "", 2, "APP HEAT"),
    ("SOL 101", "ANALYSIS = HEAT\n", "", 5, "heat transfer"),
    ("SOL 153", "", "", 1, "heat transfer"),
    ("SOL 400", "ANALYSIS = NLSTAT\n", "", 5, "nonlinear step"),
    # review6: Autodesk Nastran's prestress solutions by name and number (its reference
    # lists LINEAR PRESTRESS MODAL 182 ... NONLINEAR PRESTRESS COMPLEX EIGENVALUE 189), its
    # heat transfer names, NX's sequential SOL 401 subcases, a tab after SOL
    ("SOL LINEAR PRESTRESS MODAL", "", "", 1, "prestress"),
    ("SOL 185", "", "", 1, "prestress"),
    ("SOL NONLINEAR STEADY STATE HEAT TRANSFER", "", "", 1, "heat transfer"),
    ("SOL 401", "SUBCASE 1\nANALYSIS = STATICS\nSUBCASE 2\nANALYSIS = MODES\n", "", 8,
     "STATICS subcase of line 6"),
    ("SOL 401", "SUBCASE 1\nLOAD = 1\nSUBCASE 2\nANALYSIS = MODES\n", "", 8,
     "STATICS subcase of line 5"),  # a subcase without ANALYSIS is static (SOL 401's default)
    ("SOL\t13", "", "", 1, "differential stiffness"),
    ("SOL 200", "SUBCASE 1\nANALYSIS = MODES\nSTATSUB = 2\n", "", 7, "STATSUB"),
])
def test_refused(tmp_path, executive, case, extra, line, words):
    path = _deck(tmp_path, executive, case, extra)
    with pytest.raises(InputError) as err:
        read_nastran(path)
    text = str(err.value)
    assert f"deck.bdf: line {line}: " in text and words in text and "\n" not in text


@pytest.mark.parametrize("executive,case", [
    ("SOL 103", ""), ("SOL SEMODES", ""), ("APP DISPLACEMENT\nSOL 3,1", ""),
    ("SOL 105", "STATSUB = 2\n"),  # STATSUB there selects the buckling load: K, M as given
    ("SOL 106", ""), ("SOL 400", "ANALYSIS = MODES\n"), ("SOL 111", ""),
    # review6: a SOL 200 buckling response's STATSUB selects its load, as in SOL 105
    ("SOL 200", "SUBCASE 1\nANALYSIS = MODES\nSUBCASE 2\nANALYSIS = BUCK\nSTATSUB = 3\n"),
    ("SOL 103", "SUBCASE 1\nSTATSUB(BUCKLING) = 2\n"),
    ("SOL 401", "SUBCASE 1\nANALYSIS = MODES\nSUBCASE 2\nANALYSIS = STATICS\n"),
    ("SOL 187", ""),  # MSC's and NX's DDAM: the structure's modes (Autodesk's 187 is not)
])
def test_accepted(tmp_path, executive, case):
    """The same cantilever as K and M: the first bending frequency of its two-element
    model with the tip mass, against the hand Rayleigh bound below."""
    import numpy as np

    from eigenupdate.solve.eigen import solve_elastic

    nm = read_nastran(_deck(tmp_path, executive, case))
    f1 = solve_elastic(nm.model.stiffness(), nm.model.mass(), 1).frequencies_hz[0]
    # stiffer plane E I1 = 2e11 * 2e-7 (I1 about the bar's y); tip mass 2 kg + beam 7.8 kg:
    # between sqrt(3 E I / L^3 / (2 + 7.8)) / 2 pi (all mass at the tip, low) and the
    # massless-beam bound sqrt(3 E I / L^3 / 2) / 2 pi (high)
    k = 3 * 2e11 * 2e-7 / 1.0
    assert np.sqrt(k / 9.8) / (2 * np.pi) < f1 < np.sqrt(k / 2.0) / (2 * np.pi)


def test_cli_exit_2(tmp_path, run_cli):
    path = _deck(tmp_path, "SOL 103", "STATSUB(PRELOAD) = 2\n")
    study = tmp_path / "study.toml"
    study.write_text(f'[model]\ntype = "nastran"\nbdf = "{path}"\n')
    code, out, err = run_cli("frequencies", study, "--modes", "1")
    assert code == 2 and "line 5: STATSUB" in err and "Traceback" not in err
    assert len(err.strip().splitlines()) == 1
