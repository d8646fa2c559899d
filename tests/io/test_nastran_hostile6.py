"""Round-6 hostile NASTRAN input (tools/hostile_round6.py) on issue 20's reading: each
test fails without its fix.

* a CQUAD1 written with tabs was dropped (read_plates took ``CQUAD1<tab>2`` for its name):
  the plate lost half its elements, frequencies 3x off, exit 0;
* PQUAD1 T1 = 1e-300 raised ZeroDivisionError (T1^3 underflows), T1 = 1e308 named no card;
  EID/PID 0 or negative and TH = nan on NASTRAN-95's plates were read;
* ``SOL<tab>13``, ``SOL 013``, SOL 13 after CEND or in a deck without CEND, and
  ``PARAM<tab>NMLOOP`` were read as normal modes;
* a QSET/QSET1 naming no point (``QSET1,0``, ``QSET1,0,THRU,4``) became a Guyan
  reduction, a SPOINT in both the a-set and the q-set was read, EIGRL V1/V2 NaN let every
  fixed-interface mode through;
* a tapered PBEAM's end-B A or J of 1e-300 was read (the constant section's is refused);
* a huge offset blamed another bar's "zero length" without saying why; a CBEAM's BIT
  (a real in field 9) was refused as "OFFT None".

Independent sources: the hand-converted CQUAD4 + PSHELL deck of NASTRAN-95's User's
Manual fields (12I/T^3 = 12 I / T1^3, TS/T = T3 / T1); the comma-separated deck; the
one-line refusal standard (exit 2 through the CLI). Runs in .venv-nastran."""

from __future__ import annotations

import re
import subprocess
import sys
import warnings

import numpy as np
import pytest
from conftest import ROOT
from nastran_frames import need
from refusals import one_line

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.errors import EigenupdateWarning, InputError  # noqa: E402
from eigenupdate.io.nastran import read_nastran  # noqa: E402
from eigenupdate.solve.eigen import solve_elastic  # noqa: E402

PQ1 = "PQUAD1,1,1,.05,1,1.e-5,1,.04,.3"
PLATE = ("BEGIN BULK\nGRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nGRID,3,,2.,0.,0.\n"
         "GRID,4,,0.,1.,0.\nGRID,5,,1.,1.,0.\nGRID,6,,2.,1.,0.\n"
         f"CQUAD1,1,1,1,2,5,4\nCQUAD1,2,1,2,3,6,5\n{PQ1}\n"
         "MAT1,1,7.e10,,.33,2700.\nSPC1,1,123456,1,4\nENDDATA\n")


def _write(tmp_path, text: str, name: str = "deck.bdf"):
    path = tmp_path / name
    path.write_text(text)
    return path


def _read(path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EigenupdateWarning)
        return read_nastran(path)


def _hz(path, n: int = 4) -> np.ndarray:
    model = _read(path).model
    return solve_elastic(model.stiffness(), model.mass(), n).frequencies_hz


def test_cquad1_with_tabs_is_read_as_the_hand_converted_cquad4(tmp_path):
    """Source: the plate by hand as CQUAD4 + PSHELL (12 * 1e-5 / .05^3 = .96, .04 / .05 =
    .8). Same K and M, so 1e-9 (the eigensolver's rounding on a 14-dof model)."""
    tabs = PLATE.replace("CQUAD1,2,1,2,3,6,5", "CQUAD1\t2\t1\t2\t3\t6\t5")
    hand = PLATE.replace("CQUAD1", "CQUAD4").replace(PQ1, "PSHELL,1,1,.05,1,.96,1,.8,.3")
    got, want = _hz(_write(tmp_path, tabs)), _hz(_write(tmp_path, hand, "hand.bdf"))
    assert np.max(np.abs(got / want - 1)) < 1e-9


def test_a_plate_card_pyNastran_counted_but_not_read_is_refused():
    """The guard behind the tab fix: a CQUAD1 pyNastran counts among its rejected cards
    that read_plates does not recognise is refused, not lost."""
    from types import SimpleNamespace

    from eigenupdate.io.nastran_plates95 import read_plates

    bdf = SimpleNamespace(reject_lines=[], card_count={"CQUAD1": 1})
    with pytest.raises(InputError, match="CQUAD1: 1 cards in the deck but 0 read"):
        read_plates(SimpleNamespace(bdf=bdf, lines={}))


