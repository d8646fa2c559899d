"""PCOMP ply thickness (``PCOMP pid Tk``) as a parameter: A0(t), D0(t), H0(t) of the
laminate turned per element, mass sum RHO_k t_k + NSM.

Independent references: the deck with the ply thicknesses changed in its text and read
again; central finite differences of K, M; a one-ply PCOMP against the PSHELL of the
same material and thickness (a separate code path); an update from the frequencies of
a hand-edited deck, and the updated BDF read back. Runs in .venv-nastran (pyNastran)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from bounds import assert_matrix_derivatives
from nastran_frames import need
from plates import plate_fixed, square_mesh
from quadratic_meshes import plate_mesh

from eigenupdate.errors import EigenupdateWarning, InputError
from eigenupdate.identify.updating import update
from eigenupdate.io.measurements import Measurement
from eigenupdate.model.configurations import Configuration, mass_at
from eigenupdate.model.parameters import Parameter
from eigenupdate.solve.jacobian import solve_configurations

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.io.nastran import CardField, dof_number, read_nastran  # noqa: E402
from eigenupdate.io.nastran_write import write_updated_bdf  # noqa: E402

INIT = {"a1": 0.5e-3, "a2": 0.25e-3, "a3": 0.4e-3, "b1": 1.0e-3, "b2": 0.8e-3}
FIELDS = {"a1": ("PCOMP", 1, "T1"), "a3": ("PCOMP", 1, "T3"), "b2": ("PCOMP", 2, "T2")}
MATS = "MAT8,1,1.4e11,1.0e10,0.3,5.0e9,5.0e9,3.0e9,1600.\nMAT1,2,7.0e10,,0.33,2700.\n"


def _read(path, names=()):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EigenupdateWarning)
        return read_nastran(path, [(Parameter(n, 0.0), CardField(*FIELDS[n])) for n in names])


def laminates(v=INIT, b3=None, z0=""):
    """PCOMP 1: LAM=SYM [0/45/90]s of MAT8 1 (NSM 0.5); PCOMP 2: LAM blank, four MAT1
    plies b1, b2, b3 (blank: b2's, NASTRAN's rule), b1 (symmetric)."""
    b3 = "" if b3 is None else repr(b3)
    return (f"PCOMP,1,{z0},0.5,,,,,SYM\n,1,{v['a1']!r},0.,,1,{v['a2']!r},45.,\n"
            f",1,{v['a3']!r},90.\n"
            f"PCOMP,2\n,2,{v['b1']!r},0.,,2,{v['b2']!r},0.,\n,2,{b3},0.,,2,{v['b1']!r},0.\n"
            + MATS)


def plate(path, props, nx=6, a=0.4, triangles=True, theta=20.0):
    """An a x a plate, simply supported, property 1 on x < a/2 and 2 beyond; material
    angle ``theta`` on the elements (field THETA)."""
    xyz, el = square_mesh(nx, a, triangles)
    lines = [f"GRID,{i + 1},,{x!r},{y!r},0." for i, (x, y, _) in enumerate(xyz)]
    card = "CTRIA3" if triangles else "CQUAD4"
    for k, e in enumerate(el):
        pid = 1 if xyz[e, 0].mean() < a / 2 else 2
        lines.append(f"{card},{k + 1},{pid}," + ",".join(str(n + 1) for n in e)
                     + f",{theta!r}")
    edge = [i + 1 for i, (x, y, _) in enumerate(xyz)
            if min(x, y) < 1e-12 * a or max(x, y) > a * (1 - 1e-12)]
    lines += [f"SPC1,1,126,1,THRU,{len(xyz)}"] + [f"SPC1,1,3,{n}" for n in edge]
    path.write_text("BEGIN BULK\nPARAM,COUPMASS,1\n" + props + "\n".join(lines)
                    + "\nENDDATA\n")
    return path


@pytest.mark.parametrize("triangles", [True, False], ids=["CTRIA3", "CQUAD4"])
def test_model_at_new_ply_thicknesses_is_the_hand_edited_deck(tmp_path, triangles):
    # CQUAD4: only PCOMP 2 (one material: its condensed membrane stays linear)
    names = ["a1", "a3", "b2"] if triangles else ["b2"]
    nm = _read(plate(tmp_path / "a.bdf", laminates(), triangles=triangles), names)
    assert nm.model.nonlinear and nm.model.values.tolist() == [INIT[n] for n in names]
    new = dict(INIT, **{n: v for n, v in (("a1", 0.55e-3), ("a3", 0.37e-3), ("b2", 0.9e-3))
                        if n in names})
    # ply 3 of PCOMP 2 keeps the initial b2 it inherited (explicit in the edited deck)
    ref = _read(plate(tmp_path / "b.bdf", laminates(new, b3=INIT["b2"]),
                      triangles=triangles)).model
    s = [new[n] for n in names]
    # the same element integrals summed in another order: a few ulps of the largest entry
    for a, b in ((nm.model.stiffness(s), ref.stiffness()), (nm.model.mass(s), ref.mass())):
        assert abs(a - b).max() <= 1e-12 * abs(b).max()


def test_derivatives_match_central_differences(tmp_path):
    model = _read(plate(tmp_path / "a.bdf", laminates()), ["a1", "a3", "b2"]).model
    assert_matrix_derivatives(model)  # central differences (tests/bounds.py)


@pytest.mark.parametrize("triangles", [True, False], ids=["CTRIA3", "CQUAD4"])
def test_one_ply_pcomp_is_the_pshell(tmp_path, triangles):
    """Source: NASTRAN's equivalence of a one-ply PCOMP and PSHELL with MID1 = MID2 =
    MID3, 12I/T^3 = 1, TS/T = 5/6, read through the PSHELL code path."""
    t = 2.0e-3
    pcomp = f"PCOMP,1,,0.3\n,2,{t!r},0.\nPCOMP,2,,0.3\n,2,{t!r},0.\n" + MATS
    # TS/T given as 5/6 (blank: pyNastran fills in 0.833333)
    pshell = (f"PSHELL,1,2,{t!r},2,,2,{5 / 6!r},0.3\nPSHELL,2,2,{t!r},2,,2,{5 / 6!r},0.3\n"
              + MATS)
    a = read_nastran(plate(tmp_path / "c.bdf", pcomp, triangles=triangles),
                     [(Parameter("p", 0.0), CardField("PCOMP", 1, "T1"))]).model
    b = read_nastran(plate(tmp_path / "s.bdf", pshell, triangles=triangles),
                     [(Parameter("p", 0.0), CardField("PSHELL", 1, "T"))]).model
    for s in ([t], [1.3 * t]):
        for x, y in ((a.at(s).stiffness(), b.at(s).stiffness()), (a.at(s).mass(), b.at(s).mass()),
                     (a.at(s).k_terms[0], b.at(s).k_terms[0]),
                     (a.at(s).m_terms[0], b.at(s).m_terms[0])):
            assert abs(x - y).max() <= 1e-12 * abs(y).max()


def test_cquad4_laminate_of_different_plies(tmp_path):
    """CQUAD4 with PCOMP 1's [0/45/90]s MAT8 plies (plane moduli differ) as parameters:
    the incompatible modes condensed as under the deck's A0 (shells.local_parts
    ``condense_with``). Sources: the deck read without parameters (exact at its own
    thicknesses, round-off), central differences (the model is linear in the plies),
    and the hand-edited deck at new thicknesses, whose exact condensation differs from
    the model's by the Ritz error, second order in A's change of shape
    (tests/model/test_shells.py: below 3.2e-5 of K for a 20 % change on a badly
    distorted element), so frequencies within 1e-6."""
    names = ["a1", "a3", "b2"]
    nm = _read(plate(tmp_path / "a.bdf", laminates(), triangles=False), names)
    plain = _read(plate(tmp_path / "p.bdf", laminates(), triangles=False)).model
    s0 = [INIT[n] for n in names]
    assert abs(nm.model.stiffness(s0) - plain.stiffness()).max() <= (
        1e-12 * abs(plain.stiffness()).max())
    assert_matrix_derivatives(nm.model)
    new = dict(INIT, a1=0.55e-3, a3=0.37e-3, b2=0.9e-3)
    ref = _read(plate(tmp_path / "b.bdf", laminates(new, b3=INIT["b2"]),
                      triangles=False)).model
    s = [new[n] for n in names]
    got = solve_configurations(nm.model.at(s), [Configuration("base")], 8)[0]
    want = solve_configurations(ref, [Configuration("base")], 8)[0]
    assert np.max(np.abs(got.frequencies_hz / want.frequencies_hz - 1)) <= 1e-6


@pytest.mark.parametrize(("props", "field", "triangles", "words"), [
    # LAM blank [0/90]: one ply thicker makes B != 0
    ("PCOMP,3\n,1,1.e-3,0.,,1,1.e-3,90.\n", "T1", True, "unsymmetric"),
    # Z0 off -T/2 (a stack off the reference plane, read as an offset; with a ply
    # parameter refused as any Z0 given)
    ("PCOMP,3,-0.8e-3,,,,,,SYM\n,1,1.e-3,0.\n", "T1", True, "Z0 given on the card"),
    # Z0 = -T/2 given on the card: NASTRAN keeps it when the ply changes (then B != 0)
    ("PCOMP,3,-1.e-3,,,,,,SYM\n,1,1.e-3,0.\n", "T1", True, "Z0 given on the card"),
    ("PCOMP,3,,,,,,,SYM\n,1,1.e-3,0.\n", "T2", True, "plies 1-1"),
])
def test_refused_ply_parameters_name_card_and_field(tmp_path, props, field, triangles, words):
    deck = plate(tmp_path / "r.bdf", props.replace("PCOMP,3", "PCOMP,1") + laminates(),
                 triangles=triangles)
    deck.write_text(deck.read_text().replace("PCOMP,1,,0.5,,,,,SYM", "PCOMP,9,,0.5,,,,,SYM"))
    with pytest.raises(InputError, match=words) as err:
        read_nastran(deck, [(Parameter("x", 0.0), CardField("PCOMP", 1, field))])
    assert "PCOMP 1" in str(err.value)


@pytest.mark.parametrize("triangles", [True, False], ids=["CTRIA3", "CQUAD4"])
def test_update_recovers_ply_thicknesses_and_writes_them_back(tmp_path, triangles):
    """Error-free data from the edited deck; on CQUAD4 the model's membrane is the
    Ritz condensation under the deck's A0 (the truth's is exact), which the flat plate's
    bending modes do not see."""
    names = ["a1", "b2"]
    nm = _read(plate(tmp_path / "a.bdf", laminates(), triangles=triangles), names)
    truth = dict(INIT, a1=0.54e-3, b2=0.74e-3)
    true_model = _read(plate(tmp_path / "truth.bdf", laminates(truth, b3=INIT["b2"]),
                             triangles=triangles)).model
    grids = [dof_number(g, 3) for g in (17, 25, 31)]  # interior grids of the 7 x 7
    configs = [Configuration("base")] + [mass_at(c, 0.2, f"m{c}") for c in grids]
    modes = [1, 2, 3, 4]
    sols = solve_configurations(true_model, configs, max(modes))
    data = {(c.name, k): Measurement(c.name, k, float(sol.frequencies_hz[k - 1]))
            for c, sol in zip(configs, sols, strict=True) for k in modes}
    res = update(nm.model, configs, modes, data, max_iterations=30)
    assert res.success, res.message
    want = np.array([truth[n] for n in names])
    # error-free data: limited by the eigenvalues' round-off over cond(J)
    assert np.max(np.abs(res.x / want - 1)) < 1e-6
    out = tmp_path / "updated.bdf"
    write_updated_bdf(nm, out, res.parameters)
    back = _read(out, names)
    assert back.model.values == pytest.approx(res.x, rel=1e-11)  # 12 digits written
    # ply 3 of PCOMP 2 (blank: inherits T2) keeps its thickness
    assert back.bdf.properties[2].thicknesses[2] == INIT["b2"]
    assert abs(back.model.stiffness() - nm.model.stiffness(res.x)).max() <= (
        1e-9 * abs(back.model.stiffness()).max())


def quadratic_plate(path, props, nx=3, a=0.4, triangles=False, theta=20.0):
    """The plate of :func:`plate` in CQUAD8 (CTRIA6), hard simple support, THETA given."""
    xyz, el = plate_mesh(nx, a, a, triangles)
    lines = [f"GRID,{i + 1},,{x!r},{y!r},0." for i, (x, y, _) in enumerate(xyz)]
    for k, e in enumerate(el):
        pid = 1 if xyz[e[:3], 0].mean() < a / 2 else 2
        g = [str(n + 1) for n in e]
        head = f"{'CTRIA6' if triangles else 'CQUAD8'},{k + 1},{pid}," + ",".join(g[:6])
        lines.append(head + (f",{theta!r}" if triangles
                             else f"\n,{g[6]},{g[7]},,,,,{theta!r}"))
    for i, row in enumerate(plate_fixed(xyz, a, "ss")):
        comps = "".join(str(c + 1) for c in range(6) if row[c])
        if comps:
            lines.append(f"SPC1,1,{comps},{i + 1}")
    path.write_text("BEGIN BULK\nPARAM,COUPMASS,1\n" + props + "\n".join(lines)
                    + "\nENDDATA\n")
    return path


@pytest.mark.parametrize("triangles", [False, True], ids=["CQUAD8", "CTRIA6"])
def test_quadratic_shells_match_the_hand_edited_deck_and_differences(tmp_path, triangles):
    """Source: the edited deck read again, and central differences (tests/bounds.py); the
    shear stabilisation's T^2 / (T^2 + alpha h^2) per element size rides on H."""
    names = ["a1", "a3", "b2"]
    nm = _read(quadratic_plate(tmp_path / "a.bdf", laminates(), triangles=triangles), names)
    new = dict(INIT, a1=0.55e-3, a3=0.37e-3, b2=0.9e-3)
    ref = _read(quadratic_plate(tmp_path / "b.bdf", laminates(new, b3=INIT["b2"]),
                                triangles=triangles)).model
    s = [new[n] for n in names]
    for a, b in ((nm.model.stiffness(s), ref.stiffness()), (nm.model.mass(s), ref.mass())):
        assert abs(a - b).max() <= 1e-12 * abs(b).max()
    assert_matrix_derivatives(nm.model)


