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

The same from the shipped study files: :func:`load_study` and the ``*_study`` functions
(what the ``eigenupdate`` commands call).
"""

from eigenupdate.errors import (
    EigenupdateWarning,
    InputError,
    NotConvergedError,
    NumericalError,
    RepeatedEigenvalueError,
    SingularMatrixError,
)
from eigenupdate.identify.identifiability import IdentifiabilityReport, check, identifiability
from eigenupdate.identify.updating import STATUS_MESSAGES, Iterate, Step, UpdateResult, update
from eigenupdate.identify.weights import (
    ESTIMATORS,
    OPTIMIZERS,
    EstimatorWeights,
    estimator_weights,
)
from eigenupdate.io.frf_csv import read_frf_csv, write_frf_csv
from eigenupdate.io.matrix_market import read_matrix_model
from eigenupdate.io.measurements import Measurement, read_measurements, write_measurements
from eigenupdate.io.study import Study, load_study
from eigenupdate.io.uff import Mode, read_frf_files, read_frfs, read_modes, write_frfs, write_modes
from eigenupdate.measure.dobson import dobson_fit, dobson_fit_modes
from eigenupdate.measure.extraction import ExtractedMode, extract_configuration
from eigenupdate.measure.frf import FRF, to_receptance
from eigenupdate.measure.modal_fit import ModalFit, NoResonance
from eigenupdate.measure.rational_fraction import rational_fraction_fit
from eigenupdate.measure.synthetic import simulate_measurements, synthetic_frfs
from eigenupdate.model.beam import beam_model
from eigenupdate.model.configurations import Addition, Configuration, mass_at
from eigenupdate.model.coordinates import Coordinate, CoordinateTable
from eigenupdate.model.matrices import matrix_model
from eigenupdate.model.parameters import Parameter
from eigenupdate.model.parametric import ParametricModel
from eigenupdate.model.spring_mass import Mass, Spring, spring_mass_model
from eigenupdate.solve.eigen import EigenSolution, solve_elastic
from eigenupdate.solve.jacobian import Linearisation, linearise, solve_configurations
from eigenupdate.solve.response import receptance
from eigenupdate.solve.sweep import MassSweep, mass_sweep
from eigenupdate.workflow import (
    check_study,
    compare_frf,
    extract_study,
    simulate_study,
    simulate_study_frfs,
    study_frequencies,
    update_study,
)

__all__ = [
    # errors and warnings
    "EigenupdateWarning", "InputError", "NotConvergedError", "NumericalError",
    "RepeatedEigenvalueError", "SingularMatrixError",
    # model
    "Addition", "Configuration", "Coordinate", "CoordinateTable", "Mass", "ParametricModel",
    "Parameter", "Spring", "beam_model", "mass_at", "matrix_model", "spring_mass_model",
    # solve
    "EigenSolution", "Linearisation", "MassSweep", "linearise", "mass_sweep", "receptance",
    "solve_configurations", "solve_elastic",
    # identify
    "ESTIMATORS", "OPTIMIZERS", "EstimatorWeights", "IdentifiabilityReport", "Iterate",
    "STATUS_MESSAGES", "Step", "UpdateResult", "check", "estimator_weights", "identifiability",
    "update",
    # measure
    "ExtractedMode", "FRF", "ModalFit", "NoResonance", "dobson_fit", "dobson_fit_modes",
    "extract_configuration", "rational_fraction_fit", "simulate_measurements", "synthetic_frfs",
    "to_receptance",
    # io
    "Measurement", "Mode", "Study", "load_study", "read_frf_csv", "read_frf_files",
    "read_frfs", "read_matrix_model", "read_measurements", "read_modes", "write_frf_csv",
    "write_frfs", "write_measurements", "write_modes",
    # the commands as functions
    "check_study", "compare_frf", "extract_study", "simulate_study", "simulate_study_frfs",
    "study_frequencies", "update_study",
]
__version__ = "0.1.0"
