"""ZOFFS on CQUAD8 and CTRIA6 (model/shells_quadratic.py offset_geometry: the element on
its reference surface, the grids' nodes moved along their directors, rigidly linked to
the grids, stiffness and mass). Independent references: exact invariance of a plate
whose grid plane is not held; the Navier solution with B = z A; CalculiX's 20-node
bricks and the CQUAD4 (model/shell_offsets.py) on the plate held at its bottom face's
edges; the inextensional ring at the reference surface's radius for a curved CQUAD8
cylinder; central differences of K, M; the deck edited by hand and the written BDF read
back. Runs in .venv-nastran (pyNastran)."""

from __future__ import annotations

import shutil

import numpy as np
import pytest
from bounds import assert_matrix_derivatives
from nastran_frames import need
from quadratic_meshes import cylinder_mesh, plate_mesh
from shell_patch import rigid_motions as _rigid

from eigenupdate.errors import InputError
from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")
from test_nastran_offsets import (  # noqa: E402
    PSHELL,
    RHO,
    STEEL,
    H,
    _calculix_bricks,
    _navier_offset,
    _read,
)
from test_nastran_offsets import deck as linear_deck  # noqa: E402

from eigenupdate.io.nastran_write import write_updated_bdf  # noqa: E402

EDGES_PSHELL = f"PSHELL,1,1,{H!r},1,,1\n" + STEEL


def _element(k, g, z, triangles):
    """A CQUAD8 (ZOFFS field 17: the second continuation's eighth) or CTRIA6 (ZOFFS
    field 10: the continuation's second) card, ZOFFS blank when 0."""
    g = [str(n) for n in g]
    if triangles:
        return f"CTRIA6,{k},1," + ",".join(g) + (f"\n,,{z!r}" if z else "")
    return (f"CQUAD8,{k},1," + ",".join(g[:6]) + "\n," + ",".join(g[6:])
            + (f",,,,,,{z!r}" if z else ""))


def deck(path, nx, z, prop=PSHELL, triangles=False, spc="", coupled=True):
    """A unit plate of nx x nx CQUAD8 (2 nx x nx CTRIA6) of property 1, ZOFFS ``z``,
    normal +z; ``spc`` as test_nastran_offsets.deck ("", "S2", "edges")."""
    xyz, el = plate_mesh(nx, 1.0, 1.0, triangles)
    lines = [f"GRID,{i + 1},,{float(x)!r},{float(y)!r},0." for i, (x, y, _) in enumerate(xyz)]
    lines += [_element(k + 1, e + 1, z, triangles) for k, e in enumerate(el)]
    for i, (x, y, _) in enumerate(xyz):
        on_x, on_y = min(x, 1 - x) < 1e-12, min(y, 1 - y) < 1e-12
        c = {"S2": ("243" if on_x else "") + ("153" if on_y else ""),
             "edges": "123" if on_x or on_y else "", "": ""}[spc]
        if c:
            lines.append(f"SPC1,1,{''.join(sorted(set(c)))},{i + 1}")
    path.write_text(f"BEGIN BULK\nPARAM,COUPMASS,{1 if coupled else -1}\n" + prop
                    + "\n".join(lines) + "\nENDDATA\n")
    return path


def _hz(path, count=1):
    m = _read(path).model
    return solve_elastic(m.stiffness(), m.mass(), count).frequencies_hz




@pytest.mark.parametrize("coupled", [True, False], ids=["coupled", "lumped"])
@pytest.mark.parametrize("triangles", [False, True], ids=["CQUAD8", "CTRIA6"])
def test_free_offset_plate_keeps_its_rigid_modes_and_frequencies(tmp_path, triangles, coupled):
    """Source: exact invariance (as CQUAD4's): the grids and the reference plane are
    related by the invertible rigid link, under which the offset plate's K and M are the
    plate's without offset; free, it keeps its frequencies to the eigen-solver's
    rounding (1e-9 with room; measured 3e-12), six rigid modes, and K annihilates the
    rigid motions to 1e-10 of |K|. 4 x 4 CQUAD8 (8 x 4 CTRIA6), 1 x 1 x 0.02, ZOFFS T/2."""
    plain = _hz(deck(tmp_path / "a.bdf", 4, 0.0, triangles=triangles, coupled=coupled), 10)
    m = _read(deck(tmp_path / "b.bdf", 4, H / 2, triangles=triangles, coupled=coupled)).model
    sol = solve_elastic(m.stiffness(), m.mass(), 10)
    assert sol.n_rigid == 6
    assert np.max(np.abs(sol.frequencies_hz / plain - 1)) <= 1e-9, (plain, sol.frequencies_hz)
    K = m.stiffness().toarray()
    xyz, _ = plate_mesh(4, 1.0, 1.0, triangles)
    assert np.abs(K @ _rigid(xyz)).max() <= 1e-10 * np.abs(K).max()