def test_ply_thickness_with_its_materials_modulus_is_refused(tmp_path):
    deck = plate(tmp_path / "a.bdf", laminates())
    with pytest.raises(InputError, match="PCOMP 2 field T2: not a parameter together with "
                                         "MAT1 2"):
        read_nastran(deck, [(Parameter("b2", 0.0), CardField("PCOMP", 2, "T2")),
                            (Parameter("E", 0.0), CardField("MAT1", 2, "E"))])


def test_small_field_pcomp_is_written_back_with_the_inherited_ply(tmp_path):
    """Source: the written deck read back (pyNastran): a small-field PCOMP becomes large
    field, the new T3 (SYM) and T2 in place, ply 3's blank T (NASTRAN: ply 2's) written
    with its old value."""
    small = ("PCOMP   1               .5                                      SYM\n"
             "        1       .5-3    0.              1       .25-3   45.\n"
             "        1       .4-3    90.\n"
             "PCOMP   2\n        2       1.-3    0.              2       .8-3    0.\n"
             "        2               0.              2       1.-3    0.\n" + MATS)
    nm = _read(plate(tmp_path / "s.bdf", small), ["a3", "b2"])
    assert nm.model.values.tolist() == [0.4e-3, 0.8e-3]
    write_updated_bdf(nm, tmp_path / "out.bdf", {"a3": 0.45e-3, "b2": 0.7e-3})
    back = _read(tmp_path / "out.bdf", ["a3", "b2"])
    assert back.model.values.tolist() == [0.45e-3, 0.7e-3]  # short decimals: exact
    assert back.bdf.properties[2].thicknesses == [1e-3, 0.7e-3, 0.8e-3, 1e-3]


