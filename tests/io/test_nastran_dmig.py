"""DMIG matrices selected by K2GG and M2GG (MSC QRG: K2GG, M2GG, DMIG, PARAM CK2/CM2).

Run for real in .venv-nastran (``make test``); skipped in the core environment."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import scipy.linalg as sl
from nastran_frames import need

from eigenupdate.errors import InputError

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.io.nastran import read_nastran  # noqa: E402

# two grids free along x only, a spring between them, a scalar point 7
DECK = """SOL 103
CEND
{case}
BEGIN BULK
{params}
EIGRL,1,,,3
GRID,1,,0.,0.,0.,,23456
GRID,2,,1.,0.,0.,,23456
SPOINT,7
CELAS2,1,1000.,1,1,2,1
CONM2,5,1,,1.0
CONM2,6,2,,1.0
DMIG,KX,0,6,1,0
DMIG,KX,2,1,,2,1,500.,,+
+,7,0,-100.
DMIG,KX,7,0,,7,0,300.
DMIG,MX,0,6,1,0
DMIG,MX,2,1,,2,1,0.25
DMIG,MY,0,6,1,0
DMIG,MY,7,0,,7,0,0.5
{extra}ENDDATA
"""


def _read(tmp_path, case="K2GG = KX\nM2GG = 2.0*MX, MY", params="PARAM,CM2,1.5", extra=""):
    path = tmp_path / "dmig.bdf"
    path.write_text(DECK.format(case=case, params=params, extra=extra))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        nm = read_nastran(path)
    return nm, " ".join(str(w.message) for w in caught)


def _dense(nm):
    m = nm.model
    order = np.argsort(m.coordinates)  # 11 (grid 1 x), 21 (grid 2 x), 71 (SPOINT 7)
    K, M = m.stiffness().toarray(), m.mass().toarray()
    return m.coordinates[order], K[np.ix_(order, order)], M[np.ix_(order, order)]


def test_selected_dmig_adds_to_k_and_m_as_the_qrg_says(tmp_path):
    """Hand assembly from the QRG's rules: K2GG adds KX in the g-set (the off-diagonal
    term given once, mirrored); M2GG = 2.0*MX + MY, times PARAM CM2 = 1.5."""
    nm, _ = _read(tmp_path)
    coords, K, M = _dense(nm)
    assert coords.tolist() == [11, 21, 71]
    K_hand = np.array([[1000., -1000., 0.], [-1000., 1500., -100.], [0., -100., 300.]])
    M_hand = np.diag([1.0, 1.0 + 1.5 * 2.0 * 0.25, 1.5 * 0.5])
    np.testing.assert_allclose(K, K_hand, rtol=0, atol=1e-12 * 1500)
    np.testing.assert_allclose(M, M_hand, rtol=0, atol=1e-15 * 2)
    lam = sl.eigh(K_hand, M_hand, eigvals_only=True)
    assert np.allclose(np.sqrt(lam) / (2 * np.pi), [1.96409829, 3.23949808, 6.54385716],
                       rtol=1e-8)


def test_m2gg_is_not_scaled_by_wtmass_and_k2gg_is_by_ck2(tmp_path):
    """QRG M2GG remark: its input is not affected by PARAM WTMASS (the CONM2s are)."""
    nm, _ = _read(tmp_path, params="PARAM,WTMASS,0.5\nPARAM,CK2,2.0")
    _, K, M = _dense(nm)
    np.testing.assert_allclose(np.diag(M), [0.5, 0.5 + 2.0 * 0.25, 0.5], rtol=1e-15)
    np.testing.assert_allclose(K[1:, 1:], [[1000. + 1000., -200.], [-200., 600.]], rtol=1e-15)


def test_unselected_dmig_is_skipped_and_named(tmp_path):
    """K2GG remark 1: DMIG matrices are not used unless selected."""
    nm, note = _read(tmp_path, case="K2GG = KX")
    _, K, M = _dense(nm)
    np.testing.assert_allclose(np.diag(M), [1.0, 1.0, 0.0])
    assert "DMIG MX, MY (not selected by K2GG or M2GG)" in note
    nm, note = _read(tmp_path, case="")
    assert "DMIG KX, MX, MY (not selected" in note


def test_dmi_is_skipped(tmp_path):
    """DMI matrices enter only through DMAP (aerodynamic WKK, W2GJ): skipped, listed."""
    dmi = "DMI,WKK,0,3,1,0,,2,1\nDMI,WKK,1,1,1.0,THRU,2\n"
    _, note = _read(tmp_path, extra=dmi)
    assert "DMI x2" in note


@pytest.mark.parametrize("case, extra, expected", [
    ("K2GG = KZ", "", "case control K2GG = KZ: no DMIG KZ in the deck"),
    ("K2PP = KX", "", "K2PP (a direct input matrix added after the constraints"),
    ("K2GG = KQ", "DMIG,KQ,0,1,1,0\nDMIG,KQ,2,1,,2,1,5.\n", "IFO = 1"),
    ("K2GG = KB", "DMIG,KB,0,6,1,0\nDMIG,KB,2,1,,7,0,5.\nDMIG,KB,7,0,,2,1,5.\n",
     "given both above and below the diagonal"),
    ("K2GG = KC", "DMIG,KC,0,6,3,0\nDMIG,KC,2,1,,2,1,5.,1.\n", "TIN = 3 (complex)"),
    ("K2GG = KG", "DMIG,KG,0,6,1,0\nDMIG,KG,9,1,,9,1,5.\n", "GRID 9"),
    # pyNastran's own check while reading (was "pyNastran cannot read the deck", no card)
    ("K2GG = KH", "DMIG,KH,0,6,1,0\nDMIG,KH,2,1,,2,7,5.\n", "DMIG KH: "),
])
def test_refusals_name_the_matrix(tmp_path, case, extra, expected):
    """One line naming the DMIG (and its line, where the matrix exists)."""
    with pytest.raises(InputError) as err:
        _read(tmp_path, case=case, extra=extra)
    msg = str(err.value)
    assert expected in msg and "\n" not in msg
    if "DMIG K" in msg and "case control" not in msg:
        assert "line " in msg


def test_subcases_must_all_select_the_same(tmp_path):
    """The case control selects per subcase (global values carried into each): a subcase
    with K2GG = KX beside one without would be two models; the one model read must not
    take KX silently (it did, for both). Same selection in every subcase: read; a global
    selection inherited by all: read."""
    with pytest.raises(InputError, match="or none in some"):
        _read(tmp_path, case="SUBCASE 1\nK2GG = KX\nSUBCASE 2\nMETHOD = 1")
    with pytest.raises(InputError, match="or none in some"):
        _read(tmp_path, case="SUBCASE 1\nMETHOD = 1\nSUBCASE 2\nM2GG = MX")
    nm, _ = _read(tmp_path, case="SUBCASE 1\nK2GG = KX\nSUBCASE 2\nK2GG = KX")
    assert _dense(nm)[1][2, 2] == 300.0
    nm, _ = _read(tmp_path, case="K2GG = KX\nSUBCASE 1\nMETHOD = 1\nSUBCASE 2\nMETHOD = 1")
    assert _dense(nm)[1][2, 2] == 300.0
