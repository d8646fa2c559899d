"""MAT9 (anisotropic moduli) on solids, in basic or a rectangular PSOLID CORDM.

Run for real in .venv-nastran (``make test``); skipped in the core environment."""

from __future__ import annotations

import itertools
import warnings

import numpy as np
import pytest
from nastran_frames import need

from eigenupdate.errors import InputError
from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.io.nastran import read_nastran  # noqa: E402

# G11 G12 ... G66 (Voigt xx yy zz xy yz zx, engineering shear, as MSC QRG MAT9), Pa
G = np.array([[180., 40., 30., 8., 3., 5.],
              [40., 120., 35., 4., 6., 2.],
              [30., 35., 100., 2., 5., 7.],
              [8., 4., 2., 45., 3., 4.],
              [3., 6., 5., 3., 38., 2.],
              [5., 2., 7., 4., 2., 30.]]) * 1e9
CORD = "CORD2R,5,,0.01,0.02,-0.03,0.31,0.42,0.97\n,0.9,-0.35,0.25"
# CalculiX 2.x, the same 4 x 2 x 2 C3D20 mesh, *ELASTIC,TYPE=ANISO with these moduli
# (D1111 = G11, D1112 = G14, ...) in *ORIENTATION,SYSTEM=RECTANGULAR along CORD2R 5's
# x and y axes, *DENSITY 7800, *FREQUENCY: its printed frequencies (7 digits)
CCX_HZ = [512.1230, 678.5983, 2660.353, 2855.970, 3677.826, 5373.813, 7040.330]


def _mat9(mid: int, g: np.ndarray, rho: float) -> str:
    f = ["MAT9", str(mid)] + [repr(float(g[i, j])) for i in range(6) for j in range(i, 6)]
    f.append(repr(rho))
    return ",".join(f[:9]) + "\n," + ",".join(f[9:17]) + "\n," + ",".join(f[17:])


