"""The commands as library functions: each takes a loaded :class:`~eigenupdate.io.study.Study`
and returns a typed result, so a notebook does what ``eigenupdate <command>`` does.

>>> from eigenupdate.io.study import load_study
>>> study = load_study("examples/paper_fig2/study.toml")
>>> check_study(study).rank
10
>>> res = update_study(study)
>>> res.success, res.nit, round(res.parameters["k6"])
(True, 4, 500000)
"""

from __future__ import annotations

from eigenupdate.identify.identifiability import IdentifiabilityReport, check
from eigenupdate.identify.updating import UpdateResult, update
from eigenupdate.identify.weights import estimator_weights
from eigenupdate.io.study import Study


def _rows(study: Study) -> list[tuple[str, int]]:
    return [(c.name, k) for c in study.configurations for k in sorted(set(study.require_modes()))]


def check_study(study: Study, method: str | None = None) -> IdentifiabilityReport:
    """Identifiability of the study's plan as its estimator sees it (``eigenupdate check``).

    The equations are weighted by the measured std when the method is weighted and the
    study has a measurement file, else by 1 (a plan checked before the test); the Bayesian
    method adds its prior rows. ``method`` defaults to the study's.
    """
    method = method or study.method
    meas = study.measurements() if study.frequencies is not None else None
    w = estimator_weights(study.model, method, _rows(study), meas, str(study.frequencies))
    return check(study.model, study.configurations, study.require_modes(), weights=w.rows,
                 prior=w.prior)


def update_study(study: Study, method: str | None = None) -> UpdateResult:
    """The update with the study's measurements and settings (``eigenupdate update``)."""
    return update(
        study.model, study.configurations, study.require_modes(), study.measurements(),
        method=method or study.method, max_iterations=study.max_iterations,
        xtol=study.tolerance, source=str(study.frequencies),
    )
