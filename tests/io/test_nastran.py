"""NASTRAN bulk data: frequencies against OpenSees and closed forms, parameter matrices
against finite differences, round trip and write-back, bad input.

Run for real in .venv-nastran (``make test``); skipped in the core environment."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from conftest import EXAMPLES
from nastran_frames import need, opensees_frequencies, random_frame

from eigenupdate.errors import InputError
from eigenupdate.model.parameters import Parameter
from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.io.nastran import CardField, read_nastran  # noqa: E402

FRAME = EXAMPLES / "nastran_frame"


def _freqs(path, n, **kw):
    m = read_nastran(path).model
    return solve_elastic(m.stiffness(), m.mass(), n, **kw).frequencies_hz


def test_shipped_frame_matches_opensees():
    """Source: OpenSees elasticBeamColumn, consistent mass (-cMass), same mesh."""
    need("openseespy")
    f = _freqs(FRAME / "frame.bdf", 12)
    ref = opensees_frequencies(FRAME / "frame.bdf", 12)
    assert np.max(np.abs(f / ref - 1)) < 1e-8


@pytest.mark.slow
@pytest.mark.parametrize("consistent", [True, False], ids=["consistent", "lumped"])
def test_random_frames_match_opensees(tmp_path, consistent):
    """Source: OpenSees elasticBeamColumn with the same mass formulation, 20 random frames
    each (random geometry, sections, orientation vectors, CONM2 masses, a CELAS2 spring).
    Lumped mass leaves rotations massless: the dense path condenses them, the sparse path
    works with the singular M; both are checked."""
    need("openseespy")
    rng = np.random.default_rng(20261123 + consistent)
    worst = 0.0
    for i in range(20):
        path = tmp_path / f"frame{i}.bdf"
        path.write_text(random_frame(rng, consistent).bdf())
        ref = opensees_frequencies(path, 8)
        for dense in (True, False):
            worst = max(worst, float(np.max(np.abs(_freqs(path, 8, dense=dense) / ref - 1))))
    assert worst < 1e-8


def _line_bdf(tmp_path, n, L, *, fixed="", coupmass=True, card="CBAR", extra="",
              beam_k="0.,0."):
    """A straight line of n elements along x."""
    lines = ["BEGIN BULK"] + (["PARAM,COUPMASS,1"] if coupmass else [])
    lines += [f"GRID*,{i + 1},,{L * i / n!r},0.\n*,0." for i in range(n + 1)]
    for i in range(n):
        lines.append(f"{card},{i + 1},1,{i + 1},{i + 2}" + (",0.,1.,0." * (card != "CROD")))
    lines += [{"CBAR": "PBAR,1,1,1.e-3,2.e-7,8.e-7,5.e-7",
               "CBEAM": f"PBEAM,1,1,1.e-3,2.e-7,8.e-7,,5.e-7\n,,,,,,,,\n,{beam_k}",
               "CROD": "PROD,1,1,1.e-3,5.e-7"}[card], "MAT1,1,2.e11,,0.3,7800."]
    if fixed:
        lines.append(f"SPC1,1,{fixed},1")
    lines += [extra, "ENDDATA"]
    path = tmp_path / "line.bdf"
    path.write_text("\n".join(lines) + "\n")
    return path


def test_cantilever_closed_form(tmp_path):
    """Source: Euler-Bernoulli cantilever, omega_1 = 1.8751^2 sqrt(EI / (rho A L^4)), in
    both bending planes (I1 = 2e-7, I2 = 8e-7 m^4)."""
    f = _freqs(_line_bdf(tmp_path, 40, 2.0, fixed="123456"), 2)
    exact = [1.8751040687**2 * math.sqrt(2e11 * i / (7800 * 1e-3 * 2.0**4)) / (2 * math.pi)
             for i in (2e-7, 8e-7)]
    assert np.allclose(f, exact, rtol=1e-6)


@pytest.mark.parametrize("coupmass", [True, False], ids=["consistent", "lumped"])
def test_free_free_beam_closed_form(tmp_path, coupmass):
    """Source: free-free Euler-Bernoulli beam, beta_1 L = 4.730041 (six rigid modes)."""
    f = _freqs(_line_bdf(tmp_path, 60, 2.0, coupmass=coupmass), 1)
    exact = 4.730041**2 * math.sqrt(2e11 * 2e-7 / (7800 * 1e-3 * 2.0**4)) / (2 * math.pi)
    assert f[0] == pytest.approx(exact, rel=1e-6 if coupmass else 1e-3)


def test_free_free_rod_closed_form(tmp_path):
    """Source: free-free bar, axial f_n = n c / (2 L), c = sqrt(E / rho); torsion
    f_n = n sqrt(G / rho) / (2 L) (J = polar inertia of the section here)."""
    path = _line_bdf(tmp_path, 200, 2.0, card="CROD")
    f = _freqs(path, 2)
    axial = math.sqrt(2e11 / 7800) / 4.0
    # rod rotations carry torsion stiffness but no mass: condensed, leaving axial modes
    assert f[0] == pytest.approx(axial, rel=1e-4)
    assert f[1] == pytest.approx(2 * axial, rel=1e-4)


FIELDS = [("MAT1", 1, "E"), ("MAT1", 1, "RHO"), ("PBAR", 1, "A"), ("PBAR", 1, "I1"),
          ("PBAR", 1, "I2"), ("PBAR", 1, "J"), ("CELAS2", 7, "K"), ("PELAS", 3, "K"),
          ("CONM2", 8, "M"), ("CMASS2", 9, "M")]
EXTRA = ("CELAS2,7,3.e5,4,2\nCELAS1,6,3,3,3,2,1\nPELAS,3,2.e5\n"
         "CONM2,8,5,,12.,0.1,0.05,0.\n,2.,,3.,,,4.\nCMASS2,9,7.,2,3,3,1")


@pytest.mark.parametrize("coupmass", [True, False], ids=["consistent", "lumped"])
@pytest.mark.parametrize("field", FIELDS, ids=["-".join(map(str, f)) for f in FIELDS])
def test_parameter_matrices_finite_differences(tmp_path, field, coupmass):
    """Source: finite differences of the assembled K and M (the card's value changed in
    the file): K_j, M_j are exact derivatives, and K0 + s K_j is the assembled K."""
    path = _line_bdf(tmp_path, 4, 2.0, fixed="123456", coupmass=coupmass, extra=EXTRA)
    card, cid, name = field
    nm = read_nastran(path, [(Parameter("p", 0.0), CardField(card, cid, name))])
    base = read_nastran(path).model
    s = nm.model.values[0]
    h = 0.25 * s
    bumped = nm.bdf
    store = {"MAT1": bumped.materials, "PBAR": bumped.properties, "PELAS": bumped.properties,
             "CELAS2": bumped.elements, "CONM2": bumped.masses, "CMASS2": bumped.masses}[card]
    attr = {"E": "e", "RHO": "rho", "A": "A", "I1": "i1", "I2": "i2", "J": "j", "K": "k",
            "M": "mass"}[name]
    obj = store[cid]
    setattr(obj, attr, getattr(obj, attr) + h)
    if (card, name) == ("MAT1", "E"):
        obj.g = obj.e / (2 * (1 + obj.nu))  # G left blank follows E
    out = tmp_path / "bumped.bdf"
    bumped.write_bdf(str(out), size=16)
    up = read_nastran(out).model
    for total, plus, term, of in ((base.stiffness(), up.stiffness(), nm.model.k_terms[0], "K"),
                                  (base.mass(), up.mass(), nm.model.m_terms[0], "M")):
        fd = ((plus - total) / h).toarray()
        dj = np.zeros_like(fd) if term is None else term.toarray()
        scale = max(abs(total).max(), 1e-300)
        assert np.max(np.abs(fd - dj)) <= 1e-9 * scale / s, of
        model_total = (nm.model.stiffness() if of == "K" else nm.model.mass()).toarray()
        assert np.max(np.abs(model_total - total.toarray())) <= 1e-12 * scale, of


def test_round_trip_same_matrices(tmp_path):
    """read -> write (pyNastran's writer) -> read gives the same K and M."""
    from eigenupdate.io.nastran_write import write_updated_bdf

    nm = read_nastran(FRAME / "frame.bdf")
    out = tmp_path / "again.bdf"
    write_updated_bdf(nm, out, {})
    again = read_nastran(out).model
    assert np.array_equal(again.coordinates, nm.model.coordinates)
    for a, b in ((nm.model.stiffness(), again.stiffness()), (nm.model.mass(), again.mass())):
        assert abs(a - b).max() <= 1e-14 * abs(a).max()


def test_shipped_example_update_and_write_back(tmp_path, run_cli):
    """The shipped study recovers the truth BDF's values within 3 posterior std, and the
    written BDF holds the updated values (to the 16-character field's precision)."""
    out, res = tmp_path / "updated.bdf", tmp_path / "result.json"
    code, text, err = run_cli("update", FRAME / "study.toml", "--save-bdf", out, "--save", res)
    assert code == 0, err
    doc = json.loads(res.read_text())
    truth = read_nastran(FRAME / "truth.bdf", _study_fields()).model
    for p in truth.parameters:
        assert abs(doc["parameters"][p.name] - p.value) < 3 * doc["std"][p.name], p.name
    again = read_nastran(out, _study_fields()).model
    for p in again.parameters:
        assert p.value == pytest.approx(doc["parameters"][p.name], rel=1e-10)
    assert out.read_text().startswith("$ eigenupdate: updated from frame.bdf")


def _study_fields():
    return [(Parameter(n, 0.0), CardField(c, i, f)) for n, c, i, f in (
        ("E_columns", "MAT1", 1, "E"), ("E_beams", "MAT1", 2, "E"),
        ("rho_beams", "MAT1", 2, "RHO"), ("k_support", "CELAS2", 801, "K"),
        ("m_roof_equipment", "CONM2", 901, "M"))]


BAD = [
    ("CBAR,1,5,1,2,0.,1.,0.", "CBAR 1: property PBAR 5 is not defined"),
    ("CBAR,1,1,1,1,0.,1.,0.", "CBAR 1: zero-length element"),
    ("CBAR,1,1,1,2,1.,0.,0.", "CBAR 1: orientation vector is zero or parallel"),
    ("CBAR,1,1,1,9,0.,1.,0.", "CBAR 1: GRID 9 is referenced but not defined"),
    ("CBAR,1,1,1,2,0.,1.,0.\nMAT1,2,2.e11,,0.3,-7800.\nPBAR,2,2,1.e-3,1.e-7,1.e-7,1.e-7\n"
     "CBAR,2,2,2,3,0.,1.,0.", "MAT1 2: negative density"),
    ("CBAR,1,1,1,2,0.,1.,0.\nGRID,4,,0.,1.,0.\nCQUADX,5,1,1,2,3,4\nCQUADX,6,1,1,2,3,4\n"
     "RSPLINE,7,,1,2\nCTRIAX,8,1,1,2,3",
     "not supported: CQUADX x2, CTRIAX x1, RSPLINE x1"),
    ("CBAR,1,1,1,2,0.,1.,0.\nGRID,4,,0.,1.,0.\nCQUAD8,5,1,1,2,3,4",
     "CQUAD8 5: property PSHELL, PCOMP or PCOMPG 1 is not defined"),  # G5-G8 blank: read
    ("CBAR,1,1,1,2,0.,1.,0.\nGRID,4,,0.,1.,0.\nCQUAD4,5,1,1,2,3,4",
     "CQUAD4 5: property PSHELL, PCOMP or PCOMPG 1 is not defined"),
]


@pytest.mark.parametrize("card,message", BAD, ids=[m.split(":")[0] for _, m in BAD])
def test_bad_bdf_one_line(tmp_path, run_cli, card, message):
    """Bad bulk data: exit 2, one line naming the file, the card and the problem, and
    nothing written."""
    bdf = tmp_path / "bad.bdf"
    bdf.write_text("BEGIN BULK\nGRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nGRID,3,,2.,0.,0.\n"
                   f"{card}\nPBAR,1,1,1.e-3,1.e-7,1.e-7,1.e-7\nMAT1,1,2.e11,,0.3,7800.\n"
                   "ENDDATA\n")
    study = tmp_path / "study.toml"
    study.write_text('[model]\ntype = "nastran"\nbdf = "bad.bdf"\n[measurement]\nmodes = [1]\n')
    out = tmp_path / "out.bdf"
    code, text, err = run_cli("update", study, "--save-bdf", out)
    assert code == 2
    assert err.count("\n") == 1 and "Traceback" not in err
    assert str(bdf) in err and message in err
    assert not out.exists()


@pytest.mark.parametrize("table,message", [
    ('card = "MAT1"\nid = 1\nfield = "NU"', "MAT1 1 field NU: not a parameter"),
    ('card = "MAT1"\nid = 1\nfield = "XX"', "MAT1 1: field 'XX' is not a parameter"),
    ('card = "PBAR"\nid = 4\nfield = "A"', "PBAR 4 is not in the file (parameter 1, 'p')"),
])
def test_bad_parameter_field(tmp_path, run_cli, table, message):
    study = tmp_path / "study.toml"
    study.write_text(f'[model]\ntype = "nastran"\nbdf = "{FRAME / "frame.bdf"}"\n'
                     f'[[model.parameter]]\nname = "p"\n{table}\n')
    code, text, err = run_cli("frequencies", study, "--modes", "1")
    assert code == 2 and message in err and "frame.bdf" in err


def test_product_of_parameters(tmp_path, run_cli):
    """E and I1 of the same bars: K holds E * I1 (checked against hand-edited decks in
    test_nastran_nonlinear.py); the frame's bars are shear-rigid, so it is accepted."""
    study = tmp_path / "study.toml"
    study.write_text(f'[model]\ntype = "nastran"\nbdf = "{FRAME / "frame.bdf"}"\n'
                     '[[model.parameter]]\nname = "E"\ncard = "MAT1"\nid = 1\nfield = "E"\n'
                     '[[model.parameter]]\nname = "I"\ncard = "PBAR"\nid = 1\nfield = "I1"\n')
    code, text, err = run_cli("frequencies", study, "--modes", "1")
    assert code == 0, err


def test_perturbation_on_restrained_component(tmp_path, run_cli):
    study = tmp_path / "study.toml"
    text = (FRAME / "study.toml").read_text().replace('"frame.bdf"',
                                                      f'"{FRAME / "frame.bdf"}"')
    # the spring-supported base 1006 is free only in z (component 3)
    study.write_text(text.replace("grid = 2006\ncomponent = 2", "grid = 1006\ncomponent = 2"))
    code, out, err = run_cli("check", study)
    assert code == 2 and "GRID 1006 component 2 is restrained (SPC set 1 or GRID PS)" in err


@pytest.mark.parametrize("old,new,message", [
    ("grid = 6011\n", "grid = 6011.5\n", "perturbation[1].grid: must be an integer"),
    ("component = 2\n", 'component = "2"\n', "perturbation[1].component: must be an integer"),
])
def test_perturbation_grid_not_an_integer(tmp_path, run_cli, old, new, message):
    """One line naming the study and the field once. Source: the tester's acceptance run,
    where `grid = 18.5` printed 'study.toml: perturbation[1].grid: ' twice."""
    study = tmp_path / "study.toml"
    text = (FRAME / "study.toml").read_text().replace('"frame.bdf"',
                                                      f'"{FRAME / "frame.bdf"}"')
    study.write_text(text.replace(old, new, 1))
    code, out, err = run_cli("check", study)
    errors = [x for x in err.splitlines() if "error" in x]
    assert code == 2 and len(errors) == 1 and message in errors[0], err
    assert err.count(str(study)) == 1 and err.count("perturbation[1]") == 1, err


def test_unknown_grid_in_perturbation():
    from eigenupdate.io.nastran import NastranModel

    nm: NastranModel = read_nastran(FRAME / "frame.bdf")
    with pytest.raises(InputError, match="GRID 77 is not defined"):
        nm.grid_dof(77, 1)


def test_coordinate_systems_leave_frequencies_unchanged(tmp_path):
    """The cantilever given in a rotated and shifted CORD2R (CP) with displacements in
    another one (CD) has the same frequencies as in basic: positions and displacement
    frames go through pyNastran's transforms."""
    plain = _freqs(_line_bdf(tmp_path, 10, 2.0, fixed="123456"), 6)
    n, L = 10, 2.0
    lines = ["BEGIN BULK", "PARAM,COUPMASS,1",
             "CORD2R,5,,1.,2.,3.,1.6,2.8,3.9\n,2.,1.,3.5",
             "CORD2R,6,,0.,0.,0.,0.,1.,1.\n,1.,0.,0."]
    for i in range(n + 1):
        lines.append(f"GRID,{i + 1},5,{L * i / n!r},0.,0.,6")
    v = "0.,1.,0."  # orientation in GA's displacement system: CD 6, the same for every grid
    lines += [f"CBAR,{i + 1},1,{i + 1},{i + 2},{v}" for i in range(n)]
    lines += ["PBAR,1,1,1.e-3,2.e-7,8.e-7,5.e-7", "MAT1,1,2.e11,,0.3,7800.",
              "SPC1,1,123456,1", "ENDDATA"]
    path = tmp_path / "rotated.bdf"
    path.write_text("\n".join(lines) + "\n")
    rotated = _freqs(path, 6)
    # a straight clamped beam's frequencies do not depend on its roll about the axis
    assert np.allclose(rotated, plain, rtol=1e-9)


@pytest.mark.parametrize("coupmass", [True, False], ids=["consistent", "lumped"])
def test_cbeam_constant_section_is_the_cbar(tmp_path, coupmass):
    """A CBEAM with a constant PBEAM and K1 = K2 = 0 (no shear flexibility) has the CBAR's
    K (checked against OpenSees above); its M adds MSC's torsional inertia rho (I1 + I2)
    per length on the axial rotations alone (NASTRAN_CoFE's CBEAM): lumped, half of each
    element's at each end; coupled, linear shape functions. Summed over the free
    coordinates (the root's share is restrained) that is rho (I1 + I2) (L - L_e / 2)
    lumped and rho (I1 + I2) (L - 2 L_e / 3) coupled."""
    n, length = 6, 2.0
    bar = read_nastran(_line_bdf(tmp_path, n, length, fixed="123456",
                                 coupmass=coupmass)).model
    beam = read_nastran(_line_bdf(tmp_path, n, length, fixed="123456", coupmass=coupmass,
                                  card="CBEAM")).model
    a, b = bar.stiffness(), beam.stiffness()
    assert abs(a - b).max() <= 1e-15 * abs(a).max()
    diff = (beam.mass() - bar.mass()).tocoo()
    axial_rotation = bar.coordinates % 10 == 4
    hit = diff.data != 0
    assert axial_rotation[diff.row[hit]].all() and axial_rotation[diff.col[hit]].all()
    le, inertia = length / n, 7800.0 * (2.0e-7 + 8.0e-7)
    want = inertia * (length - (2 * le / 3 if coupmass else le / 2))
    assert diff.sum() == pytest.approx(want, rel=1e-13)


def test_cbeam_nonstructural_inertia(tmp_path):
    """PBEAM NSI adds to the CBEAM's torsional mass inertia per length (MSC): the axial
    rotations' mass grows by NSI times the free length's share (lumped: L - L_e / 2)."""
    n, length = 4, 2.0
    plain = _line_bdf(tmp_path, n, length, fixed="123456", coupmass=False, card="CBEAM")
    text = plain.read_text()
    base = read_nastran(plain).model.mass()
    plain.write_text(text.replace("\n,,,,,,,,\n,0.,0.", "\n,,,,,,,,\n,0.,0.,,,0.25,0.25"))
    diff = read_nastran(plain).model.mass() - base
    assert diff.sum() == pytest.approx(0.25 * (length - length / n / 2), rel=1e-13)


def test_timoshenko_cantilever_closed_form(tmp_path):
    """Source: Timoshenko's cantilever under a tip load P, deflection
    P L^3 / (3 E I) + P L / (K A G) in each plane (the two-node element with
    phi = 12 E I / (K A G L^2) is exact for end loads, whatever the mesh); PBEAM
    K1 = 0.85, K2 = 0.6."""
    n, length = 4, 2.0
    model = read_nastran(_line_bdf(tmp_path, n, length, fixed="123456", card="CBEAM",
                                   beam_k="0.85,0.6")).model
    e, g, area = 2.0e11, 2.0e11 / 2.6, 1.0e-3
    K = model.stiffness().toarray()
    for comp, inertia, k in ((2, 2.0e-7, 0.85), (3, 8.0e-7, 0.6)):
        force = np.zeros(model.n)
        force[model.index(10 * (n + 1) + comp)] = 1000.0
        u = np.linalg.solve(K, force)[model.index(10 * (n + 1) + comp)]
        want = 1000.0 * (length**3 / (3 * e * inertia) + length / (k * area * g))
        # K's condition number is 2.8e5: solve() errs by at most about cond eps = 6e-11
        assert u == pytest.approx(want, rel=1e-9)


def test_pbeam_area_parameter_finite_difference(tmp_path):
    """Source: finite difference of the assembled K and M in the PBEAM's A."""
    path = _line_bdf(tmp_path, 3, 2.0, fixed="123456", card="CBEAM")
    nm = read_nastran(path, [(Parameter("A", 0.0), CardField("PBEAM", 1, "A"))])
    bumped = tmp_path / "bumped.bdf"
    bumped.write_text(path.read_text().replace("PBEAM,1,1,1.e-3", "PBEAM,1,1,1.5e-3"))
    up = read_nastran(bumped).model
    for plus, base, term in ((up.stiffness(), nm.model.stiffness(), nm.model.k_terms[0]),
                             (up.mass(), nm.model.mass(), nm.model.m_terms[0])):
        fd = ((plus - base) / 0.5e-3).toarray()
        assert np.max(np.abs(fd - term.toarray())) <= 1e-9 * np.abs(fd).max()


def test_conm2_offset_and_inertia_closed_form(tmp_path):
    """Source: rigid-body mass of a point mass m at offset r with inertia I about its
    centre, seen from the grid: [[m 1, -m [r]x], [m [r]x, I + m (|r|^2 1 - r r^T)]];
    PARAM WTMASS scales all of it."""
    r = np.array([0.3, -0.2, 0.5])
    path = tmp_path / "conm2.bdf"
    path.write_text("BEGIN BULK\nPARAM,WTMASS,0.5\nPARAM,AUTOSPC,NO\nGRID,1,,1.,2.,3.\n"
                    "GRID,2,,2.,2.,3.\n"
                    "CELAS2,1,1.,1,1,2,1\n"
                    f"CONM2,7,1,,12.,{r[0]},{r[1]},{r[2]}\n,2.,0.1,3.,0.2,0.3,4.\nENDDATA\n")
    m = read_nastran(path).model
    rows = [m.index(10 + c) for c in range(1, 7)]
    got = m.mass().toarray()[np.ix_(rows, rows)]
    inertia = np.array([[2.0, -0.1, -0.2], [-0.1, 3.0, -0.3], [-0.2, -0.3, 4.0]])
    rx = np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])
    want = np.block([[12 * np.eye(3), -12 * rx],
                     [12 * rx, inertia + 12 * (r @ r * np.eye(3) - np.outer(r, r))]])
    assert np.allclose(got, 0.5 * want, rtol=1e-14, atol=1e-14)


