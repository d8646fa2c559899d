"""Scalar points, CELAS3/4, CMASS3/4, CONM1 and CBUSH/PBUSH against closed forms, and
their parameter fields against finite differences.

Run for real in .venv-nastran (``make test``); skipped in the core environment."""

from __future__ import annotations

import numpy as np
import pytest
from nastran_frames import need

from eigenupdate.model.parameters import Parameter
from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.io.nastran import (  # noqa: E402
    FIELDS,
    CardField,
    get_field,
    read_nastran,
    set_field,
    stores,
)


def _deck(tmp_path, body: str, name="deck.bdf"):
    path = tmp_path / name
    path.write_text("BEGIN BULK\n" + body + "ENDDATA\n")
    return path


def test_scalar_points_two_mass_chain(tmp_path):
    """Source: ground -k1- m1 -k2- m2 on scalar points (CELAS3 + PELAS, CELAS4; CMASS3 +
    PMASS, CMASS4): lambda solves m1 m2 l^2 - (m1 k2 + m2 (k1 + k2)) l + k1 k2 = 0."""
    k1, k2, m1, m2 = 3.0e4, 1.0e4, 2.0, 5.0
    path = _deck(tmp_path, f"SPOINT,5,6\nCELAS3,1,9,5\nPELAS,9,{k1}\nCELAS4,2,{k2},5,6\n"
                 f"CMASS3,3,8,5\nPMASS,8,{m1}\nCMASS4,4,{m2},6\n")
    model = read_nastran(path).model
    assert model.coordinates.tolist() == [51, 61]
    lam = np.roots([m1 * m2, -(m1 * k2 + m2 * (k1 + k2)), k1 * k2])
    want = np.sort(np.sqrt(lam)) / (2 * np.pi)
    got = solve_elastic(model.stiffness(), model.mass(), 2).frequencies_hz
    assert got == pytest.approx(want, rel=1e-12)


@pytest.mark.parametrize("spc", ["SPC1,1,0,5", "SPC1,1,,5", "SPC,1,5,0", "SPC,1,5,,0."])
def test_spc_on_a_scalar_point(tmp_path, spc):
    """Source: QRG SPC/SPC1, a scalar point's component is 0 or blank. Scalar point 5
    held, 6 on a 100 N/m spring to ground and one to 5, 1 kg: omega^2 = 200 (the SPC was
    dropped, leaving 5 free: two modes instead of one)."""
    path = _deck(tmp_path, f"SPOINT,5,6\nCELAS2,1,100.,5,0,6,0\nCELAS2,2,100.,6,0\n"
                 f"CMASS2,3,1.,5,0\nCMASS2,4,1.,6,0\n{spc}\n")
    nm = read_nastran(path)
    assert nm.model.coordinates.tolist() == [61] and nm.restrained == {51}
    got = solve_elastic(nm.model.stiffness(), nm.model.mass(), 1).frequencies_hz
    assert got == pytest.approx([np.sqrt(200.0) / (2 * np.pi)], rel=1e-12)


def test_spc_component_0_on_a_grid_is_named(tmp_path):
    """QRG SPC1: a grid's components are 1-6; 0 or blank (a scalar point's) on a grid
    restrains nothing, which was silent."""
    import warnings

    from eigenupdate.errors import EigenupdateWarning

    path = _deck(tmp_path, "GRID,1,,0.,0.,0.\nSPOINT,6\nCELAS2,1,100.,1,3,6,0\n"
                 "CELAS2,2,100.,6,0\nCONM2,3,1,,1.\nCMASS2,4,1.,6,0\nSPC1,1,0,1\n")
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always", EigenupdateWarning)
        nm = read_nastran(path)
    assert any("SPC1 1: GRID 1 with component 0 or blank restrains nothing" in str(w.message)
               for w in got)
    assert not nm.restrained


ROT = "CORD2R,4,,0.,0.,0.,0.,0.,1.\n,0.,1.,0.\n"  # x' = y, y' = -x: 90 degrees about z


