"""CQUAD8 and CTRIA6 decks read through read_nastran: the model-level elements on the
same mesh (a second path: tests/quadratic_meshes.py), a mixed CQUAD8/CQUAD4 plate
against Navier, PSHELL T as a parameter (hand-edited deck, central differences, the
updated BDF read back), a one-ply PCOMP against its PSHELL (blank mid-side grids:
test_nastran_transition_shells.py).
Runs in .venv-nastran (pyNastran)."""

from __future__ import annotations

import numpy as np
import pytest
from bounds import assert_matrix_derivatives
from nastran_frames import need
from plates import plate_fixed
from quadratic_meshes import NU, RHO, E, plate_frequency, plate_mesh

from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")
from test_nastran_shell_thickness import FIELDS, INIT, _read, _spec  # noqa: E402

from eigenupdate.io.nastran_write import write_updated_bdf  # noqa: E402


def _spc(xyz, a) -> list[str]:
    """SPC1 cards of :func:`plates.plate_fixed`'s hard simple support."""
    fixed = plate_fixed(xyz, a, "ss")
    out = []
    for i, row in enumerate(fixed):
        comps = "".join(str(c + 1) for c in range(6) if row[c])
        out.append(f"SPC1,1,{comps},{i + 1}")
    return out


def plate(path, v=INIT, nx=4, a=1.0, triangles=False, nsm=0.5, prop="PSHELL"):
    """An a x a CQUAD8 (CTRIA6) plate, hard simple support; PSHELL 1 (t1) on x < a/2,
    PSHELL 2 (t2, NSM) beyond (``prop`` "PCOMP": PCOMP 1 and 2 of one MAT1 ply each),
    MAT1 1; values written with every digit (repr)."""
    xyz, el = plate_mesh(nx, a, a, triangles)
    lines = [f"GRID,{i + 1},,{x!r},{y!r},0." for i, (x, y, _) in enumerate(xyz)]
    card = "CTRIA6" if triangles else "CQUAD8"
    for k, e in enumerate(el):
        pid = 1 if xyz[e[:3], 0].mean() < a / 2 else 2
        g = [str(n + 1) for n in e]
        lines.append(f"{card},{k + 1},{pid}," + ",".join(g[:6]) + ("\n," + ",".join(g[6:])
                                                                   if len(g) > 6 else ""))
    if prop == "PSHELL":
        # TS/T written as 5/6 to every digit (blank: pyNastran's .833333, 4e-7 off PCOMP's
        # and the model-level default)
        props = (f"PSHELL,1,1,{v['t1']!r},1,,1,{5 / 6!r}\n"
                 f"PSHELL,2,1,{v['t2']!r},1,,1,{5 / 6!r},{nsm!r}\n")
    else:
        props = (f"PCOMP,1\n,1,{v['t1']!r},0.\nPCOMP,2,,{nsm!r}\n,1,{v['t2']!r},30.\n")
    path.write_text("BEGIN BULK\nPARAM,COUPMASS,1\n" + props
                    + f"MAT1,1,{v['E']!r},,{NU!r},{v['rho']!r}\n"
                    + "\n".join(lines + _spc(xyz, a)) + "\nENDDATA\n")
    return path


@pytest.mark.parametrize("triangles", [False, True], ids=["CQUAD8", "CTRIA6"])
def test_deck_gives_the_elements_frequency(tmp_path, triangles):
    """Source: the model-level elements assembled directly on the same mesh and
    supports (quadratic_meshes.plate_frequency), one thickness everywhere, no NSM: the
    deck's grid order, PSHELL moduli and supports must give the same lowest frequency,
    to the eigen-solvers' agreement (1e-9 relative; both are backward-stable)."""
    h = 0.002
    v = dict(INIT, t1=h, t2=h)
    nm = _read(plate(tmp_path / "p.bdf", v, nx=4, triangles=triangles, nsm=0.0))
    f = solve_elastic(nm.model.stiffness(), nm.model.mass(), 1).frequencies_hz[0]
    ref = plate_frequency(4, 1.0, h, "ss", triangles) / (2 * np.pi)
    assert f == pytest.approx(ref, rel=1e-9)


