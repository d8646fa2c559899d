"""`eigenupdate report`: the HTML page's numbers against the library's, its inputs, and the
page in a real browser (headless Chromium)."""

import base64
import hashlib
import json
import os
import re
import shutil
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest
from conftest import EXAMPLES

from eigenupdate.identify.updating import update
from eigenupdate.io.study import load_study
from eigenupdate.report.html import GENERATOR
from eigenupdate.workflow import report as workflow_report

FIG2 = EXAMPLES / "paper_fig2" / "study.toml"
BEAM = EXAMPLES / "paper_beam" / "study.toml"
FRF = EXAMPLES / "paper_beam_frf" / "study.toml"


class _Tables(HTMLParser):
    """Every <table>: data-name, caption and body rows as lists of cell texts."""

    def __init__(self):
        super().__init__()
        self.tables, self.images, self.tags = [], [], set()
        self._cell = None
        self._where = None

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        self.tags.add(tag)
        if tag == "table":
            self.tables.append({"name": a.get("data-name", ""), "caption": "", "rows": []})
        elif tag == "caption":
            self._where = "caption"
        elif tag == "tbody":
            self._where = "body"
        elif tag == "tr" and self._where == "body":
            self.tables[-1]["rows"].append([])
        elif tag in ("td", "th") and self._where == "body":
            self._cell = ""
        elif tag == "img":
            self.images.append(a)

    def handle_endtag(self, tag):
        if tag in ("td", "th") and self._cell is not None:
            self.tables[-1]["rows"][-1].append(self._cell.strip())
            self._cell = None
        elif tag in ("caption", "tbody"):
            self._where = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell += data
        elif self._where == "caption":
            self.tables[-1]["caption"] += data


def render_report(study_path, **kwargs) -> str:
    return workflow_report(load_study(study_path), **kwargs)


def write_report(study_path, *, output, **kwargs) -> Path:
    Path(output).write_text(render_report(study_path, **kwargs), encoding="utf-8")
    return Path(output)


def parse(page: str) -> _Tables:
    p = _Tables()
    p.feed(page)
    return p


def named(doc: _Tables, name: str) -> list[dict]:
    return [t for t in doc.tables if t["name"] == name]


def column(table: dict, j: int) -> dict[str, float]:
    return {r[0]: float(r[j]) for r in table["rows"]}


@pytest.fixture(scope="module")
def fig2_report(tmp_path_factory):
    return write_report(FIG2, output=tmp_path_factory.mktemp("fig2") / "fig2.html",
                        command="test")


@pytest.fixture(scope="module")
def fig2_page(fig2_report):
    return fig2_report.read_text()


def test_self_contained(fig2_page):
    doc = parse(fig2_page)
    assert not {"script", "link", "iframe", "object"} & doc.tags
    assert not re.search(r"""(src|href)\s*=\s*["']?(https?:|//)""", fig2_page)
    assert "@import" not in fig2_page and "url(" not in fig2_page
    assert doc.images
    for img in doc.images:
        head, data = img["src"].split(",", 1)
        assert head == "data:image/svg+xml;base64"
        svg = base64.b64decode(data)
        assert b"<svg" in svg[:2000] and b"xlink:href=\"http" not in svg


def test_update_table_is_the_update(fig2_page):
    """The report's update (run by the report, no saved result) is update()'s, to the 6
    digits printed."""
    study = load_study(FIG2)
    res = update(study.model, study.configurations, study.modes, study.measurements(),
                 method=study.method, max_iterations=study.max_iterations,
                 xtol=study.tolerance)
    doc = parse(fig2_page)
    (params,) = named(doc, "parameters-updated")
    updated = column(params, 3)
    assert set(updated) == set(res.parameters)
    for n, v in res.parameters.items():
        assert updated[n] == pytest.approx(v, rel=1e-5)
    (freqs,) = named(doc, "frequencies")
    assert len(freqs["rows"]) == len(study.configurations) * len(study.modes)
    got = np.array([float(r[4]) for r in freqs["rows"]])
    np.testing.assert_allclose(got, res.updated_hz, rtol=1e-5)
    (history,) = named(doc, "history")
    assert len(history["rows"][0]) == 1 + len(res.history)
    assert "computed by this report" in fig2_page


