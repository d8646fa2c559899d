"""PBARL standard sections on CBAR: the section properties against closed forms, a frame
of PBARL members against the same frame with the equivalent PBAR cards, and the shapes,
libraries and parameters that are refused.

Run for real in .venv-nastran (``make test``); skipped in the core environment."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from nastran_frames import need, random_frame

from eigenupdate.errors import EigenupdateWarning
from eigenupdate.model.parameters import Parameter
from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.io.nastran import CardField, read_nastran  # noqa: E402
from eigenupdate.io.nastran_deck import load_deck  # noqa: E402
from eigenupdate.io.nastran_lines import pbarl_section  # noqa: E402


def closed_form(shape: str, d: list[float]) -> tuple[float, float, float, float]:
    """A, I1 (about the section's z axis, int y^2 dA), I2, J written out by hand.

    Sources: circle and annulus (J = I1 + I2 = 2 I); rectangle b h^3 / 12; box and
    channel I1 as the bounding rectangle less the inner one; T (and T2, the same T upside
    down) and I by the parallel-axis theorem from their strips; H's plates and web centred
    on the axes (I2 the plates' outer rectangle less the gap); torsion: Roark's rectangle
    approximation (BAR), Bredt (BOX), sum l t^3 / 3 over mid-lines (I, T, CHAN, T2, H), as
    NASTRAN's PBARL tables."""
    if shape in ("ROD", "TUBE"):
        ro, ri = d[0], (d[1] if shape == "TUBE" else 0.0)
        i = math.pi * (ro**4 - ri**4) / 4
        return math.pi * (ro**2 - ri**2), i, i, 2 * i
    if shape == "BAR":
        b, h = d
        lo, hi = min(b, h), max(b, h)
        j = hi * lo**3 * (1 / 3 - 0.21 * lo / hi * (1 - lo**4 / (12 * hi**4)))
        return b * h, b * h**3 / 12, h * b**3 / 12, j
    if shape == "BOX":
        b, h, t1, t2 = d
        bi, hi = b - 2 * t2, h - 2 * t1
        am = (b - t2) * (h - t1)
        j = 4 * am**2 / (2 * (b - t2) / t1 + 2 * (h - t1) / t2)
        return b * h - bi * hi, (b * h**3 - bi * hi**3) / 12, (h * b**3 - hi * bi**3) / 12, j
    if shape == "I":  # doubly symmetric here
        h, b, _, tw, tf, _ = d
        hw = h - 2 * tf
        return (2 * b * tf + hw * tw, (b * h**3 - (b - tw) * hw**3) / 12,
                (2 * tf * b**3 + hw * tw**3) / 12, (2 * b * tf**3 + (h - tf) * tw**3) / 3)
    if shape in ("T", "T2"):  # T2: a T upside down, the same A, I1, I2, J
        b, h, tf, tw = d
        hw = h - tf
        a = b * tf + hw * tw
        y = (b * tf * (h - tf / 2) + hw * tw * hw / 2) / a  # centroid above the web's end
        i1 = (b * tf**3 / 12 + b * tf * (h - tf / 2 - y) ** 2 + tw * hw**3 / 12
              + hw * tw * (hw / 2 - y) ** 2)
        return a, i1, (tf * b**3 + hw * tw**3) / 12, (b * tf**3 + (h - tf / 2) * tw**3) / 3
    if shape == "H":  # two plates DIM2 / 2 x DIM3, DIM1 apart, web DIM4 between them
        gap, tt, h, tw = d
        return (tt * h + gap * tw, tt * h**3 / 12 + gap * tw**3 / 12,
                h * ((gap + tt) ** 3 - gap**3) / 12 + tw * gap**3 / 12,
                (2 * h * (tt / 2) ** 3 + (gap + tt / 2) * tw**3) / 3)
    b, h, tw, tf = d  # CHAN
    bf = b - tw
    a = h * tw + 2 * bf * tf
    z = (h * tw * tw / 2 + 2 * bf * tf * (tw + bf / 2)) / a  # centroid from the web's back
    i2 = (h * tw**3 / 12 + h * tw * (tw / 2 - z) ** 2 + 2 * tf * bf**3 / 12
          + 2 * bf * tf * (tw + bf / 2 - z) ** 2)
    return (a, (b * h**3 - bf * (h - 2 * tf) ** 3) / 12, i2,
            (2 * (b - tw / 2) * tf**3 + (h - tf) * tw**3) / 3)


SECTIONS = {  # pid: (shape, dims), metres
    1: ("ROD", [0.03]), 2: ("TUBE", [0.06, 0.05]), 3: ("BAR", [0.04, 0.1]),
    4: ("BOX", [0.12, 0.2, 0.008, 0.01]), 5: ("I", [0.3, 0.15, 0.15, 0.0071, 0.0107, 0.0107]),
    6: ("T", [0.15, 0.2, 0.012, 0.008]), 7: ("CHAN", [0.09, 0.26, 0.01, 0.014]),
    8: ("T2", [0.12, 0.18, 0.01, 0.007]), 9: ("H", [0.1, 0.02, 0.16, 0.008]),
}


def _pbarl(pid: int, shape: str, dims: list[float]) -> str:
    fields = [f"PBARL,{pid},1,,{shape}"]
    fields.append("," + ",".join(repr(x) for x in dims))
    return "\n".join(fields)


def _bulk(cards: str) -> str:
    return ("BEGIN BULK\nPARAM,COUPMASS,1\nGRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\n"
            f"CBAR,1,1,1,2,0.,1.,0.\n{cards}\nMAT1,1,2.e11,,0.3,7800.\nSPC1,1,123456,1\n"
            "ENDDATA\n")


@pytest.mark.parametrize("pid", sorted(SECTIONS), ids=[s for s, _ in SECTIONS.values()])
def test_section_properties_closed_forms(tmp_path, pid):
    """A, I1, I2, J the reader takes from a PBARL card against the closed forms above."""
    shape, dims = SECTIONS[pid]
    path = tmp_path / "one.bdf"
    path.write_text(_bulk(_pbarl(1, shape, dims)))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EigenupdateWarning)  # shear factors not modelled
        A, i1, i2, j, nsm, mid, key, *_ = pbarl_section(load_deck(path).bdf.properties[1])
    assert (A, i1, i2, j) == pytest.approx(closed_form(shape, dims), rel=1e-13)
    assert (nsm, mid, key) == (0.0, 1, ("PBARL", 1))


def _frame_pair(tmp_path, consistent: bool):
    """The same random frame twice: members on the PBARL sections that NASTRAN gives no
    shear factors here (ROD, TUBE, BAR and BOX have theirs: test_pbarl_shear_factors),
    and on PBAR cards holding the closed-form A, I1, I2, J of those sections."""
    frame = random_frame(np.random.default_rng(5 + consistent), consistent)
    used = [p for p in sorted(SECTIONS) if SECTIONS[p][0] not in ("ROD", "TUBE", "BAR", "BOX")]
    frame.bars = [(eid, a, b, v, used[eid % len(used)]) for eid, a, b, v, _ in frame.bars]
    frame.sections = {pid: closed_form(*SECTIONS[pid]) for pid in SECTIONS}
    pbar = frame.bdf()
    lines = pbar.splitlines()
    kept = [x for i, x in enumerate(lines) if not x.startswith("PBAR*")
            and not (i and lines[i - 1].startswith("PBAR*"))]
    pbarl = "\n".join(kept[:-1] + [_pbarl(p, *SECTIONS[p]) for p in SECTIONS] + ["ENDDATA\n"])
    assert pbarl.count("PBARL") == len(SECTIONS) and "PBAR*" not in pbarl
    a, b = tmp_path / "pbar.bdf", tmp_path / "pbarl.bdf"
    a.write_text(pbar)
    b.write_text(pbarl)
    return a, b


@pytest.mark.parametrize("consistent", [True, False], ids=["consistent", "lumped"])
def test_pbarl_frame_is_the_pbar_frame(tmp_path, consistent):
    """Source: the equivalent PBAR (closed-form section values), whose frames are checked
    against OpenSees in test_nastran.py: same K and M, frequencies to 1e-12.

    The section values agree to a few ulps, not bit for bit; the shift-invert (sparse)
    path resolves the low modes to that level. The dense path's round-off on the lowest
    mode (about eps lambda_max / lambda_1 relative) is 1e-10 on this frame, larger than
    the difference being tested, so it is not used here."""
    pbar, pbarl = (read_nastran(p).model for p in _frame_pair(tmp_path, consistent))
    for x, y in ((pbar.stiffness(), pbarl.stiffness()), (pbar.mass(), pbarl.mass())):
        assert abs(x - y).max() <= 1e-13 * abs(x).max()
    f = solve_elastic(pbar.stiffness(), pbar.mass(), 10, dense=False).frequencies_hz
    g = solve_elastic(pbarl.stiffness(), pbarl.mass(), 10, dense=False).frequencies_hz
    assert np.max(np.abs(g / f - 1)) < 1e-12


# BOX 0.6 x 0.2, walls 0.0025: its walls parallel to the shear over A = 0.003975
_BOX_K = (2 * 0.195 * 0.0025 / 0.003975, 2 * 0.595 * 0.0025 / 0.003975)


@pytest.mark.parametrize("shape,dims,factor", [
    ("ROD", "0.03", (0.9, 0.9)), ("BAR", "0.03,0.05", (5.0 / 6.0, 5.0 / 6.0)),
    ("TUBE", "0.06,0.05", (0.5, 0.5)), ("BOX", "0.6,0.2,0.0025,0.0025", _BOX_K)])
def test_pbarl_shear_factors(tmp_path, shape, dims, factor):
    """PBARL ROD, BAR, TUBE and BOX are shear-flexible as NASTRAN makes them: the PBAR
    with the section's A, I1, I2, J and K1 = K2 = 0.9 (circle; Simcenter's frequencies of
    the shared pyn_beam_modes deck confirm it, test_nastran_decks.py), 5/6 (rectangle),
    0.5 (tube) or, for a box, the walls parallel to the shear over the area (TUBE's and
    BOX's from the equivalent PBEAMs in MSC Nastran 2005's fmondsp.op2: K1, K2 = 0.5 and
    0.245283, 0.7484277 of this box; test_nastran_tapered.py meets its modes)."""
    d = [float(x) for x in dims.split(",")]
    a, i1, i2, j = closed_form(shape, d)
    paths = []
    for name, card in (("pbar", f"PBAR,1,1,{a!r},{i1!r},{i2!r},{j!r}\n,,,,,,,,\n"
                                f",{factor[0]!r},{factor[1]!r}"),
                       ("pbarl", f"PBARL,1,1,,{shape}\n,{dims}")):
        paths.append(tmp_path / f"{name}.bdf")
        paths[-1].write_text(_bulk(card))
    pbar, pbarl = (read_nastran(p).model for p in paths)
    x, y = pbar.stiffness(), pbarl.stiffness()
    assert abs(x - y).max() <= 1e-13 * abs(x).max()


def test_tube2_is_the_tube_of_its_annulus(tmp_path):
    """Source: MSC's TUBE2 is the annulus of outer radius DIM1 and wall DIM2, TUBE's with
    inner radius DIM1 - DIM2: the same section, so the same K (its shear factors too)
    and M, to round-off (1e-13)."""
    models = []
    for shape, dims in (("TUBE", "0.06,0.05"), ("TUBE2", "0.06,0.01")):
        path = tmp_path / f"{shape}.bdf"
        path.write_text(_bulk(f"PBARL,1,1,,{shape}\n,{dims}"))
        models.append(read_nastran(path).model)
    tube, tube2 = models
    for a, b in ((tube.stiffness(), tube2.stiffness()), (tube.mass(), tube2.mass())):
        assert abs(a - b).max() <= 1e-13 * abs(a).max()


def test_material_parameter_on_pbarl_members(tmp_path):
    """MAT1 E stays a parameter on PBARL members: the same K_j as with PBAR."""
    spec = [(Parameter("E", 0.0), CardField("MAT1", 1, "E"))]
    pbar, pbarl = (read_nastran(p, spec).model for p in _frame_pair(tmp_path, True))
    x, y = pbar.k_terms[0], pbarl.k_terms[0]
    assert abs(x - y).max() <= 1e-13 * abs(x).max()


@pytest.mark.parametrize("card,message", [
    ("PBARL,1,1,,HAT1\n,.1,.05,.04,.005,.01",
     "PBARL 1: section type HAT1 (a closed cell with open flanges: its J is not modelled) is "
     "not supported (supported: ROD, TUBE, BAR, BOX, I, T, CHAN, T1, T2, I1, CHAN1, CHAN2, "
     "H, Z, CROSS, TUBE2, BOX1, HEXA, HAT)"),
    ("PBARL,1,1,,L\n,.1,.15,.01,.012",
     "PBARL 1: section type L (its section axes, which give I12's sign, are not established)"),
    ("PBARL,1,1,MYLIB,ROD\n,.03", "PBARL 1: GROUP MYLIB (a user section library)"),
    ("PBARL,1,1,,BOX\n,.1,.2,.01,.06", "PBARL 1: section BOX needs DIM1 > 2 DIM4"),
    ("PBARL,1,1,,BOX1\n,.1,.2,.01,.012,.006,.008", "PBARL 1: section BOX1 needs DIM3 = DIM4 "
     "or DIM5 = DIM6 (with both pairs unequal its I12's sign depends on axes not established"),
], ids=["HAT1", "L", "group", "BOX-dims", "BOX1-I12"])
def test_refused_sections_one_line(tmp_path, run_cli, card, message):
    """Exit 2, one line naming the file, the card, its id and the section type."""
    (tmp_path / "bad.bdf").write_text(_bulk(card))
    study = tmp_path / "study.toml"
    study.write_text('[model]\ntype = "nastran"\nbdf = "bad.bdf"\n')
    code, out, err = run_cli("frequencies", study, "--modes", "1")
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err
    assert str(tmp_path / "bad.bdf") in err and message in err


def test_pbarl_nonstructural_mass(tmp_path):
    """NSM after the dimensions is the PBAR's NSM: the same mass matrix (and, with
    NASTRAN's shear factors K1 = K2 = 0.9 of a circle, the same stiffness)."""
    r = 0.03
    a, i = math.pi * r**2, math.pi * r**4 / 4
    paths = []
    for name, card in (("pbar", f"PBAR,1,1,{a!r},{i!r},{i!r},{2 * i!r},2.5\n,,,,,,,,\n,0.9,0.9"),
                       ("pbarl", f"PBARL,1,1,,ROD\n,{r!r},2.5")):
        paths.append(tmp_path / f"{name}.bdf")
        paths[-1].write_text(_bulk(card))
    pbar, pbarl = (read_nastran(p).model for p in paths)
    assert abs(pbar.mass() - pbarl.mass()).max() <= 1e-15 * abs(pbar.mass()).max()
    assert abs(pbar.stiffness() - pbarl.stiffness()).max() <= 1e-15 * abs(pbar.stiffness()).max()


def test_pbeaml_monosymmetric_shear_centre_is_named(tmp_path):
    """A PBEAML T (or CHAN, or I with unequal flanges) on a CBEAM: NASTRAN puts the shear
    centre on the element axis (QRG PBEAML figures), this element the centroid; the
    warning gives the distance (model/sections.py shear_centre_offset, checked by hand in
    tests/model/test_sections.py). A PBARL T (CBAR, no offset either way) and a PBEAML BAR
    say nothing of it."""
    def warned(card: str, element: str) -> list[str]:
        path = tmp_path / "beam.bdf"
        path.write_text(_bulk(card).replace("CBAR,1,1,1,2", f"{element},1,1,1,2"))
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            read_nastran(path)
        return [str(w.message) for w in caught if "shear centre" in str(w.message)]

    (msg,) = warned("PBEAML,1,1,,T\n,.15,.2,.012,.008", "CBEAM")
    assert msg.startswith("PBEAML 1: section T's shear centre is (0.0455") and "CBEAM" in msg
    assert not warned("PBARL,1,1,,T\n,.15,.2,.012,.008", "CBAR")
    assert not warned("PBEAML,1,1,,BAR\n,.15,.2", "CBEAM")


# the dimensions of pyNastran's unit decks models/unit/bars/pbarl_<shape>.bdf (which the
# reader refused before these shapes), and of the other new shapes
LIBRARY = {"T1": "20.,20.,2.,4.", "T2": "10.,24.,1.,1.", "I1": "10.,1.,20.,25.",
           "CHAN1": "8.,2.,30.,40.", "H": "5.,3.,20.,0.5", "Z": "10.,1.,22.,28.",
           "HEXA": "3.,15.,20.", "HAT": "20.,2.,15.,5.", "CHAN2": "1.,1.5,12.,20.",
           "CROSS": "8.,2.,12.,1.5", "TUBE2": "10.,1.5", "BOX1": "10.,20.,1.,1.5,.8,.8"}


@pytest.mark.parametrize("shape", sorted(LIBRARY))
def test_library_shapes_read_with_msc_areas(tmp_path, shape):
    """Every new shape of MSC's library reads; its area is MSC's area formula for the shape
    (as pyNastran 1.4's PBARL.Area() implements them, e.g. CHAN2 = 2 DIM1 DIM3 +
    (DIM4 - 2 DIM1) DIM2), which fixes which DIM is which; the moments are those of
    model/sections.py (Green's theorem in tests/model/test_sections_library.py)."""
    from eigenupdate.model.sections import section_values

    path = tmp_path / "one.bdf"
    path.write_text(_bulk(f"PBARL,1,1,,{shape}\n,{LIBRARY[shape]}"))
    prop = load_deck(path).bdf.properties[1]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EigenupdateWarning)
        A, i1, i2, j, *_, i12 = pbarl_section(prop)
        model = read_nastran(path).model
    assert A == pytest.approx(prop.Area(), rel=1e-14)
    dims = [float(x) for x in LIBRARY[shape].split(",")]
    assert (A, i1, i2, i12, j) == section_values(shape, dims)
    assert np.isfinite(model.stiffness().toarray()).all()