def test_free_field_continuation_markers_are_written_back(tmp_path):
    """Source: the written deck read back (pyNastran) against the hand-edited deck. A
    free-field line's field 10 is its continuation field (MSC QRG, free-field format):
    a marker there (+P1, +M2) is not data, so a PCOMP T1 and a MAT1 E on cards continued
    that way are written in place, the MAT1's ST, SC, SS continuation kept."""
    deck = ("PCOMP,1,,0.5,,,,,SYM,+P1\n+P1,1,{a1!r},0.,,1,2.5e-4,45.,,+P2\n+P2,1,4.e-4,90.\n"
            "PCOMP,2\n,2,1.e-3,0.,,2,8.e-4,0.,\n,2,,0.,,2,1.e-3,0.\n"
            "MAT8,1,1.4e11,1.0e10,0.3,5.0e9,5.0e9,3.0e9,1600.\n"
            "MAT1,2,{e!r},,0.33,2700.,,,,+M2\n+M2,2.5e8,2.4e8,1.5e8\n")
    params = [(Parameter("a1", 0.0), CardField("PCOMP", 1, "T1")),
              (Parameter("E", 0.0), CardField("MAT1", 2, "E"))]

    def read(path, p=params):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", EigenupdateWarning)
            return read_nastran(path, p)

    nm = read(plate(tmp_path / "m.bdf", deck.format(a1=5e-4, e=7e10)))
    write_updated_bdf(nm, tmp_path / "out.bdf", {"a1": 5.5e-4, "E": 7.2e10})
    back = read(tmp_path / "out.bdf")
    assert back.model.values.tolist() == [5.5e-4, 7.2e10]  # short decimals: exact
    mat = back.bdf.materials[2]
    assert (mat.St, mat.Sc, mat.Ss) == (2.5e8, 2.4e8, 1.5e8)
    ref = read(plate(tmp_path / "h.bdf", deck.format(a1=5.5e-4, e=7.2e10)), []).model
    # the same element integrals summed in the same order: a few ulps of the largest
    for a, b in ((back.model.stiffness(), ref.stiffness()), (back.model.mass(), ref.mass())):
        assert abs(a - b).max() <= 1e-12 * abs(b).max()


