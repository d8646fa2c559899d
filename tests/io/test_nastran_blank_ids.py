"""A blank id (field 1) on any card that numbers itself — element EID, property PID,
material MID, SPC/MPC/EIGRL SID, coordinate system CID — is named by its file and line
(NASTRAN QRG: each of these ids is an integer > 0, no default). pyNastran's message
("eid = None (field #1) on card must be an integer") named neither the card nor the
line, and blamed the main deck for a card of an INCLUDEd file. Only the id check runs
before pyNastran, so these need no pyNastran."""

from __future__ import annotations

import pytest

from eigenupdate.errors import InputError
from eigenupdate.io.nastran_deck import load_deck

DECK = "SOL 103\nCEND\nBEGIN BULK\nGRID,1,,0.,0.,0.\n{card}\nENDDATA\n"


@pytest.mark.parametrize(("card", "kind"), [
    ("CQUAD4,,1,1,2,3,4", "element needs an id (EID)"),
    ("CTRIA3,,1,1,2,3", "element needs an id (EID)"),
    ("CHEXA,,1,1,2,3,4,5,6\n,7,8", "element needs an id (EID)"),
    ("CBAR,,1,1,2,0.,1.,0.", "element needs an id (EID)"),
    ("CONM2           1       1.", "element needs an id (EID)"),           # fixed field
    ("CSHEAR,,1,1,2,3,4", "element needs an id (EID)"),
    ("PSHELL*                        1           0.002\n*", "property needs an id (PID)"),
    ("PBAR,,1,1e-4,1e-8,1e-8,1e-8", "property needs an id (PID)"),
    ("PSHEAR,,1,0.002", "property needs an id (PID)"),
    ("MAT1,,7e10,,0.3,2700.", "material needs an id (MID)"),
    ("SPC1,,123456,1", "set needs an id (SID)"),
    ("EIGRL,,,,10", "set needs an id (SID)"),
    ("CORD2R,,0,0.,0.,0.,0.,0.,1.\n,1.,0.,0.", "coordinate system needs an id (CID)"),
])
def test_a_blank_id_names_the_card_and_its_line(tmp_path, card, kind):
    bdf = tmp_path / "m.bdf"
    bdf.write_text(DECK.format(card=card))
    with pytest.raises(InputError) as e:
        load_deck(bdf)
    name = card.split(",")[0].split()[0].rstrip("*")
    assert f"line 5: {name}: the id (field 1) is blank; every {kind}" in str(e.value)


def test_a_blank_id_in_an_included_file_names_that_file(tmp_path):
    (tmp_path / "mesh.bdf").write_text("$ mesh\nGRID,2,,1.,0.,0.\nCBAR,,1,1,2,0.,1.,0.\n")
    (tmp_path / "m.bdf").write_text(DECK.format(card="INCLUDE 'mesh.bdf'"))
    with pytest.raises(InputError, match=r"mesh.bdf:3: CBAR: the id \(field 1\) is blank"):
        load_deck(tmp_path / "m.bdf")


def test_a_given_id_and_a_blank_pid_pass_the_check(tmp_path):
    """Only field 1: CQUAD4's blank PID is NASTRAN's default PID = EID (QRG CQUAD4),
    not an error; the check lets it through to pyNastran (which gives it that default)."""
    from eigenupdate.io import nastran_deck

    lines = ["CQUAD4,7,,1,2,3,4", "CONM2          7       1      1."]
    nastran_deck._blank_ids(lines, [("m.bdf", 1), ("m.bdf", 2)], "m.bdf")


def test_tab_separated_ids_are_given(tmp_path):
    """A tab moves to the next 8-column field (as pyNastran reads it): ``PCOMP<tab>1`` has
    PID 1 (pyNastran's models/unit/pcomp deck was refused as blank by the first check)."""
    from eigenupdate.io import nastran_deck

    lines = ["PCOMP\t1", "GRID\t5\t\t0.\t0.\t0.", "CQUAD4\t7\t1\t1\t2\t3\t4"]
    nastran_deck._blank_ids(lines, [("m.bdf", i) for i in (1, 2, 3)], "m.bdf")
    with pytest.raises(InputError, match="line 1: PCOMP: the id"):
        nastran_deck._blank_ids(["PCOMP\t\t1"], [("m.bdf", 1)], "m.bdf")
