"""CSHEAR with PSHEAR F1/F2 read from decks (io/nastran_shear.py; the edge rods:
model/shear_panel.py edge_rod_stiffness, MSC's QRG PSHEAR remark). Independent
references: the statics of a shear panel framed by CRODs by hand (the edge rods add to
the side rods' EA), central differences of K and M, and the deck edited by hand and the
written BDF read back. Runs in .venv-nastran (pyNastran)."""

from __future__ import annotations

import numpy as np
import pytest
from bounds import assert_matrix_derivatives
from nastran_frames import assert_hand_edited_deck, need
from test_nastran_shear import NU, RHO, A, E, G, T, _compliance, _read, _web, framed

from eigenupdate.errors import InputError
from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.io.nastran_write import write_updated_bdf  # noqa: E402


def _sway(path):
    """x displacement of grids 3 and 4 of a framed deck under F/2 each along x, per F."""
    m = _read(path).model
    c = list(m.coordinates)
    f = np.zeros(len(c))
    f[[c.index(31), c.index(41)]] = 0.5
    u = np.linalg.solve(m.stiffness().toarray(), f)
    return u[c.index(31)], u[c.index(41)]


@pytest.mark.parametrize(("f2", "area"), [(1.0, T * A / 2), (0.4, 0.4 * T * A / 2),
                                          (30.0, 15 * T * T)],
                         ids=["F2 = 1", "F2 = 0.4", "F2 = 30 (width)"])
def test_framed_panel_statics_with_edge_rods_is_the_hand_formula(tmp_path, f2, area):
    """Source: the framed panel's compliance by hand (test_nastran_shear._compliance):
    F2 puts rods on the sides 2-3 and 4-1 beside the CRODs there, of area F2 T PA /
    (L23 + L41) = F2 T A / 2 (QRG: factor) or F2 T^2 / 2 (width), so the sides' EA
    grows by E times that; F1 = 1 on 1-2 (held) and 3-4 (the unloaded top rod) changes
    nothing. LU of a 4 x 4 matrix of condition below 1e5: 1e-10."""
    ea = 0.1 * G * T * A  # soft CRODs: the edge rods matter
    path = framed(tmp_path / "p.bdf", ea, pshear=f"PSHEAR,1,1,{T!r},,1.,{f2!r}\n")
    expected = _compliance(ea + E * area)
    for u in _sway(path):
        assert u == pytest.approx(expected, rel=1e-10)
    assert expected < 0.7 * _compliance(ea)  # the rods' share is seen


def _panels(path, f1, f2, g="", t=T):
    """Two panels side by side (a general quadrilateral and a rectangle) in the xy plane,
    no CRODs, the left side held, out-of-plane motion held: PSHEAR 1 (F1, F2) of MAT1
    1 (G as given, else E and NU)."""
    path.write_text(
        "BEGIN BULK\nGRID,1,,0.,0.,0.,,3456\nGRID,2,,0.6,0.05,0.,,3456\n"
        "GRID,3,,0.55,0.45,0.,,3456\nGRID,4,,0.,0.4,0.,,3456\n"
        "GRID,5,,1.2,0.05,0.,,3456\nGRID,6,,1.2,0.45,0.,,3456\n"
        "CSHEAR,1,1,1,2,3,4\nCSHEAR,2,1,2,5,6,3\n"
        f"PSHEAR,1,1,{t!r},0.3,{f1!r},{f2!r}\nMAT1,1,{E!r},{g},{NU!r},{RHO!r}\n"
        "SPC1,1,12,1,4\nENDDATA\n")
    return path


EDITS = {("PSHEAR", 1, "T"): (f"PSHEAR,1,1,{T!r}", "PSHEAR,1,1,{!r}"),
         ("MAT1", 1, "E"): (f"MAT1,1,{E!r}", "MAT1,1,{!r}")}


