"""Tapered CBEAMs (io/nastran_tapered.py, issue 20): MSC Nastran's modes and grid point
weights of the published fmondsp glider (tapered PBEAML TUBEs), a constant section
written with stations, a tapered PBEAML against the PBEAM of its end sections, a tapered
rod by hand, and what is refused.

Run for real in .venv-nastran (``make test``); skipped in the core environment."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import ROOT
from nastran_frames import need, read_quiet

from eigenupdate.errors import EigenupdateWarning, InputError
from eigenupdate.model.parameters import Parameter
from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.io import nastran_tapered  # noqa: E402
from eigenupdate.io.nastran import CardField, read_nastran  # noqa: E402

DATA = ROOT / "tests" / "data" / "nastran_published"


_read = read_quiet


def _fmondsp_hz() -> np.ndarray:
    model = _read(DATA / "fmondsp.dat").model
    return solve_elastic(model.stiffness(), model.mass(), 12).frequencies_hz


def test_fmondsp_reproduces_msc(monkeypatch):
    """Source: MSC.NASTRAN 2005.1.0's printed real eigenvalues of the published fmondsp
    glider (fmondsp.csv, before the residual vectors): tapered PBEAML TUBEs (fuselage,
    tail), constant BOXes, a CONM2, free-free. Beams and masses only: the shared decks'
    tolerance for line elements, 1e-5 (measured worst 3.0e-7 over 12 modes).

    The test tells the formulations apart: the same flexibility with exact integrals
    (12 Gauss points) misses by 1.1e-3 (2 points 1.5e-3, 4 points 6.2e-4)."""
    want = np.loadtxt(DATA / "fmondsp.csv", delimiter=",", comments="#", skiprows=4)[:, 1]
    got = _fmondsp_hz()
    assert np.max(np.abs(got / want - 1)) < 1e-5
    monkeypatch.setattr(nastran_tapered, "STIFFNESS_POINTS", 12)
    assert np.max(np.abs(_fmondsp_hz() / want - 1)) > 1e-4


def test_fmondsp_mass_is_msc_grid_point_weight():
    """Source: the grid point weight generator in fmondsp.f06 (reference point 0): mass
    3.304377E+02, I_xx 3.061525E+03, centre of gravity x 9.990629E-01. Each tapered
    element's ends take the first moments of its mass (half at each end would put the
    centre of gravity at 0.9995975, 5.4e-4 off). 1e-5: as the modes (measured 3.3e-7,
    6.5e-9, 2.2e-7)."""
    nm = _read(DATA / "fmondsp.dat")
    M = nm.model.mass()
    M = M.toarray() if hasattr(M, "toarray") else np.asarray(M)
    rigid = np.zeros((M.shape[0], 6))  # translations x, y, z; rotations about x, y, z
    for i, c in enumerate(nm.model.coordinates):
        grid, comp = divmod(int(c), 10)
        x = nm.bdf.nodes[grid].get_position()
        if comp <= 3:
            rigid[i, comp - 1] = 1.0
            rigid[i, 3:] = np.cross(np.eye(3), x)[:, comp - 1]
        else:
            rigid[i, comp - 1] = 1.0
    m0 = rigid.T @ M @ rigid
    mass, ixx = m0[0, 0], m0[3, 3]
    cg_x = m0[1, 5] / mass  # moment of the y motion about z: m x
    assert abs(mass / 330.4377 - 1) < 1e-5
    assert abs(ixx / 3061.525 - 1) < 1e-5
    assert abs(cg_x / 0.9990629 - 1) < 1e-5


BULK = ("GRID,1,,0.,0.,0.\nGRID,2,,0.8,0.,0.\nCBEAM,1,{pid},1,2,0.,1.,0.\n{props}\n"
        "MAT1,1,7.e10,,0.3,2700.\n{extra}SPC1,1,123456,1\nENDDATA\n")


def _deck(tmp_path, props: str, pid: int = 1, extra: str = "", name: str = "beam.bdf"):
    path = tmp_path / name
    path.write_text(BULK.format(pid=pid, props=props, extra=extra))
    return path


def _km(path):
    model = _read(path).model
    return [x.toarray() if hasattr(x, "toarray") else np.asarray(x)
            for x in (model.stiffness(), model.mass())]


@pytest.mark.parametrize("coupled", [False, True])
def test_constant_section_written_with_stations_is_the_constant_element(tmp_path, coupled):
    """Source: the constant element: a PBEAM whose end B repeats end A, and a PBEAML with
    the same dimensions at both ends, give exactly (bit for bit) the K and M of the card
    written for end A alone."""
    extra = "PARAM,COUPMASS,1\n" if coupled else ""
    a = "PBEAM,1,1,1.e-3,2.e-7,3.e-7,,4.e-7,0.5"
    b = a + "\n,,,,,,,,\n,NO,1.,1.e-3,2.e-7,3.e-7,,4.e-7,0.5"
    c = "PBEAML,1,1,,TUBE\n,.06,.05"
    d = "PBEAML,1,1,,TUBE\n,.06,.05,,NO,1.,.06,.05"
    for one, two in ((a, b), (c, d)):
        x = _km(_deck(tmp_path, one, extra=extra, name="one.bdf"))
        y = _km(_deck(tmp_path, two, extra=extra, name="two.bdf"))
        assert all(np.array_equal(p, q) for p, q in zip(x, y, strict=True))


def test_tapered_pbeaml_is_the_pbeam_of_its_end_sections(tmp_path):
    """Source: MSC's equivalent PBEAM of a PBEAML (fmondsp.op2): the section of each end
    by hand (annulus A = pi (r_o^2 - r_i^2), I = pi (r_o^4 - r_i^4) / 4, J = 2 I) and the
    TUBE's K1 = K2 = 0.5: the same K and M to rounding (1e-13 of the largest term)."""
    def tube(ro, ri):
        i = math.pi * (ro**4 - ri**4) / 4
        return math.pi * (ro**2 - ri**2), i, i, 2 * i
    (a1, i1, j1, k1), (a2, i2, j2, k2) = tube(0.06, 0.05), tube(0.04, 0.03)
    pbeam = (f"PBEAM,1,1,{a1!r},{i1!r},{j1!r},,{k1!r}\n,,,,,,,,\n"
             f",NO,1.,{a2!r},{i2!r},{j2!r},,{k2!r}\n,0.5,0.5")
    x = _km(_deck(tmp_path, pbeam, name="pbeam.bdf"))
    y = _km(_deck(tmp_path, "PBEAML,1,1,,TUBE\n,.06,.05,,NO,1.,.04,.03", name="pbeaml.bdf"))
    for p, q in zip(x, y, strict=True):
        assert np.abs(p - q).max() <= 1e-13 * np.abs(p).max()