def test_z_section_is_the_pbar_with_its_i12(tmp_path):
    """A PBARL Z is the PBAR holding its A, I1, I2, J and I12 (I12 < 0 by the flanges'
    parallel-axis terms, test_sections_library.py): the same K and M on a bent frame,
    where I12 couples the planes (test_nastran_i12.py checks PBAR I12 against the
    principal axes)."""
    from eigenupdate.model.sections import section_values

    a, i1, i2, i12, j = section_values("Z", [0.05, 0.005, 0.11, 0.13])
    assert i12 < 0
    paths = []
    for name, card in (("pbar", f"PBAR,1,1,{a!r},{i1!r},{i2!r},{j!r}\n,,,,,,,,\n,,,{i12!r}"),
                       ("pbarl", "PBARL,1,1,,Z\n,0.05,0.005,0.11,0.13")):
        text = _bulk(card).replace("CBAR,1,1,1,2,0.,1.,0.",
                                   "GRID,3,,1.,0.7,0.4\nCBAR,1,1,1,2,0.,1.,0.\n"
                                   "CBAR,2,1,2,3,0.,0.,1.")
        paths.append(tmp_path / f"{name}.bdf")
        paths[-1].write_text(text)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EigenupdateWarning)
        pbar, pbarl = (read_nastran(p).model for p in paths)
    for x, y in ((pbar.stiffness(), pbarl.stiffness()), (pbar.mass(), pbarl.mass())):
        assert abs(x - y).max() <= 1e-13 * abs(x).max()


