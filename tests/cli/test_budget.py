"""Budgets checked before allocation (eigenupdate/budget.py, issue 23): a declared matrix
size, a mesh, a [design] candidate space, a nesting depth. Each refusal states the
estimate, the limit and the environment variable that raises it."""

import itertools
import json
import time

from conftest import EXAMPLES
from hypothesis import given, settings
from hypothesis import strategies as st

from eigenupdate.budget import nesting_depth
from eigenupdate.design.plan import candidate_configurations, candidate_count
from eigenupdate.design.spec import DesignSpec

FIG2 = (EXAMPLES / "paper_fig2" / "study.toml").read_text()


def bad(run_cli, args, *fragments):
    code, out, err = run_cli(*args)
    assert code == 2, (out, err)
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    for f in fragments:
        assert f in lines[0], lines[0]
    return lines[0]


def test_matrix_market_header_of_3e6(tmp_path, run_cli):
    (tmp_path / "K0.mtx").write_text("%%MatrixMarket matrix coordinate real symmetric\n"
                                     "3000000 3000000 1\n1 1 1.0\n")
    (tmp_path / "s.toml").write_text('[model]\ntype = "matrices"\nK0 = "K0.mtx"\n'
                                     'M0 = "K0.mtx"\n[[model.parameter]]\nname = "a"\n'
                                     'value = 1.0\nK = "K0.mtx"\n')
    start = time.perf_counter()
    bad(run_cli, ["frequencies", tmp_path / "s.toml"], "K0.mtx", "3,000,000 x 3,000,000",
        "EIGENUPDATE_MAX_COORDINATES")
    assert time.perf_counter() - start < 30  # refused from the header, not after reading


def _beam(nodes: int) -> str:
    xs = ", ".join(f"{0.01 * i:.2f}" for i in range(nodes))
    return (f'[model]\ntype = "beam"\nnodes = [{xs}]\nEI = 4557.0\nmass_per_length = 3.4\n'
            f'[measurement]\nmodes = [1]\n')


def test_beam_of_10000_nodes(tmp_path, run_cli, monkeypatch):
    s = tmp_path / "beam.toml"
    s.write_text(_beam(10_000))
    # 19,998 parameters x 20,001 row pointers x 8 bytes = 3,200 MB of CSR row pointers
    bad(run_cli, ["frequencies", s], "model.nodes", "19,998 parameter matrices",
        "3,200 MB", "EIGENUPDATE_MAX_MEMORY_MB")
    s.write_text(_beam(20))
    assert run_cli("frequencies", s)[0] == 0
    monkeypatch.setenv("EIGENUPDATE_MAX_COORDINATES", "30")  # 40 coordinates now too many
    bad(run_cli, ["frequencies", s], "40 coordinates", "limit is 30")
    monkeypatch.setenv("EIGENUPDATE_MAX_COORDINATES", "lots")
    line = bad(run_cli, ["frequencies", s], "environment: EIGENUPDATE_MAX_COORDINATES",
               "integer >= 1")
    assert "beam.toml" not in line  # not blamed on the study


def test_design_additions_2e9(tmp_path, run_cli, monkeypatch):
    """additions = 2e9 on 4 coordinates with 3 masses: sum_k C(4, k) 3^k = 255 candidates
    (it hung before); with a limit of 100 the same table is refused, naming 255."""
    text = FIG2.replace("criterion = \"A\"", "criterion = \"A\"\nadditions = 2000000000")
    (tmp_path / "s.toml").write_text(text)
    (tmp_path / "measured.csv").write_text((EXAMPLES / "paper_fig2" / "measured.csv").read_text())
    code, out, err = run_cli("design", tmp_path / "s.toml", "-o", tmp_path / "p.toml")
    assert code == 0, err
    assert "255 candidates admissible" in out or "of 255 candidates" in out, out[:300]
    monkeypatch.setenv("EIGENUPDATE_MAX_CANDIDATES", "100")
    bad(run_cli, ["design", tmp_path / "s.toml", "-o", tmp_path / "q.toml"],
        "asks for 255 candidate", "limit is 100", "EIGENUPDATE_MAX_CANDIDATES", "design")
    assert not (tmp_path / "q.toml").exists()