def test_tapered_rod_stiffness_by_hand(tmp_path):
    """Source: a tapered bar's axial stiffness by hand with MSC's 3-point Gauss rule,
    k = E / (L sum_i w_i / A(s_i)) (points 1/2 -+ sqrt(15)/10, weights 5/18, 8/18, 5/18),
    within Gauss-Legendre's error bound of the exact E (A_a - A_b) / (L ln(A_a / A_b)):
    (3!)^4 / (7 (6!)^3) 6! |A_b - A_a|^6 / A_b^7 of int ds / A."""
    aa, ab, L, E = 1.e-3, 5.e-4, 0.8, 7e10
    path = _deck(tmp_path, f"PBEAM,1,1,{aa},2.e-7,3.e-7,,4.e-7\n,,,,,,,,\n"
                           f",NO,1.,{ab},1.e-7,1.5e-7,,2.e-7")
    model = _read(path).model
    k = model.stiffness()
    k = k.toarray() if hasattr(k, "toarray") else np.asarray(k)
    i = list(model.coordinates).index(21)  # grid 2, x (grid 1 is held)
    got = k[i, i]
    s = np.array([0.5 - math.sqrt(15) / 10, 0.5, 0.5 + math.sqrt(15) / 10])
    w = np.array([5.0, 8.0, 5.0]) / 18
    assert got == pytest.approx(E / (L * np.sum(w / (aa + (ab - aa) * s))), rel=1e-14)
    exact = math.log(aa / ab) / (aa - ab)
    bound = 6**4 / (7 * 720**3) * 720 * abs(ab - aa) ** 6 / ab**7
    assert abs(E / (L * got) - exact) <= bound