@pytest.mark.parametrize("triangles", [False, True], ids=["CQUAD8", "CTRIA6"])
def test_offset_lies_along_the_element_normal(tmp_path, triangles):
    """Source: NASTRAN's convention (positive ZOFFS along the element's z, the normal of
    G1-G2-G3 by the right-hand rule) and the rigid-body mass: the mass's first moment
    about the grid plane is m z (u with ry: +m z, v with rx: -m z), its second (rx, rx)
    m z^2, with m = (RHO T + NSM) times the area; coupled and lumped alike."""
    for coupled in (True, False):
        m = _read(deck(tmp_path / "one.bdf", 1, H / 2, triangles=triangles,
                       coupled=coupled)).model
        xyz, _ = plate_mesh(1, 1.0, 1.0, triangles)
        r = _rigid(xyz)
        Mr = r.T @ m.mass().toarray() @ r
        mass, z = RHO * H + 0.7, H / 2
        assert abs(Mr[0, 0] / mass - 1) <= 1e-12
        assert abs(Mr[0, 4] / (mass * z) - 1) <= 1e-12
        assert abs(Mr[1, 3] / (-mass * z) - 1) <= 1e-12
        # rotating about x moves the reference plane v = -z (its m z^2) and w = y
        w = np.zeros(r.shape[0])
        w[2::6] = xyz[:, 1]
        spread = w @ m.mass().toarray() @ w
        assert abs(Mr[3, 3] / (mass * z * z + spread) - 1) <= 1e-12


@pytest.mark.parametrize("triangles", [False, True], ids=["CQUAD8", "CTRIA6"])
def test_simply_supported_plate_on_its_bottom_face_is_navier_with_b_equal_z_a(
        tmp_path, triangles):
    """Source: the Navier solution of the laminate with B = z A, D + z^2 A about the grid
    plane, mass moved with the mid-plane (test_nastran_offsets._navier_offset; Whitney
    1987, sec. 5.4), z = T/2. Meshes 4 and 8: the 8-mesh's error below its change from
    4 (measured: CQUAD8 2e-4 against a change of 3e-3, CTRIA6 5e-3 against 2.4e-2).
    The S2 support (v, rx on x edges; u, ry on y edges; w) holds the reference plane's
    v - z rx and u + z ry too, so the plate is the one without offset to rounding."""
    exact = _navier_offset(1.0, H / 2, RHO * H + 0.7)[0] / (2 * np.pi)
    f4, f8 = (_hz(deck(tmp_path / f"s{n}.bdf", n, H / 2, triangles=triangles, spc="S2"))[0]
              for n in (4, 8))
    assert abs(f8 - exact) <= abs(f8 - f4), (f4, f8, exact)
    plain = _hz(deck(tmp_path / "p.bdf", 8, 0.0, triangles=triangles, spc="S2"))[0]
    assert abs(plain / f8 - 1) <= 1e-9


def _edges(tmp_path, triangles):
    """Our lowest frequency (Hz) of the plate held at its bottom edges (ZOFFS T/2), 8 and
    16 per side."""
    return [_hz(deck(tmp_path / f"o{n}.bdf", n, H / 2, EDGES_PSHELL, triangles, "edges"))[0]
            for n in (8, 16)]


@pytest.mark.skipif(shutil.which("ccx") is None, reason="CalculiX (ccx) absent")
@pytest.mark.parametrize("triangles", [False, True], ids=["CQUAD8", "CTRIA6"])
def test_plate_held_on_its_bottom_edges_agrees_with_calculix_bricks(tmp_path, triangles):
    """Source: a second code, CalculiX's C3D20R bricks of the 1 x 1 x 0.02 plate with
    u, v, w held along its bottom face's edges (test_nastran_offsets._calculix_bricks).
    Each code's 16-error is taken as at most its change from 8 to 16 (this edge
    condition converges slowly, about as h^1.4, in every code here: CQUAD8 141.73,
    140.92, 140.60 Hz at 4, 8, 16; CalculiX 140.34, 140.11 at 8, 16), plus the plate
    models' O((h/a)^2) = 4e-4: within the sum (measured CQUAD8 0.34 % from the bricks,
    bound 0.43 %; CTRIA6 0.02 %)."""
    ours = _edges(tmp_path, triangles)
    ccx = [_calculix_bricks(tmp_path, n) for n in (8, 16)]
    bound = abs(ours[1] - ours[0]) + abs(ccx[1] - ccx[0]) + H**2 * ccx[1]
    assert abs(ours[1] - ccx[1]) <= bound, (ours, ccx)