def test_offsets_stiffness_matches_opensees(tmp_path):
    """Source: OpenSees elastic beam-columns with rigid joint offsets (geomTransf Linear
    -jntOffset, global components as NASTRAN's OFFT GGG): static displacements of a
    portal frame whose beam has offsets at both ends, under loads at its grids. (OpenSees
    does not carry the mass through the offsets; the consistent mass with offsets is
    checked against the rigid-body inertia in test_frame3d.py.)"""
    from nastran_frames import opensees

    ops = opensees()
    nodes = {1: (0.0, 0.0, 0.0), 2: (0.0, 0.0, 3.0), 3: (1.5, 0.0, 3.0), 4: (3.0, 0.0, 3.0),
             5: (3.0, 0.0, 0.0)}
    wa, wb = (0.1, 0.0, -0.05), (-0.1, 0.02, -0.05)
    bars = [(1, 1, 2, (1.0, 0.0, 0.0), None), (2, 2, 3, (0.0, 0.3, 1.0), (wa, wb)),
            (3, 3, 4, (0.0, 0.3, 1.0), None), (4, 5, 4, (1.0, 0.0, 0.0), None)]
    bdf = ["BEGIN BULK", "PARAM,COUPMASS,1"]
    bdf += [f"GRID,{n},,{x[0]},{x[1]},{x[2]}" for n, x in nodes.items()]
    for eid, a, b, v, off in bars:
        w = "" if off is None else "\n,,,{},{},{},{},{},{}".format(*off[0], *off[1])
        bdf.append(f"CBAR,{eid},1,{a},{b},{v[0]},{v[1]},{v[2]},,GGG{w}")
    bdf += ["PBAR,1,1,4.e-3,3.e-5,1.e-5,2.e-7", "MAT1,1,2.1e11,,0.3,7850.",
            "SPC1,1,123456,1,5", "ENDDATA"]
    path = tmp_path / "portal.bdf"
    path.write_text("\n".join(bdf) + "\n")
    m = read_nastran(path).model
    loads = {(3, 1): 1000.0, (3, 3): 500.0, (2, 5): 300.0, (4, 2): -200.0}
    f = np.zeros(m.n)
    for (n, c), value in loads.items():
        f[m.index(10 * n + c)] = value
    u = np.linalg.solve(m.stiffness().toarray(), f)

    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    for n, x in nodes.items():
        ops.node(n, *x)
    ops.fix(1, 1, 1, 1, 1, 1, 1)
    ops.fix(5, 1, 1, 1, 1, 1, 1)
    for eid, a, b, v, off in bars:
        oa, ob = (np.zeros(3), np.zeros(3)) if off is None else map(np.array, off)
        xa, xb = np.array(nodes[a]) + oa, np.array(nodes[b]) + ob
        extra = [] if off is None else ["-jntOffset", *oa, *ob]
        ops.geomTransf("Linear", eid, *np.cross(xb - xa, v), *extra)
        ops.element("elasticBeamColumn", eid, a, b, 4e-3, 2.1e11, 2.1e11 / 2.6, 2e-7, 1e-5,
                    3e-5, eid)
    ops.timeSeries("Constant", 1)
    ops.pattern("Plain", 1, 1)
    for n in (2, 3, 4):
        ops.load(n, *[loads.get((n, c), 0.0) for c in range(1, 7)])
    for cmd, arg in (("system", "FullGeneral"), ("numberer", "Plain"), ("constraints", "Plain"),
                     ("algorithm", "Linear")):
        getattr(ops, cmd)(arg)
    ops.integrator("LoadControl", 1.0)
    ops.analysis("Static")
    ops.analyze(1)
    ref = np.array([ops.nodeDisp(n) for n in (2, 3, 4)]).ravel()
    ops.wipe()
    mine = np.array([u[m.index(10 * n + c)] for n in (2, 3, 4) for c in range(1, 7)])
    assert np.max(np.abs(mine - ref)) <= 1e-9 * np.max(np.abs(ref))