def test_library_caveats_are_named(tmp_path):
    """What is not established is said once per property: Z's I12 sign, CHAN2's
    orientation, HEXA's J; a PBEAML HAT's shear centre (not computed)."""
    def warned(card: str, element: str = "CBAR") -> list[str]:
        path = tmp_path / "one.bdf"
        path.write_text(_bulk(card).replace("CBAR,1,1,1,2", f"{element},1,1,1,2"))
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            read_nastran(path)
        return [str(w.message) for w in caught if "shear flexibility" not in str(w.message)]

    assert warned("PBARL,1,1,,Z\n,10.,1.,22.,28.") == [
        "PBARL 1: section Z: its I12 < 0 (top flange towards -z) follows MSC's figure as "
        "MYSTRAN and pyNastran read it, not checked against NASTRAN's output"]
    assert "torsion constant J" in warned("PBARL,1,1,,HEXA\n,3.,15.,20.")[0]
    assert "exchanging I1 and I2" in warned("PBARL,1,1,,CHAN2\n,1.,1.5,12.,20.")[0]
    (msg,) = warned("PBEAML,1,1,,HAT\n,20.,2.,15.,5.", "CBEAM")
    assert msg.startswith("PBEAML 1: section HAT's shear centre is not computed here")
    assert not warned("PBARL,1,1,,T2\n,10.,24.,1.,1.")


