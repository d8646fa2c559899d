"""Which subcase's SPC set makes the normal-modes model of a multi-analysis deck (NX's
SOL 111 with ``ANALYSIS = MODES``, pyNastran's models/cbush_psd_bug deck).

Run for real in .venv-nastran (``make test``); skipped in the core environment."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from nastran_frames import need

from eigenupdate.errors import InputError
from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.io.nastran import read_nastran  # noqa: E402

# a 2 m steel cantilever of 4 CBARs along x; SPC 1 clamps grid 1, SPC 2 also holds grid 5
BULK = ("BEGIN BULK\nEIGRL,1,,,4\n"
        + "".join(f"GRID,{i + 1},,{0.5 * i},0.,0.\n" for i in range(5))
        + "".join(f"CBAR,{i + 1},1,{i + 1},{i + 2},0.,0.,1.\n" for i in range(4))
        + "PBAR,1,1,1.e-3,2.e-7,8.e-7,5.e-7\nMAT1,1,2.e11,,0.3,7800.\n"
        + "SPC1,1,123456,1\nSPC1,2,123456,1,5\nENDDATA\n")


def _hz(tmp_path, case: str) -> np.ndarray:
    path = tmp_path / "deck.bdf"
    path.write_text("SOL 111\nCEND\nMETHOD = 1\n" + case + BULK)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        m = read_nastran(path).model
    return solve_elastic(m.stiffness(), m.mass(), 4, dense=True).eigenvalues


def test_the_modes_subcase_chooses_the_spc_set(tmp_path):
    """A modes subcase (ANALYSIS = MODES, SPC 1) beside a response subcase holding SPC 2:
    the model is the modes subcase's, the same as the deck with SPC 1 alone (exact: the
    same matrices); without ANALYSIS = MODES the two sets are refused, one line."""
    alone = _hz(tmp_path, "SPC = 1\n")
    both = ("SUBCASE 1\n  SPC = 1\n  ANALYSIS = MODES\nSUBCASE 2\n  SPC = 2\n"
            "  ANALYSIS = MFREQ\n")
    np.testing.assert_array_equal(_hz(tmp_path, both), alone)
    held = _hz(tmp_path, "SPC = 2\n")
    assert held[0] > 4 * alone[0]  # SPC 2 holds more: the test sees which set was taken
    with pytest.raises(InputError, match=r"several SPC sets \[1, 2\]"):
        _hz(tmp_path, "SUBCASE 1\n  SPC = 1\nSUBCASE 2\n  SPC = 2\n")
