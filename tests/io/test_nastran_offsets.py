"""CQUAD4/CTRIA3 ZOFFS and a PCOMP's mass off its grid plane (model/shell_offsets.py,
io/nastran_offsets.py), read from decks. Independent references: the kinematics of the
shell (a point at height z moves u + z ry, right-hand rotations) for the sign; exact
invariance of a plate whose grid plane is not held (its reference plane is its neutral
plane); the Navier solution of the laminate with B = z A; CalculiX's 20-node bricks of
the same plate restrained on its bottom face's edges; central differences of K, M; the
written BDF read back. Runs in .venv-nastran (pyNastran)."""

from __future__ import annotations

import re
import shutil
import subprocess
import warnings

import numpy as np
import pytest
from bounds import assert_matrix_derivatives
from laminate_plates import navier_coupled
from nastran_frames import need
from plates import square_mesh
from solid_meshes import box_mesh

from eigenupdate.errors import EigenupdateWarning, InputError
from eigenupdate.model.parameters import Parameter
from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.io.nastran import CardField, read_nastran  # noqa: E402
from eigenupdate.io.nastran_write import write_updated_bdf  # noqa: E402

E, NU, RHO = 2.1e11, 0.3, 7850.0
H = 0.02  # a/h = 50 on the unit plate
STEEL = f"MAT1,1,{E!r},,{NU!r},{RHO!r}\n"
PSHELL = f"PSHELL,1,1,{H!r},1,,1,,0.7\n" + STEEL  # NSM 0.7 kg/m^2


def _read(path, fields=()):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EigenupdateWarning)
        return read_nastran(path, [(Parameter(f"p{i}", 0.0), CardField(*f))
                                   for i, f in enumerate(fields)])


def deck(path, nx, z, prop=PSHELL, triangles=False, spc="", coupled=True, flip=False):
    """A unit plate of property 1 with ZOFFS ``z`` on every element (blank when 0),
    nodes counter-clockwise seen from +z (clockwise when ``flip``); ``spc``: "free",
    "S2" (navier_coupled's support) or "edges" (u, v, w held on the edges)."""
    xyz, el = square_mesh(nx, 1.0, triangles)
    if flip:
        el = el[:, ::-1]
    lines = [f"GRID,{i + 1},,{float(x)!r},{float(y)!r},0." for i, (x, y, _) in enumerate(xyz)]
    card = "CTRIA3" if triangles else "CQUAD4"
    off = f",,{z!r}" if z else ""
    lines += [f"{card},{k + 1},1," + ",".join(str(n + 1) for n in e) + off
              for k, e in enumerate(el)]
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


@pytest.mark.parametrize("triangles", [False, True], ids=["CQUAD4", "CTRIA3"])
@pytest.mark.parametrize("flip", [False, True], ids=["normal+z", "normal-z"])
def test_offset_lies_along_the_element_normal(tmp_path, triangles, flip):
    """Source: the shell's kinematics and NASTRAN's convention (QRG CQUAD4/CTRIA3:
    positive ZOFFS puts the reference plane along the element's positive z, the normal
    of G1-G2-G3 by the right-hand rule). A point at height z above a grid moves
    u + z ry (right-hand rotation about y), so the field ry = k x, w = -k x^2 / 2 with
    u = -s z k x, s = +-1 the normal's sign, leaves the reference plane unstretched: its
    energy is the bending's, D k^2 / 2 per area (constant curvature: exact in these
    elements), and the field with the other sign stretches it, adding A (2 z k)^2 / 2,
    twelve times the bending's at z = T/2. The mass's first moment about the grid plane
    (from the rigid-body mass) is m s z: its centre lies at ZOFFS along the normal."""
    z, k = H / 2, 0.3
    path = deck(tmp_path / "one.bdf", 1, z, triangles=triangles, flip=flip)
    m = _read(path).model
    xyz, _ = square_mesh(1, 1.0, triangles)  # one CQUAD4 or two CTRIA3, area 1
    K, M = m.stiffness().toarray(), m.mass().toarray()
    n = K.shape[0] // 6
    assert n == 4
    s = -1.0 if flip else 1.0
    D = E * H**3 / (12 * (1 - NU**2))
    area = 1.0
    for sign, extra in ((s, 0.0), (-s, 12.0)):
        d = np.zeros((n, 6))
        d[:, 4] = k * xyz[:, 0]
        d[:, 2] = -k * xyz[:, 0] ** 2 / 2
        d[:, 0] = -sign * z * k * xyz[:, 0]
        energy = 0.5 * d.ravel() @ K @ d.ravel()
        assert abs(energy / (0.5 * D * k**2 * area) - (1 + extra)) <= 1e-9, (sign, energy)
    rigid = np.zeros((6 * n, 6))
    for i, p in enumerate(xyz):
        rigid[6 * i:6 * i + 3, :3] = np.eye(3)
        rigid[6 * i:6 * i + 3, 3:] = -np.array([[0, -p[2], p[1]], [p[2], 0, -p[0]],
                                                [-p[1], p[0], 0]])  # theta x r
        rigid[6 * i + 3:6 * i + 6, 3:] = np.eye(3)
    Mr = rigid.T @ M @ rigid
    mass = (RHO * H + 0.7) * area
    assert abs(Mr[0, 0] / mass - 1) <= 1e-12
    assert abs(Mr[0, 4] / (mass * s * z) - 1) <= 1e-12  # u with ry: m z_cg
    assert abs(Mr[1, 3] / (-mass * s * z) - 1) <= 1e-12


