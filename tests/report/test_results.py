"""The result classes as the contract: one versioned JSON document each, written by
``to_dict`` and read back by ``from_dict`` to an equal object (JSON text in between, so
the round trip is what a saved file gives); a document of another kind or with a bad
field is refused naming the file and the field."""

import json
import re

import numpy as np
import pytest
from conftest import EXAMPLES

import eigenupdate as eu
from eigenupdate.identify.identifiability import IdentifiabilityReport
from eigenupdate.identify.updating import UpdateResult
from eigenupdate.report.text import dumps


@pytest.fixture(scope="module")
def fig2():
    return eu.load_study(EXAMPLES / "paper_fig2" / "study.toml")


@pytest.fixture(scope="module")
def result(fig2):
    return eu.update_study(fig2)


def _through_json(doc: dict) -> dict:
    return json.loads(dumps(doc))


def _same_arrays(a, b) -> None:
    # JSON writes a float with repr: the round trip is exact, so equality is the test
    assert (a is None) == (b is None)
    if a is not None:
        np.testing.assert_array_equal(np.asarray(a), np.asarray(b))


def test_update_result_round_trip(fig2, result):
    back = UpdateResult.from_dict(_through_json(result.to_dict()), "r.json", fig2.model)
    for key in result.keys():
        if key in ("model", "identifiability"):
            continue
        a, b = result[key], back[key]
        if isinstance(a, np.ndarray) or key in ("cov",):
            _same_arrays(a, b)
        else:
            assert a == b, key
    assert back.identifiability == result.identifiability
    np.testing.assert_array_equal(back.model.values, result.model.values)
    assert back.to_dict() == _through_json(result.to_dict())
    # without the study's model the numbers are there, the model is not
    assert UpdateResult.from_dict(_through_json(result.to_dict())).model is None


def test_check_round_trip(fig2):
    r = eu.check_study(fig2)
    assert IdentifiabilityReport.from_dict(_through_json(r.to_dict())) == r
    # a singular plan: the infinite condition is null in JSON and infinite again after
    singular = IdentifiabilityReport(["a", "b"], 1, 1, np.inf, np.inf, [1.0, 0.0],
                                     {"a": 1.0, "b": 0.0})
    doc = _through_json(singular.to_dict())
    assert doc["condition_J"] is None
    assert IdentifiabilityReport.from_dict(doc) == singular


@pytest.mark.parametrize("change, field", [
    ({"schema": "eigenupdate.update/1"}, "schema"),
    ({"schema": None}, "schema"),
    ({"nit": "4"}, "nit"),
    ({"success": 1}, "success"),
    ({"x": [1.0]}, "x"),
    ({"fun": [1.0, "a"]}, "fun"),
    ({"std": {}}, "std"),
    ({"cost": -1.0}, "cost"),
    ({"history": [{"iteration": 0}]}, "history[0].note"),
])
def test_update_result_refuses_a_bad_document(result, change, field):
    doc = {**_through_json(result.to_dict()), **change}
    with pytest.raises(eu.InputError, match="r.json: " + re.escape(field)):
        UpdateResult.from_dict(doc, "r.json")


def test_a_result_of_another_kind_is_refused(fig2, result):
    with pytest.raises(eu.InputError, match="schema.*expected 'eigenupdate.update/2'"):
        UpdateResult.from_dict(eu.check_study(fig2).to_dict(), "c.json")
    with pytest.raises(eu.InputError, match="must be a JSON object"):
        UpdateResult.from_dict([1, 2], "c.json")


def test_sweep_round_trip(fig2):
    s = eu.sweep(fig2, 1, 0.35)
    back = eu.MassSweep.from_dict(_through_json(s.to_dict()))
    for key in ("added_mass", "frequencies_hz"):
        _same_arrays(getattr(s, key), getattr(back, key))
    assert (back.reference_mass, back.coordinate, back.configuration) == (
        s.reference_mass, s.coordinate, s.configuration)
    bad = {**s.to_dict(), "frequencies_hz": s.frequencies_hz[:-1].tolist()}
    with pytest.raises(eu.InputError, match="s.json: frequencies_hz: needs one row"):
        eu.MassSweep.from_dict(bad, "s.json")


def test_design_round_trip(fig2):
    from eigenupdate.design.plan import DesignResult

    d = eu.design(fig2).plan
    back = DesignResult.from_dict(_through_json(d.to_dict()))
    assert back == d  # dataclasses of plain values: equal field by field
    assert [c.name for c in back.configurations] == [c.name for c in d.configurations]
    doc = {**d.to_dict(), "chosen": [len(d.candidates)]}
    with pytest.raises(eu.InputError, match="d.json: chosen: must index"):
        DesignResult.from_dict(doc, "d.json")


def test_montecarlo_round_trip():
    # one mass on one spring with priors (the doctest of design/montecarlo.py)
    from eigenupdate.design.montecarlo import MonteCarloResult, TrialSetup, montecarlo

    model = eu.spring_mass_model([eu.Mass(eu.Parameter("m", 2.0, 0.1), 1)],
                                 [eu.Spring(eu.Parameter("k", 800.0, 40.0), (0, 1))])
    configs = (eu.Configuration("base"), eu.mass_at(1, 1.0))
    setup = TrialSetup(model, configs, (1,), {(c.name, 1): 0.01 for c in configs},
                       "bayesian", 20, 1e-8)
    r = montecarlo(setup, 5, seed=1)
    back = MonteCarloResult.from_dict(_through_json(r.to_dict()))
    assert back.summary() == r.summary() and back.entropy == r.entropy
    assert back.names == r.names and back.counts() == r.counts()
    for a, b in zip(r.trials, back.trials, strict=True):
        for k in ("truth", "estimate", "std"):
            _same_arrays(a[k], b[k])
    _same_arrays(back.z_scores(), r.z_scores())
    assert back.prior.draws == r.prior.draws


def test_extraction_round_trip():
    study = eu.load_study(EXAMPLES / "paper_beam_frf" / "study.toml")
    res = eu.extract(study).result
    back = type(res).from_dict(_through_json(res.to_dict()))
    assert back == res  # every mode, fit (complex modal constant), rejection and note
    doc = _through_json(res.to_dict())
    doc["configurations"][0]["modes"][0]["fits"][0]["modal_constant"] = [1.0]
    with pytest.raises(eu.InputError, match=re.escape(
            "x.json: configurations[0].modes[0].fits[0].modal_constant")):
        type(res).from_dict(doc, "x.json")
