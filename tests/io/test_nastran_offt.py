"""CBAR/CBEAM OFFT: the orientation vector in GA's displacement system (G) or basic (B),
and each end's offset in its grid's displacement system (G) or in the offset system (O).

Source: MSC/NX Quick Reference Guide, CBAR and CBEAM field OFFT (GGG, BGG, GGO, BGO, GOG,
BOG, GOO, BOO) and the offset coordinate system of their figures: x from GA to GB (the
grids, not the offset ends), y in the plane of x and the orientation vector v, z = x cross
y; pyNastran's ``rotate_v_wa_wb`` reads it the same way. Found by tools/deck_sweep.py on
pyNastran's models/unit/bars/cbar_orientation.bdf (all eight codes), refused before.

Independent check: each code's deck against the GGG deck whose offsets were converted by
hand (below, with the axes written out): K and M identical to round-off; and the offset
system's independence of GA's displacement system (a rotated CD changes K's basis, not
its eigenvalues). Run for real in .venv-nastran (``make test``)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from nastran_frames import need

pytestmark = [pytest.mark.nastran,
              pytest.mark.filterwarnings("ignore::eigenupdate.errors.EigenupdateWarning")]
need("pyNastran")
from eigenupdate.errors import InputError  # noqa: E402
from eigenupdate.io.nastran import read_nastran  # noqa: E402

R2 = math.sqrt(2.0)
# the bar from GA (0,0,0) to GB (1,1,0), v = (0,0,1): offset system by hand
EX, EY, EZ = np.array([1, 1, 0]) / R2, np.array([0.0, 0, 1]), np.array([1, -1, 0]) / R2
WA, WB = (0.01, 0.1, 0.2), (-0.02, 0.05, -0.1)  # as written on the card


def _deck(tmp_path, offt: str, wa, wb, cd: int = 0, coupled: bool = False) -> str:
    f = lambda w: ",".join(f"{x:.17g}" for x in w)  # noqa: E731
    text = ("SOL 103\nCEND\nBEGIN BULK\n"
            "CORD2R,1,,0.,0.,0.,0.,0.,1.,+C\n+C,0.,1.,0.\n"  # x along basic y
            f"GRID,1,,0.,0.,0.,{cd}\nGRID,2,,1.,1.,0.\nGRID,3,,2.,1.,0.\n"
            f"CBAR,1,1,1,2,0.,0.,1.,{offt},+B\n+B,,,{f(wa)},{f(wb)}\n"
            "CBAR,2,1,2,3,0.,1.,0.\n"
            "PBAR,1,1,1.e-3,2.e-7,8.e-7,5.e-7,,,+P\n+P,,,,,,,,,+Q\n+Q,.8,.7\n"
            "MAT1,1,2.e11,,0.3,7800.\nCONM2,10,3,,2.\nSPC1,1,123456,1\n"
            + ("PARAM,COUPMASS,1\n" if coupled else "") + "ENDDATA\n")
    path = tmp_path / f"{offt}_{cd}.bdf"
    path.write_text(text)
    return str(path)


def _in_offset_system(w) -> np.ndarray:
    return w[0] * EX + w[1] * EY + w[2] * EZ


@pytest.mark.parametrize("coupled", [False, True])
@pytest.mark.parametrize("offt", ["BGG", "GGO", "BGO", "GOG", "BOG", "GOO", "BOO"])
def test_offt_as_hand_converted_ggg(tmp_path, offt, coupled):
    wa_g = _in_offset_system(WA) if offt[1] == "O" else np.array(WA)
    wb_g = _in_offset_system(WB) if offt[2] == "O" else np.array(WB)
    ref = read_nastran(_deck(tmp_path, "GGG", wa_g, wb_g, coupled=coupled)).model
    got = read_nastran(_deck(tmp_path, offt, WA, WB, coupled=coupled)).model
    for a, b in ((got.stiffness(), ref.stiffness()), (got.mass(), ref.mass())):
        a, b = a.toarray(), b.toarray()
        assert np.max(np.abs(a - b)) <= 1e-12 * np.max(np.abs(b))


def test_offset_system_ignores_ga_displacement_system(tmp_path):
    """GOO: GA's CD 1 (rotated 90 degrees about z) changes K's basis, not its spectrum;
    with GGG the same numbers on the card would be another offset (a control)."""
    from eigenupdate.solve.eigen import solve_elastic

    def hz(path):
        m = read_nastran(path).model
        return solve_elastic(m.stiffness(), m.mass(), 6).frequencies_hz

    base = hz(_deck(tmp_path, "GOO", WA, WB, cd=0))
    assert np.allclose(hz(_deck(tmp_path, "GOO", WA, WB, cd=1)), base, rtol=1e-10, atol=0)
    ggg0, ggg1 = hz(_deck(tmp_path, "GGG", WA, WB, 0)), hz(_deck(tmp_path, "GGG", WA, WB, 1))
    assert np.max(np.abs(ggg1 / ggg0 - 1)) > 1e-6


def test_bad_offt(tmp_path):
    with pytest.raises(InputError, match=r"CBAR 1: OFFT GBG is not one of GGG"):
        read_nastran(_deck(tmp_path, "GBG", WA, WB))
