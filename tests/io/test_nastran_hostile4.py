"""Round-4 hostile NASTRAN input (tools/hostile_round4.py): PARAMs that are no number,
PARAM SNORM beyond any angle between normals, and a pyNastran range check that says
nothing. Runs in .venv-nastran."""

from __future__ import annotations

import shutil

import pytest
from conftest import ROOT
from nastran_frames import need
from refusals import one_line

pytestmark = pytest.mark.nastran
need("pyNastran")

PANEL = ROOT / "examples" / "stiffened_panel"


def _one_line(code, err, *fragments):
    one_line(code, err, *fragments, warnings_allowed=True)


def _panel(tmp_path, old, new, file="panel.bdf"):
    d = tmp_path / "p"
    shutil.copytree(PANEL, d)
    text = (d / file).read_text()
    assert old in text
    (d / file).write_text(text.replace(old, new, 1))
    return d


@pytest.mark.parametrize(("param", "value"), [("SNORM", "nan"), ("SNORM", "inf"),
                                              ("WTMASS", "nan"), ("K6ROT", "-inf")])
def test_a_param_that_is_no_finite_number_is_refused(tmp_path, run_cli, param, value):
    """pyNastran reads 'nan' as a number: PARAM SNORM nan gave plain facets without a
    word (NaN > 0 is false), WTMASS nan failed later with no line."""
    d = _panel(tmp_path, "PARAM,COUPMASS,1", f"PARAM,COUPMASS,1\nPARAM,{param},{value}")
    code, _, err = run_cli("frequencies", d / "study.toml")
    _one_line(code, err, f"panel.bdf: line 7: PARAM {param}: {float(value)} is not a finite "
                         f"number")


def test_snorm_beyond_180_degrees_is_refused(tmp_path, run_cli):
    """SNORM is the largest angle (degrees) between a facet's normal and its grid's; the
    test compared cosines, so 380 acted as 20 (cos 380 deg = cos 20 deg) and the panel's
    blade folds stayed folds, while 180 joins them (numbers checked against each other
    below: 380 must not be read as either silently)."""
    freqs = {}
    for v in ("20.", "180."):
        d = _panel(tmp_path / v, "PARAM,COUPMASS,1", f"PARAM,COUPMASS,1\nPARAM,SNORM,{v}")
        code, out, err = run_cli("frequencies", d / "study.toml", "--json")
        assert code == 0, err
        freqs[v] = out
    assert freqs["20."] != freqs["180."]  # the fold grids' normals: what SNORM decides
    d = _panel(tmp_path / "380", "PARAM,COUPMASS,1", "PARAM,COUPMASS,1\nPARAM,SNORM,380.")
    code, _, err = run_cli("frequencies", d / "study.toml")
    _one_line(code, err, "line 7: PARAM SNORM: 380 degrees is more than 180")


def test_pshear_zero_thickness_names_the_check(tmp_path, run_cli):
    """PSHEAR T = 0: pyNastran's `assert self.t > 0.0` has no message, so the line said
    "PSHEAR 9: AssertionError: " and nothing else; now the failed check is quoted."""
    d = _panel(tmp_path, "CQUAD4,1,1,1,2,1002,1001", "CSHEAR,1,9,1,2,1002,1001", "mesh.bdf")
    text = (d / "panel.bdf").read_text()
    (d / "panel.bdf").write_text(text.replace("MAT1,", "PSHEAR,9,1,0.\nMAT1,", 1))
    code, _, err = run_cli("frequencies", d / "study.toml")
    _one_line(code, err, "panel.bdf: line 9: PSHEAR 9: a field is out of range: pyNastran's "
                         "check 't > 0.0' fails")


def test_a_param_pynastran_cannot_read_is_named_by_its_line(tmp_path, run_cli):
    """PARAM SNORM YES: pyNastran's "value = 'YES' (field #2) on card must be a float"
    quoted a PARAM by its name, not a number, so no line was found for it."""
    d = _panel(tmp_path, "PARAM,COUPMASS,1", "PARAM,COUPMASS,1\nPARAM,SNORM,YES")
    code, _, err = run_cli("frequencies", d / "study.toml")
    _one_line(code, err, "panel.bdf: line 7: PARAM SNORM: value = 'YES' (field #2)")


def test_an_offset_of_more_than_1000_thicknesses_is_refused(tmp_path, run_cli):
    """ZOFFS = 1e10 m on a 2 mm skin quad made K indefinite (D + z^2 A: 12 (z/T)^2 = 3e26
    times D, beyond double precision) and was reported as a coordinate "with stiffness
    and no mass"; between, say 1e6 T, D kept 3 digits without a word. Now refused above
    1000 T (D then to 3e-9), naming the card; 500 T is still a model."""
    q1 = "CQUAD4,1,1,1,2,1002,1001"
    d = _panel(tmp_path / "a", q1, q1 + ",,1e10", "mesh.bdf")
    code, _, err = run_cli("frequencies", d / "study.toml")
    _one_line(code, err, "mesh.bdf:527: CQUAD4 1: ZOFFS = 1e+10 is more than 1000 times the "
                         "thickness 0.002")
    d = _panel(tmp_path / "b", q1, q1 + ",,1.0", "mesh.bdf")
    code, _, err = run_cli("frequencies", d / "study.toml")
    assert code == 0, err
