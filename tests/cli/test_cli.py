"""Command line: study formats, outputs, and bad input (one line, exit status 2)."""

import json

import numpy as np
import pytest
import scipy.io
import scipy.sparse as sp
from conftest import EXAMPLES

FIG2 = (EXAMPLES / "paper_fig2" / "study.toml").read_text()


def write(tmp_path, text, name="study.toml"):
    p = tmp_path / name
    p.write_text(text)
    return p


def assert_bad(run_cli, args, *fragments):
    code, out, err = run_cli(*args)
    assert code == 2, (out, err)
    assert "Traceback" not in err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    for f in fragments:
        assert f in lines[0], lines[0]
    return lines[0]


@pytest.fixture
def fig2_dir(tmp_path, run_cli):
    (tmp_path / "truth.toml").write_text((EXAMPLES / "paper_fig2" / "truth.toml").read_text())
    write(tmp_path, FIG2)
    assert run_cli("simulate", tmp_path / "truth.toml", "-o", tmp_path / "measured.csv")[0] == 0
    return tmp_path


def test_unknown_coordinate(tmp_path, run_cli):
    s = write(tmp_path, FIG2.replace("coordinate = 4\nmass = 0.35", "coordinate = 9\nmass = 0.35"))
    assert_bad(run_cli, ["check", s], "study.toml", "perturbation", "unknown coordinate 9")


def test_non_positive_mass(tmp_path, run_cli):
    s = write(tmp_path, FIG2.replace("value = 9.7", "value = -9.7", 1))
    assert_bad(run_cli, ["check", s], "study.toml", "model.mass[1].value", ">= 0")
    s = write(tmp_path, FIG2.replace("value = 9.7", "value = 0.0", 1))
    assert_bad(run_cli, ["check", s], "model.mass[1].value", "> 0")


def test_non_positive_stiffness(tmp_path, run_cli):
    s = write(tmp_path, FIG2.replace("value = 1.200e+06", "value = 0", 1))
    assert_bad(run_cli, ["check", s], "model.spring[1].value", "> 0")


def test_duplicate_parameter_name(tmp_path, run_cli):
    s = write(tmp_path, FIG2.replace('name = "m2"', 'name = "m1"'))
    assert_bad(run_cli, ["check", s], "study.toml", "duplicate parameter name 'm1'")


def test_missing_measurement(fig2_dir, run_cli):
    csv = fig2_dir / "measured.csv"
    csv.write_text("".join(ln for ln in csv.read_text().splitlines(True)
                           if not ln.startswith("0.35 kg at 2,3")))
    assert_bad(run_cli, ["update", fig2_dir / "study.toml"], "measured.csv",
               "no measurement for configuration '0.35 kg at 2' mode 3")


def test_mode_beyond_model(fig2_dir, run_cli):
    s = write(fig2_dir, FIG2.replace("modes = [1, 2, 3]", "modes = [1, 2, 5]"))
    # found deep in the eigen-solver, still named by the study file
    assert_bad(run_cli, ["check", s], "study.toml: ", "mode 5 requested", "only 4 elastic modes")
    assert_bad(run_cli, ["frequencies", s], "study.toml: ", "only 4 elastic modes")
    line = assert_bad(run_cli, ["frequencies", s, "--modes", "0"], "--modes")
    assert "study.toml" not in line


def test_unreadable_toml_names_line(tmp_path, run_cli):
    s = write(tmp_path, FIG2.replace('type = "spring-mass"', 'type = spring-mass'))
    msg = assert_bad(run_cli, ["check", s], "study.toml", "invalid TOML")
    assert "line 6" in msg


def test_study_with_byte_order_mark_and_crlf(fig2_dir, run_cli):
    s = fig2_dir / "study.toml"
    s.write_bytes(b"\xef\xbb\xbf" + FIG2.replace("\n", "\r\n").encode())
    code, out, err = run_cli("check", s, "--json")
    assert code == 0, err
    assert json.loads(out)["rank"] == 10
    s.write_bytes(b"\xff\xfe" + FIG2.encode("utf-16-le"))
    assert_bad(run_cli, ["check", s], "study.toml", "not UTF-8")