def test_identifiability_of_the_paper_beam():
    """Paper Section 7: cond(J^T J) = 3.82e9 in the paper, 3.78e9 here (README), rank 17."""
    doc = parse(render_report(BEAM, command="test"))
    facts = {r[0]: r[1] for t in doc.tables if t["name"] == "facts" for r in t["rows"]}
    assert facts["rank of J"] == "17"
    assert float(facts["condition of J^T J"]) == pytest.approx(3.78e9, rel=0.005)
    (weakest,) = named(doc, "weakest")
    w = np.array([float(r[1]) for r in weakest["rows"]])
    assert len(w) == 17 and np.linalg.norm(w) == pytest.approx(1.0, rel=1e-5)


def test_saved_result_gives_the_same_tables(tmp_path, run_cli, fig2_page):
    saved = tmp_path / "result.json"
    assert run_cli("update", FIG2, "--save", saved)[0] == 0
    code, out, err = run_cli("report", FIG2, "--result", saved, "-o", tmp_path / "r.html")
    assert code == 0 and "wrote" in err and "kB" in err, err
    page = (tmp_path / "r.html").read_text()
    a, b = parse(page), parse(fig2_page)
    for name in ("parameters-updated", "frequencies", "history", "steps"):
        assert named(a, name) == named(b, name)
    assert "read from the saved result" in page
    assert "eigenupdate report" in page and "--result" in page  # the command, in provenance


def test_design_and_montecarlo_rendered_generically(tmp_path):
    plan = tmp_path / "plan.json"
    plan.write_text(json.dumps({
        "objective": "D-optimal", "modes": [1, 2, 3],
        "perturbations": [{"coordinate": 1, "mass": 0.2}, {"coordinate": 9, "mass": 0.3,
                                                           "note": "tip"}],
        "condition": {"J": 12.5, "JTJ": 156.25}}))
    mc = tmp_path / "mc.json"
    mc.write_text(json.dumps({"samples": 200, "parameters": [
        {"name": "k1", "mean": 1.2e6, "std": 3e3}, {"name": "m1", "mean": 10.0, "std": 0.1}],
        "by_parameter": {"k1": {"bias": 1.5, "coverage": 0.95}, "m1": {"bias": -0.01}}}))
    page = render_report(FIG2, design=plan, montecarlo=mc, command="test")
    doc = parse(page)
    tables = {t["caption"]: t["rows"] for t in named(doc, "summary")}
    assert tables["Test design"] == [["objective", "D-optimal"], ["modes", "[1, 2, 3]"]]
    assert tables["perturbations"] == [["1", "0.2", "-"], ["9", "0.3", "tip"]]
    assert tables["condition"] == [["J", "12.5"], ["JTJ", "156.25"]]
    assert tables["Monte Carlo summary"] == [["samples", "200"]]
    assert [r[0] for r in tables["parameters"]] == ["k1", "m1"]
    assert tables["by_parameter"] == [["k1", "1.5", "0.95"], ["m1", "-0.01", "-"]]
    assert "plan.json" in page and "mc.json" in page


def eigenvalues_of_fig2():
    from eigenupdate.workflow import study_frequencies

    return study_frequencies(load_study(FIG2))


def _no_eigen_solver(monkeypatch):
    """Every eigen-solver the package reaches (dense, sparse, Ritz) raises."""
    import numpy.linalg
    import scipy.linalg
    import scipy.sparse.linalg

    def refuse(*args, **kwargs):
        raise AssertionError("an eigen-solve in a report of saved results")

    import eigenupdate.solve.eigen

    for module, name in ((scipy.linalg, "eigh"), (scipy.linalg, "eig"),
                         (scipy.sparse.linalg, "eigsh"), (scipy.sparse.linalg, "lobpcg"),
                         (numpy.linalg, "eigh"), (numpy.linalg, "eig"),
                         # the dense path calls LAPACK's dsygvd itself
                         (eigenupdate.solve.eigen, "_sygvd")):
        monkeypatch.setattr(module, name, refuse)


