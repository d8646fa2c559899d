"""Shells and solids read from a deck (io/nastran_continuum.py): Navier's plate through
the deck path, MAT1 E and RHO as parameters (finite differences of re-read decks),
displacement systems (CD), PCOMP against PSHELL and against closed-form laminates, and
the refusals. Runs in .venv-nastran (pyNastran)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from bounds import EPS
from nastran_frames import need
from plates import square_mesh
from solid_meshes import box_mesh, solid_matrices

from eigenupdate.errors import EigenupdateWarning, InputError
from eigenupdate.model import laminate
from eigenupdate.model.parameters import Parameter
from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.io.nastran import CardField, read_nastran  # noqa: E402


def _read(path, specs=()):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EigenupdateWarning)
        return read_nastran(path, specs)


def plate_deck(nx: int, a: float, prop: str, triangles: bool = False, cd: int = 0,
               extra: str = "") -> str:
    """Bulk data of an a x a plate in z = 0 of CQUAD4 (or CTRIA3) with property 1,
    simply supported (w on the edges; in-plane motion and drilling held everywhere:
    a flat plate's bending is uncoupled from them). ``cd``: every GRID's CD."""
    xyz, el = square_mesh(nx, a, triangles)
    lines = [f"GRID,{i + 1},,{x!r},{y!r},0.,{cd or ''}" for i, (x, y, _) in enumerate(xyz)]
    card = "CTRIA3" if triangles else "CQUAD4"
    lines += [f"{card},{k + 1},1," + ",".join(str(n + 1) for n in e) for k, e in enumerate(el)]
    edge = [i + 1 for i, (x, y, _) in enumerate(xyz)
            if min(x, y) < 1e-12 * a or max(x, y) > a * (1 - 1e-12)]
    lines += [f"SPC1,1,126,1,THRU,{len(xyz)}"]
    lines += [f"SPC1,1,3,{n}" for n in edge]
    return "BEGIN BULK\nPARAM,COUPMASS,1\n" + prop + "\n".join(lines) + "\n" + extra + "ENDDATA\n"


E, NU, RHO = 2.0e11, 0.3, 7850.0
STEEL = f"MAT1,1,{E!r},,{NU!r},{RHO!r}\n"


def _first_hz(text: str, tmp_path, name="plate.bdf") -> float:
    path = tmp_path / name
    path.write_text(text)
    m = _read(path).model
    return float(solve_elastic(m.stiffness(), m.mass(), 1).frequencies_hz[0])


def _converges_to(f8, f16, exact, model_bound, order=2.0):
    """The error falls at least as h^order, so the 16-mesh's error is at most
    1 / (2^order - 1) of the change from 8 to 16 (a third for bilinear elements' h^2,
    asserted with a factor 3 of room): |f16 - exact| <= max(1, 1 / (2^order - 1))
    |f16 - f8| + the closed form's own modelling bound."""
    assert f16 != f8
    room = max(1.0, 1.0 / (2.0**order - 1.0))
    assert abs(f16 - exact) <= room * abs(f16 - f8) + model_bound * exact, (f8, f16, exact)


def test_navier_plate_through_the_deck(tmp_path):
    """Source: Navier's simply supported square plate, omega = 2 pi^2 / a^2
    sqrt(D / (rho h)), D = E h^3 / (12 (1 - nu^2)); a = 1, h = 0.001 (Mindlin-Kirchhoff
    difference 4.4e-5 at a/h = 1000, see tests/model/test_shells.py; bound 1e-4); meshes 8 x 8
    and 16 x 16 CQUAD4 with PSHELL."""
    a, h = 1.0, 1e-3
    D = E * h**3 / (12 * (1 - NU**2))
    exact = 2 * np.pi**2 / a**2 * np.sqrt(D / (RHO * h)) / (2 * np.pi)
    prop = f"PSHELL,1,1,{h!r},1,,1\n" + STEEL
    f8, f16 = (_first_hz(plate_deck(n, a, prop), tmp_path) for n in (8, 16))
    # the support holds w only: with CQUAD4's residual bending flexibility the Mindlin
    # boundary layer at such an edge is an element wide, so the error falls about as h
    # (measured -1.0 and -0.64 % at 8 and 16): order 1/2 allowed
    _converges_to(f8, f16, exact, 1e-4, order=0.5)


def test_displacement_systems_do_not_change_frequencies(tmp_path):
    """Source: invariance. The same plate with every GRID's displacements in a turned
    rectangular system (CD 5) has the same frequencies: K and M are congruent, so the
    eigenvalues agree to a backward-stable solver's 10 eps kappa (kappa ~ 1 for these
    well-separated modes; taken as 1e-10 with room)."""
    h = 0.01
    turned = "CORD2R,5,,0.,0.,0.,.3,.4,.866\n,1.,.2,.1\n"
    free = f"PSHELL,1,1,{h!r},1,,1\n" + STEEL
    a_ = _read_freqs(tmp_path, _unsupported(plate_deck(4, 1.0, free)), "b.bdf")
    b_ = _read_freqs(tmp_path, _unsupported(plate_deck(4, 1.0, free, cd=5, extra=turned)),
                     "c.bdf")
    assert a_.size == 6 and np.allclose(a_, b_, rtol=1e-10, atol=0)


def ring_deck(kind: str, cd: int) -> str:
    """A free steel ring in cylindrical system 7 (GRID CP 7, CD ``cd``): CQUAD4 (12
    around, 2 along), CQUAD8 (6 around, 1 along, mid-side grids) or CHEXA (8 nodes, 12
    around, 1 through the wall, 2 along); R 0.1, length 0.1, wall 0.01, coupled mass."""
    q8 = kind == "CQUAD8"
    nt, nz = 12, 2  # lattice points (CQUAD8: 6 x 1 elements with their mid-side grids)
    radii = (0.095, 0.105) if kind == "CHEXA" else (0.1,)
    gid = {}
    lines = ["CORD2C,7,,0.,0.,0.,0.,0.,1.\n,1.,0.,0."]
    for r, rad in enumerate(radii):
        for j in range(nz + 1):
            for i in range(nt):
                if q8 and i % 2 and j % 2:
                    continue
                gid[r, i, j] = len(gid) + 1
                lines.append(f"GRID,{gid[r, i, j]},7,{rad!r},{30.0 * i!r},"
                             f"{0.05 * j!r},{cd or ''}")

    def g(r, i, j):
        return gid[r, i % nt, j]

    if kind == "CQUAD4":
        lines += [f"CQUAD4,{1 + i + nt * j},1,{g(0, i, j)},{g(0, i + 1, j)},"
                  f"{g(0, i + 1, j + 1)},{g(0, i, j + 1)}" for i in range(nt) for j in range(nz)]
        prop = "PSHELL,1,1,0.01,1,,1\n"
    elif q8:
        lines += [f"CQUAD8,{1 + i},1,{g(0, i, 0)},{g(0, i + 2, 0)},{g(0, i + 2, 2)},"
                  f"{g(0, i, 2)},{g(0, i + 1, 0)},{g(0, i + 2, 1)}\n,{g(0, i + 1, 2)},"
                  f"{g(0, i, 1)}" for i in range(0, nt, 2)]
        prop = "PSHELL,1,1,0.01,1,,1\n"
    else:
        lines += [f"CHEXA,{1 + i + nt * j},1,{g(0, i, j)},{g(0, i + 1, j)},{g(1, i + 1, j)},"
                  f"{g(1, i, j)},{g(0, i, j + 1)},{g(0, i + 1, j + 1)}\n,{g(1, i + 1, j + 1)},"
                  f"{g(1, i, j + 1)}" for i in range(nt) for j in range(nz)]
        prop = "PSOLID,1,1\n"
    return ("BEGIN BULK\nPARAM,COUPMASS,1\n" + prop + STEEL + "\n".join(lines)
            + "\nENDDATA\n")


@pytest.mark.parametrize("kind", ["CQUAD4", "CQUAD8", "CHEXA"])
def test_cylindrical_displacement_systems_do_not_change_frequencies(tmp_path, kind):
    """Source: invariance, as above, with CD axes that differ from grid to grid (a
    cylindrical CD): the coupled mass's blocks between two grids must be turned too
    (they were not: a 32 x 16 CQUAD4 cylinder's n = 2 modes moved 0.7 %)."""
    a_ = _read_freqs(tmp_path, ring_deck(kind, 0), "basic.bdf")
    b_ = _read_freqs(tmp_path, ring_deck(kind, 7), "cylindrical.bdf")
    assert a_.size == 6 and np.allclose(a_, b_, rtol=1e-10, atol=0)


def test_mid3_blank_is_the_shear_rigid_plate(tmp_path):
    """Source: Navier's Kirchhoff plate, here thick (a/h = 10: shear deformation lowers
    the Mindlin plate's first frequency by about pi^2 (h/a)^2 / (kappa (1 - nu)) ~ 7 %).
    PSHELL with MID3 blank (NASTRAN: no transverse shear flexibility) converges to the
    Kirchhoff value (mesh bound as in the Navier test; the 1e3 shear stiffness leaves
    1e-3 of the 7 %); with MID3 given it stays well below it."""
    a, h = 1.0, 0.1
    D = E * h**3 / (12 * (1 - NU**2))
    exact = 2 * np.pi**2 / a**2 * np.sqrt(D / (RHO * h)) / (2 * np.pi)
    rigid = f"PSHELL,1,1,{h!r},1\n" + STEEL
    f8, f16 = (_first_hz(plate_deck(n, a, rigid), tmp_path) for n in (8, 16))
    _converges_to(f8, f16, exact, 1e-4)
    soft = _first_hz(plate_deck(16, a, f"PSHELL,1,1,{h!r},1,,1\n" + STEEL), tmp_path)
    assert soft < exact * 0.96


def _unsupported(text: str) -> str:
    return "\n".join(x for x in text.splitlines() if not x.startswith("SPC1")) + "\n"


def _read_freqs(tmp_path, text, name, n=6):
    path = tmp_path / name
    path.write_text(text)
    m = _read(path).model
    return solve_elastic(m.stiffness(), m.mass(), n).frequencies_hz


MATERIALS = {1: {"E": 7.0e10, "G": None, "NU": 0.33, "RHO": 2700.0},
             2: {"E": 2.0e11, "G": None, "NU": 0.29, "RHO": 7800.0},
             3: {"E": 1.0e10, "G": 3.5e9, "NU": 0.25, "RHO": 1500.0}}


def mixed_deck(coupmass: int, materials: dict) -> str:
    """A CHEXA8, a CTETRA4, a CQUAD4 (PSHELL 1: all three MIDs MAT1 1, NSM), a CTRIA3
    (PSHELL 3: membrane and shear MAT1 3 with its own G, bending MAT1 1) and a CQUAD4 of
    PCOMP 5 (two MAT1 3 plies at 0 and 45 degrees, NSM), WTMASS 0.5."""
    mats = "".join(f"MAT1,{m},{v['E']!r},{'' if v['G'] is None else repr(v['G'])},"
                   f"{v['NU']!r},{v['RHO']!r}\n" for m, v in materials.items())
    return (f"BEGIN BULK\nPARAM,COUPMASS,{coupmass}\nPARAM,WTMASS,.5\n"
            "GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nGRID,3,,1.,1.,0.\nGRID,4,,0.,1.,0.\n"
            "GRID,5,,0.,0.,1.\nGRID,6,,1.,0.,1.\nGRID,7,,1.,1.,1.2\nGRID,8,,0.,1.,1.\n"
            "GRID,9,,2.,0.,0.\nGRID,10,,2.,1.,0.02\nGRID,11,,.5,.5,2.\n"
            "CHEXA,1,2,1,2,3,4,5,6,\n,7,8\nCTETRA,2,2,5,6,8,11\n"
            "CQUAD4,3,1,2,9,10,3\nCTRIA3,4,3,6,7,11\nGRID,12,,3.,0.,0.\nGRID,13,,3.,1.,0.\n"
            "CQUAD4,5,5,9,12,13,10\nPCOMP,5,,.2\n,3,.01,0.,,3,.02,45.\n"
            "PSHELL,1,1,.02,1,,1,,.1\nPSHELL,3,3,.03,1,,3\nPSOLID,2,2\n"
            f"{mats}SPC1,1,123456,1,4\nENDDATA\n")


PARAMS = [(m, f) for m in MATERIALS for f in ("E", "RHO")]


@pytest.mark.parametrize("coupmass", [1, -1])
@pytest.mark.parametrize("field", PARAMS, ids=[f"MAT1-{m}-{f}" for m, f in PARAMS])
def test_material_parameters_finite_differences(tmp_path, field, coupmass):
    """Source: finite differences of the assembled K and M with the card's value changed
    in the file's text: K_j, M_j are the exact derivatives. MAT1 3 gives G: shells take
    it for transverse shear only (MSC's MAT1 rule: membrane and bending from E and NU),
    so E of MAT1 3 scales membrane and drilling but not shear; MAT1 1 leaves G blank, so
    G follows E."""
    mid, name = field
    path = tmp_path / "mixed.bdf"
    path.write_text(mixed_deck(coupmass, MATERIALS))
    nm = _read(path, [(Parameter("p", 0.0), CardField("MAT1", mid, name))])
    base = _read(path).model
    s = nm.model.values[0]
    assert s == MATERIALS[mid][name]
    h = 0.25 * s
    bumped = {m: dict(v) for m, v in MATERIALS.items()}
    bumped[mid][name] += h
    out = tmp_path / "bumped.bdf"
    out.write_text(mixed_deck(coupmass, bumped))
    up = _read(out).model
    for total, plus, term in ((base.stiffness(), up.stiffness(), nm.model.k_terms[0]),
                              (base.mass(), up.mass(), nm.model.m_terms[0])):
        fd = ((plus - total) / h).toarray()
        dj = np.zeros_like(fd) if term is None else term.toarray()
        # K is linear in the field: the difference of two assemblies of values ~|total|
        # loses ~100 eps |total| / h (sums of up to 24 x 24 products)
        assert np.max(np.abs(fd - dj)) <= 1e4 * EPS * max(abs(total).max(), 1e-300) / h
def test_ply_of_a_mixed_pcomp_refused_as_parameter(tmp_path):
    """A PCOMP of two materials: its condensed membrane is not linear in one's E (RHO
    is: mass per area sum rho_k t_k)."""
    path = tmp_path / "mixed.bdf"
    path.write_text(mixed_deck(1, MATERIALS).replace(",3,.01,0.,,3,.02,45.",
                                                     ",3,.01,0.,,1,.02,45.\n,3,.01,0."))
    with pytest.raises(InputError, match="MAT1 3 field E: not a parameter of PCOMP 5"):
        _read(path, [(Parameter("p", 0.0), CardField("MAT1", 3, "E"))])
    nm = _read(path, [(Parameter("p", 0.0), CardField("MAT1", 3, "RHO"))])
    assert nm.model.m_terms[0] is not None


def _pcomp_props(plies: str, lam: str = "") -> str:
    return f"PCOMP,1,,,,,,,{lam}\n{plies}"


def test_one_ply_pcomp_is_the_pshell(tmp_path):
    """Source: classical laminate theory of one isotropic ply of thickness T about the
    mid-plane is PSHELL's A = Q T, D = Q T^3 / 12, shear 5/6 G T, mass rho T: the two
    decks' frequencies agree to the solver's rounding (1e-9 with room)."""
    h = 0.01
    pshell = _read_freqs(tmp_path, plate_deck(4, 1.0, f"PSHELL,1,1,{h!r},1,,1,{5 / 6!r}\n"
                                              + STEEL),
                         "a.bdf")
    pcomp = _read_freqs(tmp_path, plate_deck(4, 1.0, _pcomp_props(f",1,{h!r},0.\n") + STEEL),
                        "b.bdf")
    sym = _read_freqs(tmp_path, plate_deck(4, 1.0, _pcomp_props(f",1,{h / 2!r},30.\n", "SYM")
                                           + STEEL), "c.bdf")
    assert np.allclose(pshell, pcomp, rtol=1e-9) and np.allclose(pshell, sym, rtol=1e-9)


E1, E2, NU12, G12, G13 = 140e9, 10e9, 0.3, 5e9, 5e9
MAT8 = f"MAT8,2,{E1!r},{E2!r},{NU12!r},{G12!r},{G13!r},{G13 / 1.5!r},1600.\n"


def _q() -> np.ndarray:
    """Jones (1999) eq. 2.61: Q11 = E1 / (1 - nu12 nu21), Q12 = nu12 E2 / (...)."""
    nu21 = NU12 * E2 / E1
    d = 1 - NU12 * nu21
    return np.array([[E1 / d, NU12 * E2 / d, 0], [NU12 * E2 / d, E2 / d, 0], [0, 0, G12]])


def test_cross_ply_abd_against_hand_formulas():
    """Source: hand integration of [0/90]s, plies of thickness t: A = 2t (Q0 + Q90),
    B = 0, D = (2/3) t^3 (7 Q0 + Q90) (outer plies |z| in [t, 2t], inner [0, t]), with
    Q90 the 0-degree moduli with 1 and 2 swapped; and pyNastran's own PCOMP ABD
    (another implementation). Rounding: 1e-12 of |A|, |D|."""
    t = 0.001
    q0 = _q()
    q90 = q0[[1, 0, 2]][:, [1, 0, 2]]
    A, B, D, H = laminate.abd(np.stack([q0] * 4), np.stack([np.diag([G13, G13 / 1.5])] * 4),
                              np.full(4, t), -2 * t,
                              np.radians([[0.0, 90.0, 90.0, 0.0]]))
    assert np.allclose(A[0], 2 * t * (q0 + q90), rtol=0, atol=1e-12 * abs(A).max())
    assert np.allclose(D[0], 2 / 3 * t**3 * (7 * q0 + q90), rtol=0, atol=1e-12 * abs(D).max())
    assert np.abs(B).max() <= 1e-12 * abs(A).max() * 4 * t
    assert np.allclose(H[0], 5 / 6 * 2 * t * np.diag([G13 + G13 / 1.5] * 2), rtol=1e-12)
    bdf = need("pyNastran.bdf.bdf").BDF(debug=None)
    bdf.add_mat8(2, E1, E2, NU12, G12, G13, G13 / 1.5, 1600.0)
    p = bdf.add_pcomp(1, [2] * 2, [t] * 2, [0.0, 90.0], lam="SYM")
    bdf.cross_reference()
    Ap, Bp, Dp = p.get_individual_ABD_matrices()
    assert np.allclose(A[0], Ap, rtol=0, atol=1e-9 * abs(A).max())
    assert np.allclose(D[0], Dp, rtol=0, atol=1e-9 * abs(D).max())


def test_cross_ply_plate_against_navier(tmp_path):
    """Source: Navier's specially orthotropic simply supported plate (Whitney, Structural
    Analysis of Laminated Anisotropic Plates, 1987, eq. 5.28): omega_11^2 = pi^4 / (rho h)
    (D11 + 2 (D12 + 2 D66) + D22) / a^4 for a square plate, with the hand D of [0/90]s
    above; a = 1, plies t = a / 4000 (a/h = 1000: shear deformation, of order
    pi^2 (h/a)^2 E1 / (kappa G13) = 3e-4, bound 5e-4); meshes 8 and 16."""
    a, t = 1.0, 2.5e-4
    q0 = _q()
    q90 = q0[[1, 0, 2]][:, [1, 0, 2]]
    D = 2 / 3 * t**3 * (7 * q0 + q90)
    rho_h = 1600.0 * 4 * t
    exact = np.pi**2 / a**2 * np.sqrt((D[0, 0] + 2 * (D[0, 1] + 2 * D[2, 2]) + D[1, 1])
                                      / rho_h) / (2 * np.pi)
    prop = _pcomp_props(f",2,{t!r},0.,,2,{t!r},90.\n", "SYM") + MAT8
    f8, f16 = (_first_hz(plate_deck(n, a, prop), tmp_path) for n in (8, 16))
    _converges_to(f8, f16, exact, 5e-4)


def test_ply_angles_turn_with_theta(tmp_path):
    """Source: invariance. A [30] ply on elements with THETA = 0 is a [0] ply on
    elements with THETA = 30 degrees (the material axis turned from the G1-G2 side)."""
    prop = _pcomp_props(",2,.002,30.\n") + MAT8
    a = _read_freqs(tmp_path, plate_deck(4, 1.0, prop), "a.bdf")
    text = plate_deck(4, 1.0, _pcomp_props(",2,.002,0.\n") + MAT8)
    text = "\n".join(x + ",30." if x.startswith("CQUAD4") else x for x in text.splitlines())
    b = _read_freqs(tmp_path, text + "\n", "b.bdf")
    c = _read_freqs(tmp_path, plate_deck(4, 1.0, _pcomp_props(",2,.002,0.\n") + MAT8), "c.bdf")
    assert np.allclose(a, b, rtol=1e-9) and not np.allclose(a, c, rtol=1e-3)


BAD = [
    ("PSHELL,1,1,.01\n" + STEEL, "CQUAD4,99,1,1,2,3,4,,.005",
     "CQUAD4 99: ZOFFS = 0.005 needs MID2"),
    ("PSHELL,1,1,.01,1,,1\n,,,4\n" + STEEL + "MAT1,4,1.,,.3\n", "", "PSHELL 1: MID4"),
    ("PSHELL,1,2,.01,2,,2\nMAT2,2,1.,0.,0.,1.,0.,1.\n", "",
     "PSHELL 1 MID3: MAT2 2's G13, G23, G33 must be blank"),
    (_pcomp_props(",1,.01,0.\n", "MEM") + STEEL, "", "PCOMP 1: LAM = MEM"),
    ("PSHELL,1,1,.01,1,,1\n" + STEEL,
     "GRID,9998,,.5,0.,.3\nGRID,9999,,0.,.5,.3\nCQUAD4,99,1,1,9998,5,9999", "CQUAD4 99: warped"),
]


@pytest.mark.parametrize("prop,extra,message", BAD, ids=[m for _, _, m in BAD])
def test_unsupported_shell_input_is_named(tmp_path, prop, extra, message):
    """One error naming the card and field; the file and line where known."""
    path = tmp_path / "bad.bdf"
    path.write_text(plate_deck(2, 1.0, prop, extra=extra + "\n" if extra else ""))
    with pytest.raises(InputError, match=message) as exc:
        _read(path)
    assert "bad.bdf" in str(exc.value)


def test_unsupported_solid_input_is_named(tmp_path):
    text = ("BEGIN BULK\nGRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nGRID,3,,0.,1.,0.\n"
            "GRID,4,,0.,0.,1.\nCTETRA,1,2,1,2,3,4\nPSOLID,2,1,,,,FULL\n" + STEEL + "ENDDATA\n")
    path = tmp_path / "bad.bdf"
    path.write_text(text)
    with pytest.raises(InputError, match="PSOLID 2: ISOP = FULL"):
        _read(path)
    path.write_text(text.replace("1,2,3,4\n", "1,3,2,4\n").replace(",FULL", ""))
    # nodes numbered the other way round: the same element (solids.py), accepted
    assert _read(path).model.n > 0
    flat = text.replace("GRID,4,,0.,0.,1.", "GRID,4,,.5,.5,0.").replace(",FULL", "")
    path.write_text(flat)
    with pytest.raises(InputError, match="CTETRA 1: zero or changing-sign Jacobian"):
        _read(path)


@pytest.mark.parametrize("kind", ["CHEXA8", "CHEXA20", "CPENTA6", "CPENTA15", "CTETRA4",
                                  "CTETRA10", "CPYRAM5", "CPYRAM13", "MIXED"])
def test_solid_deck_is_the_element_library(tmp_path, kind):
    """Source: the element library's own assembly (tests/model/test_solids.py checks the
    elements against closed forms); here the deck path (pyNastran's node order, PSOLID,
    MAT1, COUPMASS) must give the same free-free frequencies, to the eigen-solvers'
    rounding (1e-9 with room). MIXED: CHEXA, CPYRAM and CTETRA in one deck."""
    xyz, el = box_mesh((1.0, 0.3, 0.2), (3, 1, 1), kind)
    cards = ["CHEXA", "CPYRAM", "CTETRA"] if kind == "MIXED" else [kind.rstrip("0123456789")]
    lines = [f"GRID,{i + 1},,{x!r},{y!r},{z!r}" for i, (x, y, z) in enumerate(xyz)]
    k = 0
    for card, part in zip(cards, el if kind == "MIXED" else [el], strict=True):
        for e in part:
            k += 1
            ids = [str(n + 1) for n in e]
            text = f"{card},{k},2," + ",".join(ids[:6])
            for j in range(6, len(ids), 8):
                text += "\n," + ",".join(ids[j:j + 8])
            lines.append(text)
    path = tmp_path / "solid.bdf"
    path.write_text("BEGIN BULK\nPARAM,COUPMASS,1\nPSOLID,2,1\n" + STEEL + "\n".join(lines)
                    + "\nENDDATA\n")
    m = _read(path).model
    got = solve_elastic(m.stiffness(), m.mass(), 8).frequencies_hz
    K, M = solid_matrices(xyz, el, E, NU, RHO)
    want = solve_elastic(K, M, 8).frequencies_hz
    assert np.allclose(got, want, rtol=1e-9, atol=0)


def test_e_with_nu_blank_refused_on_shells_and_solids(tmp_path):
    """NASTRAN's MAT1 rule: with NU blank and G given, NU = E / (2 G) - 1 follows E, so
    the plane-stress and solid moduli are not linear in E (refused); RHO stays linear.
    MAT1 1 with its NU given and G blank (G follows E) is accepted."""
    mats = {m: dict(v) for m, v in MATERIALS.items()}
    path = tmp_path / "mixed.bdf"
    text = mixed_deck(1, mats)
    g = mats[1]["E"] / 2.5
    line = next(x for x in text.splitlines() if x.startswith("MAT1,1,"))
    path.write_text(text.replace(line, f"MAT1,1,{mats[1]['E']!r},{g!r},,{mats[1]['RHO']!r}"))
    with pytest.raises(InputError, match="MAT1 1 field E: not a parameter .* NU blank"):
        _read(path, [(Parameter("p", 0.0), CardField("MAT1", 1, "E"))])
    assert _read(path, [(Parameter("p", 0.0), CardField("MAT1", 1, "RHO"))]).model.m_terms[0] \
        is not None
    path.write_text(text)
    assert _read(path, [(Parameter("p", 0.0), CardField("MAT1", 1, "E"))]).model.k_terms[0] \
        is not None
