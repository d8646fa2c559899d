"""NASTRAN-95's plates CQUAD1/CQUAD2/CTRIA1/CTRIA2 with PQUAD1/PQUAD2/PTRIA1/PTRIA2
(io/nastran_plates95.py), read as the CQUAD4/CTRIA3 + PSHELL they amount to.

Independent sources: NASTRAN-95's printed frequencies of its demonstration problems
D03-01-1A and D03-01-2A and the Kirchhoff frequencies their decks state; the same plate
written by hand with CQUAD4/CTRIA3 + PSHELL from the User's Manual's field definitions;
a hand-edited deck for PQUAD2 T as a parameter. Runs in .venv-nastran (pyNastran)."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import ROOT
from nastran_frames import need
from plates import card_specs, read_deck
from refusals import one_line

from eigenupdate.errors import InputError
from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.io.nastran_write import write_updated_bdf  # noqa: E402

DATA = ROOT / "tests" / "data" / "nastran_published"
# the Kirchhoff frequencies of the simply supported plate the decks state in their
# comments (modes (1,1), (1,2), (1,3), (3,1), (3,2), (1,4))
THEORY = np.array([9.068997e-1, 2.267249, 4.534498, 4.534498, 5.894848, 7.708647])


def _printed(name: str) -> np.ndarray:
    return np.loadtxt(DATA / f"{name}.csv", delimiter=",", comments="#", skiprows=4)[:, 1]


def _hz(path, n: int) -> np.ndarray:
    model = read_deck(path).model
    return solve_elastic(model.stiffness(), model.mass(), n).frequencies_hz


def test_quarter_plate_d03011a_reproduces_nastran95_and_kirchhoff():
    """Sources: NASTRAN-95's printed frequencies (d03011a.csv: demoout/d03011a.out of
    nasa/NASTRAN-95 commit 65e29e9; deck inp/d03011a.inp, NASA Open Source Agreement 1.3)
    and the deck's theoretical values. 200 CQUAD1 + PQUAD1 (I = T1^3 / 12, MID3 blank:
    rigid in shear), CNGRNT. NASTRAN-95's QUAD1 is built from sub-triangles, ours is
    CQUAD4's MITC4, so the shared README's 1e-2 for shells holds (measured +1.1e-4,
    +1.4e-3, +4.7e-3); the 10 x 20 mesh against Kirchhoff within 1e-2 too (measured
    -1.4e-3 .. +4.3e-3; the (1,3) and (3,1) pair is repeated, as in theory)."""
    want = _printed("d03011a")
    got = _hz(DATA / "d03011a.inp", 4)
    assert np.max(np.abs(got[:want.size] / want - 1)) < 1e-2
    assert np.max(np.abs(got / THEORY[:4] - 1)) < 1e-2


def test_half_plate_d03012a_reproduces_nastran95_and_kirchhoff():
    """Sources as above (demoout/d03012a.out, inp/d03012a.inp). The 20 x 40 mesh of 800
    CQUAD1. NASTRAN-95's FEER (EIGR 20, ND 1) printed one root of the repeated (1,3)/(3,1)
    pair (4.533995 Hz, the deck's comment lists both at 4.534498) and rows 7-12 that are
    no plate modes (11.48, 12.01 Hz ...: Kirchhoff's (3,4), (1,5) are 11.34, 11.79 Hz;
    their generalized masses stray from the 1.0302e4 of the converged rows), so rows 1-6
    are compared, with our 4th mode (the pair's other root) left out (measured +2.3e-5 ..
    +2.3e-3); the first six against Kirchhoff within 1e-2 (measured -1.4e-3 .. +2.8e-3)."""
    want = _printed("d03012a")[:6]
    got = _hz(DATA / "d03012a.inp", 7)
    assert got[3] / got[2] - 1 < 1e-9  # the repeated root NASTRAN's FEER missed
    assert np.max(np.abs(got[[0, 1, 2, 4, 5, 6]] / want - 1)) < 1e-2
    assert np.max(np.abs(got[:6] / THEORY - 1)) < 1e-2


# a slightly irregular 3 x 2 mesh (1.5 x 1, grid 5 moved) with the in-plane drilling held
_GRIDS = [(1, 0.0, 0.0), (2, 0.5, 0.0), (3, 1.0, 0.0), (4, 1.5, 0.0), (5, 0.05, 0.55),
          (6, 0.5, 0.5), (7, 1.0, 0.5), (8, 1.5, 0.5), (9, 0.0, 1.0), (10, 0.5, 1.0),
          (11, 1.0, 1.0), (12, 1.5, 1.0)]
_QUADS = [(1, 2, 6, 5), (2, 3, 7, 6), (3, 4, 8, 7), (5, 6, 10, 9), (6, 7, 11, 10),
          (7, 8, 12, 11)]
_MATS = "MAT1,1,7.e10,,.33,2700.\nMAT2,2,8.e10,2.e10,0.,5.e10,0.,2.5e10,2600.\n"
# (NASTRAN-95 property card, the PSHELL it amounts to by the manual's fields)
CASES = {
    # I = 2e-5 != T1^3 / 12 = 1.04e-5: 12I/T^3 = 12 I / T1^3 = 1.92; TS/T = T3 / T1 = 0.8
    "pquad1": ("PQUAD1,1,1,.05,1,2.e-5,1,.04,.3", "PSHELL,1,1,.05,1,1.92,1,.8,.3"),
    "t3_zero": ("PQUAD1,1,1,.05,1,2.e-5,1,0.,.3", "PSHELL,1,1,.05,1,1.92,,,.3"),
    "mid3_blank": ("PQUAD1,1,1,.05,1,2.e-5,,.04", "PSHELL,1,1,.05,1,1.92"),
    "membrane": ("PQUAD1,1,1,.05", "PSHELL,1,1,.05"),
    # anisotropic MAT2 turned by TH = 30 from the G1-G2 side, as CQUAD4's THETA
    "mat2_theta": ("PQUAD1,1,2,.05,2,2.e-5,1,.04,.3", "PSHELL,1,2,.05,2,1.92,1,.8,.3"),
    # PQUAD2: I = T^3 / 12 and shear thickness T (remarks 2, 3): 12I/T^3 = 1, TS/T = 1
    "pquad2": ("PQUAD2,1,1,.05,.3", "PSHELL,1,1,.05,1,1.,1,1.,.3"),
}


def _pair(tmp_path, case: str, tria: bool, coupled: bool):
    """The same plate twice: NASTRAN-95's cards and CQUAD4/CTRIA3 + PSHELL."""
    n95, pshell = CASES[case]
    if tria:
        n95 = n95.replace("PQUAD", "PTRIA")
    theta = 30.0 if case == "mat2_theta" else 0.0
    kind = {"PQUAD1": "1", "PQUAD2": "2"}[n95[:6].replace("PTRIA", "PQUAD")]
    grids = "".join(f"GRID,{g},,{x},{y},0.,,6\n" for g, x, y in _GRIDS)
    extra = "PARAM,COUPMASS,1\n" if coupled else ""
    paths = []
    for name, prop, quad, tri in (("n95", n95, f"CQUAD{kind}", f"CTRIA{kind}"),
                                  ("msc", pshell, "CQUAD4", "CTRIA3")):
        if tria:
            els = "".join(f"{tri},{2 * i + 1},1,{a},{b},{c},{theta}\n"
                          f"{tri},{2 * i + 2},1,{a},{c},{d},{theta}\n"
                          for i, (a, b, c, d) in enumerate(_QUADS))
        else:
            els = "".join(f"{quad},{i + 1},1,{a},{b},{c},{d},{theta}\n"
                          for i, (a, b, c, d) in enumerate(_QUADS))
        path = tmp_path / f"{name}.bdf"
        path.write_text(f"BEGIN BULK\n{grids}{els}{prop}\n{_MATS}{extra}"
                        f"SPC1,1,123,1,9\nENDDATA\n")
        paths.append(path)
    return paths


@pytest.mark.parametrize("coupled", [False, True], ids=["lumped", "coupled"])
@pytest.mark.parametrize("tria", [False, True], ids=["quad", "tria"])
@pytest.mark.parametrize("case", list(CASES))
def test_nastran95_property_is_the_pshell_it_amounts_to(tmp_path, case, tria, coupled):
    """Hand translation (User's Manual PQUAD1/PQUAD2/PTRIA1/PTRIA2, module docstring):
    the PSHELL deck gives the same K and M. Both are assembled by the same code from
    moduli that differ only in how 12I/T^3 and TS/T were rounded (1.92 and 0.8 as decimal
    text against 12 I / T1^3 and T3 / T1 computed): 1e-12 of the largest entry."""
    n95, msc = (read_deck(p).model for p in _pair(tmp_path, case, tria, coupled))
    assert n95.coordinates.tolist() == msc.coordinates.tolist()
    for a, b in ((n95.stiffness(), msc.stiffness()), (n95.mass(), msc.mass())):
        assert abs(a - b).max() <= 1e-12 * abs(b).max()


def test_small_large_and_free_fields_read_alike(tmp_path):
    """The same CQUAD1 and PQUAD1 in free (the deck of the tests above), small and large
    (16-character, ``*`` continuation) fields: the same K and M, exactly (the same
    numbers read)."""
    a, _ = _pair(tmp_path, "pquad1", False, True)
    free = read_deck(a).model
    text = a.read_text()
    small = ("CQUAD1  3       1       3       4       8       7       0.0\n"
             "PQUAD1  1       1       .05     1       2.e-5   1       .04     .3\n")
    large = ("CQUAD1* 3               1               3               4\n"
             "*       8               7               0.0\n"
             "PQUAD1* 1               1               .05             1\n"
             "*       2.e-5           1               .04             .3\n")
    for cards in (small, large):
        quad, prop = "CQUAD1,3,1,3,4,8,7,0.0\n", "PQUAD1,1,1,.05,1,2.e-5,1,.04,.3\n"
        assert quad in text and prop in text
        a.write_text(text.replace(quad, "").replace(prop, cards))
        other = read_deck(a).model
        assert abs(other.stiffness() - free.stiffness()).max() == 0
        assert abs(other.mass() - free.mass()).max() == 0


def test_theta_turns_an_anisotropic_material(tmp_path):
    """Guards the MAT2 case above: TH = 0 instead of 30 changes K (the material axes
    turn), so that case checks that TH reaches the element."""
    a, _ = _pair(tmp_path, "mat2_theta", False, False)
    turned = read_deck(a).model.stiffness()
    a.write_text(a.read_text().replace(",30.0\n", ",0.0\n"))
    plain = read_deck(a).model.stiffness()
    assert abs(turned - plain).max() > 1e-3 * abs(plain).max()


def test_pquad2_thickness_is_a_parameter_written_back_into_its_card(tmp_path):
    """Hand-edited deck: a PQUAD2 card holding two properties (PID 1 and 2); T of the
    second as a parameter gives, at a new value, the deck with that T edited (same code,
    same products: 1e-12), and the updated BDF holds it in the PQUAD2 card (no PSHELL
    written) and reads back to it."""
    def deck(path, t2):
        grids = "".join(f"GRID,{g},,{x},{y},0.,,6\n" for g, x, y in _GRIDS)
        els = "".join(f"CQUAD2,{i + 1},{1 + (i % 3 == 2)},{a},{b},{c},{d}\n"
                      for i, (a, b, c, d) in enumerate(_QUADS))
        path.write_text(f"BEGIN BULK\n{grids}{els}PQUAD2  1       1       .05     .3      "
                        f"2       1       {t2:<8}.1\n{_MATS}SPC1,1,123,1,9\nENDDATA\n")
        return path

    specs = card_specs([("t", "PQUAD2", 2, "T")])
    nm = read_deck(deck(tmp_path / "a.bdf", ".07"), specs)
    assert nm.model.values.tolist() == [0.07]
    ref = read_deck(deck(tmp_path / "b.bdf", ".084")).model
    s = np.array([0.084])
    for a, b in ((nm.model.stiffness(s), ref.stiffness()), (nm.model.mass(s), ref.mass())):
        assert abs(a - b).max() <= 1e-12 * abs(b).max()
    out = tmp_path / "out.bdf"
    write_updated_bdf(nm, out, {"t": 0.084})
    text = out.read_text()
    assert "PSHELL" not in text and "PQUAD2*" in text
    assert read_deck(out, specs).model.values.tolist() == [0.084]


@pytest.mark.parametrize("tria", [False, True], ids=["quad", "tria"])
def test_mat1_of_a_pquad1_is_a_parameter(tmp_path, tria):
    """Hand-edited deck: MAT1 E and RHO of the PQUAD1/PTRIA1 plate (membrane, bending and,
    G blank, shear follow E; mass RHO T1) at new values give the deck with them edited
    (the same element matrices times the values: 1e-12)."""
    a, _ = _pair(tmp_path, "pquad1", tria, False)
    nm = read_deck(a, card_specs([("E", "MAT1", 1, "E"), ("rho", "MAT1", 1, "RHO")]))
    a.write_text(a.read_text().replace("MAT1,1,7.e10,,.33,2700.", "MAT1,1,7.7e10,,.33,2430."))
    ref = read_deck(a).model
    s = np.array([7.7e10, 2430.0])
    for x, y in ((nm.model.stiffness(s), ref.stiffness()), (nm.model.mass(s), ref.mass())):
        assert abs(x - y).max() <= 1e-12 * abs(y).max()


def test_pquad1_thickness_is_refused_as_a_parameter(tmp_path):
    """PQUAD1 T1 sets membrane and mass, not bending (I) or shear (T3): refused in one
    line naming the card, id and field."""
    a, _ = _pair(tmp_path, "pquad1", False, False)
    with pytest.raises(InputError, match=r"PQUAD1 1 field T1: not a parameter: membrane"):
        read_deck(a, card_specs([("t", "PQUAD1", 1, "T1")]))


BAD = [
    ("CQUAD1,3,1,3,4,8,7", "CQUAD1,3,9,3,4,8,7", "line 16: CQUAD1 3: PQUAD1 9 is not defined"),
    ("PQUAD1,1,1,.05,1,2.e-5,1,.04,.3", "PQUAD1,1,1,0.,1,2.e-5,1,.04,.3",
     "line 20: PQUAD1 1: T1 = 0 must be > 0"),
    ("PQUAD1,1,1,.05,1,2.e-5,1,.04,.3", "PQUAD1,1,,.05,1,2.e-5,1,.04,.3",
     "line 20: PQUAD1 1: MID1 = None (field #2) on card must be an integer (not blank)"),
    ("CQUAD1,3,1,3,4,8,7", "CQUAD1,3,1,3,4,,7",
     "line 16: CQUAD1 3: G3 = None (field #5) on card must be an integer (not blank)"),
    ("CQUAD1,3,1,3,4,8,7", "CQUAD1,3,1,3,4,8,7\nCTRIA1,30,1,3,4,8",
     "line 17: CTRIA1 30: PTRIA1 1 is not defined (property 1 is a PQUAD1)"),
    # an MSC-style ZOFFS would be dropped
    ("CQUAD1,3,1,3,4,8,7,0.0", "CQUAD1,3,1,3,4,8,7,0.0,.01",
     "line 16: CQUAD1 3: field 9 = '.01' is beyond the card's fields"),
    # G given against E / (2 (1 + NU)) = 2.632e10: NASTRAN-95's in-plane shear differs
    ("MAT1,1,7.e10,,.33", "MAT1,1,7.e10,2.5e10,.33",
     "line 20: PQUAD1 1: MAT1 1's G = 2.5e+10 is not E / (2 (1 + NU)) = 2.63158e+10"),
]


@pytest.mark.parametrize(("old", "new", "message"), BAD, ids=["missing", "t1", "mid1",
                                                             "grid", "kind", "zoffs", "g"])
def test_bad_nastran95_plate_cards_are_refused_in_one_line(tmp_path, run_cli, old, new,
                                                           message):
    """A CQUAD1 naming no PQUAD1, T1 <= 0, a blank required field, a CTRIA1 naming a
    PQUAD1, data beyond the card's fields, a MAT1 G NASTRAN-95 would use for in-plane
    shear: exit 2, one line naming the
    file, line, card and id."""
    a, _ = _pair(tmp_path, "pquad1", False, False)
    text = a.read_text()
    assert old in text
    a.write_text(text.replace(old, new, 1))
    (tmp_path / "study.toml").write_text('[model]\ntype = "nastran"\nbdf = "n95.bdf"\n')
    code, _, err = run_cli("frequencies", tmp_path / "study.toml")
    one_line(code, err, "n95.bdf", message)