def test_tapered_z_is_refused(tmp_path):
    """A PBEAML Z whose dimensions change along the beam: its I12 would be lost by the
    taper's integration, which holds A, I1, I2, J only: refused, naming the card."""
    from eigenupdate.errors import InputError

    card = "PBEAML,1,1,,Z\n,10.,1.,22.,28.,,NO,1.\n,12.,1.,22.,28."
    path = tmp_path / "taper.bdf"
    path.write_text(_bulk(card).replace("CBAR,1,1,1,2", "CBEAM,1,1,1,2"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EigenupdateWarning)
        with pytest.raises(InputError, match="PBEAML 1: a tapered section with I12 != 0"):
            read_nastran(path)


def test_parameter_on_a_z_dimension_is_refused(tmp_path):
    """A Z's I12 would change with its DIMs, and the I12 term is linear in E only: a DIM
    parameter on it is refused, naming the element."""
    from eigenupdate.errors import InputError

    path = tmp_path / "z.bdf"
    path.write_text(_bulk("PBARL,1,1,,Z\n,.05,.005,.11,.13"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EigenupdateWarning)
        with pytest.raises(InputError, match=r"CBAR 1: I12 != 0 with parameters that enter "
                           r"the element nonlinearly \(a section dimension"):
            read_nastran(path, [(Parameter("d", 0.0), CardField("PBARL", 1, "DIM2"))])
