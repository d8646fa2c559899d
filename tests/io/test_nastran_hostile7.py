"""Round-7 hostile NASTRAN input (tools/hostile_round7.py) on issue 20's newest reading:
each test fails without its fix.

* GENEL: a value in field 3 or in the field after UD (the QRG leaves them blank) was
  skipped by pyNastran without a word; a value after a blank inside the UI or UD list was
  dropped (``UD,,1,0,,,3,0`` read as UD 1-0 alone: a wrong element, exit 0);
* GENEL: a Z too ill-conditioned to invert to six digits (cond 2e13: K 7e-4 off, a
  frequency 1.2e-4 off, exit 0) was read;
* INCLUDE: a nested INCLUDE naming a symlink loop, or a name with a NUL byte, ended in a
  traceback (RuntimeError, ValueError) from the lookup beside the main deck;
* corner thicknesses under TFLAG 1: Ti and the PSHELL's T each in range, their product
  (the thickness) was not: 1e60 x 1e60 overflowed into "matrix has NaN or infinite
  entries", naming no card;
* PBARL/PBEAML dimensions of 1e-300 (a part left out, where DIM = 0 is refused) were read;
* TUBE2 (outer radius, wall t) went through TUBE's r^2 - (r - t)^2, which cancels: a wall
  1e-12 of the radius lost 4 digits of A and I (frequencies 2.6e-5 off, exit 0).

Independent sources: the same element written without the odd field (a CELAS4 spring for
the GENEL); the closed form of the annulus in exact rational arithmetic; the one-line
refusal standard (exit 2 through the CLI). Runs in .venv-nastran.
"""

from __future__ import annotations

import math
import os
from fractions import Fraction

import numpy as np
import pytest
from nastran_frames import need, read_quiet
from refusals import one_line

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.errors import InputError  # noqa: E402
from eigenupdate.model import sections  # noqa: E402

# two scalar points: k1 = 3e4 from point 1 to ground, the GENEL (or CELAS4) k2 = 1e4
# between them, masses 2 and 5
CHAIN = "BEGIN BULK\nSPOINT,1,2,3\nCELAS4,1,3.e4,1\nCMASS4,3,2.,1\nCMASS4,4,5.,2\n{}\nENDDATA\n"


def _write(tmp_path, text: str, name: str = "deck.bdf"):
    path = tmp_path / name
    path.write_text(text)
    return path


@pytest.mark.parametrize("genel,words", [
    ("GENEL,2,9,1,0,2,0\n,K,1.e4,-1.e4,1.e4", "field 3 holds '9'"),
    ("GENEL,2,,2,0\n,UD,7,1,0\n,K,1.e4\n,S,1.", "the field after UD holds '7'"),
    ("GENEL,2,,1,0,,,2,0\n,K,1.e4", "the UI list has '2' after a blank field"),
    ("GENEL,2,,2,0\n,UD,,1,0,,,3,0\n,K,1.e4\n,S,1.", "the UD list has '3' after a blank field"),
], ids=["field 3", "UD field 3", "UI gap", "UD gap"])
def test_genel_fields_pyNastran_passes_over_are_refused(tmp_path, genel, words):
    """Each was read (the UD gap as UD 1-0 alone, a different element) before."""
    with pytest.raises(InputError, match="GENEL 2") as info:
        read_quiet(_write(tmp_path, CHAIN.format(genel)))
    assert words in str(info.value)


def test_genel_without_gaps_reads_as_the_spring(tmp_path):
    """Source: the CELAS4 the GENEL stands for (K = [k, -k; -k, k]): the check passes the
    QRG's layout (blanks that end a list before the next word) and the same K results."""
    gen = read_quiet(_write(tmp_path, CHAIN.format("GENEL,2,,1,0,2,0,,\n,K,1.e4,-1.e4,1.e4,,,,")))
    spring = read_quiet(_write(tmp_path, CHAIN.format("CELAS4,2,1.e4,1,2"), "s.bdf"))
    assert np.array_equal(gen.model.stiffness().toarray(), spring.model.stiffness().toarray())


def test_genel_gap_is_one_line_through_the_cli(tmp_path, run_cli):
    (tmp_path / "deck.bdf").write_text("SOL 103\nCEND\n" + CHAIN.format(
        "GENEL,2,,2,0\n,UD,,1,0,,,3,0\n,K,1.e4\n,S,1."))
    (tmp_path / "p.csv").write_text("configuration,mode,frequency_hz,std_hz\nbase,1,10.,1.\n")
    study = tmp_path / "study.toml"
    study.write_text('title = "t"\n[model]\ntype = "nastran"\nbdf = "deck.bdf"\n'
                     '[measurement]\nfrequencies = "p.csv"\nmodes = [1]\n')
    code, _, err = run_cli("frequencies", study)
    one_line(code, err, "deck.bdf", "GENEL 2", "after a blank field", warnings_allowed=True)
    assert sorted(x.name for x in tmp_path.iterdir()) == ["deck.bdf", "p.csv", "study.toml"]


