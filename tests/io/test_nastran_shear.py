"""CSHEAR with PSHEAR read from decks (io/nastran_shear.py; the element:
model/shear_panel.py). Independent references: the statics of a shear panel framed by
CRODs (statically determinate: its compliance by hand), the sway frequency from it, a
stiffened web's in-plane rigid modes, central differences of K and M, the deck edited
by hand and the written BDF read back. Runs in .venv-nastran (pyNastran)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from bounds import assert_matrix_derivatives
from nastran_frames import need

from eigenupdate.errors import EigenupdateWarning, InputError
from eigenupdate.model.parameters import Parameter
from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.io.nastran import CardField, read_nastran  # noqa: E402
from eigenupdate.io.nastran_write import write_updated_bdf  # noqa: E402

A, B, T, E, NU, RHO = 0.6, 0.4, 0.002, 7.0e10, 0.33, 2700.0
G = E / (2 * (1 + NU))


def _read(path, fields=()):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EigenupdateWarning)
        return read_nastran(path, [(Parameter(f"p{i}", 0.0), CardField(*f))
                                   for i, f in enumerate(fields)])


def framed(path, ea, t=T, e=E, rho=RHO, mass=1.5, pshear=None, coupmass=-1):
    """An A x B panel (grids 1-4 counter-clockwise from the origin) in the xy plane,
    CRODs (EA ``ea``, massless) on its sides but the held bottom one, grids 1 and 2
    held, CONM2 ``mass`` at 3 and 4, out-of-plane motion held."""
    area = ea / E
    path.write_text(
        f"BEGIN BULK\nPARAM,COUPMASS,{coupmass}\n"
        f"GRID,1,,0.,0.,0.,,3456\nGRID,2,,{A!r},0.,0.,,3456\n"
        f"GRID,3,,{A!r},{B!r},0.,,3456\nGRID,4,,0.,{B!r},0.,,3456\n"
        f"MAT1,1,{e!r},,{NU!r},{rho!r}\nMAT1,2,{E!r},,{NU!r},0.\n"
        + (pshear or f"PSHEAR,1,1,{t!r}\n")
        + f"CSHEAR,1,1,1,2,3,4\nPROD,2,2,{area!r}\n"
        "CROD,2,2,2,3\nCROD,3,2,3,4\nCROD,4,2,4,1\n"
        f"CONM2,5,3,,{mass!r}\nCONM2,6,4,,{mass!r}\nSPC1,1,12,1,2\nENDDATA\n")
    return path


def _compliance(ea, t=T):
    """Hand statics of :func:`framed` under F/2 along x at grids 3 and 4: the panel's
    shear flow q = F / A (energy q^2 A B / (2 G t)) and the side rods' tension and
    compression F B / (2 A) (energy each (F B / 2 A)^2 B / (2 EA)); the top rod carries
    nothing. Displacement per F: B / (G t A) + B^3 / (2 A^2 EA)."""
    return B / (G * t * A) + B**3 / (2 * A * A * ea)


@pytest.mark.parametrize("ea", [3.0, 1e4], ids=["soft rods", "stiff rods"])
def test_framed_panel_statics_is_the_hand_formula(tmp_path, ea):
    """Source: the statically determinate frame's compliance by hand (_compliance),
    rods as stiff as (3 and 1e4 times) the panel's G t A: both terms matter in the first.
    The solve is LU of a 4 x 4 matrix of condition below 1e5: 1e-10."""
    m = _read(framed(tmp_path / "p.bdf", ea * G * T * A)).model
    K = m.stiffness().toarray()
    c = list(m.coordinates)
    assert sorted(c) == [31, 32, 41, 42]
    f = np.zeros(4)
    f[[c.index(31), c.index(41)]] = 0.5
    u = np.linalg.solve(K, f)
    expected = _compliance(ea * G * T * A)
    assert u[c.index(31)] == pytest.approx(expected, rel=1e-10)
    assert u[c.index(41)] == pytest.approx(expected, rel=1e-10)


@pytest.mark.parametrize("coupmass", [-1, 1], ids=["lumped", "COUPMASS"])
def test_sway_frequency_of_a_framed_panel(tmp_path, coupmass):
    """Source: omega^2 = k / m of the sway, k from the hand statics, m = 2 x 1.5 kg at the
    top grids plus the panel's lumped share (RHO T A B / 2, NASTRAN-95's lumped mass:
    used whatever COUPMASS says). Rods 1e4 times stiffer than the panel: the top grids'
    vertical motion (the rods' stretch) adds inertia of relative order (B / 2A /
    1e4)^2 ~ 1e-9; 1e-7 of the frequency."""
    ea = 1e4 * G * T * A
    m = _read(framed(tmp_path / "p.bdf", ea, coupmass=coupmass)).model
    f = solve_elastic(m.stiffness(), m.mass(), 1).frequencies_hz[0]
    hand = np.sqrt(1 / _compliance(ea) / (3.0 + RHO * T * A * B / 2)) / (2 * np.pi)
    assert f == pytest.approx(hand, rel=1e-7)


def _web(path, n=4, rho=RHO, t=T):
    """A spar web: n panels A x B in a row in the xz plane (normal -y), CROD caps and
    stiffeners (EA 10 G t A) on every side, nothing held but y; MAT1 with G given."""
    lines = []
    for i in range(n + 1):
        lines += [f"GRID,{i + 1},,{i * A!r},0.,0.,,2456",
                  f"GRID,{i + 101},,{i * A!r},0.,{B!r},,2456"]
    for i in range(n):
        lines.append(f"CSHEAR,{i + 1},1,{i + 1},{i + 2},{i + 102},{i + 101}")
        lines += [f"CROD,{i + 11},2,{i + 1},{i + 2}", f"CROD,{i + 31},2,{i + 101},{i + 102}"]
    lines += [f"CROD,{i + 51},2,{i + 1},{i + 101}" for i in range(n + 1)]
    path.write_text("BEGIN BULK\n" + "\n".join(lines) + f"\nPSHEAR,1,1,{t!r},0.3\n"
                    f"MAT1,1,{E!r},{G!r},{NU!r},{rho!r}\nMAT1,2,{E!r},,{NU!r},{rho!r}\n"
                    f"PROD,2,2,{10 * G * T * A / E!r}\nENDDATA\n")
    return path


def test_stiffened_web_has_three_rigid_modes_in_its_plane(tmp_path):
    """Source: a web of 4 panels with caps and stiffeners has 2 x 10 in-plane
    coordinates, 3 rigid motions and 17 members (4 panels, 13 rods): no mechanism, so
    three zero frequencies (translations and the in-plane turn) then elastic ones, and
    K annihilates the rigid motions (1e-12 of |K|)."""
    m = _read(_web(tmp_path / "w.bdf")).model
    sol = solve_elastic(m.stiffness(), m.mass(), 4)
    assert sol.n_rigid == 3
    assert sol.frequencies_hz[3] > 0
    K = m.stiffness().toarray()
    c = np.asarray(m.coordinates)
    grid = c // 10
    x = np.where(grid > 100, grid - 101, grid - 1) * A
    z = np.where(grid > 100, B, 0.0)
    rigid = np.stack([c % 10 == 1, c % 10 == 3,
                      np.where(c % 10 == 1, z, -x)], axis=1).astype(float)  # turn about y
    assert np.abs(K @ rigid).max() <= 1e-12 * np.abs(K).max() * (A * 5)


FIELDS = [("PSHEAR", 1, "T"), ("MAT1", 2, "E")]
EDITS = {("PSHEAR", 1, "T"): (f"PSHEAR,1,1,{T!r}", "PSHEAR,1,1,{!r}"),
         ("MAT1", 2, "E"): (f"MAT1,2,{E!r}", "MAT1,2,{!r}"),
         ("MAT1", 1, "RHO"): (f"MAT1,1,{E!r},{G!r},{NU!r},{RHO!r}",
                              f"MAT1,1,{E!r},{G!r},{NU!r},{{!r}}")}


@pytest.mark.parametrize("fields", [FIELDS, [("MAT1", 1, "RHO")]],
                         ids=["T, rods' E", "panels' RHO"])
def test_parameters_and_the_hand_edited_deck(tmp_path, fields):
    """Sources: central differences of K, M (tests/bounds.py) and the deck with the
    values changed in its text read again (the same integrals times the same factors:
    1e-12 of the largest entry). PSHEAR T scales K (G T) and M (RHO T + NSM); MAT1 1's
    RHO the panels' mass; the rods' MAT1 2 E their stiffness."""
    nm = _read(_web(tmp_path / "a.bdf"), fields)
    assert_matrix_derivatives(nm.model)
    new = [1.2 * v for v in nm.model.values]
    text = (tmp_path / "a.bdf").read_text()
    for f, v in zip(fields, new, strict=True):
        old, pattern = EDITS[f]
        assert old in text
        text = text.replace(old, pattern.format(v))
    (tmp_path / "b.bdf").write_text(text)
    ref = _read(tmp_path / "b.bdf").model
    for a, b in ((nm.model.stiffness(new), ref.stiffness()), (nm.model.mass(new), ref.mass())):
        assert abs(a - b).max() <= 1e-12 * abs(b).max()


def test_panel_e_is_a_parameter_when_g_follows_it(tmp_path):
    """Source: MAT1 with G blank: G = E / (2 (1 + NU)), so the panel's K is linear in E:
    the model at 1.1 E is the deck with 1.1 E (1e-12); with G given E leaves the panel
    alone (its K is G's), and with NU blank (NU = E / 2G - 1) E is refused, one line."""
    nm = _read(framed(tmp_path / "a.bdf", 1e4 * G * T * A), [("MAT1", 1, "E")])
    ref = _read(framed(tmp_path / "b.bdf", 1e4 * G * T * A, e=1.1 * E)).model
    assert abs(nm.model.stiffness([1.1 * E]) - ref.stiffness()).max() <= 1e-12 * abs(
        ref.stiffness()).max()
    path = framed(tmp_path / "c.bdf", 1e4 * G * T * A)
    path.write_text(path.read_text().replace(f"MAT1,1,{E!r},,{NU!r}", f"MAT1,1,{E!r},{G!r},"))
    with pytest.raises(InputError, match="MAT1 1 field E: not a parameter of a shear panel"):
        _read(path, [("MAT1", 1, "E")])


def test_written_bdf_keeps_the_new_thickness(tmp_path):
    """Source: the written deck (--save-bdf's writer) read back: PSHEAR T in its field,
    the same K and M as the model at the written value."""
    nm = _read(_web(tmp_path / "a.bdf"), FIELDS[:1])
    out = tmp_path / "w.bdf"
    write_updated_bdf(nm, out, {"p0": 0.0023})
    back = _read(out, FIELDS[:1]).model
    assert back.values.tolist() == pytest.approx([0.0023], rel=1e-11)
    again = _read(out).model
    for a, b in ((nm.model.stiffness([0.0023]), again.stiffness()),
                 (nm.model.mass([0.0023]), again.mass())):
        assert abs(a - b).max() <= 1e-12 * abs(b).max()


@pytest.mark.parametrize(("pshear", "fields", "words"), [
    (f"PSHEAR,1,1,{T!r},,-0.5\n", (), r"PSHEAR 1: F1 = -0.5 \(extensional effectiveness"),
    (f"PSHEAR,1,1,{T!r}\n", [("PSHEAR", 1, "T"), ("MAT1", 1, "RHO")],
     r"PSHEAR 1 field T and MAT1 1 field RHO: both parameters of one shear panel"),
    ("PSHEAR,1,7,0.002\nMAT8,7,1.e11,1.e10,.3,5.e9\n", (),
     r"PSHEAR 1: material 7 is MAT8 \(MAT1 only\)"),
])
def test_unsupported_pshear_is_refused(tmp_path, pshear, fields, words):
    """One line naming the card and field: a negative F1 (MSC: F1 >= 0),
    PSHEAR T with its MAT1 RHO or E (their product), a MAT8."""
    path = framed(tmp_path / "p.bdf", 1e4 * G * T * A, pshear=pshear)
    with pytest.raises(InputError, match=words):
        _read(path, fields)


def test_concave_cshear_is_refused(tmp_path):
    """One line naming the element (NASTRAN-95 stops on it too: bad geometry)."""
    path = framed(tmp_path / "p.bdf", 1e4 * G * T * A)
    path.write_text(path.read_text().replace(f"GRID,3,,{A!r},{B!r}", "GRID,3,,0.1,0.1"))
    with pytest.raises(InputError, match="CSHEAR 1: not convex"):
        _read(path)


def test_displacement_axes_do_not_change_the_frequencies(tmp_path):
    """Source: invariance. The web with every grid's displacements in a CORD2R turned
    0.4 rad about y (CD: the web's in-plane x and z mixed; y, held, kept) has the same
    frequencies as in basic axes (the panel's blocks turned node by node; 1e-9 with room
    for the eigen-solver's rounding)."""
    plain = _web(tmp_path / "a.bdf")
    c, s = np.cos(0.4), np.sin(0.4)
    turned = tmp_path / "b.bdf"
    turned.write_text(plain.read_text().replace(",,2456", ",5,2456").replace(
        "BEGIN BULK\n", f"BEGIN BULK\nCORD2R,5,,0.,0.,0.,{s!r},0.,{c!r}\n,{c!r},0.,{-s!r}\n"))
    a, b = _read(plain).model, _read(turned).model
    fa = solve_elastic(a.stiffness(), a.mass(), 8)
    fb = solve_elastic(b.stiffness(), b.mass(), 8)
    assert fa.n_rigid == fb.n_rigid == 3
    assert np.max(np.abs(fb.frequencies_hz[3:] / fa.frequencies_hz[3:] - 1)) <= 1e-9
