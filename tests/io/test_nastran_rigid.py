"""Rigid elements, MPCs and pin flags against closed forms (NASTRAN-95's CRIGD cards are
checked against NASTRAN-95's own frequencies in test_nastran_decks.py).

Run for real in .venv-nastran (``make test``); skipped in the core environment."""

from __future__ import annotations

import numpy as np
import pytest
from nastran_frames import need

from eigenupdate.errors import InputError
from eigenupdate.model.parameters import Parameter
from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.io.nastran import CardField, read_nastran  # noqa: E402

R = np.array([0.3, -0.2, 0.5])


def _deck(tmp_path, body: str, name="deck.bdf"):
    path = tmp_path / name
    path.write_text("BEGIN BULK\nPARAM,AUTOSPC,NO\n" + body + "ENDDATA\n")
    return path


def _rigid_mass(m: float, r: np.ndarray) -> np.ndarray:
    """Source: a point mass m at offset r from a grid, seen from the grid:
    [[m 1, -m [r]x], [m [r]x, m (|r|^2 1 - r r^T)]]."""
    rx = np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])
    return np.block([[m * np.eye(3), -m * rx], [m * rx, m * (r @ r * np.eye(3) - np.outer(r, r))]])


GRIDS = f"GRID,1,,1.,2.,3.\nGRID,2,,{1 + R[0]!r},{2 + R[1]!r},{3 + R[2]!r}\n"


@pytest.mark.parametrize("card", ["RBE2,9,1,123456,2", "RBAR,9,1,2,123456,,,123456",
                                  "RBAR,9,1,2,123456"],
                         ids=["RBE2", "RBAR", "RBAR-blank-CM"])
def test_rigid_element_carries_a_point_mass(tmp_path, card):
    """A CONM2 on a grid made dependent by a rigid element reaches the independent grid
    as the rigid-body mass of the closed form above; the dependent grid is eliminated."""
    path = _deck(tmp_path, GRIDS + "CONM2,7,2,,12.\n" + card + "\n"
                 "CELAS1,1,5,1,1\nCELAS1,2,5,1,2\nCELAS1,3,5,1,3\nCELAS1,4,5,1,4\n"
                 "CELAS1,5,5,1,5\nCELAS1,6,5,1,6\nPELAS,5,1000.\n")
    model = read_nastran(path).model
    assert sorted(model.coordinates.tolist()) == [11, 12, 13, 14, 15, 16]
    rows = [model.index(10 + c) for c in range(1, 7)]
    got = model.mass().toarray()[np.ix_(rows, rows)]
    assert np.allclose(got, _rigid_mass(12.0, R), rtol=1e-13, atol=1e-13)


def test_chain_of_rigid_elements_is_one(tmp_path):
    """RBE2 1 -> 2 and RBE2 2 -> 3 (a chain, as NASTRAN-95's rotor pylon has) give the
    matrices of one RBE2 1 -> 2, 3."""
    grids = GRIDS + "GRID,3,,0.,4.,1.\n"
    rest = ("CONM2,7,2,,12.\nCONM2,8,3,,3.\nCELAS1,1,5,1,1\nCELAS1,2,5,1,2\nCELAS1,3,5,1,3\n"
            "CELAS1,4,5,1,4\nCELAS1,5,5,1,5\nCELAS1,6,5,1,6\nPELAS,5,1000.\n")
    one = read_nastran(_deck(tmp_path, grids + rest + "RBE2,9,1,123456,2,3\n", "a.bdf")).model
    two = read_nastran(_deck(tmp_path, grids + rest + "RBE2,9,1,123456,2\nRBE2,10,2,123456,3\n",
                             "b.bdf")).model
    for a, b in ((one.mass(), two.mass()), (one.stiffness(), two.stiffness())):
        assert abs(a - b).max() <= 1e-13 * abs(a).max()


def test_mpc_ties_two_masses(tmp_path):
    """Source: the MPC 1 u2 - 1 u1 = 0 ties m2 to m1 on a spring k:
    f = sqrt(k / (m1 + m2)) / (2 pi)."""
    path = _deck(tmp_path, "GRID,1,,0.,0.,0.,,23456\nGRID,2,,1.,0.,0.,,23456\nCELAS2,1,4000.,1,1\n"
                 "CMASS2,2,3.,1,1\nCMASS2,3,7.,2,1\nMPC,1,2,1,1.,1,1,-1.\n")
    model = read_nastran(path).model
    f = solve_elastic(model.stiffness(), model.mass(), 1).frequencies_hz[0]
    assert f == pytest.approx(np.sqrt(4000.0 / 10.0) / (2 * np.pi), rel=1e-13)


def test_perturbation_on_a_dependent_coordinate_refused(tmp_path):
    path = _deck(tmp_path, GRIDS + "CONM2,7,2,,12.\nRBE2,9,1,123456,2\nCELAS1,1,5,1,1\n"
                 "PELAS,5,1000.\n")
    nm = read_nastran(path)
    with pytest.raises(InputError, match="GRID 2 component 3 is dependent on RBE2 9"):
        nm.grid_dof(2, 3)


def test_spc_on_a_dependent_coordinate_refused(tmp_path):
    path = _deck(tmp_path, GRIDS + "CONM2,7,2,,12.\nRBE2,9,1,123456,2\nSPC1,1,1,2\n")
    with pytest.raises(InputError, match="RBE2 9: GRID 2 component 1 is dependent and also "
                                         "restrained"):
        read_nastran(path)