@pytest.mark.parametrize(("f1", "f2", "g", "field"), [
    (0.8, 1.0, "", ("PSHEAR", 1, "T")),
    (0.8, 20.0, "", ("PSHEAR", 1, "T")),
    (30.0, 12.0, "", ("PSHEAR", 1, "T")),
    (0.8, 20.0, "", ("MAT1", 1, "E")),
    (0.8, 20.0, f"{G!r}", ("MAT1", 1, "E")),
], ids=["T, factors", "T, factor and width", "T, widths", "E (G follows)", "E (G given)"])
def test_edge_rod_parameters_and_the_hand_edited_deck(tmp_path, f1, f2, g, field):
    """Sources: central differences of K, M (tests/bounds.py: T enters as G T, E T and,
    with a width, E T^2) and the deck with the value changed in its text read again
    (1e-12 of the largest entry). MAT1 E moves the rods whether or not G follows it."""
    nm = _read(_panels(tmp_path / "a.bdf", f1, f2, g), [field])
    assert_matrix_derivatives(nm.model)
    assert_hand_edited_deck(nm.model, tmp_path / "a.bdf", *EDITS[field], _read)
    base = _read(_panels(tmp_path / "c.bdf", 0.0, 0.0, g)).model
    assert abs(nm.model.stiffness() - base.stiffness()).max() > 1e-3 * abs(
        base.stiffness()).max()  # the rods are there
    assert abs(nm.model.mass() - base.mass()).max() <= 1e-14 * abs(
        base.mass()).max()  # and carry no mass (rounding of T's share taken out and back)


def test_written_bdf_keeps_the_new_thickness_of_a_width_panel(tmp_path):
    """Source: the written deck read back: PSHEAR T in its field and the same K (with
    its E T^2 part) as the model at the written value, 1e-12."""
    nm = _read(_panels(tmp_path / "a.bdf", 30.0, 0.5), [("PSHEAR", 1, "T")])
    out = tmp_path / "w.bdf"
    write_updated_bdf(nm, out, {"p0": 0.0031})
    again = _read(out).model
    assert abs(nm.model.stiffness([0.0031]) - again.stiffness()).max() <= 1e-12 * abs(
        again.stiffness()).max()


def test_edge_rods_without_a_young_modulus_are_refused(tmp_path):
    """One line naming the card: F1/F2 rods need MAT1 E > 0 (a MAT1 with E = 0 and G
    given is a pure shear material, enough for F1 = F2 = 0)."""
    path = _panels(tmp_path / "a.bdf", 1.0, 0.0)
    path.write_text(path.read_text().replace(f"MAT1,1,{E!r},,{NU!r}", f"MAT1,1,0.,{G!r},{NU!r}"))
    with pytest.raises(InputError, match=r"PSHEAR 1: F1 = 1, F2 = 0 \(extensional rods"):
        _read(path)


def test_displacement_axes_do_not_change_the_edge_rods(tmp_path):
    """Source: invariance. test_nastran_shear's web with F1 = 0.5 (factor) and F2 = 20
    (width) and PSHEAR T a parameter (its E T^2 part a separate term), every grid's
    displacements in a CORD2R turned 0.4 rad about y: the same frequencies as in basic
    axes (1e-9 with room for the eigen-solver's rounding); the rods stiffen the web."""
    plain = _web(tmp_path / "a.bdf")
    text = plain.read_text().replace(f"PSHEAR,1,1,{T!r},0.3", f"PSHEAR,1,1,{T!r},0.3,0.5,20.")
    plain.write_text(text)
    c, s = np.cos(0.4), np.sin(0.4)
    turned = tmp_path / "b.bdf"
    turned.write_text(text.replace(",,2456", ",5,2456").replace(
        "BEGIN BULK\n", f"BEGIN BULK\nCORD2R,5,,0.,0.,0.,{s!r},0.,{c!r}\n,{c!r},0.,{-s!r}\n"))
    a, b = (_read(p, [("PSHEAR", 1, "T")]).model for p in (plain, turned))
    fa = solve_elastic(a.stiffness(), a.mass(), 8)
    fb = solve_elastic(b.stiffness(), b.mass(), 8)
    assert fa.n_rigid == fb.n_rigid == 3
    assert np.max(np.abs(fb.frequencies_hz[3:] / fa.frequencies_hz[3:] - 1)) <= 1e-9
    bare = _read(_web(tmp_path / "c.bdf")).model
    f0 = solve_elastic(bare.stiffness(), bare.mass(), 8).frequencies_hz
    assert fa.frequencies_hz[4] > 1.01 * f0[4]  # the second elastic mode (+2.2 %)
