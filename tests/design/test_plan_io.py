"""The designed plan as a study file (`design -o PLAN.toml`) must load again from wherever it
is written: a NASTRAN study names its additions by grid and component, and every model file
(BDF, Matrix Market K0/M0, parameter and term matrices) stays reachable.

Source: the tester's acceptance run (issue 21) - `design -o plan.toml` of a NASTRAN study
wrote `coordinate = 10033`, which `frequencies plan.toml` refused ("a NASTRAN model names
grid = ... and component = 1-6"), and `-o out/plan.toml` kept `bdf = "nominal.bdf"`."""

import tomllib

import pytest
from nastran_frames import need

from eigenupdate.design.plan_io import plan_study_text
from eigenupdate.io.study import load_study
from eigenupdate.model.configurations import Addition, Configuration, mass_at


def test_nastran_plan_names_grid_and_component_and_moves_the_bdf(tmp_path):
    s = tmp_path / "s.toml"
    s.write_text('[model]\ntype = "nastran"\nbdf = "deck.bdf"\n')
    plan = [mass_at(10033, 0.1),
            Configuration("two", (Addition(20012, mass=0.2), Addition(71, stiffness=5.0)))]
    doc = tomllib.loads(plan_study_text(s, plan, [1, 2], tmp_path / "out" / "p.toml"))
    assert doc["model"]["bdf"] == "../deck.bdf"
    assert doc["perturbation"][0]["add"] == [{"grid": 1003, "component": 3, "mass": 0.1}]
    assert doc["perturbation"][1]["add"] == [{"grid": 2001, "component": 2, "mass": 0.2},
                                             {"grid": 7, "component": 1, "stiffness": 5.0}]


def test_term_matrices_stay_reachable(tmp_path):
    s = tmp_path / "s.toml"
    s.write_text('[model]\ntype = "matrices"\nK0 = "K0.mtx"\nM0 = "M0.mtx"\n'
                 '[[model.parameter]]\nname = "t"\nvalue = 1.0\n'
                 '[[model.term]]\nK = "Kb.mtx"\nM = "Mt.mtx"\npowers = { t = 3 }\n')
    doc = tomllib.loads(plan_study_text(s, [mass_at(1, 0.1)], [1], tmp_path / "o" / "p.toml"))
    assert doc["model"]["term"][0]["K"] == "../Kb.mtx"
    assert doc["model"]["term"][0]["M"] == "../Mt.mtx"
    assert doc["perturbation"][0]["add"] == [{"coordinate": 1, "mass": 0.1}]


DECK = """SOL 103
CEND
BEGIN BULK
GRID,1,,0.0,0.0,0.0
GRID,2,,0.5,0.0,0.0
GRID,3,,1.0,0.0,0.0
GRID,4,,1.5,0.0,0.0
CBAR,1,1,1,2,0.0,1.0,0.0
CBAR,2,1,2,3,0.0,1.0,0.0
CBAR,3,1,3,4,0.0,1.0,0.0
PBAR,1,1,1.0e-3,1.0e-7,2.0e-7,3.0e-7
MAT1,1,2.0e11,,0.3,7850.0
SPC1,1,123456,1
ENDDATA
"""


@pytest.mark.nastran
def test_nastran_plan_loads_and_keeps_the_designed_additions(tmp_path, run_cli):
    need("pyNastran")
    (tmp_path / "deck.bdf").write_text(DECK)
    s = tmp_path / "s.toml"
    s.write_text('[model]\ntype = "nastran"\nbdf = "deck.bdf"\n'
                 '[[model.parameter]]\nname = "E"\ncard = "MAT1"\nid = 1\nfield = "E"\n'
                 '[design]\ncoordinates = [43, 42, 33]\nmasses = [0.5]\nconfigurations = 1\n'
                 'modes = [1, 2]\nfrequency_std_relative = 1e-3\n')
    (tmp_path / "out").mkdir()
    out = tmp_path / "out" / "plan.toml"
    code, _, err = run_cli("design", s, "-o", out)
    assert code == 0, err
    plan = load_study(out)
    chosen = plan.configurations[1].additions[0]
    assert chosen.coordinate in (43, 42, 33) and chosen.mass == 0.5
    assert plan.model.n == load_study(s).model.n
    # candidates named as the study names its own perturbations: grid-component
    g, c = divmod(chosen.coordinate, 10)
    assert plan.configurations[1].name == f"0.5 kg at {g}-{c}"


def test_refusal_names_bare_modes_already_too_close(tmp_path, run_cli):
    """Two nearly uncoupled oscillators: sqrt(1000) and sqrt(1010) rad/s, 0.5 % apart
    (closed form for the uncoupled pair; the 1 N/m coupling moves them by < 0.1 %), below
    the default min_relative_gap of 2 %: every candidate is refused, and the message says
    the bare structure is the cause, not the masses. Source: the tester's run on a plate
    whose modes 3 and 4 were 0.9 % apart, where the message blamed 'masses too large?'."""
    s = tmp_path / "s.toml"
    s.write_text('[model]\ntype = "spring-mass"\n'
                 '[[model.mass]]\nname = "m1"\ncoordinate = 1\nvalue = 1.0\n'
                 '[[model.mass]]\nname = "m2"\ncoordinate = 2\nvalue = 1.0\n'
                 '[[model.spring]]\nname = "k1"\ncoordinates = [0, 1]\nvalue = 1000.0\n'
                 '[[model.spring]]\nname = "k2"\ncoordinates = [0, 2]\nvalue = 1010.0\n'
                 '[[model.spring]]\nname = "k12"\ncoordinates = [1, 2]\nvalue = 1.0\n'
                 'update = false\n'
                 '[design]\ncoordinates = [1, 2]\nmasses = [0.01]\nconfigurations = 2\n'
                 'modes = [1, 2]\nfrequency_std_relative = 1e-4\n')
    code, _, err = run_cli("design", s, "-o", tmp_path / "plan.toml")
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    assert "the bare structure's modes 1 and 2" in err and "min_relative_gap" in err, err
