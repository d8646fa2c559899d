"""MSC's RBE1 (a rigid body whose six independent components lie on several grids),
RROD (a rod rigid in extension) against other cards that state the same constraint:
an RBE2 on the same grids, an MPC written by hand, and a closed form; and CBAR's OFFT
BGG (its orientation vector in basic) against GGG.

Run for real in .venv-nastran (``make test``); skipped in the core environment."""

from __future__ import annotations

import numpy as np
import pytest
from nastran_frames import need

from eigenupdate.errors import InputError
from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.io.nastran import read_nastran  # noqa: E402

SPRINGS = "".join(f"CELAS1,{c},5,1,{c}\n" for c in range(1, 7)) + "PELAS,5,1000.\n"
# a body of four grids (not in one plane) with a mass at each, on springs at grid 1
BODY = ("GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nGRID,3,,0.,1.,0.\nGRID,4,,0.3,0.4,0.5\n"
        "CONM2,11,1,,2.\nCONM2,12,2,,3.\nCONM2,13,3,,5.\nCONM2,14,4,,7.\n" + SPRINGS)


def _deck(tmp_path, body: str, name: str):
    path = tmp_path / name
    path.write_text("BEGIN BULK\nPARAM,AUTOSPC,NO\n" + body + "ENDDATA\n")
    return path


def _hz(path, n=6):
    model = read_nastran(path).model
    return solve_elastic(model.stiffness(), model.mass(), n).frequencies_hz


def test_rbe1_on_three_grids_is_the_rbe2_of_the_body(tmp_path):
    """Source: the RBE2 on grid 1 of the same four grids. RBE1's independent components
    1, 2, 3 at grid 1, 2, 3 at grid 2 and 3 at grid 3 (the 3-2-1 choice) fix the same
    rigid body, so the six frequencies of the body on its springs are the same, whichever
    components are eliminated (to the eigen-solver's precision, 1e-10)."""
    rbe2 = _hz(_deck(tmp_path, BODY + "RBE2,9,1,123456,2,3,4\n", "rbe2.bdf"))
    rbe1 = _hz(_deck(tmp_path, BODY + "RBE1,9,1,123,2,23,3,3\n"
                     ",UM,1,456,2,1456,3,12456\n,,4,123456\n", "rbe1.bdf"))
    assert np.allclose(rbe1, rbe2, rtol=1e-10, atol=0)


def test_rbe1_with_all_six_at_one_grid_is_rbe2(tmp_path):
    """Source: RBE2 (same independent grid, same dependent grids): K and M are equal."""
    a = read_nastran(_deck(tmp_path, BODY + "RBE2,9,1,123456,2,3,4\n", "a.bdf")).model
    b = read_nastran(_deck(tmp_path, BODY + "RBE1,9,1,123456\n,UM,2,123456,3,123456,4,"
                           "123456\n", "b.bdf")).model
    for x, y in ((a.mass(), b.mass()), (a.stiffness(), b.stiffness())):
        assert abs(x - y).max() <= 1e-13 * abs(x).max()


# a skew rod from grid 1 to grid 2 in the x-y plane; grid 1 on springs in x and y, grid 2
# with a mass held in y: the rod carries grid 2 along in x
ROD = ("GRID,1,,0.,0.,0.,,3456\nGRID,2,,0.6,0.8,0.,,23456\n"
       "CELAS2,1,4000.,1,1\nCELAS2,2,9000.,1,2\nCMASS2,3,3.,1,1\nCMASS2,4,3.,1,2\n"
       "CMASS2,5,7.,2,1\n")


