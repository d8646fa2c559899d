"""PSHELL with MAT8 (orthotropic) MID1/MID2/MID3 and MAT8 with G1Z/G2Z blank (MSC QRG
PSHELL, MAT8: membrane T Q, bending (12I/T^3) T^3 / 12 Q, transverse shear (TS/T) T
diag(G1Z, G2Z) in the element's material axes THETA/MCID; a blank G1Z/G2Z is an
infinite transverse shear modulus, read as PSHELL MID3 blank, shear-rigid).

Independent references: the MAT1 deck (an isotropic MAT8), the one-ply PCOMP of the
same MAT8 (classical laminate theory's path, 12I/T^3 = 1 and TS/T = 5/6), the closed
forms of a simply supported specially orthotropic plate (Kirchhoff: Navier with D11,
D12, D22, D66; first-order shear deformation: Whitney's), decks re-read with changed
values. Runs in .venv-nastran (pyNastran)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from bounds import assert_matrix_derivatives
from laminate_plates import E1, E2, G12, G13, G23, NU12, RHO, navier_coupled
from nastran_frames import need

from eigenupdate.errors import EigenupdateWarning, InputError
from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")
from plates import card_specs  # noqa: E402
from test_nastran_pcompg import MESH  # noqa: E402

from eigenupdate.io.nastran import read_nastran  # noqa: E402

E, NU = 7.0e10, 0.33
G = E / (2 * (1 + NU))
T = 0.0012


def _read(path, specs=()):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EigenupdateWarning)
        return read_nastran(path, specs)


def _mesh(tmp_path, name, prop):
    """The free mixed CQUAD4 (THETA 15 degrees)/CTRIA3 warped plate of test_nastran_pcompg
    with property 7 ``prop``."""
    path = tmp_path / name
    path.write_text(MESH.replace("{prop}", prop))
    return _read(path).model


def _same(a, b, rtol=1e-12):
    """K and M equal to a few ulps of the largest entry: the same element matrices from
    moduli that agree to rounding (formed, and turned by THETA, in another order)."""
    for x, y in ((a.stiffness(), b.stiffness()), (a.mass(), b.mass())):
        assert abs(x - y).max() <= rtol * abs(y).max(), abs(x - y).max() / abs(y).max()
    assert abs(a.stiffness()).max() > 0


ISO8 = f"MAT8,5,{E!r},{E!r},{NU!r},{G!r},{G!r},{G!r},2700.\n"
ISO1 = f"MAT1,6,{E!r},,{NU!r},2700.\n"


@pytest.mark.parametrize("mid3", ["5", ""], ids=["MID3", "shear-rigid"])
def test_isotropic_mat8_is_the_mat1_deck(tmp_path, mid3):
    """Source: the MAT1 deck. A MAT8 with E1 = E2 = E, G12 = G1Z = G2Z = E / (2 (1 + NU))
    is MAT1's shell (E, NU for membrane and bending, G for shear) in any material axes
    (the CQUAD4 carry THETA 15); with MID3 blank both are shear-rigid alike."""
    a = _mesh(tmp_path, "mat8.bdf", f"PSHELL,7,5,{T!r},5,,{mid3}\n" + ISO8)
    b = _mesh(tmp_path, "mat1.bdf", f"PSHELL,7,6,{T!r},6,,{mid3 and '6'}\n" + ISO1)
    _same(a, b)


MAT8 = f"MAT8,8,{E1!r},{E2!r},{NU12!r},{G12!r},{G13!r},{G23!r},{RHO!r}\n"
BLANK8 = f"MAT8,8,{E1!r},{E2!r},{NU12!r},{G12!r},,,{RHO!r}\n"


@pytest.mark.parametrize("pshell, pcomp, mat", [
    (f"PSHELL,7,8,{T!r},8,,8", f"PCOMP,7\n,8,{T!r},0.", MAT8),
    (f"PSHELL,7,8,{T!r},8", f"PCOMP,7\n,8,{T!r},0.", BLANK8),
    (f"PSHELL,7,8,{T!r},8,,8", f"PCOMP,7\n,8,{T!r},0.", BLANK8),
], ids=["G1Z-G2Z", "MID3-blank", "G1Z-G2Z-blank"])
def test_pshell_mat8_is_the_one_ply_pcomp(tmp_path, pshell, pcomp, mat):
    """Source: classical laminate theory's path (the PCOMP reader, model/laminate.py):
    one ply of the MAT8 at 0 degrees is the PSHELL of that MAT8 with 12I/T^3 = 1 and
    TS/T = 5/6, in the elements' material axes (THETA 15 on the CQUAD4). With G1Z/G2Z
    blank (MSC: infinite) the ply is shear-rigid as a PSHELL with MID3 blank, or with
    MID3 naming that MAT8."""
    _same(_mesh(tmp_path, "pshell.bdf", pshell + "\n" + mat),
          _mesh(tmp_path, "pcomp.bdf", pcomp + "\n" + mat))


def test_some_blank_plies_are_refused(tmp_path):
    """A PCOMP with G1Z/G2Z blank on some plies only (MSC's rule for such a stack is not
    documented): refused, naming the ply and the material."""
    prop = f"PCOMP,7\n,8,{T!r},0.,,9,{T!r},90.\n" + BLANK8 + MAT8.replace("MAT8,8", "MAT8,9")
    with pytest.raises(InputError, match=r"PCOMP 7: ply 1's MAT8 8 leaves G1Z/G2Z blank"):
        _mesh(tmp_path, "mixed.bdf", prop)


A, B = 1.0, 0.5  # a rectangle: turning the material by 90 degrees changes its modes


def _rectangle(nx: int, prop: str, axis: str = "", a: float = A, b: float = B) -> str:
    """An a x b plate of nx x nx b / a CQUAD4 (material axis ``axis``: THETA or MCID),
    simply supported (S2: w on every edge, v and rx on x = 0, a; u and ry on y = 0, b)."""
    ny = round(nx * b / a)
    lines = [f"GRID,{1 + i + (nx + 1) * j},,{a * i / nx!r},{b * j / ny!r},0."
             for j in range(ny + 1) for i in range(nx + 1)]
    lines += [f"CQUAD4,{1 + i + nx * j},1,{1 + i + (nx + 1) * j},{2 + i + (nx + 1) * j},"
              f"{2 + i + (nx + 1) * (j + 1)},{1 + i + (nx + 1) * (j + 1)}{axis}"
              for j in range(ny) for i in range(nx)]
    for j in range(ny + 1):
        for i in range(nx + 1):
            c = "".join(sorted(set(("243" if i in (0, nx) else "")
                                   + ("153" if j in (0, ny) else ""))))
            if c:
                lines.append(f"SPC1,1,{c},{1 + i + (nx + 1) * j}")
    return ("BEGIN BULK\nPARAM,COUPMASS,1\nCORD2R,5,,0.,0.,0.,0.,0.,1.\n,0.,1.,0.\n" + prop
            + "\n".join(lines) + "\nENDDATA\n")


def _first(tmp_path, text) -> float:
    path = tmp_path / "plate.bdf"
    path.write_text(text)
    m = _read(path).model
    return float(solve_elastic(m.stiffness(), m.mass(), 1).frequencies_hz[0])


def _d(h: float, turned: bool) -> tuple[float, float, float, float]:
    """D11, D12, D22, D66 of the MAT8 plate (Jones 1999, eq. 2.61 and 4.28), material 1
    along x or, ``turned``, along y."""
    nu21 = NU12 * E2 / E1
    f = h**3 / 12 / (1 - NU12 * nu21)
    d11, d22 = E1 * f, E2 * f
    return (d22, NU12 * E2 * f, d11, G12 * h**3 / 12) if turned else (
        d11, NU12 * E2 * f, d22, G12 * h**3 / 12)


@pytest.mark.parametrize("axis, turned", [("", False), (",90.", True), (",5", True)],
                         ids=["THETA-0", "THETA-90", "MCID"])
def test_shear_rigid_orthotropic_plate_converges_to_navier(tmp_path, axis, turned):
    """Source: Navier's solution for a simply supported specially orthotropic Kirchhoff
    plate (Jones 1999, sec. 5.5; Whitney 1987): omega_11^2 = pi^4 (D11 / a^4 + 2 (D12 +
    2 D66) / (a b)^2 + D22 / b^4) / (rho h). MID3 blank (shear-rigid) at a/h = 100;
    THETA 90 and a rectangular MCID whose x axis is basic y turn material 1 along y.
    Meshes 8 and 16 along a: the bilinear elements' h^2 error puts the 16-mesh within
    the change from 8 to 16 of the closed form (a third of it; room 3); the other
    orientation's value (2.8 times lower or higher) far outside."""
    h = A / 100
    prop = f"PSHELL,1,8,{h!r},8\n" + MAT8
    f8, f16 = (_first(tmp_path, _rectangle(n, prop, axis)) for n in (8, 16))

    def navier(turned):
        d11, d12, d22, d66 = _d(h, turned)
        w2 = np.pi**4 * (d11 / A**4 + 2 * (d12 + 2 * d66) / (A * B)**2 + d22 / B**4)
        return float(np.sqrt(w2 / (RHO * h))) / (2 * np.pi)

    exact, other = navier(turned), navier(not turned)
    assert abs(f16 - exact) <= abs(f16 - f8), (f8, f16, exact)
    assert abs(other / exact - 1) > 0.5 and abs(f16 - other) > 10 * abs(f16 - f8)


