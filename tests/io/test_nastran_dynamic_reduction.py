"""NASTRAN's dynamic (Craig-Bampton) reduction: ASET with QSET on SPOINTs (issue 20).

MSC's printed frequencies of NASTRAN_CoFE's two dynamic-reduction decks, a spring-mass
chain against its unreduced deck, and the refusals (parameters, perturbations on
omitted or modal coordinates, bad sets) as one line with exit 2. Runs in .venv-nastran."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest
from conftest import ROOT
from nastran_frames import need, read_quiet
from refusals import one_line

from eigenupdate.errors import EigenupdateWarning, InputError
from eigenupdate.model.parameters import Parameter
from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.io.nastran import CardField  # noqa: E402

DATA = ROOT / "tests" / "data" / "nastran_published"


_read = read_quiet


def _msc(name: str, table: int) -> np.ndarray:
    rows = np.loadtxt(DATA / f"{name}.csv", delimiter=",", comments="#", skiprows=5)
    return rows[rows[:, 0] == table, 2]


@pytest.mark.parametrize("name, n_q", [("cofe_cantilever_dynamic", 3),
                                       ("cofe_three_types_dynamic", 4)])
def test_cofe_dynamic_reduction_reproduces_msc(name, n_q):
    """Source: MSC Nastran's two printed REAL EIGENVALUES tables (the .csv beside the
    deck, see tests/data/README.md): table 1 the fixed-interface modes (the first n_q
    are the q-set's; MSC truncates the rest, its warning 9145), table 2 the reduced
    system's modes. CBAR, CBEAM and CROD only: the discrete model is the cards', MSC
    prints 7 digits (5e-7 relative), so 1e-5 as for the shared line decks (measured
    worst: 3.6e-7 and 4.2e-7 fixed-interface, 1.4e-7 and 1.1e-7 reduced)."""
    nm = _read(DATA / f"{name}.dat")
    fixed, system = _msc(name, 1), _msc(name, 2)
    assert len(nm.fixed_hz) == n_q
    assert np.max(np.abs(np.array(nm.fixed_hz) / fixed[:n_q] - 1)) < 1e-5
    model = nm.model
    k = min(system.size, model.n)
    got = solve_elastic(model.stiffness(), model.mass(), k).frequencies_hz
    assert np.max(np.abs(got / system[:k] - 1)) < 1e-5
    assert len(nm.modal) == n_q and set(nm.modal) <= set(model.coordinates.tolist())


def test_cantilever_coordinates_are_the_a_set_and_the_q_set():
    """ASET 6 26 (GRDSET PS 1345 leaves 2 and 6) and QSET on SPOINTs 100001-100003: the
    model's coordinates are grid 6's two and the three SPOINTs' (10 id + 1)."""
    nm = _read(DATA / "cofe_cantilever_dynamic.dat")
    assert nm.model.coordinates.tolist() == [62, 66, 1000011, 1000021, 1000031]
    assert nm.modal == {1000011, 1000021, 1000031}


CASE = "SOL 103\nCEND\nMETHOD = 1\nBEGIN BULK\nEIGRL,1,,,{nd}\n"
CHAIN = ("GRID,1,,0.,0.,0.,,23456\nGRID,2,,1.,0.,0.,,23456\nGRID,3,,2.,0.,0.,,23456\n"
         "GRID,4,,3.,0.,0.,,23456\nGRID,5,,4.,0.,0.,,23456\n"
         "CELAS2,1,1.e4,1,1\nCELAS2,2,2.e4,1,1,2,1\nCELAS2,3,1.5e4,2,1,3,1\n"
         "CELAS1,4,7,3,1,4,1\nCELAS2,5,1.2e4,4,1,5,1\nPELAS,7,1.1e4\n"
         "CMASS2,11,1.,1,1\nCMASS2,12,2.,2,1\nCMASS2,13,1.5,3,1\nCMASS2,14,1.,4,1\n"
         "CMASS2,15,.5,5,1\nSPOINT,101,THRU,104\n")


def _deck(tmp_path, body: str, name="deck.bdf", nd: int = 10):
    """The chain's deck with METHOD 1 an EIGRL with ND = nd (nd = 0: an EIGR instead)."""
    path = tmp_path / name
    head = CASE.format(nd=nd) if nd else CASE.replace("EIGRL,1,,,{nd}", "EIGR,1,LAN,0.,100.")
    path.write_text(head + body + "ENDDATA\n")
    return path


def _hz(nm, n):
    return solve_elastic(nm.model.stiffness(), nm.model.mass(), n).frequencies_hz


def test_chain_with_every_omitted_mode_kept_is_the_full_chain(tmp_path):
    """Second method: the unreduced deck. Grid 3 the a-set, the other four masses
    omitted, four q-set SPOINTs: the reduction is a change of coordinates and keeps
    every eigenvalue (5 masses, condition of K about 1e2: rounding far below 1e-10)."""
    full = _read(_deck(tmp_path, CHAIN, "full.bdf"))
    nm = _read(_deck(tmp_path, CHAIN + "ASET1,1,3\nQSET1,0,101,THRU,104\n"))
    assert nm.model.coordinates.tolist() == [31, 1011, 1021, 1031, 1041]
    assert _hz(nm, 5) == pytest.approx(_hz(full, 5), rel=1e-10)
    assert nm.omitted == {11, 21, 41, 51}


@pytest.mark.parametrize("spoints", ["101", "101,102", "101,102,103"])
def test_chain_with_fewer_modes_bounds_the_full_chain_from_above(tmp_path, spoints):
    """Rayleigh-Ritz: fewer fixed-interface modes give frequencies no lower than the
    full chain's (to rounding, 1e-12 relative)."""
    full = _hz(_read(_deck(tmp_path, CHAIN, "full.bdf")), 5)
    nm = _read(_deck(tmp_path, CHAIN + f"ASET1,1,3\nQSET1,0,{spoints}\nSPOINT,101,THRU,104\n"))
    got = _hz(nm, nm.model.n)
    assert got.size == 1 + spoints.count(",") + 1
    assert np.all(got >= full[:got.size] * (1 - 1e-12))


def test_qset_alone_keeps_the_lowest_modes_of_the_whole_chain(tmp_path):
    """Closed form: QSET without ASET omits every physical coordinate (QRG QSET), so the
    fixed-interface modes are the chain's own (nothing held) and the two q-set
    coordinates keep exactly its two lowest frequencies (second method: the unreduced
    deck; rounding far below 1e-10)."""
    full = _hz(_read(_deck(tmp_path, CHAIN, "full.bdf")), 2)
    nm = _read(_deck(tmp_path, CHAIN + "QSET1,0,101,102\n"))
    assert nm.model.coordinates.tolist() == [1011, 1021]
    assert _hz(nm, 2) == pytest.approx(full, rel=1e-10)
    assert np.array(nm.fixed_hz) == pytest.approx(full, rel=1e-10)


def test_parameters_of_a_dynamically_reduced_deck_refused(tmp_path):
    path = _deck(tmp_path, CHAIN + "ASET1,1,3\nQSET1,0,101,102\n")
    with pytest.raises(InputError, match=r"QSET \(Craig-Bampton reduction\): K "
                                         r"and M of the reduced model are not linear"):
        _read(path, [(Parameter("k", 0.0), CardField("PELAS", 7, "K"))])


def test_perturbations_on_omitted_and_modal_coordinates_refused(tmp_path):
    nm = _read(_deck(tmp_path, CHAIN + "ASET1,1,3\nQSET1,0,101,102\n"))
    with pytest.raises(InputError, match="GRID 2 component 1 is omitted by ASET/OMIT"):
        nm.grid_dof(2, 1)
    with pytest.raises(InputError, match="SPOINT 101 is a q-set coordinate"):
        nm.grid_dof(101, 0)
    assert nm.grid_dof(3, 1) == 31


@pytest.mark.parametrize("cards, nd, message", [
    ("ASET1,1,3\nQSET1,0,101,THRU,104\nSPOINT,105\nQSET,105\n", 10,
     "QSET: 5 q-set coordinates (SPOINTs 101 ... 105) but 4 omitted coordinates"),
    ("ASET1,1,3\nQSET,109\n", 10, "QSET: SPOINT 109 is referenced but not defined"),
    ("ASET1,1,3\nOMIT1,1,2\nQSET,101\n", 10, "both ASET and OMIT cards: give one of them"),
    ("ASET1,1,3\nQSET,2,1\n", 10, "QSET: GRID 2: the q-set (generalized coordinates"),
    ("ASET1,1,3\nQSET1,0,101,102,103\n", 2, "EIGRL 1: ND 2 is below the 3 q-set coordinates"),
    ("OMIT1,1,2\nQSET1,0,101,102\n", 10, "OMIT with QSET: with a q-set NASTRAN omits"),
    ("ASET1,1,3\nQSET1,0,101\n", 0, "QSET: METHOD 1 names no EIGRL card"),
    ("ASET1,1,3\nQSET1,0,101\nCELAS2,99,1.,101\n", 10, "QSET: SPOINT 101 carries stiffness"),
    ("ASET1,1,3\nQSET1,0,101\nSPC1,1,0,101\n", 10, "QSET: SPOINT 101 is restrained (SPC)"),
    ("ASET1,1,3\nQSET1,0,101\nMPC,1,101,0,1.,3,1,-1.\n", 10,
     "QSET: SPOINT 101 is dependent"),
])
def test_bad_reduction_sets_refused_in_one_line(tmp_path, run_cli, cards, nd, message):
    """One line naming the card and the problem, exit 2, through the CLI."""
    deck = _deck(tmp_path, CHAIN + cards, nd=nd)
    study = tmp_path / "study.toml"
    study.write_text(f'[model]\ntype = "nastran"\nbdf = "{deck}"\n')
    code, _, err = run_cli("frequencies", study, "--modes", "1")
    one_line(code, err, "deck.bdf", message, warnings_allowed=True)


def test_a_cofe_deck_through_the_cli(tmp_path, run_cli):
    """Source: MSC's table 2 (the .csv): the frequencies command's JSON on the reduced
    cantilever, within 1e-5 as above; the EIGRL that gives the fixed-interface modes is
    not in the note of skipped cards."""
    study = tmp_path / "study.toml"
    study.write_text(f'[model]\ntype = "nastran"\nbdf = "{DATA / "cofe_cantilever_dynamic.dat"}"\n')
    code, out, err = run_cli("frequencies", study, "--modes", "5", "--json")
    assert code == 0, err
    got = json.loads(out)["configurations"][0]["frequencies_hz"]
    assert np.max(np.abs(np.array(got) / _msc("cofe_cantilever_dynamic", 2) - 1)) < 1e-5
    assert "skipped" in err and "EIGRL" not in err


DESIGN = ("\n[design]\ncoordinates = {c}\nmasses = [0.1]\nconfigurations = 1\n"
          "modes = [1, 2]\nfrequency_std_relative = 1e-3\n")


def test_design_candidates_leave_out_the_q_set(tmp_path, run_cli):
    """A q-set coordinate is a mode's amplitude, not a point a mass can be put on:
    'translational' leaves the SPOINTs out and naming one is refused in one line."""
    from eigenupdate.io.study import load_study

    deck = _deck(tmp_path, CHAIN + "ASET1,1,3\nQSET1,0,101,102\n")
    study = tmp_path / "study.toml"
    head = f'[model]\ntype = "nastran"\nbdf = "{deck}"\n'
    study.write_text(head + DESIGN.format(c='"translational"'))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EigenupdateWarning)
        assert list(load_study(study).design.coordinates) == [31]
    study.write_text(head + DESIGN.format(c="[31, 1011]"))
    code, _, err = run_cli("design", study, "-o", tmp_path / "plan.toml")
    one_line(code, err, "design.coordinates", "coordinate 1011 is a q-set SPOINT",
             warnings_allowed=True)


SCALAR = ("SPOINT,5,6,7\nCELAS2,1,100.,5,0\nCELAS2,2,200.,5,0,6,0\nCELAS2,3,300.,6,0,7,0\n"
          "CMASS2,4,1.,5,0\nCMASS2,5,2.,7,0\n")


@pytest.mark.parametrize("card", ["OMIT1,0,6", "OMIT,6,0", "ASET1,,5,7", "ASET,5,0,7"])
def test_reduction_sets_on_scalar_points(tmp_path, card):
    """Source: Guyan 1965, condensing a massless coordinate changes no frequency; QRG
    ASET/OMIT: a scalar point's component is 0 or blank (such cards named no row). Three
    coordinates, condition of K about 10: rounding near 1e-15, so 1e-12."""
    full = _read(_deck(tmp_path, SCALAR, "full.bdf"))
    nm = _read(_deck(tmp_path, SCALAR + card + "\n"))
    assert nm.model.coordinates.tolist() == [51, 71]
    assert _hz(nm, 2) == pytest.approx(_hz(full, 2), rel=1e-12)
