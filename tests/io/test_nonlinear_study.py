"""[[model.term]] in a Matrix Market study: the strip of tests/models.py
(``thickness_strip``: E b t^3 / 12 bending, rho b t mass) written as one bending and one
mass matrix per thickness region, updated from its own error-free frequencies.

Reference: the Python model built term by term (a second construction) and the truth the
data were made from."""

import json

import numpy as np
import pytest
import scipy.io
import scipy.sparse as sp
from models import thickness_strip
from test_cli import assert_bad, write

from eigenupdate.io.study import load_study
from eigenupdate.model.configurations import Configuration, mass_at
from eigenupdate.solve.jacobian import solve_configurations

TRUTH = {"E": 73e9, "t1": 0.0043, "t2": 0.0047}
B, RHO = 0.05, 2700.0
PERTS = [(1, 0.05), (9, 0.05), (17, 0.08)]


def _files(tmp_path):
    _, unit = thickness_strip()
    zero = sp.coo_matrix(unit.k0.shape)
    scipy.io.mmwrite(tmp_path / "K0.mtx", zero)
    scipy.io.mmwrite(tmp_path / "M0.mtx", zero)
    for r, els in (("1", range(4)), ("2", range(4, 8))):
        scipy.io.mmwrite(tmp_path / f"Kb{r}.mtx", sp.coo_matrix(sum(unit.k_terms[e] for e in els)))
        scipy.io.mmwrite(tmp_path / f"M{r}.mtx",
                         sp.coo_matrix(sum(unit.m_terms[8 + e] for e in els)))


STUDY = f'''title = "strip, thickness and E"
[model]
type = "matrices"
K0 = "K0.mtx"
M0 = "M0.mtx"

[[model.parameter]]
name = "E"
value = 70e9

[[model.parameter]]
name = "t1"
value = 0.004

[[model.parameter]]
name = "t2"
value = 0.005

[[model.term]]                 # bending: E t1^3 b / 12
K = "Kb1.mtx"
powers = {{ E = 1, t1 = 3 }}
coefficient = {B / 12!r}

[[model.term]]
K = "Kb2.mtx"
powers = {{ E = 1, t2 = 3 }}
coefficient = {B / 12!r}

[[model.term]]                 # mass: rho b t1
M = "M1.mtx"
powers = {{ t1 = 1 }}
coefficient = {RHO * B!r}

[[model.term]]
M = "M2.mtx"
powers = {{ t2 = 1 }}
coefficient = {RHO * B!r}
''' + "".join(f'''
[[perturbation]]
name = "p{c}"
coordinate = {c}
mass = {m}
''' for c, m in PERTS) + '''
[measurement]
modes = [1, 2, 3]
frequencies = "measured.csv"

[updating]
method = "least-squares"
tolerance = 1e-10
'''


@pytest.fixture
def study(tmp_path):
    _files(tmp_path)
    model, _ = thickness_strip()
    configs = [Configuration("base")] + [mass_at(c, m, f"p{c}") for c, m in PERTS]
    sols = solve_configurations(model, configs, 3, list(TRUTH.values()))
    rows = ["configuration,mode,frequency_hz,std_hz"]
    rows += [f"{c.name},{k},{float(s.frequencies_hz[k - 1])!r}," for c, s in zip(configs, sols,
                                                                        strict=True)
             for k in (1, 2, 3)]
    (tmp_path / "measured.csv").write_text("\n".join(rows) + "\n")
    return write(tmp_path, STUDY)


def test_study_terms_build_the_strip(study):
    model, _ = thickness_strip()
    got = load_study(study).model
    assert got.nonlinear and got.names == model.names
    s = np.array(list(TRUTH.values()))
    for a, b in ((got.stiffness(s), model.stiffness(s)), (got.mass(s), model.mass(s))):
        # the same products summed in another order: a few ulps of the largest entry
        assert abs(a - b).max() <= 1e-13 * abs(b).max()
    at, ref = got.at(s), model.at(s)
    for j in range(3):
        for a, b in ((at.k_terms[j], ref.k_terms[j]), (at.m_terms[j], ref.m_terms[j])):
            assert (a is None) == (b is None)
            if a is not None:
                assert abs(a - b).max() <= 1e-13 * abs(b).max()


def test_update_from_the_study_recovers_the_truth(study, run_cli):
    code, out, err = run_cli("update", study, "--json")
    assert code == 0, err
    doc = json.loads(out)
    for name, v in TRUTH.items():  # error-free data: limited by round-off / cond(J)
        assert doc["parameters"][name] == pytest.approx(v, rel=1e-6)
    code, out, err = run_cli("check", study, "--json")
    assert code == 0 and json.loads(out)["rank"] == 3


def test_bad_terms(study, run_cli):
    text = study.read_text()
    for old, new, frag in (
            ("powers = { E = 1, t1 = 3 }", "powers = { E = 1, t9 = 3 }", "unknown parameter 't9'"),
            ("powers = { E = 1, t1 = 3 }", "powers = { E = 1, t1 = 0 }", "powers.t1"),
            ("powers = { E = 1, t1 = 3 }", "powers = { E = 1, t1 = \"3\" }", "powers.t1"),
            ("powers = { E = 1, t1 = 3 }", "powers = {}", "must name at least one"),
            ('K = "Kb1.mtx"\n', "", "a term needs a K and/or an M file"),
            ('K = "Kb1.mtx"', 'K = "nope.mtx"', "nope.mtx")):
        write(study.parent, text.replace(old, new, 1))
        line = assert_bad(run_cli, ["check", study], frag)
        assert "study.toml" in line or "nope.mtx" in line
    # a parameter no term and no file names
    write(study.parent, text.replace('name = "t2"\nvalue = 0.005\n',
                                     'name = "t2"\nvalue = 0.005\n\n[[model.parameter]]\n'
                                     'name = "t3"\nvalue = 1.0\n'))
    assert_bad(run_cli, ["check", study], "model.parameter[4]", "needs a K and/or an M file")
