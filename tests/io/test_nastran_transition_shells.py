"""CQUAD8 and CTRIA6 with blank mid-side grids read from a deck (transition elements,
model/shells_transition.py). Independent references: the model-level elements on the
same mesh; exact invariance of a free plate under ZOFFS; central differences of K, M and
the deck edited by hand for PSHELL T, MAT1 E, RHO and a PCOMP ply thickness. NASTRAN's
own frequencies (NX's trncomp12, CQUAD8/CTRIA6 with blanks beside CQUADR/CTRIAR) are in
the branch's report, not here: the deck is not in the repository. Runs in .venv-nastran
(pyNastran)."""

from __future__ import annotations

import numpy as np
import pytest
import quadratic_meshes as qm
from bounds import assert_matrix_derivatives
from nastran_frames import need
from plates import plate_fixed
from quadratic_meshes import drop_mid_sides, plate_mesh
from quadratic_meshes import transition_plate_frequency as _plate

from eigenupdate.errors import InputError
from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")
from test_nastran_offsets import PSHELL, RHO, STEEL, H, _read  # noqa: E402
from test_nastran_quadratic_offsets import _rigid  # noqa: E402


def deck(path, nx, z=0.0, prop=PSHELL, triangles=False, spc="", which="half"):
    """A unit plate of nx x nx CQUAD8 (2 nx x nx CTRIA6), mid-side grids ``which``
    (quadratic_meshes.drop_mid_sides) left blank on the cards and not defined, ZOFFS ``z``;
    ``spc`` "ss" (plates.plate_fixed) or "" (free). Returns the path and the kept
    grids' indices."""
    xyz, el = plate_mesh(nx, 1.0, 1.0, triangles)
    _, gone = drop_mid_sides(xyz, el, which)
    keep = np.setdiff1d(np.arange(len(xyz)), gone)
    lines = [f"GRID,{i + 1},,{float(xyz[i, 0])!r},{float(xyz[i, 1])!r},0." for i in keep]
    for k, e in enumerate(el):
        g = ["" if n in gone else str(n + 1) for n in e]
        if triangles:
            lines.append(f"CTRIA6,{k + 1},1," + ",".join(g) + (f"\n,,{z!r}" if z else ""))
        else:
            lines.append(f"CQUAD8,{k + 1},1," + ",".join(g[:6]) + "\n," + ",".join(g[6:])
                         + (f",,,,,,{z!r}" if z else ""))
    if spc == "ss":
        fixed = plate_fixed(xyz, 1.0, "ss")
        for i in keep:
            lines.append(f"SPC1,1,{''.join(str(c + 1) for c in range(6) if fixed[i, c])},"
                         f"{i + 1}")
    path.write_text("BEGIN BULK\nPARAM,COUPMASS,1\n" + prop + "\n".join(lines)
                    + "\nENDDATA\n")
    return path, keep


@pytest.mark.parametrize("triangles", [False, True], ids=["CQUAD8", "CTRIA6"])
def test_deck_with_blank_mid_side_grids_is_the_transition_element(tmp_path, triangles):
    """Source: the model-level transition elements on the same mesh and supports
    (quadratic_meshes.transition_plate_frequency: full for x < 1/2, linear beyond,
    transition between), PSHELL without NSM: the deck's blank fields must give the same
    lowest frequency to the eigen-solvers' agreement (1e-9 relative)."""
    steel = f"MAT1,1,{qm.E!r},,{qm.NU!r},{qm.RHO!r}\n"  # the model-level elements' steel
    path, _ = deck(tmp_path / "p.bdf", 4, prop=f"PSHELL,1,1,{H!r},1,,1,{5 / 6!r}\n" + steel,
                   triangles=triangles, spc="ss")
    m = _read(path).model
    f = solve_elastic(m.stiffness(), m.mass(), 1).frequencies_hz[0]
    assert f == pytest.approx(_plate(4, H, triangles, "half") / (2 * np.pi), rel=1e-9)


