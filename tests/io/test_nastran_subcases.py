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


def test_the_study_names_the_subcase(tmp_path):
    """Two modes subcases on different SPC sets (a symmetric and an antisymmetric
    analysis, as MSC's aeroelastic examples have): refused unless the study names one;
    ``subcase = N`` gives exactly that set's model (the deck with its SPC alone). A
    subcase the case control lacks is refused in one line naming the field."""
    two = "SUBCASE 1\n  SPC = 1\nSUBCASE 2\n  SPC = 2\n"
    path = tmp_path / "two.bdf"
    path.write_text("SOL 103\nCEND\nMETHOD = 1\n" + two + BULK)
    with pytest.raises(InputError, match=r"several SPC sets \[1, 2\].*subcase = N"):
        read_nastran(path)
    for sub, alone in ((1, _hz(tmp_path, "SPC = 1\n")), (2, _hz(tmp_path, "SPC = 2\n"))):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            m = read_nastran(path, (), subcase=sub).model
        lam = solve_elastic(m.stiffness(), m.mass(), 4, dense=True).eigenvalues
        np.testing.assert_array_equal(lam, alone)
    with pytest.raises(InputError, match=r"subcase 3 is not in the case control") as err:
        read_nastran(path, (), subcase=3)
    assert err.value.field == "model.subcase"


def test_study_subcase_from_the_command_line(tmp_path, run_cli):
    """The study's [model] subcase reaches the deck: `frequencies` of subcase 2 prints the
    held beam's first frequency, of no subcase the one-line refusal (exit 2)."""
    (tmp_path / "two.bdf").write_text("SOL 103\nCEND\nMETHOD = 1\nSUBCASE 1\n  SPC = 1\n"
                                      "SUBCASE 2\n  SPC = 2\n" + BULK)
    study = tmp_path / "study.toml"
    study.write_text('[model]\ntype = "nastran"\nbdf = "two.bdf"\nsubcase = 2\n')
    code, text, err = run_cli("frequencies", study, "--modes", "1")
    held = np.sqrt(_hz(tmp_path, "SPC = 2\n")[0]) / (2 * np.pi)
    assert code == 0, err
    printed = float(text.split()[-1])  # the table prints 6 significant digits
    assert printed == pytest.approx(held, rel=1e-5), (held, text)
    study.write_text('[model]\ntype = "nastran"\nbdf = "two.bdf"\n')
    code, text, err = run_cli("frequencies", study, "--modes", "1")
    assert code == 2 and err.count("\n") == 1 and "subcase = N" in err
