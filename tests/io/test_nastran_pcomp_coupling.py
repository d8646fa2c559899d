"""Unsymmetric PCOMP (membrane-bending coupling B) read from a deck: the antisymmetric
cross-ply plate against the same elements built directly and against the Navier
solution of laminate theory with coupling, MAT1 E of an offset one-material laminate as
a parameter (finite differences of re-read decks), and the refusal of ply thickness
parameters (CQUAD8/CTRIA6: test_nastran_quadratic_coupling.py). Runs in .venv-nastran
(pyNastran)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from bounds import EPS
from laminate_plates import E1, E2, G12, G13, G23, NU12, RHO, fe_plate, navier_coupled, stack
from nastran_frames import need
from plates import square_mesh

from eigenupdate.errors import EigenupdateWarning, InputError
from eigenupdate.model.parameters import Parameter
from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.io.nastran import CardField, read_nastran  # noqa: E402

MAT8 = f"MAT8,2,{E1!r},{E2!r},{NU12!r},{G12!r},{G13!r},{G23!r},{RHO!r}\n"
A, H = 1.0, 0.01  # a/h = 100


def _read(path, specs=()):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EigenupdateWarning)
        return read_nastran(path, specs)


def s2_plate(nx: int, prop: str, triangles: bool = False) -> str:
    """An A x A plate of property 1 with the S2 support of ``navier_coupled``: w on every
    edge, v and rx on x = 0, A; u and ry on y = 0, A (coupled mass). CTRIA3 take MCID 0
    (material x along basic x; their G1-G2 sides differ)."""
    xyz, el = square_mesh(nx, A, triangles)
    lines = [f"GRID,{i + 1},,{x!r},{y!r},0." for i, (x, y, _) in enumerate(xyz)]
    card, mcid = ("CTRIA3", ",0") if triangles else ("CQUAD4", "")
    lines += [f"{card},{k + 1},1," + ",".join(str(n + 1) for n in e) + mcid
              for k, e in enumerate(el)]
    for i, (x, y, _) in enumerate(xyz):
        on_x, on_y = min(x, A - x) < 1e-12, min(y, A - y) < 1e-12
        c = "".join(sorted(set(("243" if on_x else "") + ("153" if on_y else ""))))
        if c:
            lines.append(f"SPC1,1,{c},{i + 1}")
    return "BEGIN BULK\nPARAM,COUPMASS,1\n" + prop + "\n".join(lines) + "\nENDDATA\n"


def _first(tmp_path, text, name="plate.bdf"):
    path = tmp_path / name
    path.write_text(text)
    m = _read(path).model
    return float(solve_elastic(m.stiffness(), m.mass(), 1).frequencies_hz[0])


CROSS_PLY = f"PCOMP,1\n,2,{H / 2!r},0.,,2,{H / 2!r},90.\n" + MAT8


@pytest.mark.parametrize("triangles", [False, True], ids=["CQUAD4", "CTRIA3"])
def test_unsymmetric_pcomp_deck_is_the_direct_model_and_converges_to_navier(tmp_path,
                                                                           triangles):
    """Source: (1) the same elements built directly (tests/laminate_plates.py, no deck):
    equal to the eigen-solvers' rounding (1e-9 with room); (2) the Navier solution of
    the antisymmetric [0/90] plate with coupling (Whitney 1987, sec. 5.4; first-order
    shear deformation theory with the elements' H), meshes 8 and 16: bilinear elements'
    h^2 error puts the 16-mesh's within the change from 8 to 16 (a third of it; room 3);
    B = 0 would give 57 % more, far outside."""
    f8, f16 = (_first(tmp_path, s2_plate(n, CROSS_PLY, triangles)) for n in (8, 16))
    direct = fe_plate(8, A, (0.0, 90.0), H / 2, RHO * H, triangles) / (2 * np.pi)
    assert abs(f8 / direct - 1) <= 1e-9, (f8, direct)
    abdh = stack((0.0, 90.0), H / 2)
    exact = navier_coupled(A, abdh, RHO * H) / (2 * np.pi)
    assert abs(f16 - exact) <= abs(f16 - f8), (f8, f16, exact)
    uncoupled = navier_coupled(A, (abdh[0], 0 * abdh[1], abdh[2], abdh[3]), RHO * H)
    assert uncoupled / (2 * np.pi) > 1.5 * exact


def _offset_deck(e: float) -> str:
    """One MAT1 ply from the grids' plane up (Z0 = 0): B = Q T^2 / 2 about the grids
    (read as the ply offset by T/2, model/shell_offsets.py)."""
    return s2_plate(4, f"PCOMP,1,0.\n,3,{H!r},0.\nMAT1,3,{e!r},,.3,7850.\n")


def test_mat1_e_of_an_offset_pcomp_is_a_parameter(tmp_path):
    """Source: finite differences of the assembled K with E changed in the file's text.
    A one-material laminate's A, B, D are all proportional to E, so K_E = K / E exactly
    (coupling part included); the bound is the two assemblies' rounding, 1e4 eps |K| / h
    as for the other MAT1 parameters."""
    e0 = 2.0e11
    path = tmp_path / "a.bdf"
    path.write_text(_offset_deck(e0))
    nm = _read(path, [(Parameter("p", 0.0), CardField("MAT1", 3, "E"))]).model
    base = _read(path).model.stiffness()
    bumped = tmp_path / "b.bdf"
    bumped.write_text(_offset_deck(1.25 * e0))
    fd = ((_read(bumped).model.stiffness() - base) / (0.25 * e0)).toarray()
    assert np.max(np.abs(fd - nm.k_terms[0].toarray())) <= 1e4 * EPS * abs(base).max() / (
        0.25 * e0)
    # the coupling is in the terms: the symmetric ply (Z0 blank) gives another K_E
    path.write_text(s2_plate(4, f"PCOMP,1\n,3,{H!r},0.\nMAT1,3,{e0!r},,.3,7850.\n"))
    sym = _read(path, [(Parameter("p", 0.0), CardField("MAT1", 3, "E"))]).model
    assert abs(sym.k_terms[0] - nm.k_terms[0]).max() > 1e-3 * abs(nm.k_terms[0]).max()


def test_ply_thickness_of_an_unsymmetric_pcomp_is_refused(tmp_path):
    """One line naming the card and what is not supported."""
    path = tmp_path / "t.bdf"
    path.write_text(s2_plate(2, CROSS_PLY))
    with pytest.raises(InputError, match="PCOMP 1: membrane-bending coupling .* with a ply "
                                         "thickness parameter"):
        _read(path, [(Parameter("t", 0.0), CardField("PCOMP", 1, "T1"))])