def test_report_of_saved_results_solves_nothing(tmp_path, run_cli, monkeypatch):
    # every section from the files of update --save, design --json, montecarlo -o and
    # extract --save: rendered through their classes, with no eigen-solve
    truth = EXAMPLES / "paper_fig2" / "truth.toml"
    assert run_cli("update", FIG2, "--save", tmp_path / "r.json")[0] == 0
    code, out, err = run_cli("design", FIG2, "-o", tmp_path / "plan.toml", "--json")
    assert code == 0, err
    (tmp_path / "d.json").write_text(out)
    code, out, err = run_cli("montecarlo", FIG2, "--trials", "4", "--truth", truth, "--seed",
                             "1", "--in-process", "-o", tmp_path / "mc")
    assert code == 0, err
    csv = tmp_path / "x.csv"
    assert run_cli("extract", FRF, "-o", csv, "--save", tmp_path / "x.json")[0] == 0
    _no_eigen_solver(monkeypatch)
    with pytest.raises(AssertionError, match="an eigen-solve"):  # the guard works
        eigenvalues_of_fig2()
    code, out, err = run_cli("report", FIG2, "--result", tmp_path / "r.json", "--design",
                             tmp_path / "d.json", "--montecarlo", tmp_path / "mc" /
                             "summary.json", "--saved-only", "-o", tmp_path / "a.html")
    assert code == 0, err
    page = (tmp_path / "a.html").read_text()
    doc = parse(page)
    for name in ("parameters-updated", "frequencies", "history", "steps", "weakest",
                 "design-plan", "design-accuracy", "montecarlo"):
        assert named(doc, name), name
    assert "read from the saved result" in page and "at the saved update" in page
    assert not [i for i in doc.images if i["alt"].startswith(("FRF comparison", "mass sweep"))]
    # the saved numbers are the page's: the Monte Carlo table against its summary.json
    mc = json.loads((tmp_path / "mc" / "summary.json").read_text())
    (table,) = named(doc, "montecarlo")
    for row in table["rows"]:
        assert float(row[2]) == pytest.approx(mc["parameters"][row[0]]["empirical_std"],
                                              rel=5e-6)  # 6 digits printed
    code, out, err = run_cli("report", FRF, "--extraction", tmp_path / "x.json",
                             "--saved-only", "-o", tmp_path / "b.html")
    assert code == 0, err
    b = parse((tmp_path / "b.html").read_text())
    assert len(named(b, "extraction")) == len(load_study(FRF).configurations)
    assert sum(i["alt"].startswith("extraction fit") for i in b.images) > 0
    # provenance: the SHA-256 of every input, each FRF file included (hashlib, here)
    (prov,) = named(b, "provenance")
    hashes = {r[1] for r in prov["rows"]}
    study = load_study(FRF)
    for path in [*study.inputs(measurements=True, frf=True), tmp_path / "x.json"]:
        assert f"{path.name}  SHA-256 {hashlib.sha256(path.read_bytes()).hexdigest()}" in {
            h.replace("\u00a0", " ") for h in hashes}, path


def _one_line_error(run_cli, *args, fragments=()):
    code, out, err = run_cli(*args)
    assert code == 2, (out, err)
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1, err
    for f in fragments:
        assert f in err, err
    return err