def test_genel_z_too_ill_conditioned_to_invert_is_refused(tmp_path):
    """Z = [[1e-4, b], [b, 1e-4]] with 1e-4 - b = 1e-17 (cond 2e13): its computed inverse
    was 7e-4 off the exact one and the first frequency 1.2e-4 (12.0317 Hz against the
    closed form 12.0310), exit 0. Refused beyond m eps cond(Z) = 5e-7."""
    z = "GENEL,2,,1,0,2,0\n,Z,1.e-4,.9999999999999e-4,1.e-4"
    with pytest.raises(InputError, match="GENEL 2: Z's condition number 2e\\+13"):
        read_quiet(_write(tmp_path, CHAIN.format(z)))


def test_genel_z_of_moderate_condition_is_its_exact_inverse(tmp_path):
    """Source: the inverse of Z = [[1e-4, b], [b, 1e-4]], b = .99999e-4 (cond 2e5), in
    exact rationals. Bound: m eps cond(Z) = 9e-11 relative in norm."""
    b = 0.99999e-4
    nm = read_quiet(_write(tmp_path, CHAIN.format(f"GENEL,2,,1,0,2,0\n,Z,1.e-4,{b!r},1.e-4")))
    a, fb = Fraction(1e-4), Fraction(b)
    det = a * a - fb * fb
    want = np.array([[float(a / det) + 3e4, float(-fb / det)], [float(-fb / det), float(a / det)]])
    got = nm.model.stiffness().toarray()[:2, :2]
    assert np.linalg.norm(got - want) <= 9e-11 * np.linalg.norm(want)


PLATE = ("BEGIN BULK\nGRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nGRID,3,,1.,1.,0.\n"
         "GRID,4,,0.,1.,0.\n{quad}\nPSHELL,1,1,{t},1\nMAT1,1,7.e10,,.33,2700.\n"
         "SPC1,1,123456,1,4\nENDDATA\n")


@pytest.mark.parametrize("name,make", [
    ("loop.dat", lambda p: os.symlink("loop.dat", p)),
    ("b\x00.dat", None),
], ids=["symlink loop", "NUL byte"])
def test_nested_include_lookup_failures_are_refused(tmp_path, name, make):
    """Both raised from Path.resolve/exists in the lookup beside the main deck (a NUL
    byte now stops the file before its INCLUDE is read: io/nastran_include.py)."""
    (tmp_path / "sub").mkdir()
    if make:
        make(tmp_path / "sub" / name)
    (tmp_path / "sub" / "a.dat").write_text(f"INCLUDE '{name}'\n")
    deck = PLATE.format(quad="CQUAD4,1,1,1,2,3,4", t=".05").replace(
        "BEGIN BULK\n", "BEGIN BULK\nINCLUDE 'sub/a.dat'\n")
    with pytest.raises(InputError, match="a.dat:1: (INCLUDE .* cannot be opened|a NUL byte)"):
        read_quiet(_write(tmp_path, deck))


def test_corner_thickness_product_out_of_range_names_the_element(tmp_path):
    """TFLAG 1: T1 = 1e60 of T = 1e60, a thickness of 1e120 (t^3 overflows)."""
    quad = "CQUAD4,1,1,1,2,3,4,,\n,,1,1e60,1e60,1e60,1e60"
    with pytest.raises(InputError, match=r"CQUAD4 1: corner thicknesses .* T1 times T"):
        read_quiet(_write(tmp_path, PLATE.format(quad=quad, t="1e60")))


BAR = ("BEGIN BULK\nGRID,1,,0.,0.,0.\nGRID,2,,0.4,0.,0.\nCBAR,1,1,1,2,0.,1.,0.\n"
       "PBARL,1,1,,{shape}\n,{dims}\nMAT1,1,7.e10,,0.3,2700.\nSPC1,1,123456,1\nENDDATA\n")


@pytest.mark.parametrize("shape,dims", [("I1", "1e-300,.002,.04,.05"),
                                        ("HEXA", "1e-300,.05,.03"),
                                        ("CROSS", ".04,.005,.05,1e-101")])
def test_section_dimension_below_1e_100_is_refused(tmp_path, shape, dims):
    """A flange outstand, a hexagon's point, an arm 1e-300 deep: read as a section
    without that part before, where DIM = 0 is refused."""
    with pytest.raises(InputError, match=f"PBARL 1: section {shape} dimensions must be "
                                         f"1e-100 to 1e100"):
        read_quiet(_write(tmp_path, BAR.format(shape=shape, dims=dims)))


@pytest.mark.parametrize("ratio", [1e-12, 1e-6, 0.5, 1.0])
def test_tube2_area_and_inertia_from_the_wall(ratio):
    """Source: the annulus's A = pi (ro^2 - ri^2), I = pi (ro^4 - ri^4) / 4, J = 2 I with
    ri = ro - t, the brackets in exact rational arithmetic of the float dimensions. Bound:
    the few roundings of t (2 ro - t) (ro^2 + ri^2), 1e-15 relative; TUBE's form lost
    eps ro / t (2e-4 at 1e-12)."""
    ro = 0.03
    t = ro * ratio
    a, i1, i2, i12, j = sections.section_values("TUBE2", [ro, t])
    fro, ft = Fraction(ro), Fraction(t)
    fri = fro - ft
    want_a = math.pi * float(fro**2 - fri**2)
    want_i = math.pi / 4 * float(fro**4 - fri**4)
    assert abs(a / want_a - 1) < 1e-15 and abs(i1 / want_i - 1) < 1e-15
    assert i2 == i1 and i12 == 0.0 and abs(j / (2 * want_i) - 1) < 1e-15