@pytest.mark.parametrize("coupled", [True, False], ids=["coupled", "lumped"])
@pytest.mark.parametrize("triangles", [False, True], ids=["CQUAD4", "CTRIA3"])
def test_free_offset_plate_keeps_its_rigid_modes_and_frequencies(tmp_path, triangles, coupled):
    """Source: exact invariance. The grids' (u, v, w, rotations) and the reference plane's
    (u + z ry, v - z rx, w, rotations) are related by an invertible map, under which
    the offset plate's stiffness and (rigidly moved) mass are the plate's without offset:
    a free plate (nothing attached at the grid plane) keeps its frequencies to the
    eigen-solver's rounding (1e-9 with room, well-separated modes; 1 x 1 x 0.02, 8 x 8),
    and K annihilates the six rigid motions (u = theta x r) to rounding, 1e-10 of |K|."""
    plain = _hz(deck(tmp_path / "a.bdf", 8, 0.0, triangles=triangles, coupled=coupled), 10)
    path = deck(tmp_path / "b.bdf", 8, H / 2, triangles=triangles, coupled=coupled)
    m = _read(path).model
    sol = solve_elastic(m.stiffness(), m.mass(), 10)
    assert sol.n_rigid == 6
    offset = sol.frequencies_hz
    assert np.max(np.abs(offset / plain - 1)) <= 1e-9, (plain, offset)
    K = m.stiffness().toarray()
    xyz, _ = square_mesh(8, 1.0, triangles)
    rigid = np.zeros((K.shape[0], 6))
    for i, p in enumerate(xyz):
        rigid[6 * i:6 * i + 3, :3] = np.eye(3)
        rigid[6 * i:6 * i + 3, 3:] = -np.array([[0, -p[2], p[1]], [p[2], 0, -p[0]],
                                                [-p[1], p[0], 0]])
        rigid[6 * i + 3:6 * i + 6, 3:] = np.eye(3)
    assert np.abs(K @ rigid).max() <= 1e-10 * np.abs(K).max()


def _navier_offset(a, z, rho_h):
    """Lowest omega of the S2 plate of laminate_plates.navier_coupled whose grids lie z
    below its mid-plane: A, B = z A, D + z^2 A, H about the grids, and the mass moved
    with the mid-plane (u + z ry, v - z rx, w), the 5 x 5 generalized problem in U, V,
    W, Rx, Ry (same series, each product integrating to a^2 / 4)."""
    A = E * H / (1 - NU**2) * np.array([[1, NU, 0], [NU, 1, 0], [0, 0, (1 - NU) / 2]])
    D = A * H**2 / 12
    Hs = 5 / 6 * E / (2 * (1 + NU)) * H * np.eye(2)
    abdh = tuple(x[None] for x in (A, z * A, D + z * z * A, Hs))
    # navier_coupled's stiffness, mass on U, V, W only; here the moved mass instead
    al = np.pi / a
    C = np.block([[abdh[0][0], abdh[1][0]], [abdh[1][0], abdh[2][0]]])
    Ps, Pc = np.zeros((6, 5)), np.zeros((6, 5))
    Ps[0, 0], Ps[1, 1], Ps[3, 4], Ps[4, 3] = -al, -al, -al, al
    Pc[2, 0], Pc[2, 1], Pc[5, 4], Pc[5, 3] = al, al, al, -al
    gx, gy = np.array([0, 0, al, 0, 1.0]), np.array([0, 0, al, -1.0, 0])
    K = Ps.T @ C @ Ps + Pc.T @ C @ Pc + Hs[0, 0] * np.outer(gx, gx) + Hs[1, 1] * np.outer(
        gy, gy)
    T = np.array([[1.0, 0, 0, 0, z], [0, 1, 0, -z, 0], [0, 0, 1, 0, 0]])
    mu = np.linalg.eigvals(np.linalg.solve(K, rho_h * T.T @ T)).real
    return float(np.sqrt(1 / mu.max())), navier_coupled(a, abdh, rho_h)


