"""Corner thicknesses T1-T4 (CQUAD8) and T1-T3 (CTRIA6) with TFLAG (io/nastran_corners.py;
the corners' bilinear / linear field at every node, model/shells_quadratic.py
``nodal_profile`` and ``profile``). Independent references: the deck without T1-T4
(equal corners are the property's T), a second method (the Timoshenko beam of
tests/io/test_nastran_corners.py, Ritz to 1e-9), a second code (CalculiX 2.20's S8R with
*NODAL THICKNESS on the same CQUAD8 mesh), the closed-form mass of the tapered strip,
central differences of K, M, the deck edited and read again, and a curved CTRIA6's four
facets written by hand as CTRIA3. Runs in .venv-nastran (pyNastran)."""

from __future__ import annotations

import re
import shutil

import numpy as np
import pytest
from bounds import assert_matrix_derivatives
from nastran_frames import need, read_quiet

from eigenupdate.errors import InputError
from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")
from test_nastran_corners import (  # noqa: E402
    FIELDS,
    NSM,
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
    _specs,
    timoshenko,
)

CARDS = ["CQUAD8", "CTRIA6"]


def strip(path, nx, ny=1, card="CQUAD8", tflag=0, thick=None, zoffs="", own=None,
          held="", pshell=f"PSHELL,1,1,{T!r},1,,1"):
    """The cantilever strip L x B of tests/io/test_nastran_corners.py (clamped at x = 0)
    of nx x ny CQUAD8, or each split in two CTRIA6 along its G1-G3 diagonal, on a grid of
    corners and mid-sides (2 nx + 1 by 2 ny + 1 grids, a CQUAD8's centre unused); corner
    thickness ``thick(x)`` (default linear from T0 to T1; None: blank) as TFLAG
    ``tflag`` (1: over T); the corners of elements whose centre x fails ``own`` blank;
    ``held``: components held at every grid besides the clamp."""
    thick = thick or (lambda x: T0 + (T1 - T0) * x / L)
    ids = (np.arange((2 * nx + 1) * (2 * ny + 1)) + 1).reshape(2 * ny + 1, 2 * nx + 1)
    x = np.linspace(0.0, L, 2 * nx + 1)
    y = np.linspace(0.0, B, 2 * ny + 1)
    used = set()
    elems = []
    for j in range(0, 2 * ny, 2):
        for i in range(0, 2 * nx, 2):
            c = ids[j:j + 3, i:i + 3]  # c[row (y), column (x)]
            if card == "CQUAD8":
                elems.append([c[0, 0], c[0, 2], c[2, 2], c[2, 0], c[0, 1], c[1, 2], c[2, 1],
                              c[1, 0]])
            else:
                elems.append([c[0, 0], c[0, 2], c[2, 2], c[0, 1], c[1, 2], c[1, 1]])
                elems.append([c[0, 0], c[2, 2], c[2, 0], c[1, 1], c[2, 1], c[1, 0]])
    lines = ["BEGIN BULK", "PARAM,COUPMASS,1", pshell, f"MAT1,1,{E!r},,{NU!r},{RHO!r}"]
    xg = {int(ids[j, i]): x[i] for j in range(2 * ny + 1) for i in range(2 * nx + 1)}
    for k, g in enumerate(elems):
        used.update(g)
        corners = g[:4] if card == "CQUAD8" else g[:3]
        mine = own is None or own(np.mean([xg[n] for n in corners]))
        ts = [thick(xg[n]) for n in corners]
        ts = ["" if not mine or t is None else repr(t / T if tflag else t) for t in ts]
        g = [str(n) for n in g]
        if card == "CQUAD8":
            lines.append(f"CQUAD8,{k + 1},1,{','.join(g[:6])}\n,{','.join(g[6:])},"
                         f"{','.join(ts)},,{zoffs}\n,{tflag}")
        else:
            lines.append(f"CTRIA6,{k + 1},1,{','.join(g)}\n,,{zoffs},{','.join(ts)},{tflag}")
    for n in sorted(used):
        j, i = np.argwhere(ids == n)[0]
        lines.append(f"GRID,{n},,{x[i]!r},{y[j]!r},0.")
        if i == 0:
            lines.append(f"SPC1,1,123456,{n}")
        elif held:
            lines.append(f"SPC1,1,{held},{n}")
    path.write_text("\n".join(lines) + "\nENDDATA\n")
    return path