def test_missing_study_file(tmp_path, run_cli):
    assert_bad(run_cli, ["check", tmp_path / "nope.toml"], "nope.toml", "cannot read")


def test_unreadable_csv_names_line(fig2_dir, run_cli):
    csv = fig2_dir / "measured.csv"
    lines = csv.read_text().splitlines(True)
    lines[3] = "0.35 kg at 1,1,forty-two,\n"
    csv.write_text("".join(lines))
    assert_bad(run_cli, ["update", fig2_dir / "study.toml"], "measured.csv", "line 4",
               "frequency_hz 'forty-two' is not a number")
    csv.write_text("config,mode,f\nbase,1,3\n")
    assert_bad(run_cli, ["update", fig2_dir / "study.toml"], "measured.csv", "header")


def test_unknown_configuration_in_csv(fig2_dir, run_cli):
    csv = fig2_dir / "measured.csv"
    csv.write_text(csv.read_text() + "0.5 kg at 3,1,40.0,\n")
    assert_bad(run_cli, ["update", fig2_dir / "study.toml"], "configuration '0.5 kg at 3'")


def test_unknown_key_is_an_error(tmp_path, run_cli):
    s = write(tmp_path, FIG2.replace("max_iterations = 20", "max_iteration = 20"))
    assert_bad(run_cli, ["update", s], "updating", "unknown key(s) ['max_iteration']")


def matrices_study(tmp_path, asymmetric=False):
    """The Fig. 2 system assembled as Matrix Market files: K0 = M0 = 0, one file per
    parameter (unit spring or unit mass matrix)."""
    from models import fig2

    model = fig2()
    zero = sp.coo_matrix((4, 4))
    scipy.io.mmwrite(tmp_path / "K0.mtx", zero)
    scipy.io.mmwrite(tmp_path / "M0.mtx", zero)
    text = ['title = "Fig. 2 from matrices"\n[model]\ntype = "matrices"\nK0 = "K0.mtx"\n'
            'M0 = "M0.mtx"\n']
    for p, kt, mt in zip(model.parameters, model.k_terms, model.m_terms, strict=True):
        key, mat = ("K", kt) if kt is not None else ("M", mt)
        mat = sp.coo_matrix(mat)
        if asymmetric and p.name == "k2":
            mat = sp.coo_matrix(mat.toarray() + np.triu(np.ones((4, 4)), 1) * 0.5)
        scipy.io.mmwrite(tmp_path / f"{p.name}.mtx", mat)
        text.append(f'[[model.parameter]]\nname = "{p.name}"\nvalue = {p.value}\n'
                    f'{key} = "{p.name}.mtx"\n')
    perts = FIG2[FIG2.index("[[perturbation]]"):]
    return write(tmp_path, "".join(text) + perts)


def test_matrix_model_equals_spring_mass(fig2_dir, run_cli):
    s = matrices_study(fig2_dir)
    _, out_m, _ = run_cli("update", s, "--json")
    _, out_s, _ = run_cli("update", fig2_dir / "study.toml", "--json")
    a, b = json.loads(out_m), json.loads(out_s)
    assert a["success"]
    for ha, hb in zip(a["history"], b["history"], strict=True):
        assert ha["parameters"] == pytest.approx(hb["parameters"], rel=1e-9)


def test_non_symmetric_matrix_file(tmp_path, run_cli):
    s = matrices_study(tmp_path, asymmetric=True)
    assert_bad(run_cli, ["check", s], "k2.mtx", "not symmetric")


def test_several_masses_at_one_coordinate_and_grounded_springs(tmp_path, run_cli):
    # Paper Table 2 style: 0.35 and 0.7 kg at the same coordinate; plus a grounded spring
    # and a two-addition perturbation.
    head = FIG2[: FIG2.index("[[perturbation]]")]
    perts = (
        '[[perturbation]]\nname = "a"\ncoordinate = 1\nmass = 0.35\n\n'
        '[[perturbation]]\nname = "b"\ncoordinate = 1\nmass = 0.7\n\n'
        '[[perturbation]]\nname = "k"\ncoordinate = 3\nstiffness = 1e5\n\n'
        '[[perturbation]]\nname = "two"\nadd = [{coordinate = 2, mass = 0.2}, '
        '{coordinate = 4, mass = 0.1}]\n\n[measurement]\nmodes = [1, 2, 3, 4]\n'
    )
    s = write(tmp_path, head + perts)
    code, out, _ = run_cli("frequencies", s, "--json")
    assert code == 0
    f = {c["name"]: c["frequencies_hz"] for c in json.loads(out)["configurations"]}
    assert f["b"][0] < f["a"][0] < f["base"][0] < f["k"][0]
    code, out, _ = run_cli("check", s, "--json")
    assert code == 0 and json.loads(out)["equations"] == 20