@pytest.mark.parametrize("triangles", [False, True], ids=["CQUAD8", "CTRIA6"])
def test_plate_held_on_its_bottom_edges_converges_with_cquad4(tmp_path, triangles):
    """Source: the CQUAD4 with ZOFFS (model/shell_offsets.py, itself checked against the
    bricks) on the same problem: CQUAD4 139.14, 140.02, 140.34 Hz at 8, 16, 32 from
    below, CQUAD8 from above; at 32 (CQUAD4) and 16 (CQUAD8, CTRIA6) within the sum of
    their last changes. The offset matters: the plate without it is 30 % lower."""
    ours = _edges(tmp_path, triangles)
    quad4 = [_hz(linear_deck(tmp_path / f"q{n}.bdf", n, H / 2, EDGES_PSHELL, False,
                             "edges"))[0] for n in (16, 32)]
    assert abs(ours[1] - quad4[1]) <= abs(ours[1] - ours[0]) + abs(quad4[1] - quad4[0]), (
        ours, quad4)
    plain = _hz(deck(tmp_path / "p.bdf", 8, 0.0, EDGES_PSHELL, triangles, "edges"))[0]
    assert plain < 0.8 * ours[0], plain


def _cylinder(path, nc, nl, z, R=1.0, L=1.0, h=0.02):
    """A free cylinder (radius R, length L) of nc x nl CQUAD8 round and along (normals
    outward), PSHELL h, MAT1 with NU = 0, ZOFFS z."""
    xyz, el = cylinder_mesh(nc, nl, R, L, False)
    lines = [f"GRID,{i + 1},,{x!r},{y!r},{w!r}" for i, (x, y, w) in enumerate(xyz)]
    lines += [_element(k + 1, e + 1, z, False) for k, e in enumerate(el)]
    path.write_text("BEGIN BULK\nPARAM,COUPMASS,1\n"
                    f"PSHELL,1,1,{h!r},1,,1,{5 / 6!r}\nMAT1,1,2.1e11,,0.,{RHO!r}\n"
                    + "\n".join(lines) + "\nENDDATA\n")
    return path


@pytest.mark.parametrize("z", [0.01, -0.01], ids=["outward", "inward"])
def test_curved_cquad8_offset_is_a_cylinder_of_the_reference_radius(tmp_path, z):
    """Source: the inextensional ring (Rayleigh; Blevins table 9-2), omega_2 =
    6 / sqrt(5) sqrt(E h^2 / (12 rho R^4)), exact for a free NU = 0 cylinder's lowest
    mode up to O((h/R)^2) = 4e-4, at the reference surface's radius R + z (ZOFFS +-h/2,
    normals outward). CQUAD8's nodes move along their own surface normals, so the
    reference surface is the parallel one. 12 x 2 and 24 x 4 CQUAD8: six rigid modes,
    the 24-mesh within its change from 12 plus 4e-4 (measured 2e-5 and 1.2e-4); the
    ring at the grids' radius R is 2 % off, outside that bound."""
    h = 0.02
    ring = 6 / np.sqrt(5) * np.sqrt(2.1e11 * h**2 / (12 * RHO * (1 + z) ** 4)) / (2 * np.pi)
    got = []
    for nc, nl in ((12, 2), (24, 4)):
        model = _read(_cylinder(tmp_path / f"c{nc}.bdf", nc, nl, z, h=h)).model
        sol = solve_elastic(model.stiffness(), model.mass(), 2)
        assert sol.n_rigid == 6
        got.append(sol.frequencies_hz[0] / ring - 1)
    assert abs(got[1]) <= abs(got[1] - got[0]) + 4e-4, got
    assert abs((1 + got[1]) * (1 + z) ** 2 - 1) > abs(got[1] - got[0]) + 4e-4


FIELDS = [("PSHELL", 1, "T"), ("MAT1", 1, "E"), ("MAT1", 1, "RHO")]