@pytest.mark.parametrize("triangles", [False, True], ids=["CQUAD4", "CTRIA3"])
def test_simply_supported_plate_on_its_bottom_face_is_navier_with_b_equal_z_a(
        tmp_path, triangles):
    """Source: the Navier solution of a laminate with B = z A, D + z^2 A about the grid
    plane (the unsymmetric-laminate formula of laminate_plates.navier_coupled; Whitney
    1987, sec. 5.4), z = T/2 (grids on the bottom face), its mass moved with the
    mid-plane. Meshes 8 and 16: the 16-mesh within its change from 8 (bilinear
    elements' h^2 error: a third of it; room 3). Leaving out the coupling B (D + z^2 A
    alone) doubles the frequency; the mass left at the grids (navier_coupled's inertia
    on U, V, W) lowers it by about (pi z / a)^2 = 1e-3: the grids move in-plane by
    -z times the rotation, carrying it."""
    rho_h = RHO * H + 0.7
    exact, at_grids = _navier_offset(1.0, H / 2, rho_h)
    f8, f16 = (_hz(deck(tmp_path / f"s{n}.bdf", n, H / 2, triangles=triangles, spc="S2"))[0]
               for n in (8, 16))
    exact /= 2 * np.pi
    assert abs(f16 - exact) <= abs(f16 - f8), (f8, f16, exact)
    assert 5e-4 < 1 - at_grids / (2 * np.pi) / exact < 2e-3
    A = E * H / (1 - NU**2) * np.array([[1, NU, 0], [NU, 1, 0], [0, 0, (1 - NU) / 2]])
    Hs = 5 / 6 * E / (2 * (1 + NU)) * H * np.eye(2)
    uncoupled = navier_coupled(1.0, (A[None], 0 * A[None], A[None] * H**2 / 3, Hs[None]),
                               rho_h)
    assert uncoupled / (2 * np.pi) > 1.9 * exact


def _calculix_bricks(tmp_path, nx):
    """CalculiX's lowest frequency (Hz) of the 1 x 1 x H plate as nx x nx x 1 C3D20R
    bricks, u, v, w held at the nodes of its bottom face's edges."""
    xyz, el = box_mesh((1.0, 1.0, H), (nx, nx, 1), "CHEXA20")
    el = np.column_stack([el[:, :12], el[:, 16:20], el[:, 12:16]])  # CalculiX's order
    lines = ["*NODE"] + [f"{i + 1},{float(p[0])!r},{float(p[1])!r},{float(p[2])!r}"
                         for i, p in enumerate(xyz)]
    lines += ["*ELEMENT,TYPE=C3D20R,ELSET=EALL"]
    for k, e in enumerate(el):
        ids = [str(v + 1) for v in e]
        lines += [f"{k + 1}," + ",".join(ids[:15]) + ",", ",".join(ids[15:])]
    x, y, z = xyz.T
    edge = np.flatnonzero((np.isclose(x, 0) | np.isclose(x, 1) | np.isclose(y, 0)
                           | np.isclose(y, 1)) & np.isclose(z, 0))
    lines += ["*BOUNDARY"] + [f"{i + 1},1,3" for i in edge]
    lines += ["*MATERIAL,NAME=STEEL", "*ELASTIC", f"{E!r},{NU!r}", "*DENSITY", f"{RHO!r}",
              "*SOLID SECTION,ELSET=EALL,MATERIAL=STEEL", "*STEP", "*FREQUENCY", "1",
              "*END STEP"]
    (tmp_path / f"b{nx}.inp").write_text("\n".join(lines) + "\n")
    subprocess.run(["ccx", f"b{nx}"], cwd=tmp_path, capture_output=True, check=True,
                   env={"OMP_NUM_THREADS": "1", "PATH": "/usr/bin:/bin"})
    text = (tmp_path / f"b{nx}.dat").read_text().split("E I G E N V A L U E   O U T P U T")[1]
    return float(re.search(r"^\s+1\s+(\S+)\s+(\S+)\s+(\S+)", text, re.M).group(3))