def test_a_graded_mesh_linearises_the_ply_shear_about_the_decks_T(tmp_path):
    """Past MAX_SIZES element sizes a PCOMP's shear stabilisation f = T^2 / (T^2 + alpha
    h^2) is f(T0) + f'(T0) (T - T0) per element (T the stack's total). Sources: the deck
    read without parameters (equal at T0); central differences; and the hand-edited deck
    with ply 1 of PCOMP 1 10 % thicker: the model differs from the exact elements only in
    that shear part, by at most eps = max_e |f_lin / f - 1| of it, so every eigenvalue lies
    within a factor 1 +- eps (Courant-Fischer, K_shear <= K; measured: 128 sizes, eps
    1.6e-3, eigenvalues 1.7e-4 off)."""
    from eigenupdate.io.nastran_plies import MAX_SIZES
    from eigenupdate.model import shells

    nx, a = 16, 0.4
    xyz, el = square_mesh(nx, a, True)
    g = np.column_stack([a * (xyz[:, 0] / a) ** 1.4,
                         a * (xyz[:, 1] / a) ** 1.25 * (1 + 0.3 * xyz[:, 0] / a), xyz[:, 2]])

    def deck(path, v):
        lines = [f"GRID,{i + 1},,{x!r},{y!r},0." for i, (x, y, _) in enumerate(g)]
        pid = [1 if xyz[e, 0].mean() < a / 2 else 2 for e in el]
        lines += [f"CTRIA3,{k + 1},{p}," + ",".join(str(n + 1) for n in e) + ",20."
                  for k, (e, p) in enumerate(zip(el, pid, strict=True))]
        edge = [i + 1 for i, (x, y, _) in enumerate(xyz)
                if min(x, y) < 1e-12 * a or max(x, y) > a * (1 - 1e-12)]
        lines += [f"SPC1,1,126,1,THRU,{len(xyz)}"] + [f"SPC1,1,3,{n}" for n in edge]
        path.write_text("BEGIN BULK\nPARAM,COUPMASS,1\n" + laminates(v) + "\n".join(lines)
                        + "\nENDDATA\n")
        return path

    with pytest.warns(EigenupdateWarning, match=r"PCOMP 1 \(its ply thicknesses\): the "
                      r"transverse shear of its \d+ element sizes is linearised"):
        nm = read_nastran(deck(tmp_path / "a.bdf", INIT),
                          [(Parameter("a1", 0.0), CardField(*FIELDS["a1"]))])
    plain = _read(tmp_path / "a.bdf").model
    for x, y in ((nm.model.stiffness(), plain.stiffness()), (nm.model.mass(), plain.mass())):
        assert abs(x - y).max() <= 1e-12 * abs(y).max()
    assert_matrix_derivatives(nm.model)
    ones = np.array([xyz[e, 0].mean() < a / 2 for e in el])
    h = shells.stabilisation_size(g[el[ones]])
    assert np.unique(h).size > MAX_SIZES
    new = dict(INIT, a1=1.1 * INIT["a1"])
    T0 = 2 * (INIT["a1"] + INIT["a2"] + INIT["a3"])  # LAM=SYM
    T1 = 2 * (new["a1"] + new["a2"] + new["a3"])
    c = shells.ALPHA * h**2
    f_lin = T0**2 / (T0**2 + c) + 2 * T0 * c / (T0**2 + c) ** 2 * (T1 - T0)
    eps = np.max(np.abs(f_lin / (T1**2 / (T1**2 + c)) - 1))
    exact = _read(deck(tmp_path / "b.bdf", new)).model
    lam_exact = solve_configurations(exact, [Configuration("base")], 6)[0].eigenvalues
    lam_lin = solve_configurations(nm.model.with_values([new["a1"]]),
                                   [Configuration("base")], 6)[0].eigenvalues
    assert 0 < eps < 0.05
    assert np.all(np.abs(lam_lin / lam_exact - 1) <= eps + 1e-9)