def test_rrod_is_its_mpc(tmp_path):
    """Source: the MPC of a rod rigid in extension along e = (0.6, 0.8, 0) written by hand,
    e . (u2 - u1) = 0 with u2's y held: 0.6 u2x - 0.6 u1x - 0.8 u1y = 0; and the closed
    form of that two-degree-of-freedom system (eigenvalues of K, M with u2x = u1x + 4/3 u1y).
    RROD's dependent component at either end (CMB 1 at grid 2, or CMA 1 at grid 1) gives
    the same frequencies."""
    mpc = _hz(_deck(tmp_path, ROD + "MPC,1,2,1,0.6,1,1,-0.6\n,,1,2,-0.8\n", "mpc.bdf"), 2)
    at_b = _hz(_deck(tmp_path, ROD + "RROD,9,1,2,,1\n", "b.bdf"), 2)
    at_a = _hz(_deck(tmp_path, ROD + "RROD,9,1,2,1\n", "a.bdf"), 2)
    T = np.array([[1.0, 0.0], [0.0, 1.0], [1.0, 4.0 / 3.0]])  # (u1x, u1y) -> (u1x, u1y, u2x)
    K = T.T @ np.diag([4000.0, 9000.0, 0.0]) @ T
    M = T.T @ np.diag([3.0, 3.0, 7.0]) @ T
    exact = np.sqrt(np.sort(np.linalg.eigvals(np.linalg.solve(M, K)).real)) / (2 * np.pi)
    for f in (mpc, at_b, at_a):
        assert np.allclose(f, exact, rtol=1e-10, atol=0)


@pytest.mark.parametrize("card, message", [
    ("RBE1,9,1,123,2,23\n,UM,4,123456\n", "RBE1 9: the independent components must fix "
                                          "the rigid body: six of them, got 5"),
    ("RBE1,9,1,123,2,123\n,UM,3,123456\n", "RBE1 9: the independent components do not fix"),
    ("RBE1,9,1,123,2,23,3,3\n,UM,1,3456\n", "RBE1 9: GRID 1 component 3 is both independent "
                                            "and dependent"),
    ("RROD,9,1,2\n", "RROD 9: CMA, CMB must name one translational component"),
    ("RROD,9,1,2,1,2\n", "RROD 9: CMA, CMB must name one translational component"),
    ("RROD,9,1,3,3\n", "RROD 9: component 3 of GRID 1 is normal to the rod"),
], ids=["five", "collinear", "twice", "rrod-blank", "rrod-both", "rrod-normal"])
def test_bad_rbe1_and_rrod_refused(tmp_path, card, message):
    """Bad input: one line naming the card and the problem."""
    with pytest.raises(InputError, match=message):
        read_nastran(_deck(tmp_path, BODY + card, "bad.bdf"))


def test_cbar_orientation_in_basic_bgg(tmp_path):
    """Source: MSC QRG CBAR, OFFT's first letter: X in GA's displacement system (G) or in
    basic (B). GA's CD turns basic by 90 degrees about z (x_cd = y_basic): a bar whose X is
    (0, 1, 1) in basic under BGG is the bar whose X is (1, 0, 1) in that CD under GGG, and
    not the one with (0, 1, 1) under GGG."""
    common = ("CORD2R,5,,0.,0.,0.,0.,0.,1.\n,0.,1.,0.\n"  # x_cd = (0,1,0), y_cd = (-1,0,0)
              "GRID,1,,0.,0.,0.,5\nGRID,2,,2.,0.3,0.1\nPBAR,1,1,1.e-4,2.e-9,5.e-9,3.e-9\n"
              "MAT1,1,2.e11,,0.3,7850.\n")
    bgg = read_nastran(_deck(tmp_path, common + "CBAR,9,1,1,2,0.,1.,1.,BGG\n", "a.bdf")).model
    ggg = read_nastran(_deck(tmp_path, common + "CBAR,9,1,1,2,1.,0.,1.,GGG\n", "b.bdf")).model
    wrong = read_nastran(_deck(tmp_path, common + "CBAR,9,1,1,2,0.,1.,1.\n", "c.bdf")).model
    a, b, c = (m.stiffness().toarray() for m in (bgg, ggg, wrong))
    assert np.abs(a - b).max() <= 1e-12 * np.abs(a).max()
    assert np.abs(a - c).max() > 1e-6 * np.abs(a).max()  # the bending terms (EI << EA L^2)
