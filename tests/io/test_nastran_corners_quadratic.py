"""Corner thicknesses T1-T4 (CQUAD8) and T1-T3 (CTRIA6) with TFLAG (io/nastran_corners.py;
the corners' bilinear / linear field at every node, model/shells_quadratic.py
``nodal_profile`` and ``profile``), beyond the checks they share with CQUAD4 in
tests/io/test_nastran_corners.py (the deck without T1-T4, the Timoshenko beam, central
differences, NSM, refusals). Independent references: the closed-form mass of the
tapered strip, a second code (CalculiX 2.20's S8R with *NODAL THICKNESS on the same
CQUAD8 mesh), exact invariance under ZOFFS's rigid link, and a curved CTRIA6's four
facets written by hand as CTRIA3. Runs in .venv-nastran (pyNastran)."""

from __future__ import annotations

import re
import shutil

import numpy as np
import pytest
from nastran_frames import need, read_quiet

from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")
from test_nastran_corners import (  # noqa: E402
    NU,
    RHO,
    T0,
    T1,
    B,
    E,
    L,
    T,
    _calculix,
    _hz,
    strip,
)

CARDS = ["CQUAD8", "CTRIA6"]


@pytest.mark.parametrize("coupled", [True, False], ids=["coupled", "lumped"])
@pytest.mark.parametrize("card", CARDS)
def test_tapered_strip_mass_is_the_closed_form(tmp_path, card, coupled):
    """Source: closed form, the mass of the strip tapered linearly from T0 to T1,
    RHO B L (T0 + T1) / 2 (the profile's field is exact, and RHO t times the shape
    functions is integrated exactly: degree 3 in x on 3 x 3 Gauss points and Dunavant's
    degree 4), coupled or HRZ-lumped (which scales its diagonal to the element's mass):
    round-off, 1e-12."""
    path = strip(tmp_path / "m.bdf", 4, 2, card)
    text = re.sub(r"SPC1,.*\n", "", path.read_text())  # free: every grid's mass
    path.write_text(text if coupled else text.replace("PARAM,COUPMASS,1\n", ""))
    M = read_quiet(path).model.mass()
    ux = np.zeros(M.shape[0])
    ux[0::6] = 1.0  # every grid moved along x
    exact = RHO * B * L * (T0 + T1) / 2
    assert ux @ (M @ ux) == pytest.approx(exact, rel=1e-12)


