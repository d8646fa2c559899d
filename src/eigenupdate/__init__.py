"""eigenupdate: update FE model parameters from natural frequencies of the bare and
mass- or stiffness-perturbed structure (mass-addition model updating).

The whole workflow on the paper's Fig. 2 system (``examples/paper_fig2``): four masses
on six springs, the initial model 3-20 % off, frequencies of modes 1-3 "measured" on
the true system bare and with 0.35 kg at coordinates 1, 2 and 4.

>>> import eigenupdate as eu
>>> def fig2(k, m):
...     ends = [(0, 1), (1, 2), (2, 3), (0, 3), (2, 4), (0, 4)]
...     return eu.spring_mass_model(
...         [eu.Mass(eu.Parameter(f"m{i + 1}", m[i]), i + 1) for i in range(4)],
...         [eu.Spring(eu.Parameter(f"k{i + 1}", k[i]), ends[i]) for i in range(6)])
>>> truth = fig2([1e6] * 5 + [0.5e6], [10.0, 10.0, 5.0, 5.0])
>>> model = fig2([1.2e6, 1.2e6, 1.2e6, 0.95e6, 0.96e6, 0.6e6], [9.7, 9.7, 4.7, 4.7])
>>> plan = [eu.Configuration("base")] + [eu.mass_at(c, 0.35) for c in (1, 2, 4)]
>>> measured = {(m.configuration, m.mode): m
...             for m in eu.simulate_measurements(truth, plan, [1, 2, 3])}
>>> print(f"{measured[('base', 1)].frequency_hz:.2f} Hz")          # Table 5
42.87 Hz
>>> report = eu.check(model, plan, [1, 2, 3])
>>> report.rank, report.identifiable
(10, True)
>>> result = eu.update(model, plan, [1, 2, 3], measured, optimizer="gauss-newton")
>>> result.success, result.status, result.nit      # the paper's iteration, by name
(True, 1, 4)
>>> [round(h.parameters["k6"] / 1e6, 4) for h in result.history[1:]]   # Table 4
[0.4673, 0.4984, 0.5, 0.5]
>>> eu.update(model, plan, [1, 2, 3], measured).optimizer      # the default
'trust-region'
>>> {n: round(v, 4) for n, v in result.parameters.items() if n.startswith("m")}
{'m1': 10.0, 'm2': 10.0, 'm3': 5.0, 'm4': 5.0}

The same from the shipped study files: every command is one function taking a
:class:`Study` (``eigenupdate check`` is :func:`check_study`, ``eigenupdate update`` is
:func:`update_study`; :func:`check` and :func:`update` take the model and plan, as above):

>>> from pathlib import Path
>>> study = eu.load_study(Path(eu.__file__).parents[2] / "examples/paper_fig2/study.toml")
>>> eu.frequencies(study)["base"].round(2).tolist()     # Table 5, initial model
[46.46, 84.02, 98.9]
>>> round(eu.update_study(study).parameters["k6"])                  # Table 4
500000
>>> [c.name for c in eu.design(study).plan.configurations]       # its [design] table
['2 kg at 1', '2 kg at 3', '2 kg at 4']

Names are imported on first use (``eigenupdate --help`` needs none of them). The
commands ``design`` and ``report`` are functions here; their subpackages stay importable
by ``from eigenupdate.design import plan`` or ``from eigenupdate.design.plan import ...``.
"""

from __future__ import annotations

import importlib
import sys
import types
from importlib.metadata import PackageNotFoundError, version
from typing import Any