def test_ctria6_stabilisation_of_a_two_material_stack_is_held_at_the_deck(tmp_path):
    """CTRIA6's stabilisation ratio (model/shells_quadratic.py stabilisation_ratio) is a
    property of the ply material alone for a one-material stack (rotation invariants
    summed over the plies), so the hand-edited deck check above holds exactly; a stack of
    MAT8 and MAT1 plies moves it with a ply's thickness, so it is held at the deck's
    section and a note says so. Sources: the warning, the deck read without parameters
    (equal at the deck's thicknesses, 1e-12), central differences."""
    two = "PCOMP,1,,,,,,,SYM\n,1,5.e-4,0.,,2,5.e-4,0.\nPCOMP,2\n,2,1.e-3,0.\n" + MATS
    path = quadratic_plate(tmp_path / "a.bdf", two, triangles=True)
    with pytest.warns(EigenupdateWarning, match=r"PCOMP 1 field T1: plies of several "
                      r"materials: CTRIA6's shear stabilisation is held"):
        nm = read_nastran(path, [(Parameter("t", 0.0), CardField("PCOMP", 1, "T1"))])
    plain = _read(path).model
    for x, y in ((nm.model.stiffness(), plain.stiffness()), (nm.model.mass(), plain.mass())):
        assert abs(x - y).max() <= 1e-12 * abs(y).max()
    assert_matrix_derivatives(nm.model)
    with warnings.catch_warnings():
        warnings.filterwarnings("error", "PCOMP.*stabilisation is held", EigenupdateWarning)
        # read_nastran itself: _read would silence the warning this checks for
        read_nastran(quadratic_plate(tmp_path / "b.bdf", laminates(), triangles=True),
                     [(Parameter(n, 0.0), CardField(*FIELDS[n])) for n in ("a1", "b2")])