def test_text_outputs(fig2_dir, run_cli):
    for cmd in ("frequencies", "check", "update"):
        code, out, err = run_cli(cmd, fig2_dir / "study.toml")
        assert code == 0, err
        assert "Paper Fig. 2" in out


def test_save_result_and_nonconvergence_exit_1(fig2_dir, run_cli):
    s = write(fig2_dir, FIG2.replace("max_iterations = 20", "max_iterations = 2"))
    code, out, err = run_cli("update", s, "--json", "--save", fig2_dir / "result.json")
    assert code == 1
    assert "not converged" in err
    doc = json.loads((fig2_dir / "result.json").read_text())
    assert doc["success"] is False and len(doc["history"]) == 3
    assert json.loads(out)["parameters"] == doc["parameters"]


def test_simulate_with_noise_is_reproducible(fig2_dir, run_cli):
    t = fig2_dir / "truth.toml"
    run_cli("simulate", t, "-o", fig2_dir / "a.csv", "--noise-hz", "0.001", "--seed", "4")
    run_cli("simulate", t, "-o", fig2_dir / "measured.csv", "--noise-hz", "0.001", "--seed", "4")
    a = (fig2_dir / "a.csv").read_text()
    assert a == (fig2_dir / "measured.csv").read_text()
    assert a.startswith("# eigenupdate simulate: frequencies of truth.toml\n")
    assert a.splitlines()[2].endswith(",0.001")
    code, _, err = run_cli("update", fig2_dir / "study.toml", "--method",
                           "weighted-least-squares")
    assert code == 0, err


def test_simulate_relative_noise(fig2_dir, run_cli):
    """--noise-relative 0.001: each std is 0.1 % of its true frequency, which the noisy
    one matches within 6 of those std (6e-3 relative)."""
    code, _, err = run_cli("simulate", fig2_dir / "truth.toml", "-o", fig2_dir / "r.csv",
                           "--noise-relative", "0.001", "--seed", "3")
    assert code == 0, err
    rows = [line.split(",") for line in (fig2_dir / "r.csv").read_text().splitlines()[2:]]
    ratio = np.array([float(r[-1]) / float(r[-2]) for r in rows])
    assert np.all(np.abs(ratio / 1e-3 - 1) <= 6e-3)


def test_beam_study_errors(tmp_path, run_cli):
    beam = (EXAMPLES / "paper_beam" / "study.toml").read_text()
    s = write(tmp_path, beam.replace("0.39, 0.49", "0.49, 0.39"))
    assert_bad(run_cli, ["check", s], "model.nodes", "strictly increasing")
    s = write(tmp_path, beam.replace("coordinate = 11\nvalue", "coordinate = 19\nvalue"))
    assert_bad(run_cli, ["check", s], "point_mass m_L", "unknown coordinate 19")
    clamped = beam.replace("[model]\n", "[model]\nrestrained = [1, 2]\n", 1)
    s = write(tmp_path, clamped)
    assert_bad(run_cli, ["check", s], "perturbation '0.2 kg at 1'", "coordinate 1 is restrained",
               "3-18")
    s = write(tmp_path, clamped.replace("restrained = [1, 2]", "restrained = [1, 1]"))
    assert_bad(run_cli, ["check", s], "model.restrained", "repeated")


def test_spring_to_a_coordinate_without_mass(tmp_path, run_cli):
    s = write(tmp_path, FIG2.replace("coordinates = [2, 4]", "coordinates = [2, 5]"))
    assert_bad(run_cli, ["check", s], "model.spring[5].coordinates", "[5] have no mass")