@pytest.mark.parametrize("triangles", [False, True], ids=["CQUAD8", "CTRIA6"])
def test_parameters_of_offset_quadratic_elements(tmp_path, triangles):
    """Sources: the deck with T, E, RHO changed in its text and read again (the same
    element integrals: round-off, 1e-12 of the largest entry), and central differences
    of K, M (tests/bounds.py; T enters K nonlinearly). PSHELL T moves the mass, not ZOFFS
    (NASTRAN keeps the card's offset)."""
    path = deck(tmp_path / "a.bdf", 3, H / 2, triangles=triangles, spc="edges")
    nm = _read(path, FIELDS)
    assert_matrix_derivatives(nm.model)
    new = [1.1 * H, 1.05 * 2.1e11, 1.2 * RHO]
    prop = f"PSHELL,1,1,{new[0]!r},1,,1,,0.7\nMAT1,1,{new[1]!r},,0.3,{new[2]!r}\n"
    ref = _read(deck(tmp_path / "b.bdf", 3, H / 2, prop, triangles, "edges")).model
    for a, b in ((nm.model.stiffness(new), ref.stiffness()), (nm.model.mass(new), ref.mass())):
        assert abs(a - b).max() <= 1e-12 * abs(b).max()


@pytest.mark.parametrize("triangles", [False, True], ids=["CQUAD8", "CTRIA6"])
def test_written_bdf_keeps_zoffs(tmp_path, triangles):
    """Source: the written deck (--save-bdf's writer) read back: the same K and M at the
    new thickness, ZOFFS kept in its field on every element card."""
    path = deck(tmp_path / "a.bdf", 2, -0.007, triangles=triangles, spc="edges")
    nm = _read(path, FIELDS[:1])
    out = tmp_path / "w.bdf"
    write_updated_bdf(nm, out, {"p0": 1.1 * H})
    assert out.read_text().count(",-0.007") == path.read_text().count(",-0.007") > 0
    again = _read(out).model
    for a, b in ((nm.model.stiffness([1.1 * H]), again.stiffness()),
                 (nm.model.mass([1.1 * H]), again.mass())):
        assert abs(a - b).max() <= 1e-12 * abs(b).max()


def test_zoffs_needs_mid2_on_cquad8(tmp_path):
    """One line naming the element: as on CQUAD4, ZOFFS needs MID2 (bending)."""
    path = deck(tmp_path / "a.bdf", 1, 0.001, f"PSHELL,1,1,{H!r}\n" + STEEL)
    with pytest.raises(InputError, match=r"CQUAD8 1: ZOFFS = 0.001 needs MID2"):
        _read(path)


def test_offset_folding_a_curved_cquad8_is_refused(tmp_path):
    """A reference surface turned inside out (an inward offset beyond the radius): one
    line naming the element."""
    with pytest.raises(InputError, match=r"CQUAD8 \d+: ZOFFS = -1.5 turns its reference "
                                         r"surface inside out"):
        _read(_cylinder(tmp_path / "c.bdf", 12, 1, -1.5))


def test_curved_ctria6_with_zoffs_is_its_offset_facets(tmp_path):
    """A curved CTRIA6 (read as four flat CTRIA3 on its grids) with ZOFFS is those four
    CTRIA3 with the same ZOFFS, each offset along its own normal: the same K and M (to
    the rounding of another summation order, 1e-12 of the largest entry)."""
    from eigenupdate.model.shells_quadratic import FACETS

    xyz, el = cylinder_mesh(12, 2, 1.0, 1.0, True)
    z = 0.004
    head = ["BEGIN BULK", "PARAM,COUPMASS,1", f"PSHELL,1,1,0.01,1,,1,{5 / 6!r}",
            f"MAT1,1,2.1e11,,0.3,{RHO!r}"]
    head += [f"GRID,{i + 1},,{x!r},{y!r},{w!r}" for i, (x, y, w) in enumerate(xyz)]
    six = [_element(k + 1, e + 1, z, True) for k, e in enumerate(el)]
    three = [f"CTRIA3,{4 * k + j + 1},1," + ",".join(str(e[i] + 1) for i in f) + f",,{z!r}"
             for k, e in enumerate(el) for j, f in enumerate(FACETS)]
    models = []
    for name, cards in (("t6.bdf", six), ("t3.bdf", three)):
        (tmp_path / name).write_text("\n".join(head + cards) + "\nENDDATA\n")
        models.append(_read(tmp_path / name).model)
    a, b = models
    for x, y in ((a.stiffness(), b.stiffness()), (a.mass(), b.mass())):
        assert abs(x - y).max() <= 1e-12 * abs(y).max()