def test_mixed_cquad8_cquad4_deck_converges_to_navier(tmp_path):
    """Source: Navier's omega_11 = 2 pi^2 / a^2 sqrt(D / (rho h)) of the simply supported
    square, a/h = 500. Left half CQUAD8 (n x 2n), right half CQUAD4 twice as fine, the
    CQUAD8 mid-side grids shared with the CQUAD4 corners on the interface (as NASTRAN
    meshes are joined). Meshes n = 2, 4: the error falls (both elements converge as the
    mesh size squared here), and the finer one's is below the change between them plus
    Mindlin's difference ((pi h / a)^2 (1 + 2 / (kappa (1 - nu))) = 1.8e-4)."""
    a, h = 1.0, 0.002
    D = E * h**3 / (12 * (1 - NU**2))
    navier = 2 * np.pi**2 / a**2 * np.sqrt(D / (RHO * h)) / (2 * np.pi)
    errs = []
    for n in (2, 4):
        m = 4 * n  # fine grid intervals per side
        ix, iy = np.meshgrid(np.arange(m + 1), np.arange(m + 1), indexing="ij")
        ix, iy = ix.ravel(), iy.ravel()
        gid = {(i, j): k + 1 for k, (i, j) in enumerate(zip(ix, iy, strict=True))}
        used, cards = set(), []
        for i in range(0, m // 2, 2):  # CQUAD8 on the left half
            for j in range(0, m, 2):
                g = [gid[p] for p in ((i, j), (i + 2, j), (i + 2, j + 2), (i, j + 2),
                                      (i + 1, j), (i + 2, j + 1), (i + 1, j + 2),
                                      (i, j + 1))]
                cards.append(f"CQUAD8,{len(cards) + 1},1," + ",".join(map(str, g[:6]))
                             + "\n," + ",".join(map(str, g[6:])))
                used.update(g)
        for i in range(m // 2, m):
            for j in range(m):
                g = [gid[p] for p in ((i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1))]
                cards.append(f"CQUAD4,{len(cards) + 1},1," + ",".join(map(str, g)))
                used.update(g)
        xyz = np.column_stack([ix / m * a, iy / m * a, np.zeros(ix.size)])
        keep = sorted(used)
        grids = [f"GRID,{g},,{xyz[g - 1, 0]!r},{xyz[g - 1, 1]!r},0." for g in keep]
        fixed = plate_fixed(xyz, a, "ss")
        spc = [f"SPC1,1,{''.join(str(c + 1) for c in range(6) if fixed[g - 1, c])},{g}"
               for g in keep]
        deck = tmp_path / f"mixed{n}.bdf"
        deck.write_text("BEGIN BULK\nPARAM,COUPMASS,1\n" + f"PSHELL,1,1,{h!r},1,,1\n"
                        + f"MAT1,1,{E!r},,{NU!r},{RHO!r}\n"
                        + "\n".join(grids + cards + spc) + "\nENDDATA\n")
        nm = _read(deck)
        f = solve_elastic(nm.model.stiffness(), nm.model.mass(), 1).frequencies_hz[0]
        errs.append(f / navier - 1)
    assert abs(errs[1]) < abs(errs[0])
    assert abs(errs[1]) <= abs(errs[1] - errs[0]) + 1.8e-4, errs


@pytest.mark.parametrize("triangles", [False, True], ids=["CQUAD8", "CTRIA6"])
def test_thickness_parameters_match_the_hand_edited_deck_and_differences(tmp_path,
                                                                          triangles):
    """Source: the deck with T, E, RHO changed in its text and read again (the same
    element matrices times products of the same values: a few ulps of the largest
    entry), and central differences of K(s), M(s) (tests/bounds.py)."""
    nm = _read(plate(tmp_path / "a.bdf", triangles=triangles), _spec())
    assert nm.model.nonlinear
    new = dict(zip(INIT, np.array(list(INIT.values())) * [1.1, 0.93, 1.05, 0.97],
                   strict=True))
    ref = _read(plate(tmp_path / "b.bdf", new, triangles=triangles)).model
    s = np.array(list(new.values()))
    for a, b in ((nm.model.stiffness(s), ref.stiffness()), (nm.model.mass(s), ref.mass())):
        assert abs(a - b).max() <= 1e-12 * abs(b).max()
    assert_matrix_derivatives(nm.model)


def test_updated_bdf_writes_the_cquad8_thickness(tmp_path):
    """Source: the written deck read back (12 significant digits written)."""
    nm = _read(plate(tmp_path / "a.bdf"), _spec(FIELDS[:2]))
    out = tmp_path / "updated.bdf"
    write_updated_bdf(nm, out, {"t1": 0.0043, "t2": 0.0057})
    back = _read(out, _spec(FIELDS[:2])).model.values
    assert back == pytest.approx([0.0043, 0.0057], rel=1e-11)
    # and the model read back is the model at those values
    again = _read(out).model
    s = np.array([0.0043, 0.0057])  # written with 12 digits: exact for these
    assert abs(again.stiffness() - nm.model.stiffness(s)).max() <= 1e-12 * abs(
        again.stiffness()).max()


def test_one_ply_pcomp_is_its_pshell(tmp_path):
    """Source: classical laminate theory of one isotropic ply of thickness T (A = Q T,
    D = Q T^3 / 12, shear 5/6 G T: PSHELL's defaults), whatever its angle (30 degrees on
    PCOMP 2: the material axes enter through CQUAD8's centre axes)."""
    a = _read(plate(tmp_path / "s.bdf")).model
    b = _read(plate(tmp_path / "c.bdf", prop="PCOMP")).model
    for x, y in ((a.stiffness(), b.stiffness()), (a.mass(), b.mass())):
        assert abs(x - y).max() <= 1e-12 * abs(x).max()


@pytest.mark.parametrize("card", ["CQUAD8", "CTRIA6"])
def test_ply_angle_follows_the_element_axes(tmp_path, card):
    """Source: THETA is measured from the element's xi line (CQUAD8 remark 3; CTRIA6:
    from G1-G2). Numbering a square CQUAD8 from G2 instead of G1 turns that line by +90
    degrees, so THETA - 90 gives the same material axes and the same K (a CTRIA6 with
    right-angled corners numbered from G2: its G1-G2 line turns by +135 degrees). An
    orthotropic MAT8 ply at 30 degrees, so a wrong angle changes K at order one. K6ROT
    0: the drilling penalty takes the in-plane shear modulus in element axes, which for
    an orthotropic ply changes with them (period 90 degrees: 2.5e-6 of K here)."""
    base = ("BEGIN BULK\nPARAM,K6ROT,0.\nGRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nGRID,3,,1.,1.,0.\n"
            "GRID,4,,0.,1.,0.\nGRID,5,,.5,0.,0.\nGRID,6,,1.,.5,0.\nGRID,7,,.5,1.,0.\n"
            "GRID,8,,0.,.5,0.\nGRID,9,,.5,.5,0.\n"
            "MAT8,2,1.4e11,9.e9,.3,5.e9,5.e9,3.e9,1600.\n")
    if card == "CQUAD8":
        order = [(1, 2, 3, 4, 5, 6, 7, 8), (2, 3, 4, 1, 6, 7, 8, 5)]
        turn = 90.0
    else:
        order = [(1, 2, 4, 5, 9, 8), (2, 4, 1, 9, 8, 5)]
        turn = 135.0
    mats = []
    for nodes, theta in zip(order, (30.0, 30.0 - turn), strict=True):
        head, tail = nodes[:6], nodes[6:]
        el = f"{card},1,1," + ",".join(map(str, head))
        el += ("\n," + ",".join(map(str, tail)) if tail else "")
        deck = tmp_path / f"{card}{len(mats)}.bdf"
        deck.write_text(base + el + f"\nPCOMP,1\n,2,.01,{theta!r}\nENDDATA\n")
        mats.append(_read(deck).model.stiffness())
    a, b = mats
    assert abs(a - b).max() <= 1e-12 * abs(a).max()


def _cylinder_deck(path, nc, nl, facets=False, R=1.0, L=1.0, h=0.01):
    """A free cylinder (radius R, length L, PSHELL h, MAT1 with NU = 0) of nc x nl x 2
    CTRIA6 with their mid-side grids on the surface; ``facets``: the same grids as four
    CTRIA3 per triangle (shells_quadratic.FACETS)."""
    from quadratic_meshes import cylinder_mesh

    from eigenupdate.model.shells_quadratic import FACETS

    xyz, el = cylinder_mesh(nc, nl, R, L, True)
    lines = [f"GRID,{i + 1},,{x!r},{y!r},{z!r}" for i, (x, y, z) in enumerate(xyz)]
    for k, e in enumerate(el):
        g = [str(n + 1) for n in e]
        if facets:
            lines += [f"CTRIA3,{4 * k + j + 1},1," + ",".join(g[i] for i in f)
                      for j, f in enumerate(FACETS)]
        else:
            lines.append(f"CTRIA6,{k + 1},1," + ",".join(g))
    path.write_text("BEGIN BULK\nPARAM,COUPMASS,1\n"
                    f"PSHELL,1,1,{h!r},1,,1,{5 / 6!r}\nMAT1,1,{E!r},,0.,{RHO!r}\n"
                    + "\n".join(lines) + "\nENDDATA\n")
    return path


def test_curved_ctria6_are_four_flat_facets(tmp_path):
    """A CTRIA6 too curved for the flat projection (mid-side grids on a cylinder of 12
    elements round, 0.19 sqrt(area) off the corners' plane) reads as the four CTRIA3 on
    its grids: the deck written with those CTRIA3 gives the same K and M (to the rounding
    of a different summation order)."""
    curved = _read(_cylinder_deck(tmp_path / "t6.bdf", 12, 2)).model
    flat = _read(_cylinder_deck(tmp_path / "t3.bdf", 12, 2, facets=True)).model
    for a, b in ((curved.stiffness(), flat.stiffness()), (curved.mass(), flat.mass())):
        assert abs(a - b).max() <= 1e-12 * abs(b).max()


def test_curved_ctria6_cylinder_ring_mode(tmp_path):
    """Source: the inextensional ring (Rayleigh; Blevins table 9-2), exact for a free
    cylinder's modes uniform along it when NU = 0, up to O((h/R)^2) = 1e-4 at R/h = 100.
    Curved CTRIA6 (12 x 2 and 24 x 4 x 2 round and along; both refused before as
    curved): six rigid-body modes, then the n = 2 pair; the finer mesh's error is below
    its change from the coarser one (the facets converge at least linearly) plus 1e-4."""
    R, h = 1.0, 0.01
    ring = 2 * 3 / np.sqrt(5) * np.sqrt(E * h**2 / (12 * RHO * R**4))
    got = []
    for nc, nl in ((12, 2), (24, 4)):
        model = _read(_cylinder_deck(tmp_path / f"c{nc}.bdf", nc, nl, R=R, h=h)).model
        sol = solve_elastic(model.stiffness(), model.mass(), 2)
        assert sol.n_rigid == 6
        assert sol.eigenvalues[1] == pytest.approx(sol.eigenvalues[0], rel=1e-6)
        got.append(np.sqrt(sol.eigenvalues[0]) / ring - 1)
    assert abs(got[1]) <= abs(got[1] - got[0]) + 1e-4, got
