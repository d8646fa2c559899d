"""CQUAD4 facets on a curved surface (issue 20): a cylinder at R/T = 50 read through
read_nastran converges to the curved shell's frequencies and hardly depends on K6ROT
(model/shell_normals.py, PARAM SNORM); flat and folded meshes are unchanged.
Sources: CalculiX S8R on the same cylinder, Flugge's simply supported cylinder (Leissa,
Vibration of Shells, NASA SP-288, 1973, sec. 2.3), central differences.
Runs in .venv-nastran (pyNastran)."""

from __future__ import annotations

import re
import shutil
import subprocess
import warnings

import numpy as np
import pytest
from bounds import assert_matrix_derivatives
from nastran_frames import need

from eigenupdate.errors import EigenupdateWarning
from eigenupdate.model.parameters import Parameter
from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.io.nastran import CardField, read_nastran  # noqa: E402

E, NU, RHO = 70e9, 0.3, 2700.0
R, T, L = 0.1, 0.002, 0.4  # R/T = 50, L/R = 4


def _mesh(nc: int, nl: int):
    """Grids and CQUAD4 (normal outward) of a closed cylinder round z."""
    a = 2 * np.pi * np.arange(nc) / nc
    xyz = np.array([[R * np.cos(t), R * np.sin(t), L * j / nl]
                    for j in range(nl + 1) for t in a])
    el = [[j * nc + i, j * nc + (i + 1) % nc, (j + 1) * nc + (i + 1) % nc, (j + 1) * nc + i]
          for j in range(nl) for i in range(nc)]
    return xyz, np.array(el)


def _deck(path, xyz, el, params="", ss=False, snorm="PARAM,SNORM,20.\n"):
    """CQUAD4 + PSHELL 1 + MAT1 1 (COUPMASS 1), grid normals asked for (PARAM SNORM 20,
    MSC's default since V2001; without the card, none: io/nastran_offsets.SNORM) unless
    ``params`` sets SNORM; ``ss``: the ends (z = 0, L) held in x and y (radial and
    tangential: Flugge's shear diaphragm, axial motion free)."""
    params = params if "SNORM" in params else snorm + params
    lines = [f"GRID,{i + 1},,{float(x)!r},{float(y)!r},{float(z)!r}"
             for i, (x, y, z) in enumerate(xyz)]
    lines += [f"CQUAD4,{k + 1},1," + ",".join(str(n + 1) for n in e) for k, e in enumerate(el)]
    if ss:
        ends = np.flatnonzero(np.isclose(xyz[:, 2], 0.0) | np.isclose(xyz[:, 2], L)) + 1
        lines += [f"SPC1,1,12,{g}" for g in ends]
    path.write_text(("SPC = 1\n" if ss else "") + "BEGIN BULK\nPARAM,COUPMASS,1\n" + params
                    + f"PSHELL,1,1,{T!r},1,,1\nMAT1,1,{E!r},,{NU!r},{RHO!r}\n"
                    + "\n".join(lines) + "\nENDDATA\n")
    return path


def _read(path, specs=()):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EigenupdateWarning)
        return read_nastran(path, specs)


def _hz(path, n=4) -> np.ndarray:
    model = _read(path).model
    return solve_elastic(model.stiffness(), model.mass(), n).frequencies_hz


def _cylinder_hz(tmp_path, nc, nl, params="", ss=False, n=4):
    name = re.sub(r"\W", "", params)
    return _hz(_deck(tmp_path / f"c{nc}_{nl}{name}{ss}.bdf", *_mesh(nc, nl), params, ss), n)


def _calculix_s8r(tmp_path, nc: int, nl: int) -> np.ndarray:
    """CalculiX S8R elastic frequencies (Hz) of the same free cylinder (nc x nl 8-node
    shells, mid-side nodes on the circle; ccx expands them to C3D20R)."""
    from quadratic_meshes import cylinder_mesh

    xyz, el = cylinder_mesh(nc, nl, R, L, False)
    # 12 digits: ccx reads at most 20 characters a number (a longer one is cut)
    lines = ["*NODE,NSET=NALL"] + [f"{i + 1},{x:.12g},{y:.12g},{z:.12g}"
                                   for i, (x, y, z) in enumerate(xyz)]
    lines += ["*ELEMENT,TYPE=S8R,ELSET=EALL"]
    lines += [f"{k + 1}," + ",".join(str(n + 1) for n in e) for k, e in enumerate(el)]
    lines += ["*MATERIAL,NAME=AL", "*ELASTIC", f"{E!r},{NU!r}", "*DENSITY", f"{RHO!r}",
              "*SHELL SECTION,ELSET=EALL,MATERIAL=AL", f"{T!r}", "*STEP", "*FREQUENCY",
              "12", "*END STEP"]
    (tmp_path / "s8r.inp").write_text("\n".join(lines) + "\n")
    subprocess.run(["ccx", "s8r"], cwd=tmp_path, capture_output=True, check=True,
                   env={"OMP_NUM_THREADS": "1", "PATH": "/usr/bin:/bin"})
    text = (tmp_path / "s8r.dat").read_text().split("E I G E N V A L U E   O U T P U T")[1]
    rows = re.findall(r"^\s+\d+\s+\S+\s+\S+\s+(\S+)\s+\S+\s*$", text, re.M)
    return np.array([float(f) for f in rows])[6:]  # six rigid-body modes first