@pytest.mark.skipif(shutil.which("ccx") is None, reason="CalculiX (ccx) absent")
def test_tapered_cantilever_cquad8_strip_agrees_with_calculix(tmp_path):
    """Source: a second code, CalculiX 2.20's S8R (8-node shells expanded to 20-node
    bricks) with *NODAL THICKNESS on the same CQUAD8 mesh (nx x nx / 10, clamped at its
    root, T0 to T0/2 at its tip, every node's thickness the linear taper's): the three
    bending modes and the in-plane bending mode (membrane t). The formulations differ
    on one mesh, so the bound is each code's 40-element error plus their plate models'
    difference O((T0/L)^2) = 4e-4. Ours: its change from 20 elements (CQUAD8 converges
    as h^4 in bending, above). CalculiX's S8R converges more slowly (measured ratios of
    successive changes 1.7-2.0 in the bending modes: its change would not bound its
    error), so its error is Richardson's estimate |c40 - c20| / (r - 1), r the ratio of
    its changes from 10 to 20 and 20 to 40 (required > 1.2: converging). Measured: 0.18,
    0.19, 0.001, 0.19 % apart, bounds 0.31, 0.33, 0.11, 0.30 %. The torsion mode is
    left out (a strip B / T0 = 5 twists as a solid section, not a plate)."""
    ours = [_hz(strip(tmp_path / f"o{n}.bdf", n, n // 10, "CQUAD8"), 6) for n in (20, 40)]
    ccx = [_calculix(tmp_path, n) for n in (10, 20, 40)]
    modes = [0, 1, 2, 3]
    got = [np.array([o[np.argmin(np.abs(o - c))] for c in ccx[2][modes]]) for o in ours]
    c10, c20, c40 = (c[modes] for c in ccx)
    ratio = np.abs(c20 - c10) / np.abs(c40 - c20)
    assert np.all(ratio > 1.2), ratio
    bound = (np.abs(got[1] - got[0]) + np.abs(c40 - c20) / (ratio - 1)
             + (T0 / L) ** 2 * c40)
    assert np.all(np.abs(got[1] - c40) <= bound), (got, c40, bound)


@pytest.mark.parametrize("card", CARDS)
def test_free_offset_tapered_strip_keeps_its_frequencies(tmp_path, card):
    """Source: exact invariance (as test_nastran_quadratic_offsets.py's plate): ZOFFS
    puts the tapered element on its reference plane rigidly linked to the grids, an
    invertible link, so the free strip keeps the frequencies of the one without ZOFFS
    to the eigen-solver's rounding (1e-9 with room) and six rigid modes; and the mass's
    first moment about the grid plane (u with ry) is the closed form m z, m = RHO B L
    (T0 + T1) / 2 (round-off, 1e-12)."""
    z = 0.01

    def free(name, zoffs):
        path = strip(tmp_path / name, 6, 1, card, zoffs=zoffs)
        path.write_text(re.sub(r"SPC1,.*\n", "", path.read_text()))
        return read_quiet(path).model

    plain, moved = free("a.bdf", ""), free("b.bdf", repr(z))
    ref = solve_elastic(plain.stiffness(), plain.mass(), 10).frequencies_hz
    sol = solve_elastic(moved.stiffness(), moved.mass(), 10)
    assert sol.n_rigid == 6
    assert np.max(np.abs(sol.frequencies_hz[6:] / ref[6:] - 1)) <= 1e-9
    M = moved.mass()
    u, ry = np.zeros(M.shape[0]), np.zeros(M.shape[0])
    u[0::6], ry[4::6] = 1.0, 1.0
    assert u @ (M @ ry) == pytest.approx(RHO * B * L * (T0 + T1) / 2 * z, rel=1e-12)


def _curved_tria6(path, facets, tapered=True):
    """A free cylinder patch (radius 1, 12 elements round, 2 x 2 along 1) of CTRIA6,
    curved beyond the flat projection (read as four CTRIA3, shells_quadratic.FACETS),
    their corners tapered along the axis z (0.02 to 0.01, TFLAG 0); ``facets``: the same
    grids written as those four CTRIA3, each grid's thickness the CTRIA6's field there
    (a mid-side grid the mean of its edge's corners); not ``tapered``: corners blank."""
    from quadratic_meshes import cylinder_mesh

    from eigenupdate.model.shells_quadratic import FACETS

    xyz, el = cylinder_mesh(12, 2, 1.0, 1.0, True)
    lines = [f"GRID,{i + 1},,{x!r},{y!r},{z!r}" for i, (x, y, z) in enumerate(xyz)]
    for k, e in enumerate(el):
        t = [T0 + (T1 - T0) * xyz[n, 2] for n in e[:3]]
        t += [(t[a] + t[b]) / 2 for a, b in ((0, 1), (1, 2), (2, 0))]
        g = [str(n + 1) for n in e]
        if facets:
            lines += [f"CTRIA3,{4 * k + j + 1},1," + ",".join(g[i] for i in f)
                      + ",,\n,,0," + ",".join(repr(t[i]) for i in f)
                      for j, f in enumerate(FACETS)]
        else:
            lines.append(f"CTRIA6,{k + 1},1," + ",".join(g) + "\n,,," +
                         ",".join(repr(x) if tapered else "" for x in t[:3]) + ",0")
    path.write_text("BEGIN BULK\nPARAM,COUPMASS,1\n" f"PSHELL,1,1,{T!r},1,,1\n"
                    f"MAT1,1,{E!r},,{NU!r},{RHO!r}\n" + "\n".join(lines) + "\nENDDATA\n")
    return path


def test_curved_tapered_ctria6_is_its_four_tapered_facets(tmp_path):
    """Source: the deck written by hand with the four CTRIA3 a curved CTRIA6 is read as,
    each grid's thickness the CTRIA6's linear field there (its facets interpolate it
    exactly): the same K and M (the corners over T and their means in another order:
    round-off, 1e-12)."""
    curved = read_quiet(_curved_tria6(tmp_path / "t6.bdf", False)).model
    flat = read_quiet(_curved_tria6(tmp_path / "t3.bdf", True)).model
    plain = read_quiet(_curved_tria6(tmp_path / "u6.bdf", False, False)).model
    assert abs(curved.stiffness() - plain.stiffness()).max() > 0.1 * abs(
        plain.stiffness()).max()
    for a, b in ((curved.stiffness(), flat.stiffness()), (curved.mass(), flat.mass())):
        assert abs(a - b).max() <= 1e-12 * abs(b).max()
