"""The error family: bad input vs numerical trouble, exit statuses, warnings, and the
statuses that replaced exceptions as control flow."""

import warnings

import numpy as np
import pytest
from _synth import Mode, receptance

import eigenupdate as eu
from eigenupdate.measure import extraction
from eigenupdate.measure.dobson import dobson_fit_modes
from eigenupdate.measure.frf import FRF

TWIN = """title = "two identical uncoupled oscillators"
[model]
type = "spring-mass"
[[model.mass]]
name = "m1"
coordinate = 1
value = 1.0
[[model.mass]]
name = "m2"
coordinate = 2
value = 1.0
[[model.spring]]
name = "k1"
coordinates = [0, 1]
value = 100.0
[[model.spring]]
name = "k2"
coordinates = [0, 2]
value = 100.0
[measurement]
modes = [1, 2]
"""


def test_numerical_errors_are_not_input_errors():
    for cls in (eu.SingularMatrixError, eu.RepeatedEigenvalueError, eu.NotConvergedError):
        assert issubclass(cls, eu.NumericalError) and not issubclass(cls, eu.InputError)
    assert eu.RepeatedEigenvalueError("x").exit_status == 2
    assert eu.NotConvergedError("x").exit_status == 1
    assert str(eu.SingularMatrixError("singular", source="a.toml", field="model")) == \
        "a.toml: model: singular"


def test_repeated_eigenvalue_is_one_line_exit_2(tmp_path, run_cli):
    study = tmp_path / "twin.toml"
    study.write_text(TWIN)
    code, out, err = run_cli("check", study)
    assert code == 2 and "Traceback" not in err
    assert len(err.strip().splitlines()) == 1
    assert "twin.toml" in err and "modes 1 and 2 have a repeated eigenvalue" in err


def test_band_without_peak_is_a_status_not_an_error():
    f = np.arange(50.0, 200.0, 0.25)
    h = receptance(f, [Mode(100.0, 0.01)])
    fits = dobson_fit_modes(f, h, [(95.0, 105.0), (150.0, 160.0)], skip_missing=True)
    assert fits[1] is None and abs(fits[0].frequency_hz - 100.0) < 1e-9


def test_disagreeing_estimates_warn(monkeypatch):
    f = np.arange(1.0, 400.0, 0.25)
    h = receptance(f, [Mode(100.0, 0.01), Mode(250.0, 0.01)], noise=1e-3, seed=1)
    frf = FRF(f, h)
    monkeypatch.setattr(extraction, "DISAGREEMENT_WARNING", -1.0)  # every mode warns
    with pytest.warns(eu.EigenupdateWarning) as record:
        extraction.extract_configuration([frf], [1, 2], "base")
    got = [str(r.message)[:21] for r in record]
    assert got == ["base mode 1: Dobson 1", "base mode 2: Dobson 2"]
    monkeypatch.undo()
    with warnings.catch_warnings():
        warnings.simplefilter("error", eu.EigenupdateWarning)
        extraction.extract_configuration([frf], [1, 2], "base")


def test_lanczos_not_converged_is_exit_1(tmp_path, run_cli, monkeypatch):
    import scipy.sparse.linalg as spla

    def no_convergence(*args, **kwargs):
        raise spla.ArpackNoConvergence("ARPACK error -1: No convergence", np.zeros(0),
                                       np.zeros((0, 0)))

    from eigenupdate.solve import eigen

    monkeypatch.setattr(eigen.spla, "eigsh", no_convergence)
    model = eu.beam_model(np.linspace(0.0, 1.0, 300), 4557.0, 3.4)  # 600 coordinates: sparse
    with pytest.raises(eu.NotConvergedError, match="did not converge"):
        eu.solve_configurations(model, [eu.Configuration("base")], 2)
    study = tmp_path / "beam.toml"
    nodes = ", ".join(f"{x:.6f}" for x in np.linspace(0.0, 1.0, 300))
    study.write_text(f'title = "t"\n[model]\ntype = "beam"\nnodes = [{nodes}]\nEI = 4557.0\n'
                     f'mass_per_length = 3.4\n[measurement]\nmodes = [1]\n')
    code, _, err = run_cli("frequencies", study)
    assert code == 1 and "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert "did not converge" in err