def _z90() -> np.ndarray:
    """Rows: axes of CORD2R 4 in basic (z' = z, x' = basic y)."""
    return np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])


@pytest.mark.parametrize("cid", [0, 4])
def test_conm1_closed_form(tmp_path, cid):
    """Source: CONM1's symmetric 6 x 6 matrix (lower triangle on the card) in system
    CID, seen in basic: B^T M B with B = blockdiag(axes of CID); times WTMASS."""
    lower = [2.0, 0.1, 3.0, 0.0, 0.0, 4.0, 0.0, 0.2, 0.0, 1.5,
             0.0, 0.0, 0.0, 0.0, 1.6, 0.3, 0.0, 0.0, 0.0, 0.0, 1.7]
    fields = ",".join(map(str, lower))
    # 21 values after EID, G, CID: 5 on the first line, 8 and 8 on continuations
    vals = fields.split(",")
    card = (f"CONM1,5,1,{cid}," + ",".join(vals[:5]) + "\n," + ",".join(vals[5:13]) + "\n,"
            + ",".join(vals[13:]))
    path = _deck(tmp_path, ROT + "PARAM,WTMASS,0.5\nPARAM,AUTOSPC,NO\nGRID,1,,1.,2.,3.\n"
                 + card + "\n")
    model = read_nastran(path).model
    full = np.zeros((6, 6))
    full[np.tril_indices(6)] = lower
    full = full + np.tril(full, -1).T
    b = np.zeros((6, 6))
    b[:3, :3] = b[3:, 3:] = _z90() if cid else np.eye(3)
    rows = [model.index(10 + c) for c in range(1, 7)]
    got = model.mass().toarray()[np.ix_(rows, rows)]
    assert np.allclose(got, 0.5 * b.T @ full @ b, rtol=1e-14, atol=1e-14)


def test_grounded_cbush_is_six_springs(tmp_path):
    """Source: a grounded CBUSH in CID 4 is K = B^T diag(K1..K6) B at its grid."""
    k = [1.0e5, 2.0e5, 3.0e5, 4.0e3, 5.0e3, 6.0e3]
    path = _deck(tmp_path, ROT + "GRID,1,,1.,2.,3.\nCBUSH,1,2,1,,,,,4\n"
                 "PBUSH,2,K," + ",".join(map(str, k)) + "\nCONM2,3,1,,1.\n,1.,,1.,,,1.\n")
    model = read_nastran(path).model
    b = np.zeros((6, 6))
    b[:3, :3] = b[3:, 3:] = _z90()
    rows = [model.index(10 + c) for c in range(1, 7)]
    got = model.stiffness().toarray()[np.ix_(rows, rows)]
    assert np.allclose(got, b.T @ np.diag(k) @ b, rtol=1e-14, atol=1e-9)


def test_cbush_between_grids_closed_form(tmp_path):
    """Source: springs at the mid-point of a bar of length L along x, rigidly linked to
    both ends: the transverse spring K2 acts on v_B - v_A - (L/2) (rz_A + rz_B), so
    K[v_B, rz_B] = -K2 L / 2 and K[rz_B, rz_B] = K2 L^2 / 4 + K6."""
    k2, k6, length = 2.0e5, 6.0e3, 1.5
    path = _deck(tmp_path, f"GRID,1,,0.,0.,0.\nGRID,2,,{length},0.,0.\nCBUSH,1,2,1,2,0.,1.,0.\n"
                 f"PBUSH,2,K,1.e5,{k2},3.e5,4.e3,5.e3,{k6}\nSPC1,1,123456,1\n")
    model = read_nastran(path).model
    K = model.stiffness().toarray()
    v, rz = model.index(22), model.index(26)
    assert K[v, rz] == pytest.approx(-k2 * length / 2, rel=1e-14)
    assert K[rz, rz] == pytest.approx(k2 * length**2 / 4 + k6, rel=1e-14)