@pytest.mark.slow
@pytest.mark.skipif(shutil.which("ccx") is None, reason="CalculiX (ccx) absent")
def test_free_cylinder_converges_to_calculix_s8r(tmp_path):
    """Source: CalculiX S8R, 32 x 16 on the same free cylinder (its 64 x 32 differs by
    0.04 %: 144.52 and 144.46 Hz). The n = 2 mode that varies along the axis (third and
    fourth elastic modes; the first pair is the ring mode, uniform along it).

    CQUAD4 at 32 x 16 and 64 x 32 (measured +0.86 %, +0.17 %; 96 x 48: +0.04 %): the
    64 x 32 error is within a second-order extrapolation's, (f32 - f64) / 3, plus 0.1 %
    for S8R's own. Before the drilling was tied on curved facets they converged away,
    -0.66 %, -1.43 %, -1.7 % (the tester's 145.84, 144.72, 144.38 Hz on another cylinder)."""
    ref = _calculix_s8r(tmp_path, 32, 16)
    assert ref[2] == pytest.approx(ref[3], rel=1e-6)
    f32, f64 = (_cylinder_hz(tmp_path, nc, nl)[2] for nc, nl in ((32, 16), (64, 32)))
    assert f32 > f64 > ref[2] * (1 - 1e-3), (f32, f64, ref[2])
    assert abs(f64 / ref[2] - 1) <= (f32 - f64) / (3 * f64) + 1e-3, (f32, f64, ref[2])


def test_k6rot_hardly_moves_a_curved_facet_mesh(tmp_path):
    """Source: Rayleigh's bound: a penalty only adds stiffness, so the frequency rises
    with K6ROT, and what K6ROT can still add is bounded by the hinge that
    CURVED_DRILLING = 1000 leaves: 0.03 % at 32 x 16 (145.76 Hz against 145.80 with the
    factor 1e4, the drilling as good as held to the membrane rotation). K6ROT 0, 100
    and 1e4 (the largest default a NASTRAN uses: Autodesk's for modal solutions): within
    0.05 % (measured 145.76, 145.76, 145.77 Hz). With the K6ROT penalty alone it was
    141.86, 143.57, 145.74 Hz: 2.7 %. (Beyond 1e4 the penalty stiffens the membrane
    itself, plain facets as these: +0.1 % at 1e6.)"""
    f = [_cylinder_hz(tmp_path, 32, 16, f"PARAM,K6ROT,{k!r}\n")[2] for k in (0.0, 100.0, 1e4)]
    assert f[0] <= f[1] * (1 + 1e-9) and f[1] <= f[2] * (1 + 1e-9), f
    assert f[2] / f[0] - 1 <= 5e-4, f


def test_param_snorm_zero_keeps_plain_facets(tmp_path):
    """PARAM SNORM 0 (no grid normals, MSC V70.7's default) gives the plain facets:
    the n = 2 mode as before the change, K6ROT-dependent (measured 143.57 Hz at the
    default K6ROT, 145.76 with SNORM 20). A deck without PARAM SNORM reads as SNORM 0
    (the published decks we compare with were run so: io/nastran_offsets.SNORM): its K
    is that of SNORM 0 exactly."""
    plain = _cylinder_hz(tmp_path, 32, 16, "PARAM,SNORM,0.\n")[2]
    tied = _cylinder_hz(tmp_path, 32, 16)[2]
    assert tied / plain - 1 > 0.01, (plain, tied)
    mesh = _mesh(12, 2)
    a, b = (_read(_deck(tmp_path / f"u{i}.bdf", *mesh, snorm=p)).model.stiffness()
            for i, p in enumerate(("", "PARAM,SNORM,0.\n")))
    assert abs(a - b).max() == 0.0


