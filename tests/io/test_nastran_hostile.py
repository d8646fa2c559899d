"""Hostile shell and solid decks (issue 20's "Bad input"): `eigenupdate frequencies` on a
study whose model is the deck exits 2 with one line naming the file, the line, the card
and its id; nothing else is printed. Each deck is a good element of its family beside a
bad element 99; the source of each refusal is the geometry or card rule named in its
case (a collapsed corner has det J = 0 there, NASTRAN's MAT8 G1Z blank is rigid, a
GRID id is a 32-bit integer). Runs in .venv-nastran (pyNastran)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from nastran_frames import need

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.cli import main  # noqa: E402

PRISM = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (0, 1, 1)]
PYRAMID = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0.5, 0.5, 1)]
SQUARE = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
CUBE = SQUARE + [(x, y, 1) for x, y, _ in SQUARE]
TET = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
EDGES = {"CQUAD8": [(0, 1), (1, 2), (2, 3), (3, 0)],
         "CHEXA20": [(0, 1), (1, 2), (2, 3), (3, 0), (0, 4), (1, 5), (2, 6), (3, 7),
                     (4, 5), (5, 6), (6, 7), (7, 4)],
         "CTETRA10": [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)],
         "CPENTA15": [(0, 1), (1, 2), (2, 0), (0, 3), (1, 4), (2, 5), (3, 4), (4, 5), (5, 3)]}
STEEL = "MAT1,1,2.e11,,.3,7850.\n"
PSHELL = "PSHELL,1,1,.01,1,,1\n"
M8 = "MAT8,8,1.4e11,1.e10,.3,5.e9,5.e9,5.e9,1600.\n"
PLIES = ",8,.001,0.,,8,.001,90.\n,8,.001,90.,,8,.001,0.\n"


def _nodes(corners, kind=""):
    c = np.array(corners, float)
    if kind in EDGES:
        c = np.vstack([c, [(c[a] + c[b]) / 2 for a, b in EDGES[kind]]])
    return c


def _card(name, eid, ids):
    ids = [str(i) for i in ids]
    text = f"{name},{eid},1," + ",".join(ids[:6])
    for j in range(6, len(ids), 8):
        text += "\n," + ",".join(ids[j:j + 8])
    return text


def deck(name, xyz, ids=None, prop=None, mat=STEEL, kind=""):
    """Element 99 on grids 1.. at ``xyz`` (node order ``ids``) and a good copy, element 1
    on grids 101.. at x + 5 (so the deck is otherwise sound)."""
    good = _nodes({"CPENTA": PRISM, "CPYRAM": PYRAMID, "CHEXA": CUBE, "CTETRA": TET,
                   "CQUAD8": SQUARE, "CQUAD4": SQUARE}[name], kind)
    lines = ["BEGIN BULK"]
    lines += [f"GRID,{i + 1},,{float(x)!r},{float(y)!r},{float(z)!r}"
              for i, (x, y, z) in enumerate(xyz)]
    lines.append(_card(name, 99, ids or range(1, len(xyz) + 1)))
    lines += [f"GRID,{i + 101},,{float(x) + 5!r},{float(y)!r},{float(z)!r}"
              for i, (x, y, z) in enumerate(good)]
    lines.append(_card(name, 1, range(101, 101 + len(good))))
    if prop is None:
        prop = "PSOLID,1,1\n" if name.startswith(("CHEXA", "CPENTA", "CTETRA", "CPYRAM")) \
            else PSHELL
    return "\n".join(lines) + "\n" + prop + mat + "ENDDATA\n"


def refused(tmp_path, capsys, text, params=(), includes=None) -> str:
    """The one line `frequencies` prints (exit 2), checked to name deck.bdf."""
    (tmp_path / "deck.bdf").write_text(text)
    for name, body in (includes or {}).items():
        (tmp_path / name).write_text(body)
    study = '[model]\ntype = "nastran"\nbdf = "deck.bdf"\n'
    for k, (card, cid, field) in enumerate(params):
        study += (f'[[model.parameter]]\nname = "p{k}"\ncard = "{card}"\nid = {cid}\n'
                  f'field = "{field}"\nstd = 1.0\n')
    (tmp_path / "study.toml").write_text(study)
    capsys.readouterr()
    code = main(["frequencies", str(tmp_path / "study.toml"), "--modes", "3"])
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert code == 2 and out == "" and len(lines) == 1, (code, out, err)
    assert "Traceback" not in err and "deck.bdf" in lines[0], lines
    return lines[0]


def _moved(corners, i, to, kind=""):
    c = np.array(corners, float)
    c[i] = to
    return _nodes(c, kind)


# (name, deck, words the line must hold): each was exit 0 with a number, or a line
# naming neither card nor id, before
GEOMETRY = [
    # two corners at one point: the bottom face collapses, det J = 0 at those corners
    ("CPENTA6 coincident corners", lambda: deck("CPENTA", _moved(PRISM, 2, PRISM[1])),
     "line 8: CPENTA 99: zero or changing-sign Jacobian"),
    ("CPENTA6 corner on its neighbours' line",
     lambda: deck("CPENTA", _moved(PRISM, 1, (0, 0.5, 0))), "CPENTA 99: zero or"),
    ("CPENTA15 coincident corners",
     lambda: deck("CPENTA", _moved(PRISM, 2, PRISM[1], "CPENTA15"), kind="CPENTA15"),
     "CPENTA 99: zero or"),
    ("CPYRAM5 coincident base corners", lambda: deck("CPYRAM", _moved(PYRAMID, 2, PYRAMID[1])),
     "CPYRAM 99: zero or"),
    ("CPYRAM5 base corner on its neighbours' line",
     lambda: deck("CPYRAM", _moved(PYRAMID, 1, (0.5, 0.5, 0))), "CPYRAM 99: zero or"),
    ("CPENTA6 grid twice", lambda: deck("CPENTA", _nodes(PRISM), [1, 2, 2, 4, 5, 6]),
     "line 8: CPENTA 99: GRID 2 appears twice"),
    ("CPYRAM5 grid twice", lambda: deck("CPYRAM", _nodes(PYRAMID), [1, 2, 2, 4, 5]),
     "CPYRAM 99: GRID 2 appears twice"),
    ("CQUAD4 grid twice (pyNastran's check, located)",
     lambda: deck("CQUAD4", _nodes(SQUARE), [1, 2, 2, 4]),
     "line 6: CQUAD4 99: a grid appears twice"),
    # a mid-edge node 3 edge lengths off: det J stays positive (an outward bulge), a
    # wrong grid all the same (solids.MAX_MID_OFFSET)
    ("CHEXA20 mid-edge node far off", lambda: deck(
        "CHEXA", _far(CUBE, "CHEXA20"), kind="CHEXA20"),
     "CHEXA 99: mid-edge node G9 is 3 edge lengths"),
    ("CTETRA10 mid-edge node far off", lambda: deck(
        "CTETRA", _far(TET, "CTETRA10"), kind="CTETRA10"), "CTETRA 99: mid-edge node G5"),
    # 1e-9 thick: the plate's own modes fell below the rigid-body cut (exit 0, wrong)
    ("CHEXA8 1e-9 thick", lambda: deck("CHEXA", _nodes(CUBE) * (1, 1e-9, 1)),
     "CHEXA 99: zero or changing-sign Jacobian"),
    ("CQUAD4 1e-9 wide", lambda: deck("CQUAD4", _nodes(SQUARE) * (1, 1e-9, 1)),
     "line 6: CQUAD4 99: zero area"),
    ("CQUAD8 mid-edge node far off", lambda: deck(
        "CQUAD8", _far(SQUARE, "CQUAD8"), kind="CQUAD8"), "CQUAD8 99: mid-edge node G5"),
]


def _far(corners, kind):
    xyz = _nodes(corners, kind)
    n = len(corners)
    xyz[n] += (0.0, -3.0, 0.0)  # edge G1-G2 runs along x from the origin
    return xyz


@pytest.mark.parametrize("name,make,words", GEOMETRY, ids=[g[0] for g in GEOMETRY])
def test_bad_geometry_is_one_line_naming_the_element(tmp_path, capsys, name, make, words):
    """Sources: det J of the isoparametric map vanishes at a collapsed corner (the
    integration points alone miss it on a CPENTA or CPYRAM); NASTRAN refuses a grid
    given twice in one element; a quadratic edge cannot follow a node 3 edges away."""
    assert words in refused(tmp_path, capsys, make())


CARDS = [
    ("MAT1 NU = -1 (pyNastran's division by zero, located)",
     deck("CHEXA", _nodes(CUBE), mat="MAT1,1,2.e11,,-1.,7850.\n"),
     "line 23: MAT1 1: a division by zero in G = E / (2 (1 + NU))"),
    # pyNastran's CONM2 validate() quotes no card: found from the card it was checking
    ("CONM2 mass < 0", deck("CQUAD4", _nodes(SQUARE)).replace(
        "ENDDATA", "CONM2,7,1,,-150.\nENDDATA"), "line 14: CONM2 7: mass=-150.0"),
    ("PSHELL T < 0 (pyNastran's check, located)",
     deck("CQUAD4", _nodes(SQUARE), prop="PSHELL,1,1,-.01,1,,1\n"), "line 12: PSHELL 1:"),
    ("MAT1 G < 0", deck("CQUAD4", _nodes(SQUARE), mat="MAT1,1,2.e11,-8.e10,.3,7850.\n"),
     "MAT1 1: negative shear modulus"),
    # E alone: NASTRAN's G = NU = 0, so MID3's transverse shear would vanish
    ("MAT1 E alone as MID3", deck("CQUAD4", _nodes(SQUARE), mat="MAT1,1,2.e11,,,7850.\n"),
     "line 12: PSHELL 1: MID3's MAT1 1 has G = 0"),
    ("PSHELL NSM making the mass negative",
     deck("CQUAD4", _nodes(SQUARE), prop="PSHELL,1,1,.01,1,,1,,-1.e9\n"),
     "PSHELL 1: NSM = -1e+09"),
    ("PCOMP THETA 1e9", deck("CQUAD4", _nodes(SQUARE), mat=M8,
                             prop="PCOMP,1\n" + PLIES.replace("90.", "1.e9")),
     "line 12: PCOMP 1: ply angles THETA"),
    ("PCOMP THETA -1e300", deck("CQUAD4", _nodes(SQUARE), mat=M8,
                                prop="PCOMP,1\n" + PLIES.replace("90.", "-1.e300")),
     "PCOMP 1: ply angles THETA"),
    # NASTRAN's blank G1Z is rigid transverse shear (pyNastran puts 1e8 Pa in its place):
    # read where every ply leaves both blank; G1Z alone blank in turned plies is refused
    ("MAT8 G1Z blank", deck("CQUAD4", _nodes(SQUARE), prop="PCOMP,1\n" + PLIES,
                            mat=M8.replace(",5.e9,5.e9,1600", ",,5.e9,1600")),
     "line 12: PCOMP 1: ply 1's MAT8 8 leaves G1Z/G2Z blank"),
    ("PSOLID CORDM undefined", deck("CHEXA", _nodes(CUBE), prop="PSOLID,1,1,5\n"),
     "line 22: PSOLID 1: CORDM 5"),
    ("GRID id beyond 2**31 - 1", deck("CQUAD4", _nodes(SQUARE)).replace(
        "GRID,1,", "GRID,1000000000000000000,").replace("CQUAD4,99,1,1,",
                                                        "CQUAD4,99,1,1000000000000000000,"),
     "line 2: GRID 1000000000000000000: id outside"),
]


@pytest.mark.parametrize("name,text,words", CARDS, ids=[c[0] for c in CARDS])
def test_bad_cards_are_one_line_naming_card_and_id(tmp_path, capsys, name, text, words):
    """Sources: MSC's MAT1/MAT8/PSHELL/PCOMP/PSOLID remarks (moduli and mass > 0, MAT8's
    blank G1Z rigid, CORDM a defined system) and NASTRAN's 32-bit ids; a THETA beyond one
    turn is a typing error (cos of 1e300 degrees has no digits left)."""
    assert words in refused(tmp_path, capsys, text)


def test_parameter_on_a_field_that_is_none_names_card_and_id(tmp_path, capsys):
    line = refused(tmp_path, capsys, deck("CQUAD4", _nodes(SQUARE), mat=M8,
                                          prop="PCOMP,1\n" + PLIES), [("MAT8", 8, "ST")])
    assert "line 15: MAT8 8: field 'ST' is not a parameter; the parameter fields" in line


def test_deep_include_chain_and_a_device_are_refused(tmp_path, capsys):
    """A 150-deep INCLUDE chain was a RecursionError's traceback past 1000; /dev/zero as
    the deck filled memory."""
    chain = {f"i{k}.bdf": f"INCLUDE 'i{k + 1}.bdf'\n" for k in range(150)}
    chain["i150.bdf"] = "$\n"
    text = deck("CQUAD4", _nodes(SQUARE)).replace("BEGIN BULK", "BEGIN BULK\nINCLUDE 'i0.bdf'")
    assert "more than 100 nested INCLUDE levels" in refused(tmp_path, capsys, text,
                                                            includes=chain)
    (tmp_path / "study.toml").write_text('[model]\ntype = "nastran"\nbdf = "/dev/zero"\n')
    assert main(["frequencies", str(tmp_path / "study.toml")]) == 2
    assert "not a regular file" in capsys.readouterr().err
    # as an INCLUDE: it was "INCLUDE file /dev/zero not found (looked in ...)"
    (tmp_path / "deck.bdf").write_text(text.replace("INCLUDE 'i0.bdf'", "INCLUDE '/dev/zero'"))
    (tmp_path / "study.toml").write_text('[model]\ntype = "nastran"\nbdf = "deck.bdf"\n')
    assert main(["frequencies", str(tmp_path / "study.toml")]) == 2
    assert "INCLUDE /dev/zero is not a regular file" in capsys.readouterr().err


def test_mirrored_solids_and_valid_quadratics_still_run(tmp_path, capsys):
    """The checks leave sound elements alone: a 1e-4 thick brick (aspect 1e4, inside
    solids.MIN_DET's 1e6) runs, and a CPYRAM5 numbered the other way round
    gives the same frequencies as the usual numbering (the same element, solids.py), to
    the eigen-solver's rounding (1e-9 with room)."""
    (tmp_path / "deck.bdf").write_text(deck("CHEXA", _nodes(CUBE) * (1, 1e-4, 1)))
    (tmp_path / "study.toml").write_text('[model]\ntype = "nastran"\nbdf = "deck.bdf"\n')
    assert main(["frequencies", str(tmp_path / "study.toml"), "--modes", "1"]) == 0  # 1e4:1
    got = []
    for ids in ([1, 2, 3, 4, 5], [1, 4, 3, 2, 5]):
        (tmp_path / "deck.bdf").write_text(deck("CPYRAM", _nodes(PYRAMID), ids))
        (tmp_path / "study.toml").write_text('[model]\ntype = "nastran"\nbdf = "deck.bdf"\n')
        capsys.readouterr()
        assert main(["frequencies", str(tmp_path / "study.toml"), "--modes", "4",
                     "--json"]) == 0
        got.append(capsys.readouterr().out)
    a, b = (np.array(json.loads(g)["configurations"][0]["frequencies_hz"]) for g in got)
    assert np.allclose(a, b, rtol=1e-9)


@pytest.mark.parametrize("coordinate, says", [
    (60117, "no GRID component"),                   # component 7
    (6011, "GRID 601 has no free coordinate"),       # GRID 6011 without its component
    (10011, "GRID 1001 has no free coordinate"),     # a base clamped in all six
    (99991, "GRID 9999 has no free coordinate")])    # no such GRID
def test_missing_nastran_coordinate_named_for_what_it_is(tmp_path, capsys, coordinate, says):
    """Coordinates are 10 * GRID + component: every one of these was called 'restrained'
    (a gap in 1..max, as on a beam), 6011 and 60117 with no such component in the deck."""
    from conftest import EXAMPLES

    code = main(["sweep", str(EXAMPLES / "nastran_frame" / "study.toml"), "--coordinate",
                 str(coordinate), "--max-mass", "10", "-o", str(tmp_path / "s.png")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2
    assert says in err[-1] and "is restrained" not in err[-1], err
    assert not (tmp_path / "s.png").exists()