@pytest.mark.parametrize("card", CARDS)
def test_corners_equal_to_t_read_as_without_them(tmp_path, card):
    """Source: NASTRAN's convention (MSC QRG CQUAD8/CTRIA6: Ti the thickness at corner
    Gi, blank the PSHELL's T; TFLAG 1: fractions of it): T1-T4 all equal to T (TFLAG 0),
    all 1.0 (TFLAG 1) or blank give the matrices of the deck without them, bit for bit
    (uniform elements keep their path), and a linear taper written as thicknesses
    (TFLAG 0) or fractions (TFLAG 1) the same K and M (the fractions' product with T:
    round-off, 1e-12)."""
    ref = read_quiet(strip(tmp_path / "r.bdf", 4, 2, card, own=lambda x: False)).model
    for tflag, name in ((0, "t"), (1, "f")):
        m = read_quiet(strip(tmp_path / f"{name}.bdf", 4, 2, card, tflag,
                             thick=lambda x: T)).model
        for a, b in ((m.stiffness(), ref.stiffness()), (m.mass(), ref.mass())):
            assert (a != b).nnz == 0
    a, b = (read_quiet(strip(tmp_path / f"l{f}.bdf", 4, 2, card, f)).model for f in (0, 1))
    assert abs(a.stiffness() - ref.stiffness()).max() > 0.1 * abs(ref.stiffness()).max()
    for x, y in ((a.stiffness(), b.stiffness()), (a.mass(), b.mass())):
        assert abs(x - y).max() <= 1e-12 * abs(y).max()


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