# --- outputs that cannot be written, and option values (review of the CLI) -------------


def test_simulate_frf_repeated_outputs(fig2_dir, run_cli):
    assert_bad(run_cli, ["simulate-frf", fig2_dir / "study.toml", "-o", fig2_dir / "frf",
                         "--input", 1, "--outputs", 2, 2, "--fmax", 200], "--outputs", "repeated")
    assert not (fig2_dir / "frf").exists()


def test_unwritable_outputs_fail_before_any_work(fig2_dir, run_cli):
    s, d = fig2_dir / "study.toml", fig2_dir
    assert_bad(run_cli, ["simulate", s, "-o", d / "nodir" / "x.csv"], "-o", "does not exist")
    assert_bad(run_cli, ["simulate", s, "-o", d], "-o", "is a directory")
    assert_bad(run_cli, ["update", s, "--save", d / "nodir" / "r.json"], "--save")
    assert_bad(run_cli, ["sweep", s, "--coordinate", 1, "--max-mass", 1, "-o", d], "-o")
    (d / "file").write_text("")
    assert_bad(run_cli, ["simulate-frf", s, "-o", d / "file", "--input", 1, "--outputs", 2,
                         "--fmax", 200], "exists and is not a directory")
    # extract: a bad --uff55 must not leave the CSV written
    frf = write(d, FIG2 + '\n[measurement.frf]\n"base" = "none.uff"\n', "frf.toml")
    assert_bad(run_cli, ["extract", frf, "-o", d / "x.csv", "--uff55", d / "no" / "m.uff"],
               "--uff55")
    assert not (d / "x.csv").exists()


def test_simulate_frf_bad_values_leave_no_directory(fig2_dir, run_cli):
    s, out = fig2_dir / "study.toml", fig2_dir / "frf_out"
    for extra in (["--fmax", "inf"], ["--fmax", "-5"], ["--fmax", 200, "--df", 0],
                  ["--fmax", 200, "--input", 99]):
        args = ["simulate-frf", s, "-o", out, "--input", 1, "--outputs", 2, "--fmax", 200]
        code, _, err = run_cli(*args[:-2], *extra)
        assert code == 2 and "Traceback" not in err and len(err.strip().splitlines()) == 1, err
        assert not out.exists()


def test_negative_seed_is_a_usage_error(fig2_dir, run_cli):
    code, _, err = run_cli("simulate", fig2_dir / "study.toml", "-o", fig2_dir / "x.csv",
                           "--seed", "-1")
    assert code == 2 and "--seed" in err and "Traceback" not in err


@pytest.mark.parametrize("flags, fragment", [
    (["--noise-hz", "nan"], "--noise-hz"),
    (["--noise-hz", "inf"], "--noise-hz"),
    (["--std-hz", "0"], "--std-hz"),
    (["--std-hz", "-1"], "--std-hz"),
    (["--noise-hz", "100", "--seed", "3"], "negative"),
])
def test_simulate_refuses_what_its_reader_would(fig2_dir, run_cli, flags, fragment):
    out = fig2_dir / "sim.csv"
    assert_bad(run_cli, ["simulate", fig2_dir / "truth.toml", "-o", out, *flags], fragment)
    assert not out.exists()


@pytest.mark.parametrize("fmax", ["-5", "nan", "inf", "0"])
def test_frf_bad_fmax(fig2_dir, run_cli, fmax):
    assert_bad(run_cli, ["frf", fig2_dir / "study.toml", "--input", 1, "--output", 2,
                         "--fmax", fmax, "-o", fig2_dir / "f.png"], "--fmax")


def test_frf_updated_result_is_validated(fig2_dir, run_cli):
    s = fig2_dir / "study.toml"
    assert run_cli("update", s, "--save", fig2_dir / "r.json")[0] == 0
    doc = json.loads((fig2_dir / "r.json").read_text())
    args = ["frf", s, "--input", 1, "--output", 2, "--updated", fig2_dir / "bad.json",
            "-o", fig2_dir / "f.png"]
    for change, fragment in (({"k1": "abc"}, "parameters.k1"), ({"m1": 0.0}, "parameters.m1"),
                             ({"k2": None}, "no value for ['k2']")):
        bad = json.loads(json.dumps(doc))
        for k, v in change.items():
            if v is None:
                del bad["parameters"][k]
            else:
                bad["parameters"][k] = v
        (fig2_dir / "bad.json").write_text(json.dumps(bad))
        assert_bad(run_cli, args, "bad.json", fragment)