@pytest.mark.parametrize("triangles", [False, True], ids=["CQUAD8", "CTRIA6"])
def test_free_offset_transition_plate_keeps_its_rigid_modes_and_frequencies(tmp_path,
                                                                            triangles):
    """Source: exact invariance (as test_nastran_quadratic_offsets'): the offset plate's
    K and M are the plate's without offset under an invertible rigid link, so free it
    keeps its ten lowest frequencies to the eigen-solver's rounding (1e-9), six rigid
    modes, and K annihilates the rigid motions of its grids to 1e-10 of |K|. Mid-side
    grids blank at random (every pattern), ZOFFS T/2."""
    plain = solve_elastic(*(lambda m: (m.stiffness(), m.mass()))(_read(deck(
        tmp_path / "a.bdf", 4, triangles=triangles, which="random")[0]).model), 10)
    path, keep = deck(tmp_path / "b.bdf", 4, H / 2, triangles=triangles, which="random")
    m = _read(path).model
    sol = solve_elastic(m.stiffness(), m.mass(), 10)
    assert sol.n_rigid == plain.n_rigid == 6
    assert np.max(np.abs(sol.frequencies_hz / plain.frequencies_hz - 1)) <= 1e-9
    K = m.stiffness().toarray()
    xyz, _ = plate_mesh(4, 1.0, 1.0, triangles)
    assert np.abs(K @ _rigid(xyz[keep])).max() <= 1e-10 * np.abs(K).max()


FIELDS = [("PSHELL", 1, "T"), ("MAT1", 1, "E"), ("MAT1", 1, "RHO")]
PCOMP = f"PCOMP,1,,0.4\n,1,{H / 2!r},30.,,1,{H / 2!r},-30.\n" + STEEL


@pytest.mark.parametrize("triangles", [False, True], ids=["CQUAD8", "CTRIA6"])
@pytest.mark.parametrize("prop", ["PSHELL", "PCOMP"])
def test_parameters_of_offset_transition_elements(tmp_path, triangles, prop):
    """Sources: central differences of K, M (tests/bounds.py; a thickness enters K
    nonlinearly), and the deck with the parameters' values written in its text and read
    again (the same integrals: 1e-12 of the largest entry). PSHELL T, MAT1 E, RHO; a
    PCOMP's first ply thickness T1 (alone: not allowed with its plies' MAT1 fields).
    ZOFFS T/2, mid-side grids blank at random."""
    fields = FIELDS if prop == "PSHELL" else [("PCOMP", 1, "T1")]
    text = PSHELL if prop == "PSHELL" else PCOMP
    path, _ = deck(tmp_path / "a.bdf", 3, H / 2, text, triangles, "ss", "random")
    nm = _read(path, fields)
    assert_matrix_derivatives(nm.model)
    new = [1.1 * H, 1.05 * 2.1e11, 1.2 * RHO] if prop == "PSHELL" else [0.55 * H]
    mat = f"MAT1,1,{new[1]!r},,0.3,{new[2]!r}\n" if prop == "PSHELL" else STEEL
    edited = (f"PSHELL,1,1,{new[0]!r},1,,1,,0.7\n" + mat if prop == "PSHELL" else
              f"PCOMP,1,,0.4\n,1,{new[0]!r},30.,,1,{H / 2!r},-30.\n" + mat)
    assert STEEL == f"MAT1,1,{2.1e11!r},,0.3,{RHO!r}\n"  # the edit above is of this card
    ref = _read(deck(tmp_path / "b.bdf", 3, H / 2, edited, triangles, "ss", "random")[0]).model
    for a, b in ((nm.model.stiffness(new), ref.stiffness()), (nm.model.mass(new), ref.mass())):
        assert abs(a - b).max() <= 1e-12 * abs(b).max()


def test_blank_corner_grid_is_refused(tmp_path):
    """One line naming the file, line, element and field: only mid-side grids may be
    blank (pyNastran's own check of the card, located by the reader)."""
    path, _ = deck(tmp_path / "a.bdf", 1, which="none")
    text = path.read_text().replace("CQUAD8,1,1,1,", "CQUAD8,1,1,,")
    path.write_text(text)
    with pytest.raises(InputError, match=r"a\.bdf: line \d+: CQUAD8 1: .*field #3.*not blank"):
        _read(path)
