"""Round-3 hostile NASTRAN input (tools/hostile_round3.py): a GRID with a blank id is
named by its line like every other card error, and `update --save-bdf` does not replace
a file it did not write (another study's deck) without --force. Runs in .venv-nastran."""

from __future__ import annotations

import shutil

import pytest
from conftest import ROOT
from nastran_frames import need
from refusals import one_line

pytestmark = pytest.mark.nastran
need("pyNastran")

FRAME = ROOT / "examples" / "nastran_frame"
G1002 = "GRID        1002              0.      3.      0."


def _one_line(code, err, *fragments):
    one_line(code, err, *fragments, warnings_allowed=True)


@pytest.mark.parametrize("card", [
    "GRID                          0.      3.      0.",   # fixed field
    "GRID,,,0.,3.,0.",                                    # free field
    "GRID*                                           0.              3.\n*       0.",
])
def test_grid_with_a_blank_id_names_its_line(tmp_path, run_cli, card):
    """GRID 1002 of the shipped frame (line 19 of frame.bdf) with its id blanked: was
    "pyNastran cannot read the deck: ValueError: SyntaxError: nid = None (field #1)",
    no line; the QRG's GRID needs an id (0 < ID < 100,000,000)."""
    d = tmp_path / "f"
    shutil.copytree(FRAME, d)
    text = (d / "frame.bdf").read_text()
    assert text.splitlines()[18] == G1002
    (d / "frame.bdf").write_text(text.replace(G1002, card, 1))
    code, _, err = run_cli("frequencies", d / "study.toml")
    _one_line(code, err, "frame.bdf: line 19: GRID: the id (field 1) is blank")
    assert "pyNastran" not in err


def test_grid_with_a_blank_id_in_an_included_file(tmp_path, run_cli):
    d = tmp_path / "f"
    shutil.copytree(FRAME, d)
    text = (d / "frame.bdf").read_text()
    (d / "grids.bdf").write_text("$ grids\n" + G1002.replace("1002", "    ") + "\n")
    (d / "frame.bdf").write_text(text.replace(G1002, "INCLUDE 'grids.bdf'", 1))
    code, _, err = run_cli("frequencies", d / "study.toml")
    _one_line(code, err, "frame.bdf: grids.bdf:2: GRID: the id (field 1) is blank")


def test_save_bdf_does_not_replace_another_studys_deck(tmp_path, run_cli):
    """`update --save-bdf truth.bdf` replaced the truth deck of the example (not an input
    of the study, so nothing stopped it); refused before the update runs, unchanged."""
    d = tmp_path / "f"
    shutil.copytree(FRAME, d)
    before = (d / "truth.bdf").read_bytes()
    code, out, err = run_cli("update", d / "study.toml", "--save-bdf", d / "truth.bdf")
    _one_line(code, err, "truth.bdf: --save-bdf: exists and is not an earlier output of "
                         "--save-bdf", "--force")
    assert out == "" and (d / "truth.bdf").read_bytes() == before


CD7 = ("GRID        3001              0.      0.      6.",
       "GRID        3001              0.      0.      6.       7")


@pytest.mark.parametrize("edits, expected", [
    # grids 1001 (0,0,0), 2001 (0,0,3), 3001 (0,0,6) lie on one line: no xz-plane
    ([CD7, ("BEGIN BULK\n", "BEGIN BULK\nCORD1R,7,1001,2001,3001\n")],
     "line 14: CORD1R 7: its defining points coincide or are collinear"),
    ([CD7, ("BEGIN BULK\n", "BEGIN BULK\nCORD1R,7,1001,1001,3002\n")],
     "line 14: CORD1R 7: G1, G2 and G3 must be three different grids"),
    # grid 1002 is given in the system it defines: "maximum recursion depth exceeded"
    ([("GRID        1002              0.      3.      0.",
       "GRID        1002       7      0.      3.      0."),
      ("BEGIN BULK\n", "BEGIN BULK\nCORD1S,7,1002,2001,3002\n")],
     "line 14: CORD1S 7: coordinate systems defined through one another in a loop"),
])
def test_cord1_systems_without_axes_are_named_in_nastran_terms(tmp_path, run_cli, edits,
                                                                expected):
    """QRG CORD1R/C/S: G1, G2, G3 distinct and not collinear, defined in other systems.
    pyNastran said "v=[0. 0. 0.] norm(v)=0.0", echoed the card, or ran out of stack."""
    d = tmp_path / "f"
    shutil.copytree(FRAME, d)
    text = (d / "frame.bdf").read_text()
    for old, new in edits:
        assert old in text
        text = text.replace(old, new, 1)
    (d / "frame.bdf").write_text(text)
    code, _, err = run_cli("check", d / "study.toml")
    _one_line(code, err, expected)
    assert "norm(v)" not in err and "recursion" not in err


def test_pcompg_without_plies(tmp_path, run_cli):
    """A PCOMPG with no ply lines: numpy's "need at least one array to stack" in a
    traceback (exit 1); the laminate needs one ply at least (QRG PCOMPG)."""
    d = tmp_path / "p"
    shutil.copytree(ROOT / "examples" / "stiffened_panel", d)
    text = (d / "panel.bdf").read_text()
    (d / "panel.bdf").write_text(text.replace("PSHELL,1,1,0.002,1,,1", "PCOMPG,1,,,,,,,", 1))
    study = (d / "study.toml").read_text()
    start = study.index('[[model.parameter]]\nname = "t_skin"')
    (d / "study.toml").write_text(study[:start] + study[study.index(
        "[[model.parameter]]", start + 1):])
    code, _, err = run_cli("check", d / "study.toml")
    _one_line(code, err, "panel.bdf: line 7: PCOMPG 1: needs plies", "got []")
