"""PCOMPG: a PCOMP whose plies carry global ply ids (MSC QRG PCOMPG: the same laminate;
GPLYID only names the ply for output).

Run for real in .venv-nastran (``make test``); skipped in the core environment."""

from __future__ import annotations

import warnings

import pytest
from nastran_frames import need

from eigenupdate.errors import InputError

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.io.nastran import read_nastran  # noqa: E402

MESH = """SOL 103
CEND
BEGIN BULK
PARAM,COUPMASS,1
MAT8,3,1.4e11,9.e9,0.3,5.e9,5.e9,3.e9,1600.
MAT1,4,7.e10,,0.33,2700.
""" + "".join(f"GRID,{1 + i + 4 * j},,{0.1 * i + 0.01 * j},{0.1 * j},{0.002 * i * j}\n"
              for j in range(4) for i in range(4)) + "".join(
    f"CQUAD4,{1 + i + 3 * j},7,{1 + i + 4 * j},{2 + i + 4 * j},{6 + i + 4 * j},"
    f"{5 + i + 4 * j},15.\n" for j in range(3) for i in range(3) if (i + j) % 2) + "".join(
    f"CTRIA3,{20 + i + 3 * j},7,{1 + i + 4 * j},{2 + i + 4 * j},{6 + i + 4 * j}\n"
    f"CTRIA3,{40 + i + 3 * j},7,{1 + i + 4 * j},{6 + i + 4 * j},{5 + i + 4 * j}\n"
    for j in range(3) for i in range(3) if not (i + j) % 2) + "{prop}\nENDDATA\n"

# unsymmetric, two materials, Z0 given, NSM: every part of the laminate's reading
PCOMP = ("PCOMP,7,-0.0012,0.3\n,3,0.0004,0.,,3,0.0003,45.\n,4,0.0005,90.,,3,0.0004,-30.")
PCOMPG = ("PCOMPG,7,-0.0012,0.3\n,101,3,0.0004,0.\n,102,3,0.0003,45.\n,205,4,0.0005,90.\n"
          ",7,3,0.0004,-30.")


def _read(tmp_path, prop):
    path = tmp_path / "plate.bdf"
    path.write_text(MESH.replace("{prop}", prop))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return read_nastran(path).model


def test_pcompg_is_the_same_laminate_as_pcomp(tmp_path):
    """MSC QRG PCOMPG: the plies as PCOMP's; the global ply ids change nothing. K and M
    of a free mixed CQUAD4/CTRIA3 plate agree to round-off."""
    a, b = _read(tmp_path, PCOMP), _read(tmp_path, PCOMPG)
    for x, y in ((a.stiffness(), b.stiffness()), (a.mass(), b.mass())):
        assert abs(x - y).max() <= 1e-13 * abs(x).max()
    assert abs(a.stiffness()).max() > 0


def test_pcompg_lam_options_other_than_blank_are_refused(tmp_path):
    """PCOMPG's LAM = SMEAR, MEM, BEND, SMCORE change the laminate: refused, one line."""
    prop = PCOMPG.replace("PCOMPG,7,-0.0012,0.3", "PCOMPG,7,-0.0012,0.3,,,,,SMEAR")
    with pytest.raises(InputError, match="PCOMPG 7: LAM = SMEAR is not supported"):
        _read(tmp_path, prop)