@pytest.mark.skipif(shutil.which("ccx") is None, reason="CalculiX (ccx) absent")
@pytest.mark.parametrize("triangles", [False, True], ids=["CQUAD4", "CTRIA3"])
def test_plate_held_on_its_bottom_edges_agrees_with_calculix_bricks(tmp_path, triangles):
    """Source: a second code, CalculiX 2.20's C3D20R bricks (exact offset geometry and
    mass) of the 1 x 1 x 0.02 steel plate with u, v, w held along its bottom face's
    edges, against the shell with its grids there (ZOFFS = T/2, u, v, w held at the edge
    grids; either sign, by symmetry). Holding the grid plane in-plane makes the coupling
    work: 44 % above the same shell without offset. Each code's 16-mesh error is below
    its change from 8 to 16, and their plate models differ by O((h/a)^2) = 4e-4, so they
    agree within the sum (measured 0.06 % apart at 16)."""
    prop = f"PSHELL,1,1,{H!r},1,,1\n" + STEEL
    ours = [_hz(deck(tmp_path / f"o{n}.bdf", n, H / 2, prop, triangles, "edges"))[0]
            for n in (8, 16)]
    ccx = [_calculix_bricks(tmp_path, n) for n in (8, 16)]
    bound = abs(ours[1] - ours[0]) + abs(ccx[1] - ccx[0]) + (H / 1.0) ** 2 * ccx[1]
    assert abs(ours[1] - ccx[1]) <= bound, (ours, ccx)
    below = _hz(deck(tmp_path / "m.bdf", 16, -H / 2, prop, triangles, "edges"))[0]
    assert abs(below / ours[1] - 1) <= 1e-9  # the plate turned over
    plain = _hz(deck(tmp_path / "p.bdf", 16, 0.0, prop, triangles, "edges"))[0]
    assert plain < 0.8 * ccx[1]


MIXED = (f"PSHELL,1,1,{H!r},1,,1,,0.7\n" + STEEL
         + "PCOMP,2,,0.4\n,2,.004,0.,,3,.006,45.,\n,2,.004,90.\n"
         + "MAT1,2,7.e10,,.33,2700.\nMAT1,3,1.2e11,,.3,4400.\n")


def _mixed(path, t=H, e3=1.2e11, rho2=2700.0, triangles=True):
    """A unit plate, S2-supported at its grids: PSHELL 1 (T = ``t``, ZOFFS T/2) on x <
    1/2, PCOMP 2 (three MAT1 plies, symmetric, ZOFFS -0.007) beyond."""
    text = deck(path, 6, H / 2, MIXED, triangles, "S2").read_text()
    text = text.replace(f"PSHELL,1,1,{H!r}", f"PSHELL,1,1,{t!r}").replace(
        "MAT1,3,1.2e11", f"MAT1,3,{e3!r}").replace("2700.", f"{rho2!r}")
    xyz, el = square_mesh(6, 1.0, triangles)
    lines = text.splitlines()
    for k, e in enumerate(el):
        if xyz[e, 0].mean() > 0.5:
            i = next(j for j, x in enumerate(lines) if x.startswith(("CQUAD4", "CTRIA3"))
                     and x.split(",")[1] == str(k + 1))
            f = lines[i].split(",")
            f[2], f[-1] = "2", "-0.007"
            lines[i] = ",".join(f)
    path.write_text("\n".join(lines) + "\n")
    return path


FIELDS = [("PSHELL", 1, "T"), ("MAT1", 1, "E"), ("MAT1", 1, "RHO"), ("MAT1", 3, "E"),
          ("MAT1", 2, "RHO")]


