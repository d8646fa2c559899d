"""PCOMP membrane-bending coupling and Z0 != -T/2 on CQUAD8 and CTRIA6 read from decks
(model/shells_quadratic.py local_parts with coupling; the mass off the reference
surface: model/shells_quadratic_mass.py). Independent references: the Navier solution
of the antisymmetric [0/90] plate with coupling and CQUAD4 converging to it on the same
problem; a free plate whose stack lies on its grids (Z0 = 0) is the same plate with
ZOFFS = T/2 and keeps the frequencies of the plate without offset; the rigid-body mass
of an unsymmetric two-material stack by hand; central differences of K, M and the deck
edited by hand. Runs in .venv-nastran (pyNastran)."""

from __future__ import annotations

import numpy as np
import pytest
from bounds import assert_matrix_derivatives
from laminate_plates import E1, E2, G12, G13, G23, NU12, RHO, fe_plate, navier_coupled, stack
from nastran_frames import assert_hand_edited_deck, need
from quadratic_meshes import plate_mesh

from eigenupdate.errors import InputError
from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")
from test_nastran_offsets import _read  # noqa: E402
from test_nastran_quadratic_offsets import _rigid  # noqa: E402

H = 0.01  # a/h = 100 on the unit plate
MAT8 = f"MAT8,2,{E1!r},{E2!r},{NU12!r},{G12!r},{G13!r},{G23!r},{RHO!r}\n"
CROSS_PLY = f"PCOMP,1\n,2,{H / 2!r},0.,,2,{H / 2!r},90.\n" + MAT8
STEEL = "MAT1,3,2.1e11,,.3,7850.\n"
ALUMINIUM = "MAT1,4,7.e10,,.33,2700.\n"


def _element(k, g, triangles, z=0.0):
    """CQUAD8 or CTRIA6 card with MCID 0 (material x along basic x) and ZOFFS z."""
    g = [str(n) for n in g]
    zo = f",{z!r}" if z else ""
    if triangles:
        return f"CTRIA6,{k},1," + ",".join(g) + "\n,0" + zo
    return f"CQUAD8,{k},1," + ",".join(g[:6]) + "\n," + ",".join(g[6:]) + ",,,,,0" + zo


def deck(path, nx, prop, triangles=False, s2=False, z=0.0):
    """A unit plate of nx x nx CQUAD8 (2 nx x nx CTRIA6) of property 1, coupled mass;
    ``s2``: laminate_plates.navier_coupled's support (w on the edges, v and rx on x = 0,
    1, u and ry on y = 0, 1), else free."""
    xyz, el = plate_mesh(nx, 1.0, 1.0, triangles)
    lines = [f"GRID,{i + 1},,{float(x)!r},{float(y)!r},0." for i, (x, y, _) in enumerate(xyz)]
    lines += [_element(k + 1, e + 1, triangles, z) for k, e in enumerate(el)]
    for i, (x, y, _) in enumerate(xyz):
        on_x, on_y = min(x, 1 - x) < 1e-12, min(y, 1 - y) < 1e-12
        c = ("243" if on_x else "") + ("153" if on_y else "") if s2 else ""
        if c:
            lines.append(f"SPC1,1,{''.join(sorted(set(c)))},{i + 1}")
    path.write_text("BEGIN BULK\nPARAM,COUPMASS,1\n" + prop + "\n".join(lines)
                    + "\nENDDATA\n")
    return path


def _hz(path, count=1):
    m = _read(path).model
    return solve_elastic(m.stiffness(), m.mass(), count).frequencies_hz


@pytest.mark.parametrize(("triangles", "meshes"), [(False, (4, 8)), (True, (8, 16))],
                         ids=["CQUAD8", "CTRIA6"])
