"""PSHELL with MAT2 (anisotropic shell material) as MID1/MID2/MID3 (MSC QRG MAT2:
{s1, s2, t12} = G {e1, e2, g12}, G from G11, G12, G13, G22, G23, G33; as MID3 G11, G12,
G22 relate {t1z, t2z} to {g1z, g2z}, G13, G23, G33 blank; in the element's material axes
THETA/MCID). pyNastran's models/other/pmultrand.bdf and sdbush10.bdf (MAT2 as MID3, and
as MID1/MID2/MID3) were refused for it (tools/deck_sweep.py, issue 20); they have no
eigenvalue table.

Independent references: the MAT1 deck (an isotropic MAT2: G = E / (1 - NU^2) [[1, NU,
0], [NU, 1, 0], [0, 0, (1 - NU) / 2]], shear G11 = G22 = E / (2 (1 + NU))) and the MAT8
deck (an orthotropic MAT2 with Q11 = E1 / (1 - NU12 NU21), Q12 = NU12 E2 / (1 - NU12
NU21), Q22 = E2 / (1 - NU12 NU21), Q66 = G12, shear diag(G1Z, G2Z)), both written out by
hand here, on the warped mixed CQUAD4 (THETA 15)/CTRIA3 plate of test_nastran_pcompg.
Runs in .venv-nastran (pyNastran)."""

from __future__ import annotations

import pytest
from laminate_plates import E1, E2, G12, G13, G23, NU12, RHO
from nastran_frames import need

from eigenupdate.errors import InputError

pytestmark = pytest.mark.nastran
need("pyNastran")
from test_nastran_pshell_mat8 import ISO1, MAT8, NU, E, G, T, _mesh, _same  # noqa: E402


def _mat2(mid, g, rho):
    """A MAT2 card, G = (G11, G12, G13, G22, G23, G33), blanks as None."""
    return f"MAT2,{mid}," + ",".join("" if x is None else repr(float(x)) for x in g) \
        + f",{rho!r}\n"


ISO_PLANE = (E / (1 - NU**2), NU * E / (1 - NU**2), 0.0, E / (1 - NU**2), 0.0,
             E / (2 * (1 + NU)))
ISO_SHEAR = (G, 0.0, None, G, None, None)


@pytest.mark.parametrize("mid3", ["shear", "", "none"])
def test_isotropic_mat2_is_the_mat1_deck(tmp_path, mid3):
    """Source: the MAT1 deck (MID1 = MID2 = MID3 = MAT1 E, NU, RHO 2700), K and M equal
    to rounding (the moduli formed in another order). MID3 a MAT2 of G11 = G22 = G, MID3
    blank (shear-rigid, as MAT1's), or no MID2 (membrane only)."""
    cards = _mat2(5, ISO_PLANE, 2700.0) + _mat2(9, ISO_SHEAR, 0.0)
    if mid3 == "none":
        a = _mesh(tmp_path, "mat2.bdf", f"PSHELL,7,5,{T!r}\n" + cards)
        b = _mesh(tmp_path, "mat1.bdf", f"PSHELL,7,6,{T!r}\n" + ISO1)
    else:
        m3 = "9" if mid3 else ""
        a = _mesh(tmp_path, "mat2.bdf", f"PSHELL,7,5,{T!r},5,,{m3}\n" + cards)
        b = _mesh(tmp_path, "mat1.bdf", f"PSHELL,7,6,{T!r},6,,{mid3 and '6'}\n" + ISO1)
    _same(a, b)


def test_orthotropic_mat2_is_the_mat8_deck(tmp_path):
    """Source: the MAT8 deck (E1, E2, NU12, G12, G1Z, G2Z; THETA 15 on the CQUAD4 turns
    both alike), K and M equal to rounding."""
    nu21 = NU12 * E2 / E1
    d = 1 - NU12 * nu21
    plane = (E1 / d, NU12 * E2 / d, 0.0, E2 / d, 0.0, G12)
    cards = _mat2(5, plane, RHO) + _mat2(9, (G13, 0.0, None, G23, None, None), 0.0)
    a = _mesh(tmp_path, "mat2.bdf", f"PSHELL,7,5,{T!r},5,,9\n" + cards)
    b = _mesh(tmp_path, "mat8.bdf", f"PSHELL,7,8,{T!r},8,,8\n" + MAT8)
    _same(a, b)


@pytest.mark.parametrize("cards, match", [
    (f"PSHELL,7,5,{T!r},5,,5\n" + _mat2(5, ISO_PLANE, 2700.0),
     r"PSHELL 7 MID3: MAT2 5's G13, G23, G33 must be blank"),
    (f"PSHELL,7,5,{T!r}\n" + _mat2(5, (1.0, 2.0, 0.0, 1.0, 0.0, 1.0), 1.0),
     r"PSHELL 7 MID1: MAT2 5's G \(G11 \.\. G33\) is not positive definite"),
    (f"PSHELL,7,5,{T!r}\nMAT2,5,1.,0.,0.,1.,0.,1.,1.\n,,,,,,,,\n,9\n",
     r"MAT2 5: MCSID 9 \(a material system of its own\) is not supported"),
], ids=["G33 in MID3", "indefinite", "MCSID"])
def test_mat2_refusals(tmp_path, cards, match):
    with pytest.raises(InputError, match=match):
        _mesh(tmp_path, "bad.bdf", cards)
