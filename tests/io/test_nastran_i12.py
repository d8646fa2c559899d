"""PBAR and PBEAM I12 (unsymmetric sections) on CBAR and CBEAM.

Run for real in .venv-nastran (``make test``); skipped in the core environment."""

from __future__ import annotations

import re
import warnings

import numpy as np
import pytest
from nastran_frames import need

from eigenupdate.errors import InputError
from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.io.nastran import read_nastran  # noqa: E402

GRIDS = {1: (0.0, 0.0, 0.0), 2: (1.0, 0.0, 0.2), 3: (1.5, 0.8, 0.1), 4: (0.4, 1.2, 0.5),
         5: (0.9, 0.5, 1.1)}
MEMBERS = [(1, 2, (0.2, 1.0, 0.3)), (2, 3, (0.0, 0.3, 1.0)), (3, 4, (1.0, 0.1, 0.4)),
           (4, 5, (0.3, -0.6, 0.2)), (5, 2, (-0.5, 0.2, 1.0)), (1, 4, (0.7, 0.1, -0.4))]
A, I1, I2, I12, J = 1.0e-4, 2.0e-9, 1.0e-9, 0.8e-9, 1.5e-9


def _deck(element: str, prop: str, vectors) -> str:
    cards = ["SOL 103", "CEND", "SPC = 1", "BEGIN BULK", "PARAM,COUPMASS,1",
             "MAT1,1,2.e11,,0.3,7800.", prop, "SPC1,1,123456,1", "CONM2,91,3,,2.0",
             "CONM2,92,5,,1.5"]
    cards += [f"GRID,{g},,{x!r},{y!r},{z!r}" for g, (x, y, z) in GRIDS.items()]
    cards += [f"{element},{k},1,{a},{b},{v[0]!r},{v[1]!r},{v[2]!r}"
              for k, ((a, b, _), v) in enumerate(zip(MEMBERS, vectors, strict=True), 1)]
    return "\n".join(cards + ["ENDDATA", ""])


def _hz(tmp_path, text: str) -> np.ndarray:
    path = tmp_path / "frame.bdf"
    path.write_text(text)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = read_nastran(path).model
    return solve_elastic(model.stiffness(), model.mass(), 10).frequencies_hz


def _principal():
    """I1', I2' and each member's orientation vector along the first principal axis:
    y' = c_y y + c_z z with (c_y, c_z) an eigenvector of [[I1, I12], [I12, I2]]."""
    lam, vec = np.linalg.eigh(np.array([[I1, I12], [I12, I2]]))
    c = vec[:, 1]
    out = []
    for a, b, v in MEMBERS:
        x = np.subtract(GRIDS[b], GRIDS[a])
        x = x / np.linalg.norm(x)
        y = np.asarray(v) - (np.asarray(v) @ x) * x
        y = y / np.linalg.norm(y)
        out.append(c[0] * y + c[1] * np.cross(x, y))
    return lam[1], lam[0], out


@pytest.mark.parametrize("element, card", [("CBAR", "PBAR"), ("CBEAM", "PBEAM")])
def test_i12_is_the_principal_section(tmp_path, element, card):
    """A space frame whose members have I12 != 0 against the same frame with the
    section's principal moments and each orientation vector turned onto the principal
    axis (the bending energy is E int (I1 v''^2 + 2 I12 v'' w'' + I2 w''^2), I12 =
    int y z dA, as NASTRAN-95's KBAR; the CBEAM's torsional inertia rho (I1 + I2) is the
    tensor's trace). Both are exact, so they agree to round-off (1e-9). A frame with
    I12 of the other sign differs by more than 1 %: the test sees the sign."""
    p1, p2, turned = _principal()
    if card == "PBAR":
        given = f"PBAR,1,1,{A!r},{I1!r},{I2!r},{J!r}\n,,,,,,,,\n,,,{I12!r}"
        principal = f"PBAR,1,1,{A!r},{p1!r},{p2!r},{J!r}"
        flipped = given.replace(f",,,{I12!r}", f",,,{-I12!r}")
    else:
        rigid = "\n,,,,,,,,\n,0.,0."  # K1 = K2 = 0: shear-rigid, as PBAR's blank
        given = f"PBEAM,1,1,{A!r},{I1!r},{I2!r},{I12!r},{J!r}" + rigid
        principal = f"PBEAM,1,1,{A!r},{p1!r},{p2!r},,{J!r}" + rigid
        flipped = given.replace(f",{I12!r},", f",{-I12!r},")
    vectors = [v for _, _, v in MEMBERS]
    hz = _hz(tmp_path, _deck(element, given, vectors))
    np.testing.assert_allclose(hz, _hz(tmp_path, _deck(element, principal, turned)), rtol=1e-9)
    assert np.max(np.abs(_hz(tmp_path, _deck(element, flipped, vectors)) / hz - 1)) > 0.01


def test_i12_ignores_shear_factors(tmp_path):
    """NASTRAN ignores K1, K2 when I12 != 0 (QRG PBAR remark; NASTRAN-95 KBAR): the
    same frequencies with and without K1 = K2 = 0.85."""
    base = f"PBAR,1,1,{A!r},{I1!r},{I2!r},{J!r}\n,,,,,,,,\n,,,{I12!r}"
    vectors = [v for _, _, v in MEMBERS]
    np.testing.assert_allclose(
        _hz(tmp_path, _deck("CBAR", base.replace("\n,,,", "\n,0.85,0.85,"), vectors)),
        _hz(tmp_path, _deck("CBAR", base, vectors)), rtol=1e-12)


@pytest.mark.parametrize("prop, message", [
    (f"PBAR,1,1,{A!r},{I1!r},{I2!r},{J!r}\n,,,,,,,,\n,,,2.e-9", "I12 = 2e-09 needs I1 I2 > "
     "I12^2"),
    (f"PBEAM,1,1,{A!r},{I1!r},{I2!r},{I12!r},{J!r}", "PBEAM 1: I12 = 8e-10 with shear factors "
     "K1 = 1, K2 = 1 (PBEAM's default 1.0) is not supported"),
])
def test_i12_refusals(tmp_path, prop, message):
    """An inertia tensor that is not positive definite is named; so is a PBEAM I12 with
    shear factors (NASTRAN's rule to ignore them is stated for PBAR only)."""
    path = tmp_path / "frame.bdf"
    element = "CBEAM" if prop.startswith("PBEAM") else "CBAR"
    path.write_text(_deck(element, prop, [v for _, _, v in MEMBERS]))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(InputError, match=re.escape(message)):
            read_nastran(path)


def test_material_parameter_with_i12(tmp_path):
    """MAT1 E is a parameter of a frame with I12: K is E times a fixed matrix (G follows
    E, MAT1 G blank), so dK/dE = K / E exactly, coupling included (to round-off)."""
    from eigenupdate.io.nastran import CardField
    from eigenupdate.model.parameters import Parameter

    path = tmp_path / "frame.bdf"
    path.write_text(_deck("CBAR", f"PBAR,1,1,{A!r},{I1!r},{I2!r},{J!r}\n,,,,,,,,\n,,,{I12!r}",
                          [v for _, _, v in MEMBERS]))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = read_nastran(path, [(Parameter("E", 0.0), CardField("MAT1", 1, "E"))]).model
    k, kj = model.stiffness(), model.k_terms[0]
    assert abs(kj * 2.0e11 - k).max() <= 1e-12 * abs(k).max()