def test_bad_inputs_write_nothing(tmp_path, run_cli):
    out = tmp_path / "report.html"
    other = tmp_path / "other.json"
    assert run_cli("update", BEAM, "--save", other)[0] == 0
    _one_line_error(run_cli, "report", FIG2, "--result", other, "-o", out,
                    fragments=("other.json", "parameters", "not in the study's model"))
    assert not out.exists()
    previous = f"<!DOCTYPE html>\n{GENERATOR}\nprevious report"  # an earlier report
    out.write_text(previous)
    bad = tmp_path / "plan.json"
    bad.write_text("[1, 2]")
    _one_line_error(run_cli, "report", FIG2, "--design", bad, "-o", out,
                    fragments=("plan.json", "JSON object"))
    csv = tmp_path / "extracted.csv"
    csv.write_text("configuration,mode,frequency_hz,std_hz,loss_factor\nbase,1,10.0,0.1,x\n")
    _one_line_error(run_cli, "report", FIG2, "--extracted", csv, "-o", out,
                    fragments=("extracted.csv", "loss_factor", "not a number"))
    _one_line_error(run_cli, "report", FIG2, "--result", tmp_path / "missing.json", "-o", out,
                    fragments=("missing.json", "cannot read"))
    _one_line_error(run_cli, "report", FIG2, "-o", tmp_path / "no" / "r.html",
                    fragments=("does not exist",))
    assert out.read_text() == previous


# ------------------------------------------------------- the shipped FRF example


@pytest.fixture(scope="module")
def frf_report(tmp_path_factory):
    """The README's report of the shipped FRF example, from a saved update result."""
    from eigenupdate.cli import main

    tmp = tmp_path_factory.mktemp("report")
    assert main(["update", str(FRF), "--save", str(tmp / "result.json")]) == 0
    out = write_report(FRF, output=tmp / "report.html", result=tmp / "result.json",
                       extracted=FRF.parent / "extracted.csv", command="test")
    return out


def expected_rows(study) -> dict[str, list[int]]:
    """Body rows of every named table of the FRF example's report, from the study."""
    n_cfg, n_modes = len(study.configurations), len(study.modes)
    upd = len(study.model.updated)
    return {
        "parameters": [len(study.model.parameters)],
        "configurations": [sum(max(1, len(c.additions)) for c in study.configurations)],
        "weakest": [upd],
        "extraction": [3] * n_cfg,  # three resonances found below 1600 Hz, modes 1-2 used
        "parameters-updated": [upd],
        "history": [upd],
        "frequencies": [n_cfg * n_modes],
        # version, date, command; every input: study, model, measurement and FRF files,
        # the saved result and the extraction CSV
        "provenance": [3 + len(study.inputs(measurements=True, frf=True)) + 2],
    }


@pytest.mark.slow
def test_frf_example_report(frf_report):
    study = load_study(FRF)
    page = frf_report.read_text()
    doc = parse(page)
    for name, rows in expected_rows(study).items():
        assert [len(t["rows"]) for t in named(doc, name)] == rows, name
    # fits: one per FRF (2 per configuration); Fig. 7 at both response points; Fig. 4 at
    # each of the 9 perturbed coordinates; 4 report figures
    alts = [i["alt"] for i in doc.images]
    assert sum(a.startswith("extraction fit") for a in alts) == 2 * len(study.configurations)
    assert sorted(a for a in alts if a.startswith("FRF comparison")) == [
        "FRF comparison 1/11", "FRF comparison 15/11"]
    assert sum(a.startswith("mass sweep") for a in alts) == 9
    # the extraction CSV shown is the one the FRF files give: no mismatch warning
    assert "WARNING" not in page
    assert "extracted loss factors 0.0201, 0.0079, 0.00206" in page


def _two_configurations(tmp_path) -> Path:
    """The FRF example cut to the base and one perturbation (4 equations, 17 parameters),
    plain least squares (no prior rows)."""
    text = FRF.read_text().replace('"frf/', f'"{FRF.parent.as_posix()}/frf/')
    head, _, rest = text.partition("[[perturbation]]")
    keep = "[[perturbation]]\ncoordinate = 1\nmass = 0.2\n\n"
    tail = rest[rest.index("[measurement]"):]
    tail = "\n".join(ln for ln in tail.splitlines()
                     if not re.match(r'"0\.2 kg at (?!1")', ln))
    study = tmp_path / "study.toml"
    tail = tail.replace('"extracted.csv"', '"measured.csv"').replace('"bayesian"',
                                                                    '"least-squares"')
    study.write_text(head + keep + tail)
    return study