def test_orthotropic_transverse_shear_converges_to_fsdt_navier(tmp_path):
    """Source: the Navier solution of first-order shear deformation theory for the
    simply supported specially orthotropic square plate (Whitney 1987, sec. 5.4; the
    coupled one of tests/laminate_plates.py with B = 0), A = h Q, D = h^3 Q / 12,
    H = (5/6) h diag(G1Z, G2Z) by hand. a/h = 10, where G2Z is 125 times below E1 and
    the shear lowers the frequency by 18 %: the 16-mesh within the change from 8 to 16
    (as above), the shear-rigid plate's value more than 3 times that change away."""
    h = A / 10
    prop = f"PSHELL,1,8,{h!r},8,,8\n" + MAT8
    f8, f16 = (_first(tmp_path, _rectangle(n, prop, "", A, A)) for n in (8, 16))
    nu21 = NU12 * E2 / E1
    q = np.array([[E1, NU12 * E2, 0], [NU12 * E2, E2, 0], [0, 0, 0]]) / (1 - NU12 * nu21)
    q[2, 2] = G12
    H = 5 / 6 * h * np.diag([G13, G23])
    exact = navier_coupled(A, ((h * q)[None], np.zeros((1, 3, 3)), (h**3 / 12 * q)[None],
                               H[None]), RHO * h) / (2 * np.pi)
    rigid = navier_coupled(A, ((h * q)[None], np.zeros((1, 3, 3)), (h**3 / 12 * q)[None],
                               1e6 * H[None]), RHO * h) / (2 * np.pi)
    assert abs(f16 - exact) <= abs(f16 - f8), (f8, f16, exact)
    assert rigid > 1.2 * exact and abs(f16 - rigid) > 3 * abs(f16 - f8), (f16, rigid)