def test_g0_orientation_is_the_vector_to_that_grid(tmp_path):
    """CBAR's G0 gives v = x(G0) - x(GA): a grid off the axis in +y gives the same
    matrices as the vector (0, 1, 0)."""
    plain = read_nastran(_line_bdf(tmp_path, 4, 2.0, fixed="123456")).model
    text = _line_bdf(tmp_path, 4, 2.0, fixed="123456").read_text()
    for i in range(4):
        text = text.replace(f"CBAR,{i + 1},1,{i + 1},{i + 2},0.,1.,0.",
                            f"CBAR,{i + 1},1,{i + 1},{i + 2},99")
    path = tmp_path / "g0.bdf"
    path.write_text(text.replace("ENDDATA", "GRID,99,,0.3,5.,0.\nSPC1,1,123456,99\nENDDATA"))
    g0 = read_nastran(path).model
    assert np.array_equal(g0.coordinates, plain.coordinates)
    for a, b in ((plain.stiffness(), g0.stiffness()), (plain.mass(), g0.mass())):
        assert abs(a - b).max() <= 1e-13 * abs(a).max()


def test_missing_bdf_file(tmp_path, run_cli):
    study = tmp_path / "study.toml"
    study.write_text('[model]\ntype = "nastran"\nbdf = "nowhere.bdf"\n')
    code, out, err = run_cli("frequencies", study, "--modes", "1")
    assert code == 2 and "nowhere.bdf" in err and err.count("\n") == 1


