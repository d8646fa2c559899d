"""MAT8 E1, E2, NU12, G12, G1Z, G2Z and RHO of PCOMP plies as parameters: the laminate's
A0, D0, H0 as functions of the plies' moduli on the unit-modulus basis of the ply
thicknesses (io/nastran_plies.py), mass linear in RHO.

Independent references: central finite differences of K and M from the deck re-read with
the field changed in its text; an isotropic [0/90]s laminate against the PSHELL of a MAT1
(a separate code path); the scaling of every modulus (K scales, M stays); the refusals'
one line. Runs in .venv-nastran (pyNastran)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from nastran_frames import need
from plates import square_mesh
from quadratic_meshes import plate_mesh
from refusals import one_line

from eigenupdate.errors import EigenupdateWarning, InputError
from eigenupdate.model.configurations import Configuration
from eigenupdate.model.parameters import Parameter
from eigenupdate.solve.jacobian import solve_configurations

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.cli import main  # noqa: E402
from eigenupdate.io.nastran import CardField, read_nastran  # noqa: E402

EPS = np.finfo(float).eps
# MAT8 MID E1 E2 NU12 G12 G1Z G2Z RHO: 1 a carbon ply, 3 a glass ply
MAT = {1: [1.4e11, 1.0e10, 0.3, 5.0e9, 5.0e9, 3.0e9, 1600.0],
       3: [4.5e10, 1.2e10, 0.28, 4.4e9, 4.0e9, 3.5e9, 1900.0]}
NAMES = ("E1", "E2", "NU12", "G12", "G1Z", "G2Z", "RHO")


def props(mat=MAT, t1=5e-4):
    """PCOMP 1: LAM=SYM [0/45/90]s of MAT8 1, NSM 0.5; PCOMP 2: [30/-60/30] of MAT8 1,
    3, 1 (symmetric, LAM blank). MAT8 1 is shared by both and by several plies."""
    cards = [f"MAT8,{m}," + ",".join("" if x is None else repr(float(x)) for x in v)
             for m, v in mat.items()]
    return (f"PCOMP,1,,0.5,,,,,SYM\n,1,{t1!r},0.,,1,2.5e-4,45.\n,1,4.e-4,90.\n"
            f"PCOMP,2\n,1,3.e-4,30.,,3,6.e-4,-60.\n,1,3.e-4,30.\n" + "\n".join(cards) + "\n")


def mixed_plate(path, text, nx=4, a=0.4):
    """An a x a plate, simply supported: CQUAD4 on x < a/2, CTRIA3 beyond (each quad cut
    in two); PCOMP 1 on y < a/2, PCOMP 2 beyond; material angle THETA 20 degrees."""
    xyz, quads = square_mesh(nx, a, False)
    lines = [f"GRID,{i + 1},,{x!r},{y!r},0." for i, (x, y, _) in enumerate(xyz)]
    k = 0
    for q in quads:
        c = xyz[q].mean(axis=0)
        pid = 1 if c[1] < a / 2 else 2
        for card, e in ((("CQUAD4", q),) if c[0] < a / 2 else
                        (("CTRIA3", q[[0, 1, 2]]), ("CTRIA3", q[[0, 2, 3]]))):
            k += 1
            lines.append(f"{card},{k},{pid}," + ",".join(str(n + 1) for n in e) + ",20.")
    edge = [i + 1 for i, (x, y, _) in enumerate(xyz)
            if min(x, y) < 1e-12 * a or max(x, y) > a * (1 - 1e-12)]
    lines += _supports(xyz, edge, a)
    path.write_text("BEGIN BULK\nPARAM,COUPMASS,1\n" + text + "\n".join(lines) + "\nENDDATA\n")
    return path


def _supports(xyz, edge, a) -> list[str]:
    """Simple support (w = 0 on the edges) and the in-plane rigid motions held at two
    corners, so that membrane and bending both enter K."""
    corner = [i + 1 for i, (x, y, _) in enumerate(xyz) if x > a * (1 - 1e-12) and y < 1e-12]
    return [f"SPC1,1,3,{n}" for n in edge] + ["SPC1,1,12,1", f"SPC1,1,2,{corner[0]}"]


def quad8_plate(path, text, nx=2, a=0.4):
    """The plate in CQUAD8, PCOMP 1 on x < a/2 and 2 beyond, THETA 20 degrees."""
    xyz, el = plate_mesh(nx, a, a, False)
    lines = [f"GRID,{i + 1},,{x!r},{y!r},0." for i, (x, y, _) in enumerate(xyz)]
    for k, e in enumerate(el):
        pid = 1 if xyz[e[:4], 0].mean() < a / 2 else 2
        g = [str(n + 1) for n in e]
        lines.append(f"CQUAD8,{k + 1},{pid}," + ",".join(g[:6]) + f"\n,{g[6]},{g[7]},,,,,20.")
    edge = [i + 1 for i, (x, y, _) in enumerate(xyz)
            if min(x, y) < 1e-12 * a or max(x, y) > a * (1 - 1e-12)]
    lines += _supports(xyz, edge, a)
    path.write_text("BEGIN BULK\nPARAM,COUPMASS,1\n" + text + "\n".join(lines) + "\nENDDATA\n")
    return path


def _read(path, fields=()):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EigenupdateWarning)
        return read_nastran(path, [(Parameter(f"p{k}", 0.0), CardField(*f))
                                   for k, f in enumerate(fields)])


FD_FIELDS = [("MAT8", 1, n) for n in NAMES] + [("MAT8", 3, "E1"), ("MAT8", 3, "G12"),
                                               ("MAT8", 3, "RHO"), ("PCOMP", 1, "T1")]


def _deck_at(field, value):
    mat = {m: list(v) for m, v in MAT.items()}
    card, cid, name = field
    if card == "MAT8":
        mat[cid][NAMES.index(name)] = value
        return props(mat)
    return props(t1=value)


@pytest.mark.parametrize("build", [mixed_plate, quad8_plate], ids=["CQUAD4+CTRIA3", "CQUAD8"])
def test_derivatives_are_central_differences_of_the_re_read_deck(tmp_path, build):
    """dK/dp, dM/dp of each field (every MAT8 1 field, MAT8 3's E1, G12, RHO, and a ply
    thickness of the same PCOMP, combined) against (X(p + h) - X(p - h)) / 2h of the deck
    re-read with the field changed, h = 1e-4 p. Bound: the truncation error, estimated from
    h and 2h (|D_h - D_2h| is 3/4 of D_2h's, 4 times D_h's: ~(h/p)^2 = 1e-8 relative, and
    on CQUAD4 the Ritz condensation's error, second order in the change), plus the
    round-off 4 eps |X| / h of a difference of two re-read decks."""
    model = _read(build(tmp_path / "a.bdf", props()), FD_FIELDS).model
    for j, f in enumerate(FD_FIELDS):
        p = model.values[j]

        def at(v, f=f):
            return _read(build(tmp_path / "fd.bdf", _deck_at(f, v))).model

        def central(h, p=p, at=at):
            up, dn = at(p + h), at(p - h)
            return [(x(up) - x(dn)) / (2 * h) for x in (lambda m: m.stiffness(),
                                                          lambda m: m.mass())]

        h = 1e-4 * p
        (k1, m1), (k2, m2) = central(h), central(2 * h)
        for exact, d1, d2, scale in ((model.k_terms[j], k1, k2, abs(model.stiffness()).max()),
                                     (model.m_terms[j], m1, m2, abs(model.mass()).max())):
            if exact is None:
                assert abs(d1).max() <= 4 * EPS * scale / h, f
                continue
            err = abs(d1 - exact).toarray()
            bound = abs(d1 - d2).toarray() + 4 * EPS * scale / h
            assert np.all(err <= bound), (f, err.max(), abs(exact).max())
            # and the bound is no wider than 1e-5 of the derivative: a real check
            assert bound.max() <= 1e-5 * abs(exact).max(), (f, bound.max())


def _iso(E, nu, G, rho):
    return [E, E, nu, G, G, G, rho]


@pytest.mark.parametrize("build", [mixed_plate, quad8_plate], ids=["CQUAD4+CTRIA3", "CQUAD8"])
def test_isotropic_plies_are_the_mat1_pshell_and_moduli_scale_k(tmp_path, build):
    """Source: classical laminate theory (Jones 4.2) for plies of one isotropic material:
    A = Q T, B = 0, D = Q T^3 / 12, H = 5/6 G T whatever the angles, i.e. the PSHELL of
    the MAT1 (MID1 = MID2 = MID3, TS/T 5/6), read through the PSHELL code path. With
    every modulus of the MAT8 scaled by c the laminate's A, D, H scale by c, so K is the
    MAT1 deck's with E c, M unchanged: equal to the round-off of sums in another order."""
    E, nu, rho, T = 7.0e10, 0.33, 2700.0, 2e-3
    G = E / (2 * (1 + nu))
    lam = (f"PCOMP,{{p}},,,,,,,SYM\n,8,{T / 4!r},0.,,8,{T / 4!r},90.\n")
    mat8 = "MAT8,8," + ",".join(repr(x) for x in _iso(E, nu, G, rho)) + "\n"
    fields = [("MAT8", 8, n) for n in ("E1", "E2", "G12", "G1Z", "G2Z")]
    a = _read(build(tmp_path / "a.bdf", lam.format(p=1) + lam.format(p=2) + mat8),
              fields).model
    for c in (1.0, 1.7):
        mat1 = f"MAT1,9,{c * E!r},,{nu!r},{rho!r}\n"
        shell = "".join(f"PSHELL,{p},9,{T!r},9,,9,{5 / 6!r}\n" for p in (1, 2))
        b = _read(build(tmp_path / "b.bdf", shell + mat1)).model
        s = c * a.values
        for x, y in ((a.stiffness(s), b.stiffness()), (a.mass(s), b.mass())):
            assert abs(x - y).max() <= 1e-12 * abs(y).max()
    # and the eigenvalues scale by c (backward-stable solver: 1e-9 covers eps times the
    # spread of the lowest eight eigenvalues over K's largest)
    conf = [Configuration("base")]
    lam0 = solve_configurations(a, conf, 8)[0].eigenvalues
    lam1 = solve_configurations(a.at(1.7 * a.values), conf, 8)[0].eigenvalues
    assert np.allclose(lam1, 1.7 * lam0, rtol=1e-9, atol=0)


def test_scaling_every_modulus_of_an_angle_ply_laminate_scales_k(tmp_path):
    """Source: A, D, H are linear and homogeneous in the plies' moduli (Jones 4.2), and
    CQUAD4's incompatible modes are invariant to a scaling of A: K(c E) = c K(E) exactly,
    M unchanged, on PCOMP 1 and 2 of two materials with every modulus a parameter."""
    fields = [("MAT8", m, n) for m in (1, 3) for n in ("E1", "E2", "G12", "G1Z", "G2Z")]
    model = _read(mixed_plate(tmp_path / "a.bdf", props()), fields).model
    s = model.values
    K, M = model.stiffness(), model.mass()
    assert abs(model.stiffness(2.5 * s) - 2.5 * K).max() <= 1e-12 * abs(K).max()
    assert abs(model.mass(2.5 * s) - M).max() == 0


def test_the_written_bdf_holds_the_new_mat8_fields(tmp_path):
    """Source: the written deck read back (pyNastran) against a deck with the new values
    typed in: the same K and M to the round-off of the same sums."""
    from eigenupdate.io.nastran_write import write_updated_bdf

    fields = [("MAT8", 1, "E1"), ("MAT8", 1, "G12"), ("MAT8", 3, "RHO"), ("MAT8", 1, "NU12")]
    nm = _read(mixed_plate(tmp_path / "a.bdf", props()), fields)
    new = {"p0": 1.3e11, "p1": 4.5e9, "p2": 2000.0, "p3": 0.31}
    write_updated_bdf(nm, tmp_path / "out.bdf", new)
    back = _read(tmp_path / "out.bdf", fields).model
    assert back.values.tolist() == list(new.values())  # short decimals: exact
    mat = {1: list(MAT[1]), 3: list(MAT[3])}
    mat[1][0], mat[1][3], mat[3][6], mat[1][2] = new.values()
    ref = _read(mixed_plate(tmp_path / "h.bdf", props(mat))).model
    for x, y in ((back.stiffness(), ref.stiffness()), (back.mass(), ref.mass())):
        assert abs(x - y).max() <= 1e-12 * abs(y).max()


def test_a_rigid_shear_ply_moves_its_penalty_with_its_moduli(tmp_path):
    """MAT8 G1Z, G2Z blank (MSC: rigid) on every ply: H is RIGID_SHEAR times
    reference_shear(Q) T, which follows E1, E2, NU12. Source: the deck re-read at a new
    E1 and NU12 (round-off of the same sums; CQUAD8, whose K is exact in A: CQUAD4's
    Ritz condensation would differ by its second-order error), central differences of
    the model."""
    from bounds import assert_matrix_derivatives

    def text(e1, nu):
        return (f"PCOMP,1,,,,,,,SYM\n,7,5.e-4,0.,,7,5.e-4,45.\nPCOMP,2\n,7,1.e-3,0.\n"
                f"MAT8,7,{e1!r},1.0e10,{nu!r},5.0e9,,,1600.\n")

    fields = [("MAT8", 7, "E1"), ("MAT8", 7, "NU12")]
    model = _read(quad8_plate(tmp_path / "a.bdf", text(1.4e11, 0.3)), fields).model
    ref = _read(quad8_plate(tmp_path / "b.bdf", text(1.2e11, 0.25))).model
    x = model.stiffness([1.2e11, 0.25])
    assert abs(x - ref.stiffness()).max() <= 1e-12 * abs(x).max()
    assert_matrix_derivatives(model)


@pytest.mark.parametrize("field", ["G1Z", "G2Z", "RHO"])
def test_a_field_alone_of_its_material(tmp_path, field):
    """A transverse shear modulus (or the density) the only parameter of its material:
    the plane moduli stay real numbers in the complex step. Sources: the deck re-read at
    1.3 times the value (round-off of the same sums; H is linear in G1Z, G2Z on every
    element, and the CQUAD4's membrane does not see them), central differences."""
    from bounds import assert_matrix_derivatives

    f = ("MAT8", 3, field)
    model = _read(mixed_plate(tmp_path / "a.bdf", props()), [f]).model
    v = 1.3 * model.values[0]
    ref = _read(mixed_plate(tmp_path / "b.bdf", _deck_at(f, v))).model
    for x, y in ((model.stiffness([v]), ref.stiffness()), (model.mass([v]), ref.mass())):
        assert abs(x - y).max() <= 1e-12 * abs(y).max()
    assert_matrix_derivatives(model)


def test_out_of_range_values_the_update_may_reach_are_refused(tmp_path):
    """E1 <= 0 and NU12^2 >= E1 / E2 (MSC QRG MAT8 remarks: the ply's compliance must be
    positive definite) make no laminate: one line naming the card and the field."""
    fields = [("MAT8", 1, "E1"), ("MAT8", 1, "NU12")]
    model = _read(mixed_plate(tmp_path / "a.bdf", props()), fields).model
    with pytest.raises(InputError, match=r"^MAT8 1: E1 = -1e\+09 \(reached by the update\) "
                                         r"must be > 0$"):
        model.stiffness([-1e9, 0.3])
    with pytest.raises(InputError, match=r"^MAT8 1: NU12 = 4 with E1 = 1.4e\+11, E2 = 1e\+10 "
                                         r"\(reached by the update\) makes the ply's moduli "
                                         r"indefinite \(NU12\^2 >= E1 / E2\)$"):
        model.stiffness([1.4e11, 4.0])


PSHELL8 = "PSHELL,1,1,2.e-3,1,,1\nPSHELL,2,1,2.e-3,1,,1\n" + props().split("PCOMP,2")[1].split(
    "\n", 3)[3]
UNSYM = props().replace(",3,6.e-4,-60.\n,1,3.e-4,30.", ",3,6.e-4,-60.\n,1,3.e-4,-30.")


@pytest.mark.parametrize(("text", "params", "words"), [
    (props(), [("MAT8", 1, "ST")], "MAT8 1: field 'ST' is not a parameter; the parameter "
                                   "fields of MAT8 are E1"),
    (PSHELL8, [("MAT8", 1, "E1")], "MAT8 1 field E1: not a parameter as PSHELL 1's "
                                   "MID1/MID2/MID3"),
    (props({1: MAT[1][:4] + [None, None, 1600.0],
            3: MAT[3][:4] + [None, None, 1900.0]}), [("MAT8", 3, "G1Z")],
     "field G1Z: blank (MSC: a rigid transverse shear) is not a parameter"),
    (UNSYM, [("MAT8", 3, "E1")], "not a parameter: a change makes the stack unsymmetric"),
    (props().replace("PCOMP,1,,0.5", "PCOMP,1,-1.e-3,0.5"), [("MAT8", 1, "G12")],
     "not a parameter with Z0 given on the card"),
])
def test_refusals_are_one_line(tmp_path, capsys, text, params, words):
    """Sources: the card's fields (MSC QRG MAT8, PCOMP), and what the basis cannot hold:
    a PSHELL's MAT8 (its own code path), a blank rigid shear (no number to start from),
    B != 0 and a Z0 off the mid-plane (no coupling or mass-moment terms)."""
    mixed_plate(tmp_path / "deck.bdf", text)
    study = '[model]\ntype = "nastran"\nbdf = "deck.bdf"\n' + "".join(
        f'[[model.parameter]]\nname = "p{k}"\ncard = "{c}"\nid = {i}\nfield = "{f}"\n'
        f'std = 1.0\n' for k, (c, i, f) in enumerate(params))
    (tmp_path / "study.toml").write_text(study)
    capsys.readouterr()
    code = main(["frequencies", str(tmp_path / "study.toml"), "--modes", "3"])
    one_line(code, capsys.readouterr().err, "deck.bdf", words, warnings_allowed=True)


def test_a_pshell_mat8_density_with_its_thickness(tmp_path):
    """A PSHELL whose MID1 = MID2 = MID3 is a MAT8: its RHO and T both parameters (mass
    WTMASS RHO T, a product). Sources: the deck re-read with both changed in its text
    (round-off of the same sums), central differences of the model."""
    from bounds import assert_matrix_derivatives

    fields = [("PSHELL", 1, "T"), ("MAT8", 1, "RHO")]
    model = _read(mixed_plate(tmp_path / "a.bdf", PSHELL8), fields).model
    edited = PSHELL8.replace("PSHELL,1,1,2.e-3", "PSHELL,1,1,2.2e-3").replace(
        "3000000000.0,1600.0", "3000000000.0,1750.0")
    ref = _read(mixed_plate(tmp_path / "b.bdf", edited)).model
    s = [2.2e-3, 1750.0]
    for x, y in ((model.stiffness(s), ref.stiffness()), (model.mass(s), ref.mass())):
        assert abs(x - y).max() <= 1e-12 * abs(y).max()
    assert_matrix_derivatives(model)