NEW = [("PBUSH", 2, "K1"), ("PBUSH", 2, "K6"), ("CONM1", 5, "M11"), ("CONM1", 5, "M42"),
       ("CELAS4", 3, "K"), ("CMASS4", 4, "M")]
BODY = (ROT + "GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nSPOINT,9\nCBUSH,1,2,1,2,0.,1.,0.\n"
        "PBUSH,2,K,1.e5,2.e5,3.e5,4.e3,5.e3,6.e3\nSPC1,1,123456,1\n"
        "CONM1,5,2,4,2.,0.,2.,0.,0.\n,2.,0.,0.3,0.,1.,0.,0.,0.\n,0.,1.,0.,0.,0.,0.,0.,1.\n"
        "CELAS4,3,7.e4,9\nCMASS4,4,3.,9\n")


@pytest.mark.parametrize("field", NEW, ids=["-".join(map(str, f)) for f in NEW])
def test_new_parameters_finite_differences(tmp_path, field):
    """Source: finite differences of the assembled K and M with the card's value changed
    in the file: K_j, M_j are exact derivatives."""
    path = _deck(tmp_path, BODY)
    card, cid, name = field
    nm = read_nastran(path, [(Parameter("p", 0.0), CardField(card, cid, name))])
    base = read_nastran(path).model
    s = nm.model.values[0]
    h = 0.25 * s
    obj = stores(nm.bdf)[card][cid]
    set_field(obj, FIELDS[card][name], get_field(obj, FIELDS[card][name]) + h)
    out = tmp_path / "bumped.bdf"
    nm.bdf.write_bdf(str(out), size=16)
    up = read_nastran(out).model
    for total, plus, term in ((base.stiffness(), up.stiffness(), nm.model.k_terms[0]),
                              (base.mass(), up.mass(), nm.model.m_terms[0])):
        fd = ((plus - total) / h).toarray()
        dj = np.zeros_like(fd) if term is None else term.toarray()
        # the difference of two assemblies of values ~|total| loses ~eps |total| / h
        assert np.max(np.abs(fd - dj)) <= 1e-9 * max(abs(total).max(), 1e-300) / s


WRITTEN = NEW + [("PELAS", 12, "K"), ("PMASS", 14, "M"), ("MAT1", 1, "E"), ("PBAR", 1, "I2"),
                 ("CONM2", 8, "M")]
# small-field and free-field cards; PELAS and PMASS with their id in a later pair
MORE = ("PELAS,11,1.e3,,,12,2.5e3\nCELAS1,21,12,9\nPMASS   13      1.5     14      2500.\n"
        "CMASS1,22,14,9\nMAT1           1  2.1+11              .3   7850.\n"
        "PBAR           1       1    .001   2.e-7   8.e-7   5.e-7\n"
        "GRID,3,,2.,0.,0.\nCBAR,31,1,2,3,0.,1.,0.\nCONM2          8       3            150.\n")


@pytest.mark.parametrize("field", WRITTEN, ids=["-".join(map(str, f)) for f in WRITTEN])
def test_write_back_changes_exactly_the_updated_field(tmp_path, field):
    """The deck written back differs from the read one only in the updated card, whose
    field reads back as the new value (12 digits); unchanged parameters are not touched
    (their text, e.g. 2500., stays as it was given)."""
    from eigenupdate.io.nastran_write import write_updated_bdf

    path = _deck(tmp_path, BODY + MORE)
    card, cid, name = field
    specs = [(Parameter("p", 0.0), CardField(card, cid, name)),
             (Parameter("fixed", 0.0, update=False), CardField("PMASS", 14, "M"))]
    if (card, cid, name) == ("PMASS", 14, "M"):
        specs = specs[:1]
    nm = read_nastran(path, specs)
    new = nm.model.values[0] * 1.2345678901234
    out = tmp_path / "out.bdf"
    write_updated_bdf(nm, out, {"p": new, "fixed": nm.model.values[-1]})
    again = read_nastran(out, specs[:1])
    assert again.model.values[0] == pytest.approx(new, rel=1e-11)
    before = path.read_text().splitlines()
    after = out.read_text().splitlines()
    gone = [x for x in before if x not in after]
    assert gone and all(x.startswith(",") or x.split(",")[0].split()[0].startswith(card)
                        for x in gone)
    assert "PMASS   13      1.5     14      2500." in after or card == "PMASS"