def test_antisymmetric_cross_ply_converges_to_navier_with_coupling(tmp_path, triangles,
                                                                   meshes):
    """Source: the Navier solution of the simply supported antisymmetric [0/90] plate
    with coupling (Whitney 1987 sec. 5.4; laminate_plates.navier_coupled, the CQUAD4
    test's numbers), a/h = 100. The finer mesh's error is below its change from the
    coarser (measured: CQUAD8 +0.33 %, +0.021 % at 4, 8, the fourth power; CTRIA6
    +0.68 %, +0.072 % at 8, 16, its stabilisation scaled by the coupled section's
    bending, D - B A^-1 B: -0.27, -0.09 % without). Leaving B out is 57 % high (the
    CQUAD4 test), far outside. Convergence with CQUAD4 on the same problem: CQUAD4 at 8
    and 16 (-1.8, -0.46 %), extrapolated as h^2, lies within a third of its own change
    of CQUAD8's."""
    exact = navier_coupled(1.0, stack((0.0, 90.0), H / 2), RHO * H) / (2 * np.pi)
    coarse, fine = (_hz(deck(tmp_path / f"p{n}.bdf", n, CROSS_PLY, triangles, s2=True))[0]
                    for n in meshes)
    assert abs(fine - exact) <= abs(fine - coarse), (coarse, fine, exact)
    if not triangles:
        q8, q16 = (fe_plate(n, 1.0, (0.0, 90.0), H / 2, RHO * H, False) / (2 * np.pi)
                   for n in (8, 16))
        richardson = q16 + (q16 - q8) / 3
        assert abs(richardson - fine) <= abs(q16 - q8) / 3, (q8, q16, fine)


@pytest.mark.parametrize("ply", [f",3,{H!r},0.\n" + STEEL, CROSS_PLY.split("\n", 1)[1]],
                         ids=["steel", "[0/90]"])
@pytest.mark.parametrize("triangles", [False, True], ids=["CQUAD8", "CTRIA6"])
def test_stack_on_its_grids_is_the_zoffs_plate(tmp_path, triangles, ply):
    """Source: NASTRAN's Z0 (the stack's bottom at Z0 above the reference plane) and
    ZOFFS describe the same plate: a stack with Z0 = 0 is the stack with Z0 blank and
    ZOFFS = T/2 (K and M to 1e-12 of the largest entry: two paths, the stack's shift
    and the element's offset, the mass's moments against the offset surface's mass; the
    [0/90] stack with its coupling too), and free it keeps the frequencies of the plate
    without offset (exact invariance under the rigid link; 1e-9 for the eigen-solver)
    and six rigid modes."""
    shifted = _read(deck(tmp_path / "a.bdf", 3, "PCOMP,1,0.\n" + ply, triangles)).model
    zoffs = _read(deck(tmp_path / "b.bdf", 3, "PCOMP,1\n" + ply, triangles, z=H / 2)).model
    for a, b in ((shifted.stiffness(), zoffs.stiffness()), (shifted.mass(), zoffs.mass())):
        assert abs(a - b).max() <= 1e-12 * abs(b).max()
    plain = _hz(deck(tmp_path / "c.bdf", 3, "PCOMP,1\n" + ply, triangles), 10)
    sol = solve_elastic(shifted.stiffness(), shifted.mass(), 10)
    assert sol.n_rigid == 6
    assert np.max(np.abs(sol.frequencies_hz / plain - 1)) <= 1e-9


@pytest.mark.parametrize("coupmass", ["1", "-1"], ids=["coupled", "lumped"])
@pytest.mark.parametrize("triangles", [False, True], ids=["CQUAD8", "CTRIA6"])
def test_unsymmetric_stack_mass_has_its_first_moment(tmp_path, triangles, coupmass):
    """Source: rigid-body statics by hand. A 4 mm steel ply under a 6 mm aluminium one
    (Z0 blank: from -5 mm) has m = 7850 x 0.004 + 2700 x 0.006 and first moment
    7850 x 0.004 x (-0.003) + 2700 x 0.006 x 0.002 per area about the grids: r^T M r
    of the unit plate shows them on u-ry and v-rx (1e-12)."""
    prop = "PCOMP,1\n,3,.004,0.,,4,.006,0.\n" + STEEL + ALUMINIUM
    path = deck(tmp_path / "a.bdf", 2, prop, triangles)
    path.write_text(path.read_text().replace("COUPMASS,1", f"COUPMASS,{coupmass}"))
    m = _read(path).model
    xyz, _ = plate_mesh(2, 1.0, 1.0, triangles)
    r = _rigid(xyz)[_rows(m)]
    Mr = r.T @ m.mass().toarray() @ r
    mass = 7850 * 0.004 + 2700 * 0.006
    first = 7850 * 0.004 * -0.003 + 2700 * 0.006 * 0.002
    assert Mr[0, 0] == pytest.approx(mass, rel=1e-12)
    assert Mr[0, 4] == pytest.approx(first, rel=1e-12)
    assert Mr[1, 3] == pytest.approx(-first, rel=1e-12)


