"""CORD1R/CORD1C (systems defined by three grids) are read as the CORD2R/CORD2C through
the same three points (MSC QRG CORD1R: origin G1, z axis towards G2, G3 in the xz
plane; CORD2R: A, B, C the same). Runs in .venv-nastran (pyNastran)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from nastran_frames import need

from eigenupdate.errors import EigenupdateWarning
from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.io.nastran import read_nastran  # noqa: E402

# CORD2R 5 by hand: origin (0.2, 0.1, 0), z along (0, 0.6, 0.8), xz plane through (1.2, 0.1, 0)
O5 = np.array([0.2, 0.1, 0.0])
Z5 = np.array([0.0, 0.6, 0.8])
X5 = np.array([1.0, 0.0, 0.0])
R5 = np.array([X5, np.cross(Z5, X5), Z5])  # rows: its axes in basic (orthonormal)
GRID2_IN_5 = np.array([0.3, -0.4, 0.5])
POINTS = {1: np.array([0.0, 0.0, 0.0]), 2: O5 + R5.T @ GRID2_IN_5,
          3: np.array([1.1, 0.9, 0.4]), 4: np.array([0.4, 1.5, -0.3])}


def _deck(path, cord1: bool):
    if cord1:
        systems = "CORD1R,6,1,2,3\nCORD1C,7,3,1,2\n"
    else:
        p = POINTS
        systems = "".join(
            f"CORD2{t},{cid},,{a[0]!r},{a[1]!r},{a[2]!r},{b[0]!r},{b[1]!r},{b[2]!r},\n"
            f",{c[0]!r},{c[1]!r},{c[2]!r}\n"
            for t, cid, (a, b, c) in (("R", 6, (p[1], p[2], p[3])),
                                      ("C", 7, (p[3], p[1], p[2]))))
    g = POINTS
    text = f"""SOL 103
CEND
SPC = 1
BEGIN BULK
CORD2R,5,,{O5[0]!r},{O5[1]!r},{O5[2]!r},{(O5 + Z5)[0]!r},{(O5 + Z5)[1]!r},{(O5 + Z5)[2]!r},
,{(O5 + X5)[0]!r},{(O5 + X5)[1]!r},{(O5 + X5)[2]!r}
{systems}GRID,1,,0.,0.,0.,6
GRID,2,5,{GRID2_IN_5[0]!r},{GRID2_IN_5[1]!r},{GRID2_IN_5[2]!r}
GRID,3,,{g[3][0]!r},{g[3][1]!r},{g[3][2]!r}
GRID,4,,{g[4][0]!r},{g[4][1]!r},{g[4][2]!r},7
MAT1,1,2.1e11,,0.3,7850.
PBAR,1,1,3.e-4,2.e-8,3.e-8,4.e-8
CBAR,1,1,1,2,1.,0.,0.
CBAR,2,1,2,3,0.,0.,1.
CBAR,3,1,3,4,0.,0.,1.
SPC1,1,123,1
PELAS,9,1.e3
PELAS,10,4.e3
PELAS,11,2.e4
CELAS1,21,9,1,4
CELAS1,22,10,1,5
CELAS1,23,11,4,1
CONM2,31,4,,3.0
CMASS1,32,33,4,2
PMASS,33,1.5
ENDDATA
"""
    path.write_text(text)
    return path


def _read(path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EigenupdateWarning)
        return read_nastran(path).model


def test_cord1_systems_are_the_cord2_through_their_grids(tmp_path):
    """Source: the QRG definitions above; the CORD2 reference takes the grids' basic
    positions computed by hand (grid 2 given in CORD2R 5). Grid 1 carries CD = CORD1R 6
    (its rotational springs see the axes), grid 4 CD = CORD1C 7 (its radial spring
    does). Same K and M to round-off; a deck with a CORD1 card was refused before."""
    a, b = _read(_deck(tmp_path / "c1.bdf", True)), _read(_deck(tmp_path / "c2.bdf", False))
    Ka, Kb = a.stiffness().toarray(), b.stiffness().toarray()
    Ma, Mb = a.mass().toarray(), b.mass().toarray()
    # entries of K are sums of terms up to max|K|; the systems' axes carry ~1e-16 each
    assert np.abs(Ka - Kb).max() <= 1e-12 * np.abs(Kb).max()
    assert np.abs(Ma - Mb).max() <= 1e-12 * np.abs(Mb).max()
    assert np.all(np.isfinite(solve_elastic(Ka, Ma, 4).frequencies_hz))
    # the systems are used: without the CDs the springs act along other axes (M, in
    # each grid's own axes, is the same scalar masses either way)
    path = _deck(tmp_path / "c3.bdf", True)
    path.write_text(path.read_text().replace("0.,0.,0.,6\n", "0.,0.,0.\n")
                    .replace(",7\nMAT1", "\nMAT1"))
    c = _read(path)
    assert np.abs(c.stiffness().toarray() - Ka).max() > 1e-3 * np.abs(Ka).max()