@pytest.mark.parametrize("triangles", [True, False], ids=["CTRIA3", "CQUAD4"])
def test_parameters_of_offset_elements(tmp_path, triangles):
    """Sources: the deck with the values changed in its text and read again (the same
    element integrals: round-off, 1e-12 of the largest entry), and central differences
    of K, M (tests/bounds.py; T enters K nonlinearly: T^3 bending, the shear factor).
    PSHELL T moves the mass, not ZOFFS (NASTRAN keeps the card's offset); a PCOMP
    material's RHO enters its mass's moments linearly (its plies' centroid is fixed);
    MAT1 3 is the middle ply of PCOMP 2 alone, so its E is refused there (several
    materials), E of MAT1 1 (PSHELL) and the densities are parameters."""
    fields = [f for f in FIELDS if f != ("MAT1", 3, "E")]
    path = _mixed(tmp_path / "a.bdf", triangles=triangles)
    nm = _read(path, fields)
    assert_matrix_derivatives(nm.model)
    new = [1.1 * H, 1.05 * E, 1.2 * RHO, 3000.0]
    edited = _mixed(tmp_path / "b.bdf", 1.1 * H, rho2=3000.0, triangles=triangles)
    text = edited.read_text().replace(f"MAT1,1,{E!r},,{NU!r},{RHO!r}",
                                      f"MAT1,1,{1.05 * E!r},,{NU!r},{1.2 * RHO!r}")
    edited.write_text(text)
    ref = _read(edited).model
    for a, b in ((nm.model.stiffness(new), ref.stiffness()), (nm.model.mass(new), ref.mass())):
        assert abs(a - b).max() <= 1e-12 * abs(b).max()
    with pytest.raises(InputError, match="MAT1 3 field E: not a parameter of PCOMP 2"):
        _read(path, [("MAT1", 3, "E")])


def test_ply_thickness_with_zoffs(tmp_path):
    """Ply thicknesses of a symmetric PCOMP (LAM=SYM, Z0 blank) on offset elements:
    the stack stays about its mid-plane, ZOFFS from the grids, so K and M stay sums of
    fixed matrices times functions of the plies (central differences), and the deck
    edited to new thicknesses is the model there (round-off)."""
    prop = "PCOMP,1,,0.3,,,,,SYM\n,2,.002,0.,,2,.003,45.\nMAT1,2,7.e10,,.33,2700.\n"
    path = deck(tmp_path / "a.bdf", 6, 0.004, prop, True, "S2")
    nm = _read(path, [("PCOMP", 1, "T1"), ("PCOMP", 1, "T2")])
    assert_matrix_derivatives(nm.model)
    edited = tmp_path / "b.bdf"
    edited.write_text(path.read_text().replace(",2,.002,0.,,2,.003,45.",
                                               ",2,.0025,0.,,2,.0028,45."))
    ref = _read(edited).model
    s = [0.0025, 0.0028]
    for a, b in ((nm.model.stiffness(s), ref.stiffness()), (nm.model.mass(s), ref.mass())):
        assert abs(a - b).max() <= 1e-12 * abs(b).max()


def test_pcomp_with_z0_is_the_offset_pshell(tmp_path):
    """Source: a one-ply PCOMP from the grids up (Z0 = 0) is a PSHELL of its material
    with ZOFFS = T/2 (the same stack, its mid-plane T/2 above the grids): the same K and
    M (the PCOMP's Z0 shift and ZOFFS are both the rigid offset; its mass's first and
    second moments moved with it) to round-off, CQUAD4 and CTRIA3. Before the shift was
    an offset (B = s A about the grids with CQUAD4's incompatible modes condensed by the
    membrane alone) the free plate's CQUAD4 modes were up to 1 % stiff."""
    pcomp = f"PCOMP,1,0.\n,1,{H!r},0.\n" + STEEL  # NSM 0: a PCOMP's is on the grids
    for triangles in (True, False):
        a = _read(deck(tmp_path / "c.bdf", 4, 0.0, pcomp, triangles)).model
        b = _read(deck(tmp_path / "s.bdf", 4, H / 2,
                       f"PSHELL,1,1,{H!r},1,,1,{5 / 6!r}\n" + STEEL, triangles)).model
        for x, y in ((a.mass(), b.mass()), (a.stiffness(), b.stiffness())):
            assert abs(x - y).max() <= 1e-12 * abs(y).max()


@pytest.mark.parametrize("triangles", [True, False], ids=["CTRIA3", "CQUAD4"])
def test_written_bdf_keeps_zoffs(tmp_path, triangles):
    """Source: the written deck read back (--save-bdf's writer) gives the same K and M
    at the new thickness, ZOFFS kept on the element cards."""
    path = _mixed(tmp_path / "a.bdf", triangles=triangles)
    nm = _read(path, [("PSHELL", 1, "T")])
    out = tmp_path / "w.bdf"
    write_updated_bdf(nm, out, {"p0": 1.1 * H})
    assert out.read_text().count(",-0.007") == path.read_text().count(",-0.007") > 0
    again = _read(out).model
    for a, b in ((nm.model.stiffness([1.1 * H]), again.stiffness()),
                 (nm.model.mass([1.1 * H]), again.mass())):
        assert abs(a - b).max() <= 1e-12 * abs(b).max()