def _rows(model):
    """Rows of _rigid's (6 N) for the model's coordinates (grid id x 10 + component)."""
    c = np.asarray(model.coordinates)
    return 6 * (c // 10 - 1) + c % 10 - 1


EDIT = {("MAT1", 3, "E"): ("MAT1,3,2.1e11", "MAT1,3,{!r}"),
        ("MAT1", 3, "RHO"): ("MAT1,3,2.1e11,,.3,7850.", "MAT1,3,2.1e11,,.3,{!r}"),
        ("MAT1", 4, "RHO"): ("MAT1,4,7.e10,,.33,2700.", "MAT1,4,7.e10,,.33,{!r}")}


@pytest.mark.parametrize(("prop", "field"), [
    ("PCOMP,1,0.\n,3,.01,0.\n" + STEEL, ("MAT1", 3, "E")),
    ("PCOMP,1\n,3,.004,0.,,4,.006,0.\n" + STEEL + ALUMINIUM, ("MAT1", 3, "RHO")),
    ("PCOMP,1\n,3,.004,0.,,4,.006,0.\n" + STEEL + ALUMINIUM, ("MAT1", 4, "RHO")),
], ids=["E of a stack on its grids", "steel RHO", "aluminium RHO"])
@pytest.mark.parametrize("triangles", [False, True], ids=["CQUAD8", "CTRIA6"])
def test_parameters_of_coupled_stacks(tmp_path, triangles, prop, field):
    """Sources: central differences of K, M (tests/bounds.py) and the deck with the
    value changed in its text read again (1e-12 of the largest entry): a one-material
    stack's A, B, D are proportional to its E (coupling and shift included), and each
    material's mass moments to its RHO."""
    nm = _read(deck(tmp_path / "a.bdf", 2, prop, triangles), [field])
    assert_matrix_derivatives(nm.model)
    assert_hand_edited_deck(nm.model, tmp_path / "a.bdf", *EDIT[field], _read)


def _one_cquad8(path, prop, g5=""):
    """One unit CQUAD8 (G5 as given: blank makes it a transition element), free."""
    grids = [(0., 0.), (1., 0.), (1., 1.), (0., 1.), (.5, 0.), (1., .5), (.5, 1.), (0., .5)]
    lines = [f"GRID,{i + 1},,{x!r},{y!r},0." for i, (x, y) in enumerate(grids)]
    path.write_text("BEGIN BULK\n" + prop + "\n".join(lines)
                    + f"\nCQUAD8,1,1,1,2,3,4,{g5},6\n,7,8,,,,,0\nENDDATA\n")
    return path


def test_coupling_on_a_transition_cquad8_and_its_refused_offset_mass(tmp_path):
    """Source: equilibrium and positive energy. A CQUAD8 with G5 blank (the transition
    element of model/shells_transition.py) takes the [0/90] coupling on the same membrane
    and bending strains: K annihilates the rigid motions of its seven grids (1e-10 of
    |K|) and has no negative eigenvalue (below -1e-12 |K|). An unsymmetric two-material
    stack's mass (a first moment) on it is refused in one line naming the element (its
    moments are built for all nodes present)."""
    m = _read(_one_cquad8(tmp_path / "a.bdf", CROSS_PLY)).model
    K = m.stiffness().toarray()
    xyz = np.array([(0., 0., 0.), (1., 0., 0.), (1., 1., 0.), (0., 1., 0.), (.5, 0., 0.),
                    (1., .5, 0.), (.5, 1., 0.), (0., .5, 0.)])
    r = _rigid(xyz)[_rows(m)]
    assert np.abs(K @ r).max() <= 1e-10 * np.abs(K).max()
    w = np.linalg.eigvalsh(K)
    assert w.min() >= -1e-12 * w.max()
    prop = "PCOMP,1\n,3,.004,0.,,4,.006,0.\n" + STEEL + ALUMINIUM
    with pytest.raises(InputError, match=r"CQUAD8 1: blank mid-side grids with its "
                                         r"property's mass off its reference plane"):
        _read(_one_cquad8(tmp_path / "b.bdf", prop))