def test_parameter_through_a_rigid_element(tmp_path):
    """Source: finite difference of K and M in CONM2 M on a dependent grid (the reduced
    matrices are linear in it: T does not depend on the parameter)."""
    body = GRIDS + "CONM2,7,2,,{m}\nRBE2,9,1,123456,2\nCELAS1,1,5,1,1\nPELAS,5,1000.\n"
    nm = read_nastran(_deck(tmp_path, body.format(m="12."), "a.bdf"),
                      [(Parameter("m", 0.0), CardField("CONM2", 7, "M"))])
    up = read_nastran(_deck(tmp_path, body.format(m="12.5"), "b.bdf")).model
    fd = ((up.mass() - nm.model.mass()) / 0.5).toarray()
    assert np.max(np.abs(fd - nm.model.m_terms[0].toarray())) <= 1e-12 * np.abs(fd).max()


def test_pin_flag_closed_form(tmp_path):
    """Source: a beam hinged (PA = 6, rotation about z released) at its clamped end A,
    end B guided (rotation held): B's plane-1 stiffness is 3 E I1 / L^3."""
    path = _deck(tmp_path, "GRID,1,,0.,0.,0.\nGRID,2,,2.,0.,0.\nCBAR,1,1,1,2,0.,1.,0.\n"
                 ",6\nPBAR,1,1,1.e-3,2.e-7,8.e-7,5.e-7\nMAT1,1,2.e11,,0.3\n"
                 "SPC1,1,123456,1\nSPC1,1,6,2\n")
    model = read_nastran(path).model
    K = model.stiffness().toarray()
    force = np.zeros(model.n)
    force[model.index(22)] = 1.0
    u = np.linalg.solve(K, force)[model.index(22)]
    # K's condition number is 6.7e3: solve() errs by at most about cond eps = 1.5e-12
    assert u == pytest.approx(8.0 / (3 * 2.0e11 * 2.0e-7), rel=1e-11)


def test_rbe3_is_the_weighted_average(tmp_path):
    """Source: an RBE3 reference grid at the weighted centroid of three grids (weights
    1, 2, 3, translations 123) moves with their weighted mean translation: a unit mass
    there adds m w_i w_j / W^2 to M between the grids' same translations (x here)."""
    w = np.array([1.0, 2.0, 3.0])
    pts = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    c = w @ pts / w.sum()
    body = "".join(f"GRID,{i + 1},,{p[0]},{p[1]},{p[2]}\n" for i, p in enumerate(pts))
    body += f"GRID,4,,{c[0]!r},{c[1]!r},0.\nCONM2,7,4,,5.\n"
    body += "RBE3,9,,4,123,1.,123,1,2.\n,123,2,3.,123,3\n"
    body += "".join(f"CELAS1,{10 + i},5,{i},1\n" for i in (1, 2, 3)) + "PELAS,5,1.e3\n"
    model = read_nastran(_deck(tmp_path, body)).model
    rows = [model.index(10 * i + 1) for i in (1, 2, 3)]
    got = model.mass().toarray()[np.ix_(rows, rows)]
    assert np.allclose(got, 5.0 * np.outer(w, w) / w.sum() ** 2, rtol=1e-13, atol=1e-15)


CHAIN = ("GRID,1,,0.,0.,0.,,23456\nGRID,2,,1.,0.,0.,,23456\nGRID,3,,2.,0.,0.,,23456\n"
         "CELAS1,1,5,1,1\nCELAS1,2,5,1,1,2,1\nCELAS1,3,5,2,1,3,1\nPELAS,5,1.e4\n"
         "CMASS2,4,2.,1,1\nCMASS2,5,3.,3,1\n")


@pytest.mark.parametrize("card", ["OMIT1,1,2", "ASET1,1,1,3", "OMIT,2,1", "ASET,1,1,3,1"])
def test_guyan_reduction_of_a_massless_coordinate_is_exact(tmp_path, card):
    """Source: static condensation of a coordinate without mass changes no frequency
    (Guyan 1965): the chain reduced by OMIT/OMIT1/ASET/ASET1 has the full chain's
    frequencies, on the kept coordinates only."""
    full = read_nastran(_deck(tmp_path, CHAIN, "full.bdf")).model
    reduced = read_nastran(_deck(tmp_path, CHAIN + card + "\n", "reduced.bdf")).model
    assert sorted(reduced.coordinates.tolist()) == [11, 31]
    f = solve_elastic(full.stiffness(), full.mass(), 2).frequencies_hz
    g = solve_elastic(reduced.stiffness(), reduced.mass(), 2).frequencies_hz
    assert g == pytest.approx(f, rel=1e-12)


def test_parameters_of_a_reduced_deck_refused(tmp_path):
    path = _deck(tmp_path, CHAIN + "OMIT1,1,2\n")
    with pytest.raises(InputError, match="ASET/OMIT .Guyan reduction.: K and M of the reduced"):
        read_nastran(path, [(Parameter("k", 0.0), CardField("PELAS", 5, "K"))])


def test_perturbation_on_an_omitted_coordinate_refused(tmp_path):
    nm = read_nastran(_deck(tmp_path, CHAIN + "OMIT1,1,2\n"))
    with pytest.raises(InputError, match="GRID 2 component 1 is omitted by ASET/OMIT"):
        nm.grid_dof(2, 1)
    assert nm.grid_dof(3, 1) == 31