# where each public name lives: module, or (module, name there) where the names differ
_WHERE: dict[str, str | tuple[str, str]] = {
    # errors and warnings
    **dict.fromkeys(["EigenupdateWarning", "InputError", "NotConvergedError", "NumericalError",
                     "RepeatedEigenvalueError", "SingularMatrixError"], "eigenupdate.errors"),
    # model
    "Addition": "eigenupdate.model.configurations",
    "Configuration": "eigenupdate.model.configurations",
    "mass_at": "eigenupdate.model.configurations",
    "Coordinate": "eigenupdate.model.coordinates",
    "CoordinateTable": "eigenupdate.model.coordinates",
    "Mass": "eigenupdate.model.spring_mass",
    "Spring": "eigenupdate.model.spring_mass",
    "spring_mass_model": "eigenupdate.model.spring_mass",
    "ParametricModel": "eigenupdate.model.parametric",
    "Parameter": "eigenupdate.model.parameters",
    "beam_model": "eigenupdate.model.beam",
    "matrix_model": "eigenupdate.model.matrices",
    # solve
    "EigenSolution": "eigenupdate.solve.eigen",
    "solve_elastic": "eigenupdate.solve.eigen",
    "Linearisation": "eigenupdate.solve.jacobian",
    "linearise": "eigenupdate.solve.jacobian",
    "solve_configurations": "eigenupdate.solve.jacobian",
    "MassSweep": "eigenupdate.solve.sweep",
    "mass_sweep": "eigenupdate.solve.sweep",
    "receptance": "eigenupdate.solve.response",
    # identify
    "ESTIMATORS": "eigenupdate.choices",
    "OPTIMIZERS": "eigenupdate.choices",
    "EstimatorWeights": "eigenupdate.identify.weights",
    "estimator_weights": "eigenupdate.identify.weights",
    "IdentifiabilityReport": "eigenupdate.identify.identifiability",
    "check": "eigenupdate.identify.identifiability",
    "identifiability": "eigenupdate.identify.identifiability",
    **dict.fromkeys(["STATUS_MESSAGES", "Step", "update"], "eigenupdate.identify.updating"),
    **dict.fromkeys(["Iterate", "UpdateResult"], "eigenupdate.identify.result"),
    # measure
    "ExtractedMode": "eigenupdate.measure.extraction",
    "extract_configuration": "eigenupdate.measure.extraction",
    "FRF": "eigenupdate.measure.frf",
    "to_receptance": "eigenupdate.measure.frf",
    "ModalFit": "eigenupdate.measure.modal_fit",
    "NoResonance": "eigenupdate.measure.modal_fit",
    "dobson_fit": "eigenupdate.measure.dobson",
    "dobson_fit_modes": "eigenupdate.measure.dobson",
    "rational_fraction_fit": "eigenupdate.measure.rational_fraction",
    "simulate_measurements": "eigenupdate.measure.synthetic",
    "synthetic_frfs": "eigenupdate.measure.synthetic",
    # io
    "Measurement": "eigenupdate.measure.measurement",
    "read_measurements": "eigenupdate.io.measurements",
    "write_measurements": "eigenupdate.io.measurements",
    "Study": "eigenupdate.io.study",
    "load_study": "eigenupdate.io.study",
    "read_frf_csv": "eigenupdate.io.frf_csv",
    "write_frf_csv": "eigenupdate.io.frf_csv",
    "read_matrix_model": "eigenupdate.io.matrix_market",
    **dict.fromkeys(["read_frfs", "read_modes", "write_frfs", "write_modes"],
                    "eigenupdate.io.uff"),
    "read_frf_files": "eigenupdate.io.frf_files",
    "Mode": "eigenupdate.measure.modes",
    "read_nastran": "eigenupdate.io.nastran",
    # the commands as functions of a Study (check and update: of a model, above)
    **dict.fromkeys(["check_study", "compare_frf", "extract_files", "extract_study",
                     "simulate_study", "simulate_study_frfs", "study_frequencies",
                     "update_study", "design", "montecarlo", "report", "report_data", "sweep"],
                    "eigenupdate.workflow"),
    "frequencies": ("eigenupdate.workflow", "study_frequencies"),
    "extract": ("eigenupdate.workflow", "extract_study"),
    "frf": ("eigenupdate.workflow", "compare_frf"),
}

__all__ = sorted(_WHERE)

try:
    __version__ = version("eigenupdate")
except PackageNotFoundError:  # run from a source tree that was never installed
    __version__ = "0+unknown"


def __getattr__(name: str) -> Any:
    """Import a public name on first use (PEP 562) and keep it."""
    where = _WHERE.get(name)
    if where is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    module, attr = (where, name) if isinstance(where, str) else where
    value = getattr(importlib.import_module(module), attr)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *__all__})


class _Package(types.ModuleType):
    """This package, whose public functions ``design`` and ``report`` keep their names
    when the subpackages of the same names are imported (the import system binds a
    subpackage to its parent's attribute; that binding is refused here)."""

    def __setattr__(self, name: str, value: Any) -> None:
        if name in _WHERE and isinstance(value, types.ModuleType):
            return
        super().__setattr__(name, value)


sys.modules[__name__].__class__ = _Package