def test_coupled_mass_of_a_tapered_beam_warns(tmp_path):
    """NASTRAN's integration of a tapered CBEAM's coupled mass is not established here:
    the warning names the property."""
    path = _deck(tmp_path, "PBEAML,1,1,,TUBE\n,.06,.05,,NO,1.,.04,.03",
                 extra="PARAM,COUPMASS,1\n")
    with pytest.warns(EigenupdateWarning, match="PBEAML 1: coupled mass"):
        read_nastran(path)


@pytest.mark.parametrize("props,pid,extra,message", [
    ("PBEAM,1,1,1.e-3,2.e-7,3.e-7,,4.e-7\n,,,,,,,,\n,NO,0.5,7.e-4,1.e-7,1.5e-7,,2.e-7\n"
     ",NO,1.,5.e-4,1.e-7,1.5e-7,,2.e-7", 1, "",
     "PBEAM 1: stations X/XB = [0.0, 0.5, 1.0]: a tapered section with intermediate "
     "stations is not supported"),
    ("PBEAM,1,1,1.e-3,2.e-7,3.e-7,1.e-8,4.e-7\n,,,,,,,,\n,NO,1.,5.e-4,1.e-7,1.5e-7,1.e-8,"
     "2.e-7", 1, "", "PBEAM 1: a tapered section with I12 != 0 is not supported"),
    ("PBEAML,1,1,,BOX\n,.6,.2,.0025,.0025,,NO,1.,.4\n,.2,.0025,.0025", 1, "",
     "PBEAML 1: the shear factors differ between the ends"),
], ids=["stations", "I12", "BOX-K"])
def test_refused_tapers_name_the_card(tmp_path, props, pid, extra, message):
    """One InputError naming the card and id."""
    with pytest.raises(InputError, match=message.replace("[", r"\[").replace("]", r"\]")):
        read_nastran(_deck(tmp_path, props, pid, extra))


def test_pin_flags_on_a_tapered_beam_are_refused(tmp_path):
    """CBEAM pin flags with a taper: one line naming the element and the property."""
    path = _deck(tmp_path, "PBEAML,1,1,,TUBE\n,.06,.05,,NO,1.,.04,.03")
    path.write_text(path.read_text().replace("CBEAM,1,1,1,2,0.,1.,0.",
                                             "CBEAM,1,1,1,2,0.,1.,0.\n,,6"))
    with pytest.raises(InputError, match="CBEAM 1: pin flags on a tapered beam "
                                         r"\(PBEAML 1\) are not supported"):
        read_nastran(path)


@pytest.mark.parametrize("field,nsm,message", [
    (CardField("PBEAM", 1, "A"), "", "PBEAM 1: parameters on a tapered section"),
    (CardField("MAT1", 1, "RHO"), "0.5", "MAT1 1: RHO as a parameter of the tapered PBEAM 1 "
                                         "with NSM or NSI"),
])
def test_parameters_a_taper_does_not_scale_are_refused(tmp_path, field, nsm, message):
    """A PBEAM field of a tapered property, or MAT1 RHO when NSM shapes the mass per
    length, would not scale the element's parts: refused naming the card."""
    path = _deck(tmp_path, f"PBEAM,1,1,1.e-3,2.e-7,3.e-7,,4.e-7,{nsm}\n,,,,,,,,\n"
                           f",NO,1.,5.e-4,1.e-7,1.5e-7,,2.e-7,{nsm}")
    with pytest.raises(InputError, match=message):
        read_nastran(path, [(Parameter("p", 0.0), field)])


def test_material_e_stays_a_linear_parameter_of_a_tapered_beam(tmp_path):
    """Source: K is linear in MAT1 E when G follows it (G blank): the derivative is the
    stiffness at unit E, K_E = K / E (rounding: 1e-13 of the largest term)."""
    path = _deck(tmp_path, "PBEAML,1,1,,TUBE\n,.06,.05,,NO,1.,.04,.03")
    model = _read(path, [(Parameter("E", 0.0), CardField("MAT1", 1, "E"))]).model
    k, kj = model.stiffness(), model.k_terms[0]
    k = k.toarray() if hasattr(k, "toarray") else np.asarray(k)
    kj = kj.toarray() if hasattr(kj, "toarray") else np.asarray(kj)
    assert np.abs(kj * 7e10 - k).max() <= 1e-13 * np.abs(k).max()
