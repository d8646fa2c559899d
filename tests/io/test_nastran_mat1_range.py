"""MAT1 NU at the end of its range (QRG MAT1: -1.0 < NU <= 0.5): a shell with NU = 0.5 is
plane stress, finite (E / (1 - NU^2), G = E / 3), and is read; a solid's bulk modulus
E / (3 (1 - 2 NU)) is infinite there, so a solid's NU = 0.5 is refused.
Source of the issue: issue 20's acceptance run (accept8), where a plate of NU = 0.5 was
refused as out of range. Runs in .venv-nastran (pyNastran)."""

from __future__ import annotations

import numpy as np
import pytest
from nastran_frames import need
from plates import plate_fixed, read_deck
from quadratic_meshes import RHO, E, plate_mesh
from refusals import one_line

from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")


def _plate(path, nx, nu, h=0.002, a=1.0):
    """An a x a CQUAD8 plate, hard simple support, coupled mass."""
    xyz, el = plate_mesh(nx, a, a, False)
    lines = [f"GRID,{i + 1},,{x!r},{y!r},0." for i, (x, y, _) in enumerate(xyz)]
    for k, e in enumerate(el):
        g = [str(n + 1) for n in e]
        lines.append(f"CQUAD8,{k + 1},1," + ",".join(g[:6]) + "\n," + ",".join(g[6:]))
    for i, row in enumerate(plate_fixed(xyz, a, "ss")):
        lines.append(f"SPC1,1,{''.join(str(c + 1) for c in range(6) if row[c])},{i + 1}")
    path.write_text("BEGIN BULK\nPARAM,COUPMASS,1\n" + f"PSHELL,1,1,{h!r},1,,1\n"
                    + f"MAT1,1,{E!r},,{nu!r},{RHO!r}\n" + "\n".join(lines) + "\nENDDATA\n")
    return path


def test_a_shell_of_nu_one_half_converges_to_navier(tmp_path):
    """Source: Navier's omega_11 = 2 pi^2 / a^2 sqrt(D / (rho h)), D = E h^3 / (12 (1 -
    NU^2)) at NU = 0.5, a/h = 500. Meshes 2 x 2 and 4 x 4: the error falls, and the
    finer one's is below the change between them plus Mindlin's difference
    ((pi h / a)^2 (1 + 2 / (kappa (1 - nu))) = 2.3e-4 at NU = 0.5)."""
    a, h, nu = 1.0, 0.002, 0.5
    D = E * h**3 / (12 * (1 - nu**2))
    navier = 2 * np.pi**2 / a**2 * np.sqrt(D / (RHO * h)) / (2 * np.pi)
    errs = []
    for nx in (2, 4):
        nm = read_deck(_plate(tmp_path / f"p{nx}.bdf", nx, nu, h, a))
        f = solve_elastic(nm.model.stiffness(), nm.model.mass(), 1).frequencies_hz[0]
        errs.append(f / navier - 1)
    assert abs(errs[1]) < abs(errs[0])
    assert abs(errs[1]) <= abs(errs[1] - errs[0]) + 2.3e-4, errs


@pytest.mark.parametrize("nu", [0.5000001, -1.2])
def test_a_shell_nu_outside_the_range_is_refused(tmp_path, run_cli, nu):
    _plate(tmp_path / "p.bdf", 2, nu)
    study = tmp_path / "s.toml"
    study.write_text('[model]\ntype = "nastran"\nbdf = "p.bdf"\n')
    code, out, err = run_cli("frequencies", study)
    one_line(code, err, "p.bdf: line 4: MAT1 1", f"NU = {nu}", "(-1, 0.5] for a shell")


def test_a_solid_of_nu_one_half_is_refused(tmp_path, run_cli):
    grids = [f"GRID,{i + 1},,{x}.,{y}.,{z}." for i, (x, y, z) in enumerate(
        [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1),
         (0, 1, 1)])]
    (tmp_path / "h.bdf").write_text("BEGIN BULK\nCHEXA,1,1,1,2,3,4,5,6\n,7,8\nPSOLID,1,1\n"
                                    "MAT1,1,2.e11,,0.5,7850.\n" + "\n".join(grids)
                                    + "\nSPC1,1,123,1,2,3,4\nENDDATA\n")
    study = tmp_path / "s.toml"
    study.write_text('[model]\ntype = "nastran"\nbdf = "h.bdf"\n')
    code, out, err = run_cli("frequencies", study)
    one_line(code, err, "h.bdf: line 5: MAT1 1", "NU = 0.5", "(-1, 0.5) for a solid")