def test_design_space_of_a_small_table(tmp_path, run_cli):
    """60 coordinates, 10 masses, 4 additions: 4.9e10 candidates from a 400-byte table."""
    coords = ", ".join(str(i) for i in range(1, 61))
    masses = ", ".join(f"{0.1 * i:.1f}" for i in range(1, 11))
    nodes = ", ".join(f"{0.01 * i:.2f}" for i in range(30))
    (tmp_path / "s.toml").write_text(
        f'[model]\ntype = "beam"\nnodes = [{nodes}]\nEI = 4557.0\nmass_per_length = 3.4\n'
        f'[design]\ncoordinates = [{coords}]\nmasses = [{masses}]\nconfigurations = 3\n'
        f'additions = 4\nmodes = [1, 2]\nfrequency_std_hz = 0.01\n')
    n = sum(__import__("math").comb(60, k) * 10 ** k for k in range(1, 5))
    bad(run_cli, ["design", tmp_path / "s.toml", "-o", tmp_path / "p.toml"], f"{n:,}",
        "limit is 20,000")


@settings(max_examples=60, deadline=None)
@given(n_coords=st.integers(1, 5), n_masses=st.integers(1, 3), n_springs=st.integers(0, 2),
       additions=st.integers(1, 7))
def test_candidate_count_matches_the_enumeration(n_coords, n_masses, n_springs, additions):
    """The estimate is exact: against the brute force of itertools.combinations filtered
    to distinct coordinates (the enumeration before this change)."""
    spec = DesignSpec(coordinates=tuple(range(1, n_coords + 1)),
                      masses=tuple(0.1 * (i + 1) for i in range(n_masses)),
                      stiffnesses=tuple(1e3 * (i + 1) for i in range(n_springs)),
                      configurations=1, modes=(1,), additions=additions)
    got = candidate_configurations(spec)
    singles = [(c, v) for c in spec.coordinates for v in range(spec.values)]
    brute = [g for k in range(1, additions + 1) for g in itertools.combinations(singles, k)
             if len({c for c, _ in g}) == k]
    assert candidate_count(spec) == len(got) == len(brute)


def _nest(depth: int) -> object:
    x: object = 1
    for i in range(depth):
        x = [x] if i % 2 else {"k": x}
    return x


@given(st.integers(0, 300))
def test_nesting_depth_of_json(depth):
    """Depth against the object's own construction (json.dumps of ``depth`` levels)."""
    assert nesting_depth(json.dumps(_nest(depth))) == depth


def test_nesting_ignores_strings_and_comments():
    text = 'a = "[[[[" # {{{{\nb = \'\'\'\n[[[[\n\'\'\'\nc = [[1], {d = "]"}]\n'
    assert nesting_depth(text) == 2


def test_deep_toml_and_json(tmp_path, run_cli):
    (tmp_path / "s.toml").write_text("a = " + "[" * 5000 + "]" * 5000 + "\n" + FIG2)
    bad(run_cli, ["check", tmp_path / "s.toml"], "s.toml", "nested 5000 levels deep",
        "EIGENUPDATE_MAX_NESTING")
    (tmp_path / "study.toml").write_text(FIG2)
    (tmp_path / "measured.csv").write_text((EXAMPLES / "paper_fig2" / "measured.csv").read_text())
    (tmp_path / "r.json").write_text('{"parameters": ' + "[" * 5000 + "]" * 5000 + "}")
    bad(run_cli, ["report", tmp_path / "study.toml", "--result", tmp_path / "r.json", "-o",
                  tmp_path / "r.html"], "r.json", "nested 5001 levels deep")
    bad(run_cli, ["frf", tmp_path / "study.toml", "--input", "1", "--output", "1",
                  "--updated", tmp_path / "r.json", "-o", tmp_path / "f.png"], "r.json",
        "nested")