MIXED = (f"PSHELL,7,9,{T!r},8,,8\n" + MAT8 + f"MAT1,9,{E!r},,{NU!r},2700.\n")
FIELDS = [("t", "PSHELL", 7, "T"), ("E", "MAT1", 9, "E"), ("rho", "MAT1", 9, "RHO")]


def test_mixed_mat1_mat8_parameters_are_the_re_read_deck(tmp_path):
    """Source: the deck with T, MAT1 E and RHO changed in its text and read again, and
    central differences (tests/bounds.py). MID1 a MAT1 (membrane, mass), MID2/MID3 a
    MAT8: T scales membrane (T), bending (T^3, the MAT8's moduli) and shear; E only the
    membrane, RHO the mass."""
    path = tmp_path / "p.bdf"
    path.write_text(MESH.replace("{prop}", MIXED))
    model = _read(path, card_specs(FIELDS)).model
    new = np.array([1.1 * T, 0.93 * E, 1.05 * 2700.0])
    edited = MIXED.replace(f"{T!r}", f"{new[0]!r}").replace(f"{E!r}", f"{new[1]!r}")
    ref = _mesh(tmp_path, "q.bdf", edited.replace("2700.", f"{new[2]!r}"))
    for a, b in ((model.stiffness(new), ref.stiffness()), (model.mass(new), ref.mass())):
        assert abs(a - b).max() <= 1e-12 * abs(b).max()
    assert_matrix_derivatives(model)


def test_mat8_moduli_of_a_pshell_are_not_parameters(tmp_path):
    """A PSHELL's MAT8 moduli as parameters are refused (they are parameters as PCOMP
    plies only: tests/io/test_nastran_mat8_parameters.py), naming the card."""
    path = tmp_path / "p.bdf"
    path.write_text(MESH.replace("{prop}", f"PSHELL,7,8,{T!r},8,,8\n" + MAT8))
    with pytest.raises(InputError, match="MAT8 8 field E1: not a parameter as PSHELL 7's "
                                         "MID1/MID2/MID3"):
        _read(path, card_specs([("e1", "MAT8", 8, "E1")]))