@pytest.mark.parametrize("card", CARDS)
def test_tapered_strip_in_cylindrical_bending_is_the_timoshenko_beam(tmp_path, card):
    """Source: a second method, the strip tapered T0 to T0/2 with rx held everywhere
    (cylindrical bending) is a Timoshenko beam of plate modulus (test_nastran_corners.py
    :func:`timoshenko`, converged to 1e-9): bending t^3, shear and mass t at each point,
    three bending modes. The finer mesh's error is below its change from the coarser
    when the error falls at least by half from one to the other, and it falls faster:
    measured at 10, 20, 40 elements, CQUAD8 1.7e-6, 1.1e-7, 7.7e-9 (first mode; the
    third 5.9e-4, 3.9e-5, 2.6e-6: as h^4), CTRIA6 -4.3e-4, -1.1e-4, -2.8e-5 (the third
    -2.5e-3, -7.8e-4, -2.7e-4: as h^2): the change from 10 to 20 bounds the error at 20."""
    ref = timoshenko()
    nx = (10, 20)
    got = [_hz(strip(tmp_path / f"s{n}.bdf", n, max(1, n // 10), card, held="4"), 6)
           for n in nx]
    bending = [np.argmin(np.abs(got[1] - f)) for f in ref]
    a, b = (g[bending] for g in got)
    assert np.all(np.abs(b - ref) <= np.abs(b - a)), (a, b, ref)


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
    ours = [_hz(strip(tmp_path / f"o{n}.bdf", n, n // 10), 6) for n in (20, 40)]
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
def test_thickness_parameter_scales_a_tflag1_taper(tmp_path, card):
    """Sources: central differences of K, M (tests/bounds.py: K is a polynomial in T,
    E, RHO but CTRIA6's shear stabilisation, smooth) of a strip tapered by fractions of
    T (TFLAG 1) with NSM and ZOFFS, and the deck with T, E and RHO edited in its text and
    read again (the same element integrals: round-off, 1e-12 of the largest entry)."""
    path = strip(tmp_path / "a.bdf", 6, 2, card, 1, zoffs="0.005", pshell=NSM)
    text = path.read_text()
    nm = read_quiet(path, _specs(FIELDS))
    assert_matrix_derivatives(nm.model)
    new = [1.1 * T, 1.05 * E, 1.2 * RHO]
    edited = tmp_path / "b.bdf"
    edited.write_text(text.replace(NSM, NSM.replace("0.02", repr(new[0]))).replace(
        f"MAT1,1,{E!r},,{NU!r},{RHO!r}", f"MAT1,1,{new[1]!r},,{NU!r},{new[2]!r}"))
    ref = read_quiet(edited).model
    for a, b in ((nm.model.stiffness(new), ref.stiffness()), (nm.model.mass(new), ref.mass())):
        assert abs(a - b).max() <= 1e-12 * abs(b).max()


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


@pytest.mark.parametrize("card", CARDS)
def test_nsm_stays_uniform_per_area_under_a_taper(tmp_path, card):
    """Source: MSC QRG PSHELL (NSM is mass per unit area), as CQUAD4's
    (test_nastran_corners.py): with RHO = 0 the mass is NSM's alone, so a strip tapered
    8:1 has the M of one without corners (round-off, 1e-12)."""
    pshell = f"PSHELL,1,1,{T!r},1,,1,,3.5"
    mat = f"MAT1,1,{E!r},,{NU!r},{RHO!r}"

    def mass(name, thick):
        path = strip(tmp_path / name, 4, 1, card, pshell=pshell, thick=thick)
        path.write_text(path.read_text().replace(mat, f"MAT1,1,{E!r},,{NU!r},0."))
        return read_quiet(path).model.mass()

    uniform, tapered = mass("u.bdf", lambda x: None), mass("t.bdf", lambda x: 0.04 - 0.035 * x)
    assert abs(uniform).max() > 0
    assert abs(tapered - uniform).max() <= 1e-12 * abs(uniform).max()


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


PCOMP = "PCOMP,1\n,1,0.02,0."


@pytest.mark.parametrize(("edit", "fields", "message"), [
    (lambda p: strip(p, 4, 1, "CQUAD8", pshell=PCOMP), (), "CQUAD8 1: corner "
     "thicknesses T1-T4 (TFLAG 0): differing from PCOMP 1's thickness 0.02 (the sum of "
     "its plies)"),
    (lambda p: strip(p, 4, 1, "CTRIA6", pshell=PCOMP), (), "CTRIA6 1: corner "
     "thicknesses T1-T3 (TFLAG 0): differing from PCOMP 1's thickness 0.02"),
    (lambda p: strip(p, 4, 1, "CTRIA6", thick=lambda x: 0.0), (), "CTRIA6 1: corner "
     "thicknesses T1-T3 (TFLAG 0): all zero"),
    (lambda p: strip(p, 4, 1, "CQUAD8", thick=lambda x: T if x < 0.6 else None),
     FIELDS[:1], "PSHELL 1 field T: not a parameter of CQUAD8 3, whose corner "
     "thicknesses are partly its own"),
], ids=["CQUAD8-PCOMP", "CTRIA6-PCOMP", "CTRIA6-all-zero", "CQUAD8-mixed-with-T"])
def test_corner_thicknesses_refused_in_one_line(tmp_path, run_cli, edit, fields, message):
    """Unsupported corner thicknesses on CQUAD8 / CTRIA6 (a laminate's, whose coupling
    with a taper is not formed) and bad ones: one line naming the element (or the
    parameter's card) and the problem, exit 2, through the CLI."""
    from refusals import one_line

    deck = edit(tmp_path / "deck.bdf")
    table = "".join(f'[[model.parameter]]\nname = "p{i}"\ncard = "{c}"\nid = {j}\n'
                    f'field = "{f}"\n' for i, (c, j, f) in enumerate(fields))
    study = tmp_path / "study.toml"
    study.write_text(f'[model]\ntype = "nastran"\nbdf = "{deck}"\n{table}')
    code, _, err = run_cli("frequencies", study, "--modes", "1")
    one_line(code, err, "deck.bdf", message, warnings_allowed=True)
    with pytest.raises(InputError, match=re.escape(message.split(": ", 1)[-1][:30])):
        read_quiet(deck, _specs(fields))