def test_ctube_is_the_crod_of_its_annulus(tmp_path):
    """Source: PTUBE OD, T make A = pi (OD^2 - ID^2) / 4 and J = pi (OD^4 - ID^4) / 32,
    the PROD of the same values (NASTRAN's CTUBE is a CROD of that section)."""
    od, t = 0.05, 0.004
    inner = od - 2 * t
    a = np.pi * (od**2 - inner**2) / 4
    j = np.pi * (od**4 - inner**4) / 32
    common = ("GRID,1,,0.,0.,0.\nGRID,2,,1.,0.3,0.\nMAT1,1,2.e11,,0.3,7800.\nSPC1,1,123,1\n"
              "PARAM,COUPMASS,1\n")
    tube = read_nastran(_deck(tmp_path, common + f"CTUBE,1,1,1,2\nPTUBE,1,1,{od},{t}\n",
                              "tube.bdf")).model
    rod = read_nastran(_deck(tmp_path, common + f"CROD,1,1,1,2\nPROD,1,1,{a!r},{j!r}\n",
                             "rod.bdf")).model
    for x, y in ((tube.stiffness(), rod.stiffness()), (tube.mass(), rod.mass())):
        assert abs(x - y).max() <= 1e-13 * abs(x).max()


def test_negative_coupling_mass_of_a_lumped_mass_matrix(tmp_path):
    """Closed form: NASTRAN's CMASS M is any real number (NASTRAN-95 User's Manual CMASS2);
    masses m on two scalar points and -c between them are M = [[m - c, c], [c, m - c]]
    with eigenvalues m and m - 2c; springs k to ground give lambda = k / m and
    k / (m - 2c): m 3, c 1, k 6 give 2 and 6 (exact: 1e-12)."""
    path = _deck(tmp_path, "SPOINT,1,2\nCELAS4,1,6.,1\nCELAS4,2,6.,2\nCMASS4,3,3.,1\n"
                           "CMASS4,4,3.,2\nCMASS4,5,-1.,1,2\n")
    model = read_nastran(path).model
    lam = solve_elastic(model.stiffness(), model.mass(), 2).eigenvalues
    assert np.allclose(lam, [2.0, 6.0], rtol=1e-12)


@pytest.mark.parametrize("body,words", [
    # m 1 on each point, -2 between: M = [[-1, 2], [2, -1]], eigenvalues 1 and -3
    ("SPOINT,1,2\nCELAS4,1,6.,1\nCMASS4,3,1.,1\nCMASS4,4,1.,2\nCMASS4,5,-2.,1,2\n",
     "CMASS4 5: negative mass between two coordinates makes the scalar masses on them "
     "indefinite"),
    ("SPOINT,1\nCELAS4,1,6.,1\nCMASS4,3,-1.,1\n", "CMASS4 3: negative mass -1"),
], ids=["coupling making M indefinite", "grounded"])
def test_negative_mass_refused(tmp_path, body, words):
    """Source: M must be positive semi-definite (a mass matrix); the scalar masses on the
    coordinates a negative coupling mass joins are a principal block the other elements
    can only add semi-definite terms to, and a grounded negative mass is a negative
    diagonal term. The message names the line and the card."""
    from eigenupdate.errors import InputError

    with pytest.raises(InputError, match=words) as info:
        read_nastran(_deck(tmp_path, body))
    assert "deck.bdf: line " in str(info.value)
