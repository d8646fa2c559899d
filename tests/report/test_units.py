"""Parameter units: stated by each model (SI for the package's own models, the field's
dimension for a NASTRAN deck), overridden by a study's ``unit`` key, carried by the
update result and printed in its table."""

import shutil

import pytest
from conftest import EXAMPLES

import eigenupdate as eu
from eigenupdate.errors import InputError
from eigenupdate.model.beam import beam_model
from eigenupdate.model.parameters import Parameter
from eigenupdate.report.text import update_text


@pytest.fixture(scope="module")
def fig2():
    return eu.load_study(EXAMPLES / "paper_fig2" / "study.toml")


def test_spring_mass_units_reach_the_result_and_its_table(fig2):
    units = {p.name: p.unit for p in fig2.model.parameters}
    assert units == {**{f"m{i}": "kg" for i in range(1, 5)},
                     **{f"k{i}": "N/m" for i in range(1, 7)}}
    res = eu.update_study(fig2)
    assert res.units == units
    assert res.to_dict()["units"] == units
    lines = update_text(res, {p.name: p.value for p in fig2.model.parameters},
                        fig2.title).splitlines()
    header = next(line for line in lines if line.split()[:2] == ["parameter", "unit"])
    assert header.split()[2:4] == ["initial", "updated"]
    assert next(line for line in lines if line.split()[:1] == ["k1"]).split()[1] == "N/m"


def test_beam_units_mass_on_translation_inertia_on_rotation():
    model = beam_model([0.0, 0.5, 1.0], 10.0, 2.0,
                       point_masses=[(Parameter("m", 0.1), 3), (Parameter("J", 0.01), 4)])
    units = {p.name: p.unit for p in model.parameters}
    assert units == {"EI1": "N m^2", "EI2": "N m^2", "rhoA1": "kg/m", "rhoA2": "kg/m",
                     "m": "kg", "J": "kg m^2"}


def test_a_studys_unit_overrides_and_a_bad_one_is_refused(tmp_path, fig2):
    src = EXAMPLES / "paper_fig2"
    for f in src.iterdir():
        if f.is_file():
            shutil.copy(f, tmp_path / f.name)
    text = (src / "study.toml").read_text()
    stated = text.replace('name = "k1"\n', 'name = "k1"\nunit = "kN/mm"\n', 1)
    assert stated != text
    # a label is not converted: 1.2e6 under kN/mm would be 1000 times the model's k1
    (tmp_path / "study.toml").write_text(stated)
    with pytest.raises(InputError, match=r"model\.spring\[1\]\.unit: 'kN/mm' is not the "
                                         r"unit of this value: the model's values are SI, N/m"):
        eu.load_study(tmp_path / "study.toml")
    (tmp_path / "study.toml").write_text(stated.replace('"kN/mm"', '"N / m"'))
    model = eu.load_study(tmp_path / "study.toml").model
    assert {p.name: p.unit for p in model.parameters}["k1"] == "N / m"
    assert {p.name: p.unit for p in model.parameters}["k2"] == "N/m"
    (tmp_path / "study.toml").write_text(stated.replace('"kN/mm"', '"kN\\u0007"'))
    with pytest.raises(InputError, match=r"model\.spring\[1\]\.unit"):
        eu.load_study(tmp_path / "study.toml")


def test_a_result_without_units_reads_back_with_none(fig2):
    res = eu.update_study(fig2)
    doc = res.to_dict()
    del doc["units"]  # a result written before units were stated
    assert type(res).from_dict(doc, "old.json", fig2.model).units == {}


@pytest.mark.nastran
def test_nastran_parameters_state_their_fields_dimension(tmp_path):
    """The example states SI units; without them each field's dimension in the deck's
    units is stated instead."""
    pytest.importorskip("pyNastran")
    src = EXAMPLES / "stiffened_panel"
    study = eu.load_study(src / "study.toml")
    assert {p.name: p.unit for p in study.model.parameters} == {
        "t_skin": "m", "t_blade": "m", "E": "Pa"}
    for f in src.iterdir():
        if f.is_file():
            shutil.copy(f, tmp_path / f.name)
    text = (src / "study.toml").read_text()
    bare = "".join(line for line in text.splitlines(keepends=True)
                   if not line.startswith("unit ="))
    assert bare != text
    (tmp_path / "study.toml").write_text(bare)
    study = eu.load_study(tmp_path / "study.toml")
    assert {p.name: p.unit for p in study.model.parameters} == {
        "t_skin": "length", "t_blade": "length", "E": "force/length^2"}


def test_the_montecarlo_table_states_units(fig2):
    from eigenupdate.report.text import montecarlo_text

    truth = eu.load_study(EXAMPLES / "paper_fig2" / "truth.toml")
    doc = eu.montecarlo(fig2, 3, truth=truth.path, seed=4).summary()
    assert doc["statistics_refused"] is None
    units = {p.name: p.unit for p in fig2.model.parameters}
    lines = montecarlo_text(doc, fig2.title, units).splitlines()
    header = next(line for line in lines if line.split()[:2] == ["parameter", "unit"])
    assert header.split()[2] == "bias"
    assert next(line for line in lines if line.split()[:1] == ["m1"]).split()[1] == "kg"


def test_the_design_table_states_units(fig2):
    from eigenupdate.report.design import design_text

    d = eu.design(fig2).plan
    initial = {p.name: p.value for p in fig2.model.parameters}
    units = {p.name: p.unit for p in fig2.model.parameters}
    lines = design_text(d, initial, fig2.title, units).splitlines()
    header = next(line for line in lines if line.split()[:2] == ["parameter", "unit"])
    assert header.split()[2] == "initial"
    rows = {line.split()[0]: line.split() for line in lines if line.split()[:1] in
            (["k1"], ["m1"])}
    assert rows["k1"][1] == "N/m" and rows["m1"][1] == "kg"
    # without units the table is as before
    assert not any(line.split()[:2] == ["parameter", "unit"]
                   for line in design_text(d, initial, fig2.title).splitlines())