def test_rank_deficient_plan_is_not_reported_converged(fig2_dir, run_cli):
    # Fig. 2 with one mode: 4 equations for 10 parameters (plain least squares)
    s = write(fig2_dir, FIG2.replace("modes = [1, 2, 3]", "modes = [1]"), "one_mode.toml")
    assert_bad(run_cli, ["update", s], "rank 4 of J for 10 updated parameters")


@pytest.mark.parametrize("csv_text, fragment", [
    ("configuration,mode,frequency_hz,std_hz\nbase,1,1e200,0.1\n", "< 1e12"),
    ("configuration,mode,frequency_hz,std_hz\nbase,1,42.0,0.1,7\n", "5 fields, expected 4"),
    ("configuration,mode,frequency_hz,frequency_hz\nbase,1,42.0,43\n", "appear twice"),
])
def test_measurement_csv_more_cases(fig2_dir, run_cli, csv_text, fragment):
    (fig2_dir / "measured.csv").write_text(csv_text)
    assert_bad(run_cli, ["update", fig2_dir / "study.toml"], "measured.csv", fragment)


def test_study_value_cases(tmp_path, run_cli):
    s = write(tmp_path, FIG2.replace("max_iterations", "tolerance = 1\nmax_iterations"))
    assert_bad(run_cli, ["check", s], "updating.tolerance", "<= 0.01")
    s = write(tmp_path, FIG2.replace("coordinate = 1\nmass = 0.35",
                                     "coordinate = 1\nmass = 0.35\nadd = [{coordinate = 2, "
                                     "mass = 0.1}]"))
    assert_bad(run_cli, ["check", s], "add", "not both")


def test_matrix_files_with_nan_or_pattern(tmp_path, run_cli):
    K = sp.csr_array(np.array([[2.0, -1.0], [-1.0, 2.0]]))
    scipy.io.mmwrite(tmp_path / "K0.mtx", K)
    scipy.io.mmwrite(tmp_path / "M0.mtx", sp.eye_array(2) * np.nan)
    (tmp_path / "P.mtx").write_text("%%MatrixMarket matrix coordinate pattern symmetric\n"
                                    "2 2 2\n1 1\n2 2\n")
    study = ('[model]\ntype = "matrices"\nK0 = "K0.mtx"\nM0 = "M0.mtx"\n'
             '[[model.parameter]]\nname = "a"\nvalue = 1.0\nK = "K0.mtx"\n')
    assert_bad(run_cli, ["frequencies", write(tmp_path, study), "--modes", 1], "M0.mtx",
               "NaN or infinite")
    assert_bad(run_cli, ["frequencies", write(tmp_path, study.replace('M0 = "M0.mtx"',
                                                                      'M0 = "P.mtx"')),
                         "--modes", 1], "P.mtx", "pattern")


def test_beam_nodes_too_close_or_too_far(tmp_path, run_cli):
    beam = (EXAMPLES / "paper_beam" / "study.toml").read_text()
    for nodes, why in (("0.69, 0.69000000000001", "element lengths"),
                       ("0.69, 1e300", "magnitude 1e-100 to 1e+100")):
        s = write(tmp_path, beam.replace("0.69, 0.80", nodes).replace(
            'frequencies = "measured.csv"', 'frequencies = "none.csv"'))
        assert_bad(run_cli, ["check", s], "model.nodes", why)


@pytest.mark.parametrize("args, fragment", [
    (["update"], "required: study"),
    (["update", "s.toml", "--method", "newton"], "invalid choice: 'newton'"),
    (["simulate", "s.toml", "-o", "m.csv", "--seed", "-1"], "--seed: -1 must be >= 0"),
])
def test_usage_errors_one_line(run_cli, args, fragment):
    assert_bad(run_cli, args, fragment, "--help")
