"""tools/deck_sweep.py's readers of what NASTRAN printed and of the deck's eigenvalue
method, and its grouping of refusals. Source: the layout of NASTRAN's .f06 REAL
EIGENVALUES table (rows copied from pyNastran's models/beam_modes/beam_modes.f06, BSD-3)
and the EIGRL card's fields (MSC QRG: SID, V1, V2, ND). Core environment: no pyNastran."""

from __future__ import annotations

import sys

from conftest import ROOT

sys.path.insert(0, str(ROOT / "tools"))
import deck_sweep  # noqa: E402

HEADER = ("                                              R E A L   E I G E N V A L U E S\n"
          "   MODE    EXTRACTION      EIGENVALUE            RADIANS             CYCLES      "
          "      GENERALIZED         GENERALIZED\n"
          "    NO.       ORDER                                                              "
          "         MASS              STIFFNESS\n")
ROW = ("        {0}         {0}        8.232777E+06        2.869282E+03        {1}        "
       "8.801022E-03        7.245685E+04\n")


def test_f06_table_follows_page_breaks_and_stops_at_the_next_subcase(tmp_path):
    """Rows 1, 2 on one page, 3 after a page header that repeats the title: one table;
    a second subcase's table restarts at mode 1 and is not read."""
    text = (HEADER + ROW.format(1, "4.566603E+02") + ROW.format(2, "4.566603E+02")
            + "1    MSC.NASTRAN JOB                                   PAGE    12\n"
            + HEADER + ROW.format(3, "2.674588E+03")
            + "1    SUBCASE 2\n" + HEADER + ROW.format(1, "9.999999E+02"))
    path = tmp_path / "x.f06"
    path.write_text(text)
    assert deck_sweep.f06_table(path) == [456.6603, 456.6603, 2674.588]


def test_f06_without_a_table(tmp_path):
    path = tmp_path / "x.f06"
    path.write_text("1    MSC.NASTRAN JOB\n    nothing here\n")
    assert deck_sweep.f06_table(path) is None


def test_eigrl_of_the_selected_method():
    """Fixed field (cbush_psd_bug's EIGRL: V2 = 2000 Hz, ND = 7) and free field; the
    case control's METHOD picks the card."""
    text = ["SOL 111", "CEND", "METHOD = 100", "BEGIN BULK",
            "EIGRL,7,,,3",
            "EIGRL        1000.100000 2000.00               0       7            MASS"]
    assert deck_sweep.eigrl(text) == (2000.0, None)  # ND is field 5: blank here
    free = ["CEND", "  METHOD = 7", "BEGIN BULK", "EIGRL,7,,,3"]
    assert deck_sweep.eigrl(free) == (None, 3)
    assert deck_sweep.eigrl(["BEGIN BULK", "EIGR,1,LAN,0.,.1,,6"]) == (None, None)


def test_eigr_feer_rows_beyond_nd_are_left_out():
    """NASTRAN-95's FEER prints approximations beyond the ND roots asked for (D03-01-2A's
    EIGR 20: ND 1, 12 rows); its INV/GIV rows beyond ND are eigenvalues (EIGR fields:
    SID, METHOD, F1, F2, NE, ND; NASTRAN-95 User's Manual, EIGR)."""
    feer = ["  METHOD = 20", "BEGIN BULK",
            "EIGR    5       INV     .89     2.4     1       3       0",
            "EIGR    20      FEER    .87                     1"]
    assert deck_sweep.eigrl(feer) == (None, 1)
    assert deck_sweep.eigrl([feer[0].replace("20", "5"), *feer[1:]]) == (None, None)


def test_refusals_are_grouped_by_card():
    msg = ("/x/deck.bdf: cards that would change K or M and are not supported: CBEND x2, "
           "PBEND x2")
    assert deck_sweep.kinds(msg) == ["card CBEND not supported", "card PBEND not supported"]
    one = "/x/deck.bdf: line 12: PBARL 100: section type Z is not supported"
    assert deck_sweep.kinds(one) == ["line N: PBARL N: section type Z is not supported"]


def test_included_files_are_fragments(tmp_path):
    (tmp_path / "main.bdf").write_text("BEGIN BULK\nINCLUDE 'geom.inc'\nENDDATA\n")
    (tmp_path / "geom.inc").write_text("GRID,1,,0.,0.,0.\n")
    (tmp_path / "loads.blk").write_text("FORCE,1,1,,1.,1.,0.,0.\n")  # no GRID: a fragment
    found, fragments = deck_sweep.decks(tmp_path)
    assert [p.name for p in found] == ["main.bdf"]
    assert sorted(p.name for p in fragments) == ["geom.inc", "loads.blk"]


def test_an_include_with_windows_separators_names_a_fragment(tmp_path):
    """NASTRAN_CoFE's superelement decks: INCLUDE '..\\se0.dat' (was swept as a deck)."""
    (tmp_path / "job").mkdir()
    (tmp_path / "job" / "main.bdf").write_text("BEGIN BULK\nINCLUDE '..\\se0.dat'\nENDDATA\n")
    (tmp_path / "se0.dat").write_text("GRID,1,,0.,0.,0.\n")
    found, fragments = deck_sweep.decks(tmp_path)
    assert [p.name for p in found] == ["main.bdf"]
    assert [p.name for p in fragments] == ["se0.dat"]


def test_ref_json_that_names_the_deck_is_the_reference(tmp_path):
    """The layout of ../shared/data/nastran/: ref.json's cycles_hz, for the deck it names
    (another deck of the folder has none from it); a NASTRAN-95 .inp deck is a deck."""
    (tmp_path / "ref.json").write_text('{"deck": "a.inp", "cycles_hz": [0.0, 12.5]}')
    (tmp_path / "a.inp").write_text("BEGIN BULK\nGRID,1,,0.,0.,0.\nENDDATA\n")
    (tmp_path / "b.bdf").write_text("BEGIN BULK\nGRID,1,,0.,0.,0.\nENDDATA\n")
    assert deck_sweep.reference(tmp_path / "a.inp") == ("ref.json", [0.0, 12.5])
    assert deck_sweep.reference(tmp_path / "b.bdf") is None
    assert [p.name for p in deck_sweep.decks(tmp_path)[0]] == ["a.inp", "b.bdf"]


def test_f06_table_after_the_fixed_interface_modes(tmp_path):
    """A dynamic reduction's .f06 (QSET) prints the fixed-interface modes first, then
    the reduced model's table, both from mode 1: skip=1 reads the second; without a
    second table there is nothing to compare."""
    text = (HEADER + ROW.format(1, "1.380011E+03") + ROW.format(2, "8.287086E+03")
            + HEADER + ROW.format(1, "3.497303E+02") + ROW.format(2, "2.168717E+03")
            + ROW.format(3, "6.015472E+03"))
    path = tmp_path / "x.f06"
    path.write_text(text)
    assert deck_sweep.f06_table(path, skip=1) == [349.7303, 2168.717, 6015.472]
    assert deck_sweep.f06_table(path) == [1380.011, 8287.086]
    path.write_text(HEADER + ROW.format(1, "1.380011E+03"))
    assert deck_sweep.f06_table(path, skip=1) is None