def test_ctria6_stabilisation_with_a_modulus_of_bending_not_shear_is_held(tmp_path):
    """A MAT1 E parameter that is MID2 of a CTRIA6 PSHELL whose MID3 is another material
    moves the bending and not the shear, so the stabilisation ratio, held at the deck's:
    a note says so (none where MID1 = MID2 = MID3, whose ratio E cancels from). Sources:
    the warning, the deck read without parameters (1e-12), central differences."""
    props = ("PSHELL,1,2,2.e-3,2,,3\nPSHELL,2,2,2.e-3,2,,2\n"
             "MAT1,2,7.0e10,,0.33,2700.\nMAT1,3,2.1e11,,0.3,7850.\n")
    path = quadratic_plate(tmp_path / "a.bdf", props, triangles=True)
    spec = [(Parameter("E", 0.0), CardField("MAT1", 2, "E"))]
    with pytest.warns(EigenupdateWarning, match=r"MAT1 2 field E: its bending and shear "
                      r"apart: CTRIA6's shear stabilisation is held"):
        nm = read_nastran(path, spec)
    plain = _read(path).model
    for x, y in ((nm.model.stiffness(), plain.stiffness()), (nm.model.mass(), plain.mass())):
        assert abs(x - y).max() <= 1e-12 * abs(y).max()
    assert_matrix_derivatives(nm.model)
    path = quadratic_plate(tmp_path / "b.bdf", props.replace(",,3\n", ",,2\n"),
                           triangles=True)
    with warnings.catch_warnings():
        warnings.filterwarnings("error", ".*stabilisation is held", EigenupdateWarning)
        read_nastran(path, spec)