def _flugge(m: int, n: int) -> float:
    """Flugge's lowest frequency (Hz) of a simply supported (shear diaphragm) cylinder,
    m axial half-waves and n circumferential waves: the smallest root of Leissa's 3 x 3
    determinant (NASA SP-288, eq. 2.3 with Flugge's operator), k = T^2 / (12 R^2),
    lam = m pi R / L, Omega^2 = rho (1 - nu^2) R^2 omega^2 / E."""
    k, lam = T**2 / (12 * R**2), m * np.pi * R / L
    a = np.array([
        [lam**2 + (1 - NU) / 2 * n**2 * (1 + k), -(1 + NU) / 2 * lam * n,
         NU * lam + k * (lam**3 - (1 - NU) / 2 * lam * n**2)],
        [0.0, (1 - NU) / 2 * lam**2 * (1 + 3 * k) + n**2, -n - (3 - NU) / 2 * k * lam**2 * n],
        [0.0, 0.0, 1 + k * (lam**4 + 2 * lam**2 * n**2 + n**4 - 2 * n**2 + 1)]])
    om2 = np.linalg.eigvalsh(np.triu(a) + np.triu(a, 1).T)[0]
    return float(np.sqrt(om2 * E / (RHO * (1 - NU**2) * R**2)) / (2 * np.pi))


@pytest.mark.slow
def test_simply_supported_cylinder_agrees_with_flugge(tmp_path):
    """Source: Flugge (Leissa, NASA SP-288): m = 1, n = 3, 4, 2, 5 (631.9, 796.1, 969.5,
    1197.7 Hz). CQUAD4 at 32 x 16 and 64 x 32: each 64 x 32 frequency within a
    second-order extrapolation's error, (f32 - f64) / 3, plus 0.3 % for the difference
    between Flugge's thin-shell theory and a Reissner-Mindlin shell (CQUAD8 at 32 x 16
    differs from Flugge by -0.16 .. -0.01 % on these modes)."""
    ref = np.sort([_flugge(1, n) for n in (2, 3, 4, 5)])
    f32, f64 = (_cylinder_hz(tmp_path, nc, nl, ss=True, n=8)[0::2]
                for nc, nl in ((32, 16), (64, 32)))
    assert np.all(np.abs(f64 / ref - 1) <= (f32 - f64) / (3 * f64) + 3e-3), (f32, f64, ref)


def test_flat_and_folded_meshes_are_unchanged(tmp_path):
    """Grid normals change only grids on a smooth curved surface: a flat plate's K is bit
    for bit that of PARAM SNORM 0, and a 90-degree fold's (a box corner: beyond SNORM's
    20 degrees; equal sides, whose n n^T sum has no principal axis) too; turned to a
    general orientation, both agree to rounding (1e-12 of the largest entry; the normals
    there have rounding errors of 1e-16). A curved mesh's K differs (measured 2e-4 of
    the largest entry, a membrane one; the test can fail)."""
    g = np.linspace(0.0, 1.0, 4)
    flat = np.array([[a, b, 0.0] for a in g for b in g])  # grid (i, j): 4 i + j
    q = np.array([[4 * i + j, 4 * i + 4 + j, 4 * i + 5 + j, 4 * i + j + 1]
                  for i in range(3) for j in range(3)])
    # a wall in y = 0 rising in z from the plate's edge j = 0: grid (i, j > 0) 16 + 3 i + j - 1

    def w(i, j):
        return 4 * i if j == 0 else 16 + 3 * i + j - 1

    folded = np.vstack([flat, [[a, 0.0, b] for a in g for b in g[1:]]])
    wall = np.array([[w(i, j), w(i, j + 1), w(i + 1, j + 1), w(i + 1, j)]
                     for i in range(3) for j in range(3)])
    turn = np.linalg.qr(np.array([[1.0, 0.3, -0.2], [0.4, 1.0, 0.7], [-0.5, 0.2, 1.0]]))[0]
    cases = {"flat": (flat, q, 0.0), "fold": (folded, np.vstack([q, wall]), 0.0),
             "turned flat": (flat @ turn.T, q, 1e-12),
             "turned fold": (folded @ turn.T, np.vstack([q, wall]), 1e-12),
             "curved": (*_mesh(12, 2), None)}
    for i, (name, (xyz, el, tol)) in enumerate(cases.items()):
        a, b = (_read(_deck(tmp_path / f"{i}{s}.bdf", xyz, el, p)).model.stiffness()
                for s, p in ((0, ""), (1, "PARAM,SNORM,0.\n")))
        diff = abs(a - b).max() / abs(b).max()
        assert diff <= tol if tol is not None else diff > 1e-6, (name, diff)


def test_curved_thickness_and_modulus_derivatives(tmp_path):
    """Source: central differences (tests/bounds.py): PSHELL T and MAT1 E as parameters
    of a curved mesh, whose bending part now holds the curvature's drilling term
    (thickness power 3, MID2's modulus)."""
    path = _deck(tmp_path / "c.bdf", *_mesh(12, 2))
    specs = [(Parameter("t", 0.0), CardField("PSHELL", 1, "T")),
             (Parameter("E", 0.0), CardField("MAT1", 1, "E"))]
    assert_matrix_derivatives(_read(path, specs).model)