@pytest.mark.parametrize("old,new,words", [
    (PQ1, "PQUAD1,1,1,1e-300,1,1.e-5,1,.04,.3", "PQUAD1 1: T1 = 1e-300 is out of range"),
    (PQ1, "PQUAD1,1,1,1e308,1,1.e-5,1,.04,.3", "PQUAD1 1: T1 = 1e+308 is out of range"),
    (PQ1, "PQUAD1,1,1,.05,1,1e-200,1,.04,.3", "PQUAD1 1: I = 1e-200 is out of range"),
    ("CQUAD1,1,1,", "CQUAD1,0,1,", "CQUAD1 0: EID = 0 must be > 0"),
    ("CQUAD1,1,1,", "CQUAD1,-3,1,", "CQUAD1 -3: EID = -3 must be > 0"),
    ("PQUAD1,1,", "PQUAD1,0,", "PQUAD1 0: PID = 0 must be > 0"),
    ("CQUAD1,1,1,1,2,5,4", "CQUAD1,1,1,1,2,5,4,nan", "CQUAD1 1: TH = nan is out of range"),
])
def test_nastran95_plate_fields_out_of_range_are_refused(tmp_path, old, new, words):
    with pytest.raises(InputError, match=re.escape(words)):
        _read(_write(tmp_path, PLATE.replace(old, new, 1)))


CANTILEVER = ("SPC = 1\nMETHOD = 1\nBEGIN BULK\nGRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\n"
              "CBAR,1,1,1,2,0.,0.,1.\nPBAR,1,1,1.e-3,2.e-7,8.e-7,5.e-7\n"
              "MAT1,1,2.e11,,0.3,7800.\nSPC1,1,123456,1\nEIGRL,1,,,4\n{bulk}ENDDATA\n")


@pytest.mark.parametrize("head,bulk,line,words", [
    ("SOL\t13\nCEND\n", "", 1, "SOL 13 (NASTRAN-95's normal modes"),
    ("SOL 013\nCEND\n", "", 1, "SOL 13 (NASTRAN-95's normal modes"),
    ("CEND\nSOL 13\n", "", 2, "SOL 13 (after CEND)"),
    ("CEND\nsol 153\n", "", 2, "SOL 153 (after CEND) is a heat transfer analysis"),
    ("SOL 13\n", "", 1, "SOL 13 (NASTRAN-95's normal modes"),
    ("APP HEAT\n", "", 1, "APP HEAT makes it a heat transfer analysis"),
    ("APP\tHEAT\nCEND\n", "", 1, "APP HEAT makes it a heat transfer analysis"),
    ("SOL 106\nCEND\n", "PARAM\tNMLOOP\t1\n", 13, "SOL 106 with PARAM NMLOOP"),
])
def test_solution_lines_in_odd_forms_are_refused(tmp_path, head, bulk, line, words):
    """Sources as tests/io/test_nastran_solution.py (QRG, NASTRAN-95 User's Manual);
    pyNastran reads ``SOL<tab>13`` and ``SOL 013`` as SOL 13; a SOL line after CEND, or
    before BEGIN BULK in a deck without CEND, is judged as if it were in its place."""
    path = _write(tmp_path, head + CANTILEVER.format(bulk=bulk))
    with pytest.raises(InputError, match=re.escape(f"line {line}: {words}")):
        _read(path)


def test_sol_13_after_cend_is_one_line_through_the_cli(tmp_path):
    d = tmp_path / "ex"
    d.mkdir()
    (d / "deck.bdf").write_text("CEND\nSOL 13\n" + CANTILEVER.format(bulk=""))
    (d / "study.toml").write_text(
        'title = "t"\n[model]\ntype = "nastran"\nbdf = "deck.bdf"\n[measurement]\n'
        'frequencies = "p.csv"\nmodes = [1]\n')
    (d / "p.csv").write_text("configuration,mode,frequency_hz,std_hz\nbase,1,10.0,1.0\n")
    p = subprocess.run([sys.executable, "-m", "eigenupdate", "frequencies", "study.toml"],
                       cwd=d, capture_output=True, text=True,
                       env={"PYTHONPATH": str(ROOT / "src"), "PATH": "/usr/bin:/bin"})
    one_line(p.returncode, p.stderr, "deck.bdf", "line 2", "SOL 13 (after CEND)")
    assert sorted(x.name for x in d.iterdir()) == ["deck.bdf", "p.csv", "study.toml"]