def _block(material: str, cordm: str = "") -> str:
    """A 0.2 x 0.04 x 0.03 cantilever of 4 x 2 x 2 CHEXA20, clamped at x = 0."""
    nx, ny, nz = 4, 2, 2
    size = np.array([0.2 / nx, 0.04 / ny, 0.03 / nz]) / 2
    ids: dict = {}
    corners = [(0, 0, 0), (2, 0, 0), (2, 2, 0), (0, 2, 0),
               (0, 0, 2), (2, 0, 2), (2, 2, 2), (0, 2, 2)]
    edges = [(0, 1), (1, 2), (2, 3), (3, 0), (0, 4), (1, 5), (2, 6), (3, 7),
             (4, 5), (5, 6), (6, 7), (7, 4)]
    cards = []
    for e, (i, j, k) in enumerate(itertools.product(range(nx), range(ny), range(nz)), 1):
        c = [(2 * i + a, 2 * j + b, 2 * k + d) for a, b, d in corners]
        pts = c + [tuple((p + q) // 2 for p, q in zip(c[a], c[b], strict=True))
                   for a, b in edges]
        nodes = [ids.setdefault(p, len(ids) + 1) for p in pts]
        cards.append(f"CHEXA,{e},1," + ",".join(map(str, nodes[:6])) + "\n,"
                     + ",".join(map(str, nodes[6:14])) + "\n," + ",".join(map(str, nodes[14:])))
    grids = [f"GRID,{n},,{p[0] * size[0]!r},{p[1] * size[1]!r},{p[2] * size[2]!r}"
             for p, n in ids.items()]
    spc = [f"SPC1,1,123,{n}" for p, n in ids.items() if p[0] == 0]
    return "\n".join(["SOL 103", "CEND", "SPC = 1", "BEGIN BULK", "PARAM,COUPMASS,1",
                      f"PSOLID,1,9,{cordm}", material, CORD, *grids, *cards, *spc,
                      "ENDDATA", ""])


def _hz(tmp_path, text: str, n: int = 7) -> np.ndarray:
    path = tmp_path / "block.bdf"
    path.write_text(text)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = read_nastran(path).model
    return solve_elastic(model.stiffness(), model.mass(), n).frequencies_hz


def test_anisotropic_mat9_in_a_rotated_cordm_matches_calculix(tmp_path):
    """General anisotropic MAT9 (all 21 moduli) in a rotated rectangular CORDM against
    CalculiX's C3D20 with *ELASTIC,TYPE=ANISO in the same material axes (CCX_HZ). Both
    are the 20-node serendipity hexahedron with 3 x 3 x 3 Gauss points and consistent
    mass, so they differ by CalculiX's 7-digit print (5e-7) and round-off: 2e-6. Without
    the CORDM the frequencies move by up to 8 %, so the test sees the rotation."""
    hz = _hz(tmp_path, _block(_mat9(9, G, 7800.0), "5"))
    np.testing.assert_allclose(hz, CCX_HZ, rtol=2e-6)
    basic = _hz(tmp_path, _block(_mat9(9, G, 7800.0)))
    assert np.max(np.abs(basic / CCX_HZ - 1)) > 0.05


def test_isotropic_mat9_is_mat1(tmp_path):
    """Hooke's law: MAT9 with G11 = lambda + 2 mu, G12 = lambda, G44 = mu (from E, NU)
    is MAT1 E, NU in any material axes; same element and mass, so the frequencies agree
    to the eigen-solver's round-off (1e-9 here, far above 1e-12)."""
    e, nu = 2.0e11, 0.3
    lam, mu = e * nu / ((1 + nu) * (1 - 2 * nu)), e / (2 * (1 + nu))
    g = np.zeros((6, 6))
    g[:3, :3] = lam
    g[range(3), range(3)] += 2 * mu
    g[range(3, 6), range(3, 6)] = mu
    mat1 = _hz(tmp_path, _block(f"MAT1,9,{e!r},,{nu!r},7800."))
    for cordm in ("", "5"):
        np.testing.assert_allclose(_hz(tmp_path, _block(_mat9(9, g, 7800.0), cordm)), mat1,
                                   rtol=1e-9)


@pytest.mark.parametrize("edit, message", [
    (lambda t: t.replace("CORD2R,5", "CORD2C,5"), "PSOLID 1: CORDM 5 with MAT9 9: only a "
     "rectangular"),
    (lambda t: t.replace("PSOLID,1,9,5", "PSOLID,1,9,-1"), "CORDM -1 with MAT9 9"),
    (lambda t: t.replace("MAT9,9,180", "MAT9,9,-180"), "MAT9 9: G11 ... G66 is not positive "
     "definite"),
])
def test_mat9_refusals(tmp_path, edit, message):
    """What is not supported is named: a cylindrical or element material system (axes
    that vary over the element) and moduli that are no elastic material."""
    path = tmp_path / "block.bdf"
    path.write_text(edit(_block(_mat9(9, G, 7800.0), "5")))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(InputError, match=message.replace(".", r"\.")):
            read_nastran(path)


def test_mat9_on_a_bar_is_named(tmp_path):
    """A MAT9 is read for solids only: a CBAR's PBAR naming one is refused naming the
    material's card (it used to say 'MAT1 9 is not defined')."""
    path = tmp_path / "bar.bdf"
    path.write_text("\n".join([
        "SOL 103", "CEND", "BEGIN BULK", "GRID,1,,0.,0.,0.", "GRID,2,,1.,0.,0.",
        "CBAR,1,1,1,2,0.,1.,0.", "PBAR,1,9,1.e-4,1.e-9,1.e-9,2.e-9", _mat9(9, G, 7800.0),
        "SPC1,1,123456,1", "ENDDATA", ""]))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(InputError, match="material MAT9 9 is not supported here"):
            read_nastran(path)