def test_extraction_mismatch_and_refused_update_are_said(tmp_path):
    """An extraction CSV that the study's FRF files do not give is flagged on the page; an
    update the plan cannot determine is not run, and the page says why."""
    study = _two_configurations(tmp_path)
    text = (FRF.parent / "extracted.csv").read_text().splitlines()
    rows = [ln for ln in text[1:] if ln.startswith(("base,", "0.2 kg at 1,"))]
    cells = rows[0].split(",")
    cells[2] = repr(float(cells[2]) + 0.5)
    rows[0] = ",".join(cells)
    (tmp_path / "measured.csv").write_text("\n".join([text[0], *rows]) + "\n")
    page = render_report(study, extracted=tmp_path / "measured.csv", command="test")
    assert "WARNING: the extraction file does not match" in page
    assert "base mode 1: measured.csv has 200.377 Hz" in page
    assert "NOT identifiable: rank 4 &lt; 17 parameters" in page
    assert "The update was not run" in page
    assert len(named(parse(page), "extraction")) == 2


# ----------------------------------------------------------------- in a browser


def _browser_or_skip():
    import _browser

    if _browser.chromium() is None:
        msg = f"headless Chromium not installed; install it with: {_browser.INSTALL}"
        if os.environ.get("CI") == "true":
            pytest.fail(f"CI must run the browser test: {msg}")
        pytest.skip(msg)
    return _browser


@pytest.mark.slow
def test_reports_in_chromium(frf_report, fig2_report, tmp_path):
    """The shipped examples' reports (Fig. 2 system; beam from FRFs) as a person would see
    them, in headless Chromium: (a) a screenshot that is not blank and no console errors
    (nor any request outside the file), (b) printed to PDF with a reasonable page count,
    (c) every image decoded with a width and every table with the expected rows, (d) the
    text of every figure inside it."""
    _browser = _browser_or_skip()
    pages = {"frf": frf_report, "fig2": fig2_report}
    with _browser.Browser() as browser:
        seen = {name: browser.open(path) for name, path in pages.items()}
        # (d) no figure clips its text: every title, label and tick inside the SVG (the
        # Fig. 7 titles were cut off on both sides, the history's 10^7 at the top)
        clipped = {}
        for name, path in pages.items():
            for img in parse(path.read_text()).images:
                svg = base64.b64decode(img["src"].split(",", 1)[1]).decode()
                out = browser.text_outside(svg, tmp_path)
                if out:
                    clipped[f"{name}: {img['alt']}"] = out[:2]
        assert not clipped, clipped
    for name, page in seen.items():
        assert page.errors == [], name
        assert all(u.startswith(("file:", "data:")) for u in page.requests), page.requests
        assert _browser.pixel_std(page.screenshot_png) > 0.05, f"{name}: blank screenshot"
        assert page.images and all(i["ok"] and i["complete"] and i["width"] > 0
                                   for i in page.images), (name, page.images)
        expected_tables = len(parse(pages[name].read_text()).tables)
        assert len(page.tables) == expected_tables
    pages_pdf = {name: _browser.pdf_pages(p.pdf) for name, p in seen.items()}
    # a section per page at least, and no runaway (one figure per page would be ~40)
    assert 6 <= pages_pdf["fig2"] <= 12, pages_pdf
    assert 15 <= pages_pdf["frf"] <= 40, pages_pdf
    study = load_study(FRF)
    rows = {}
    for t in seen["frf"].tables:
        rows.setdefault(t["name"], []).append(t["rows"])
    for name, want in expected_rows(study).items():
        assert rows[name] == want, name


def test_browser_test_needs_chromium_in_ci(monkeypatch):
    """Locally a missing browser skips with the install command; with CI=true it fails."""
    import _browser

    monkeypatch.setattr(shutil, "which", lambda name: None)
    assert _browser.chromium() is None
    monkeypatch.setenv("CI", "true")
    with pytest.raises(pytest.fail.Exception, match="apt-get"):
        _browser_or_skip()
    monkeypatch.setenv("CI", "false")
    with pytest.raises(pytest.skip.Exception, match="apt-get install -y chromium"):
        _browser_or_skip()
