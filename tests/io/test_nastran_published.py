"""Decks as other NASTRANs write them (survey of published SOL 103 / SOL 3 decks, issue 20):
decks of tests/data/nastran_published/ against the frequencies their NASTRAN printed (an
MPC on a scalar point, NASTRAN-95's APP statement and GRDSET), GRDSET's CP/CD defaults,
NASTRAN-95's EIGR methods, and MATT1 without a TEMPERATURE set."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from conftest import ROOT
from nastran_frames import need

from eigenupdate.errors import EigenupdateWarning, InputError
from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.io.nastran import read_nastran  # noqa: E402

DATA = ROOT / "tests" / "data" / "nastran_published"


def _hz(path, n: int) -> np.ndarray:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EigenupdateWarning)
        model = read_nastran(path).model
    return solve_elastic(model.stiffness(), model.mass(), n).frequencies_hz


def test_nastran95_flutter_deck_reproduces_nastran95():
    """Source: NASTRAN-95's printed natural frequencies (d10021a.csv: demoout/d10021a.out of
    nasa/NASTRAN-95 commit 65e29e9, SUN SOLARIS version, system release 1995 ed.; deck
    inp/d10021a.inp, NASA Open Source Agreement 1.3). CBARs and CMASS2s only, so the
    discrete model is the cards' and NASTRAN prints 7 digits (5e-7 relative): 1e-5.
    It reads only if ``APP AERO``, GRDSET CP 1 / CD 1 / PS 126 and the aero cards are
    taken as NASTRAN does (measured worst 1.3e-6). CORD2R 1 turns the whole model 15
    degrees about z, which moves no frequency: CP/CD are checked by the next test."""
    want = np.loadtxt(DATA / "d10021a.csv", delimiter=",", comments="#", skiprows=4)[:, 1]
    got = _hz(DATA / "d10021a.inp", want.size)
    assert np.max(np.abs(got / want - 1)) < 1e-5


def test_nastran95_rocket_deck_reproduces_nastran95():
    """Source: NASTRAN-95's printed natural frequencies (d10011a.csv: demoout/d10011a.out
    of nasa/NASTRAN-95 commit 65e29e9; deck inp/d10011a.inp, NASA Open Source Agreement
    1.3), 1e-5 as above (line, spring and mass elements). CELAS4 and CMASS4 define two
    elements on a card (NASTRAN-95 User's Manual, CELAS3 remark 3) on scalar points no
    SPOINT card names, which MPCs tie to the bars (measured worst 4.5e-7)."""
    want = np.loadtxt(DATA / "d10011a.csv", delimiter=",", comments="#", skiprows=4)[:, 1]
    got = _hz(DATA / "d10011a.inp", want.size)
    assert np.max(np.abs(got / want - 1)) < 1e-5


def test_two_scalar_elements_on_a_card_and_implicit_scalar_points(tmp_path):
    """Closed form: scalar points 1 and 2 (on no SPOINT card) of 2 and 1 kg, a 3 N/m
    spring from 1 to ground and a 1 N/m spring between them (two CELAS4 on one card, two
    CMASS4 on one card, fixed and free field): det(K - w2 M) = 2 w2^2 - 6 w2 + 3 = 0,
    omega^2 = (3 -+ sqrt(3)) / 2 (rad/s)^2."""
    want = np.sqrt([(3 - np.sqrt(3)) / 2, (3 + np.sqrt(3)) / 2]) / (2 * np.pi)
    for name, cards in (("fixed.bdf", "CELAS4  1       3.      1               2       1.      "
                                      "1       2\nCMASS4  3       2.      1               4"
                                      "       1.      2\n"),
                        ("free.bdf", "CELAS4,1,3.,1,,2,1.,1,2\nCMASS4,3,2.,1,,4,1.,2\n")):
        path = tmp_path / name
        path.write_text("BEGIN BULK\n" + cards + "ENDDATA\n")
        assert np.allclose(_hz(path, 2), want, rtol=1e-10), name


def test_mpc_on_a_scalar_point_reproduces_msc():
    """Source: MSC.NASTRAN 6/17/05's printed frequencies (actuator_tf_modeling.csv, from
    pyNastran's models/transfer_function, BSD-3-Clause) and the closed form: masses 1 and
    2 kg, a 1 N/m spring to ground and 1.5 N/m between them give omega^2 = 1/4 and 3
    (rad/s)^2. The MPC defines scalar point 1001 as x3 - x2 (component blank); the TFs
    act on the dynamic response only. Springs and masses: 1e-5 (7 printed digits)."""
    want = np.loadtxt(DATA / "actuator_tf_modeling.csv", delimiter=",", comments="#",
                      skiprows=4)[:, 1]
    got = _hz(DATA / "actuator_tf_modeling.bdf", 2)
    assert np.max(np.abs(got / want - 1)) < 1e-5
    assert np.allclose(got, np.sqrt([0.25, 3.0]) / (2 * np.pi), rtol=1e-10)


def test_msc_flutter_decks_reproduce_msc():
    """Source: MSC Nastran's printed real eigenvalues of two flutter (SOL 145) decks of
    pyNastran's models/aero (BSD-3-Clause; pt145.csv, bah_plane.csv name the f06s): pt145,
    a CBAR beam with CMASS2s (all 27 printed modes), and the BAH wing, CBARs with CONM2s
    on RBE2 and RBAR arms, held by SPC1 1246 at its root so that heave and pitch are
    rigid (modes 3-8). The aerodynamic cards change neither K nor M. Bars, springs, masses
    and rigid elements: the discrete model is the cards', NASTRAN prints 7 digits: 1e-5
    (measured worst 4.6e-7 and 2.3e-7)."""
    for deck, table in (("pt145.bdf", "pt145.csv"), ("bah_plane/bah_plane.bdf",
                                                      "bah_plane.csv")):
        want = np.loadtxt(DATA / table, delimiter=",", comments="#", skiprows=4)[:, 1]
        got = _hz(DATA / deck, want.size)
        assert np.max(np.abs(got / want - 1)) < 1e-5, deck


# a cantilever of 4 CBARs along the x axis of CORD2R 7, which is the basic system turned
# 90 degrees about z (x7 = basic y): the bar lies along basic y; the SPC1 13 holds the
# axial and z motion if CD is 7 (the bar bends in basic x-y), both bending ones if not
FRAME = ("CORD2R,7,,0.,0.,0.,0.,0.,1.,\n,0.,1.,0.\n"
         "CBAR,1,1,1,2,0.,0.,1.\nCBAR,2,1,2,3,0.,0.,1.\nCBAR,3,1,3,4,0.,0.,1.\n"
         "CBAR,4,1,4,5,0.,0.,1.\nPBAR,1,1,1.e-3,2.e-7,8.e-7,5.e-7\n"
         "MAT1,1,2.e11,,0.3,7800.\nSPC1,1,123456,1\nSPC1,1,13,2,3,4,5\n")


def _frame_deck(tmp_path, name, grids):
    path = tmp_path / name
    path.write_text("BEGIN BULK\n" + grids + FRAME + "ENDDATA\n")
    return path


def test_grdset_cp_and_cd_are_the_defaults_of_blank_grid_fields(tmp_path):
    """QRG GRDSET: its CP and CD are used for the GRID fields left blank, an explicit 0
    is the basic system. Source of the numbers: the same bar with CP and CD written on
    every GRID, read identically (the modes depend on CD: SPC1 13 holds the axes 1 and
    3, the bar's axis and z with CD 7, both bending directions in the basic system)."""
    given = "".join(f"GRID,{i},7,{i - 1}.,0.,0.,7\n" for i in range(1, 6))
    defaulted = "GRDSET,,7,,,,7\n" + "".join(f"GRID,{i},,{i - 1}.,0.,0.\n"
                                               for i in range(1, 6))
    zero = "GRDSET,,7,,,,7\n" + "".join(f"GRID,{i},,{i - 1}.,0.,0.,0\n" for i in range(1, 6))
    basic_cd = "".join(f"GRID,{i},7,{i - 1}.,0.,0.\n" for i in range(1, 6))
    a = _hz(_frame_deck(tmp_path, "given.bdf", given), 4)
    b = _hz(_frame_deck(tmp_path, "defaulted.bdf", defaulted), 4)
    c = _hz(_frame_deck(tmp_path, "zero.bdf", zero), 4)
    d = _hz(_frame_deck(tmp_path, "basic_cd.bdf", basic_cd), 4)
    assert np.allclose(a, b, rtol=1e-12)
    assert np.allclose(c, d, rtol=1e-12)
    assert not np.allclose(a, d, rtol=1e-3)  # CD does change the modes


BAR = ("GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nGRID,3,,2.,0.,0.\n"
       "CBAR,1,1,1,2,0.,1.,0.\nCBAR,2,1,2,3,0.,1.,0.\n"
       "PBAR,1,1,1.e-3,2.e-7,8.e-7,5.e-7\nMAT1,1,2.e11,,0.3,7800.\nSPC1,1,123456,1\n")
# E halved at any temperature, were the table used
MATT1 = "MATT1,1,5\nTABLEM1,5,\n,-1000.,1.e11,1000.,1.e11,ENDT\n"


def _deck(tmp_path, name, executive, case, bulk):
    path = tmp_path / name
    path.write_text(f"{executive}SOL 103\nCEND\n{case}BEGIN BULK\n{bulk}ENDDATA\n")
    return path


def test_nastran95_app_and_eigr_methods_change_nothing(tmp_path):
    """NASTRAN-95's executive ``APP DISP`` and EIGR method DET (pyNastran knows neither)
    are read past: the frequencies equal the plain deck's (both readings of one model)."""
    plain = _deck(tmp_path, "plain.bdf", "", "SPC = 1\n", BAR)
    n95 = _deck(tmp_path, "n95.bdf", "ID D01,NASTRAN\nAPP   DISP\n", "SPC = 1\nMETHOD = 1\n",
                BAR + "EIGR,1,DET,0.,100.,2,2\n")
    assert np.array_equal(_hz(plain, 3), _hz(n95, 3))


def test_matt1_without_temperature_is_skipped(tmp_path):
    """MATT1 remark 1 (QRG): temperature-dependent properties are computed only when the
    case control selects a TEMPERATURE set; without one the MAT1 values hold (the table
    here would halve E, so a reading that used it would be 29 % low)."""
    plain = _deck(tmp_path, "plain.bdf", "", "SPC = 1\n", BAR)
    tabled = _deck(tmp_path, "tabled.bdf", "", "SPC = 1\n", BAR + MATT1)
    with pytest.warns(EigenupdateWarning, match=r"skipped .*MATT1 x1, .*TABLEM1 x1"):
        read_nastran(tabled)
    assert np.array_equal(_hz(plain, 3), _hz(tabled, 3))


@pytest.mark.parametrize("command", ["TEMPERATURE(MATERIAL) = 3", "TEMP = 3",
                                     "  temperature(initial) = 3"])
def test_matt1_with_a_temperature_set_is_refused(tmp_path, command):
    deck = _deck(tmp_path, "hot.bdf", "", f"SPC = 1\n{command}\n",
                 BAR + MATT1 + "TEMPD,3,300.\n")
    with pytest.raises(InputError, match=r"not supported: MATT1 x1 \(the case control "
                                         r"selects a TEMPERATURE set\)"):
        read_nastran(deck)


def test_scalar_element_on_an_extra_point_is_refused(tmp_path):
    """An extra point (EPOINT) is not a scalar point: a spring on it is not made one."""
    deck = tmp_path / "extra.bdf"
    deck.write_text("BEGIN BULK\nGRID,1,,0.,0.,0.\nEPOINT,7\nCELAS2,1,3.,1,1,7\n"
                    "CELAS4,2,3.,7,\nCMASS2,3,1.,1,1\nENDDATA\n")
    with pytest.raises(InputError, match=r"CELAS2 1: GRID 7 is referenced but not defined"):
        read_nastran(deck)


def test_property_no_element_uses_is_skipped(tmp_path):
    """A property card of a type we do not assemble (PBEND, PBUSH1D) that no element names
    cannot change K or M: skipped with a note, the frequencies equal the plain deck's;
    once an element names it, it is refused."""
    plain = _deck(tmp_path, "plain.bdf", "", "SPC = 1\n", BAR)
    extra = BAR + "PBEND,7,1,1.e-3,2.e-7,2.e-7,4.e-7\nPBUSH1D,8,1.e5\n"
    props = _deck(tmp_path, "props.bdf", "", "SPC = 1\n", extra)
    with pytest.warns(EigenupdateWarning, match=r"PBEND x1 \(no element uses it\), PBUSH1D x1 "
                                                 r"\(no element uses it\)"):
        read_nastran(props)
    assert np.array_equal(_hz(plain, 3), _hz(props, 3))
    used = _deck(tmp_path, "used.bdf", "", "SPC = 1\n",
                 extra + "CBUSH1D,9,8,2,3\n")
    with pytest.raises(InputError, match=r"not supported: CBUSH1D x1, PBUSH1D x1"):
        read_nastran(used)