CHAIN = ("SOL 103\nCEND\nMETHOD = 1\nBEGIN BULK\nEIGRL,1,,,10\n"
         "GRID,1,,0.,0.,0.,,23456\nGRID,2,,1.,0.,0.,,23456\nGRID,3,,2.,0.,0.,,23456\n"
         "CELAS2,1,1.e4,1,1\nCELAS2,2,2.e4,1,1,2,1\nCELAS2,3,1.5e4,2,1,3,1\n"
         "CMASS2,11,1.,1,1\nCMASS2,12,2.,2,1\nCMASS2,13,1.5,3,1\n"
         "SPOINT,101,102\nASET1,1,3\nQSET1,0,101,102\nENDDATA\n")


@pytest.mark.parametrize("old,new,words", [
    ("QSET1,0,101,102", "QSET1,0", "QSET1: a card that names no SPOINT"),
    ("QSET1,0,101,102", "QSET1,0,THRU,102", "QSET1: a card that names no SPOINT"),
    ("QSET1,0,101,102", "QSET", "QSET: a card that names no SPOINT"),
    ("ASET1,1,3", "ASET1,1,3\nASET1,0,101", "QSET: SPOINT 101 is also in the a-set"),
    ("EIGRL,1,,,10", "EIGRL,1,nan,,10", "EIGRL 1: V1 = nan bounds"),
    ("EIGRL,1,,,10", "EIGRL,1,,inf,10", "EIGRL 1: V2 = inf bounds"),
])
def test_bad_q_sets_are_refused(tmp_path, old, new, words):
    """The unrefused deck reduces to the a-set and both q-set SPOINTs (its control)."""
    assert _read(_write(tmp_path, CHAIN, "ok.bdf")).model.n == 3
    with pytest.raises(InputError, match=words):
        _read(_write(tmp_path, CHAIN.replace(old, new, 1)))


BEAM = ("BEGIN BULK\nGRID,1,,0.,0.,0.\nGRID,2,,0.8,0.,0.\nCBEAM,1,1,1,2,0.,1.,0.\n"
        "PBEAM,1,1,1.e-3,2.e-7,3.e-7,,4.e-7\n,,,,,,,,\n,NO,1.,{b}\n"
        "MAT1,1,7.e10,,0.3,2700.\nSPC1,1,123456,1\nENDDATA\n")


@pytest.mark.parametrize("b,words", [
    ("1e-300,1.e-7,1.5e-7,,2.e-7", "PBEAM 1: A at end B = 1e-300 is out of range"),
    ("5.e-4,1.e-7,1.5e-7,,1e-200", "PBEAM 1: J at end B = 1e-200 is out of range"),
])
def test_tapered_end_values_out_of_range_are_refused(tmp_path, b, words):
    """As a constant PBEAM's A = 1e-300 is (nastran_fields.in_range)."""
    with pytest.raises(InputError, match=words):
        _read(_write(tmp_path, BEAM.format(b=b)))


def test_huge_offset_says_why_another_bar_is_zero_length(tmp_path):
    """CBAR 2 (length 1) is 'zero-length' only against CBAR 1's 1e30 offset: the message
    gives the length and the coordinates' scale."""
    deck = ("BEGIN BULK\nGRID,1,,0.,0.,0.\nGRID,2,,1.,1.,0.\nGRID,3,,2.,1.,0.\n"
            "CBAR,1,1,1,2,0.,0.,1.,GGO\n,,,1e30,.1,.2,-.02,.05,-.1\n"
            "CBAR,2,1,2,3,0.,1.,0.\nPBAR,1,1,1.e-3,2.e-7,8.e-7,5.e-7\n"
            "MAT1,1,2.e11,,0.3,7800.\nSPC1,1,123456,1\nENDDATA\n")
    with pytest.raises(InputError, match=r"CBAR 2: zero-length element \(length 1 "
                                         r"against coordinates up to 1e\+30\)"):
        _read(_write(tmp_path, deck))


def test_cbeam_bit_is_named_as_bit(tmp_path):
    """A real in CBEAM field 9 is BIT (QRG CBEAM), not an OFFT: it named 'OFFT None'."""
    deck = ("BEGIN BULK\nGRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nCBEAM,1,1,1,2,0.,0.,1.,1.\n"
            "PBEAM,1,1,1.e-3,2.e-7,8.e-7,,5.e-7\nMAT1,1,2.e11,,0.3,7800.\nSPC1,1,123456,1\n"
            "ENDDATA\n")
    with pytest.raises(InputError, match="CBEAM 1: field 9 = 1 is BIT"):
        _read(_write(tmp_path, deck))