@pytest.mark.parametrize("system", ["CORD2C", "CORD2S"])
def test_curvilinear_displacement_systems(tmp_path, system):
    """Displacements in a cylindrical (spherical) CD are along the local r, theta, z
    (R, theta, phi) at each grid: a cantilever on a ray at 30 degrees in the x-y plane
    whose free end is held across the ray in the plane (cylindrical theta, spherical phi)
    has the frequencies of the same cantilever along x held in y. The CBAR orientation
    vector is given in GA's CD too."""
    n, L = 8, 2.0
    held = _freqs(_line_bdf(tmp_path, n, L, fixed="123456",
                            extra=f"SPC1,1,2,{n + 1}"), 6)
    c, s = math.cos(math.pi / 6), math.sin(math.pi / 6)
    # both systems' z axis is basic z; the grids lie at polar angle 90 degrees, so the
    # spherical theta is -z and phi the in-plane direction across the ray
    lines = ["BEGIN BULK", "PARAM,COUPMASS,1", f"{system},4,,0.,0.,0.,0.,0.,1.\n,1.,0.,0."]
    v = "0.,0.,1." if system == "CORD2C" else "0.,-1.,0."  # basic +z, in GA's CD
    for i in range(n + 1):  # the ray starts 0.5 m out: no grid on the system's axis
        r = 0.5 + L * i / n
        lines.append(f"GRID,{i + 1},,{r * c!r},{r * s!r},0.,4")
    lines += [f"CBAR,{i + 1},1,{i + 1},{i + 2},{v}" for i in range(n)]
    lines += ["PBAR,1,1,1.e-3,8.e-7,2.e-7,5.e-7", "MAT1,1,2.e11,,0.3,7800.",
              "SPC1,1,123456,1", f"SPC1,1,{2 if system == 'CORD2C' else 3},{n + 1}",
              "ENDDATA"]
    path = tmp_path / "ray.bdf"
    path.write_text("\n".join(lines) + "\n")
    assert np.allclose(_freqs(path, 6), held, rtol=1e-9)


def test_report_states_the_decks_units():
    """A deck has no units (README, "Units"): the report must not call its parameters and
    added masses SI. Source: the tester's acceptance run, whose report of a NASTRAN study
    headed the parameter table "(SI units)"."""
    import html
    import warnings

    import eigenupdate as eu

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the deck's skipped cards
        page = html.unescape(eu.report(eu.load_study(FRAME / "study.toml"), solve=False))
    assert "Parameters of the initial model (the deck's units)" in page
    assert "SI units" not in page and "(kg; kg m^2" not in page
    assert "coordinate = 10 x GRID + component" in page
