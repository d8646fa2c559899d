"""The result of :func:`eigenupdate.identify.updating.update`: :class:`UpdateResult` (in
the shape of SciPy's ``OptimizeResult``) and its history of :class:`Iterate` records, with
their JSON document (schema ``eigenupdate.update/2``) both ways."""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields
from typing import ClassVar

import numpy as np

from eigenupdate.identify.identifiability import IdentifiabilityReport
from eigenupdate.identify.optimizers import Step
from eigenupdate.model.parametric import ParametricModel
from eigenupdate.schema import Reader, reader

__all__ = ["Iterate", "UpdateResult"]


@dataclass(frozen=True)
class Iterate:
    """One entry of the history: the model after ``iteration`` iterations.

    ``parameters`` holds every parameter (updated and fixed) by name; ``objective`` is
    the weighted sum of squares (plus the prior term); ``step`` the fraction of the
    Gauss-Newton step taken; ``kind`` how it was taken.
    """

    iteration: int
    parameters: dict[str, float]
    objective: float
    step: float
    kind: Step

    def to_dict(self) -> dict:
        return {"iteration": self.iteration, "parameters": self.parameters,
                "objective": self.objective, "step": self.step, "note": self.kind.value}

    @classmethod
    def from_dict(cls, r: Reader) -> Iterate:
        note = r.str("note")
        kinds = {k.value: k for k in Step}
        if note not in kinds:
            raise r.fail("note", f"{note!r} is not one of {sorted(kinds)}")
        return cls(r.int("iteration"), r.mapping("parameters", lambda p, k: p.number(k)),
                   r.number("objective", minimum=0.0), r.number("step", minimum=0.0),
                   kinds[note])


@dataclass(frozen=True)
class UpdateResult:
    """Outcome of :func:`update`, with the attributes and mapping behaviour of SciPy's
    ``OptimizeResult`` (``res.x`` and ``res["x"]``, ``res.keys()``).

    Attributes
    ----------
    x : final physical values of the updated parameters, in the order of ``names``.
    names : names of the updated parameters.
    success : True if the iteration converged.
    status : integer code, see :data:`STATUS_MESSAGES`.
    message : what happened, with the numbers of the convergence test.
    nit : iterations taken; ``nfev``: model linearisations (eigen-solutions + J).
    cost : half the final objective, ``0.5 * fun @ fun`` as ``scipy.optimize.least_squares``.
    fun : the residual vector at the solution: weighted eigenvalue residuals (model -
        measured) of the equations, then the prior rows (normalised parameters).
    jac : d lambda / d s at the solution, physical units (equations x updated parameters).
    cov : posterior covariance of ``x`` (physical units), None where undefined.
    std : posterior standard deviation of each updated parameter by name, None where
        undefined (rank-deficient A; no residual degrees of freedom).
    method : the estimator.
    parameters : final value of every parameter (updated and fixed), by name.
    history : one :class:`Iterate` per iterate; ``history[0]`` is the initial model.
    rows : (configuration, mode) of each equation.
    measured_hz, initial_hz, updated_hz : frequencies of each row.
    identifiability : the SVD report at the solution (what ``check`` computes there).
    model : the updated model (None for a result read back without the study's model).
    solver : sparse models: what the perturbed-configuration fast path did over all
        linearisations (:meth:`eigenupdate.solve.perturbed.CertificateReport.as_dict`
        plus ``linearisations``); None on the dense path.
    optimizer : ``trust-region`` or ``gauss-newton``.
    pairing : equations, clusters and re-pairings (:meth:`Pairing.to_dict`).
    units : the stated unit of each parameter that has one, by name
        (:attr:`~eigenupdate.model.parameters.Parameter.unit`).
    perturbations : each configuration's additions, by name, as [coordinate, mass,
        stiffness] lists (so that a saved result can be matched to its study).
    """

    SCHEMA: ClassVar[str] = "eigenupdate.update/2"

    x: np.ndarray
    names: list[str]
    success: bool
    status: int
    message: str
    nit: int
    nfev: int
    cost: float
    fun: np.ndarray = field(repr=False)
    jac: np.ndarray = field(repr=False)
    cov: np.ndarray | None = field(repr=False)
    std: dict[str, float | None]
    method: str
    parameters: dict[str, float]
    history: tuple[Iterate, ...] = field(repr=False)
    rows: list[tuple[str, int]] = field(repr=False)
    measured_hz: np.ndarray = field(repr=False)
    initial_hz: np.ndarray = field(repr=False)
    updated_hz: np.ndarray = field(repr=False)
    identifiability: IdentifiabilityReport = field(repr=False)
    model: ParametricModel | None = field(repr=False)
    solver: dict | None = field(default=None, repr=False)
    optimizer: str = "trust-region"
    pairing: dict | None = field(default=None, repr=False)
    units: dict[str, str] = field(default_factory=dict, repr=False)
    perturbations: dict[str, list] = field(default_factory=dict, repr=False)

    def __getitem__(self, key: str):
        if key not in self.keys():
            raise KeyError(key)
        return getattr(self, key)

    def __contains__(self, key: object) -> bool:
        return key in self.keys()

    def keys(self) -> list[str]:
        """The attribute names, as ``OptimizeResult.keys()``."""
        return [f.name for f in fields(self)]

    def to_dict(self) -> dict:
        """JSON-ready document (``eigenupdate update --json`` and ``--save``); read back
        by :meth:`from_dict`."""
        return {
            "schema": self.SCHEMA,
            "method": self.method,
            "optimizer": self.optimizer,
            "success": self.success,
            "status": self.status,
            "message": self.message,
            "nit": self.nit,
            "nfev": self.nfev,
            "cost": self.cost,
            "names": self.names,
            "x": self.x.tolist(),
            "fun": self.fun.tolist(),
            "jac": self.jac.tolist(),
            "cov": None if self.cov is None else self.cov.tolist(),
            "std": self.std,
            "parameters": self.parameters,
            "history": [h.to_dict() for h in self.history],
            "frequencies": [
                {"configuration": c, "mode": k, "measured_hz": float(m), "initial_hz": float(i),
                 "updated_hz": float(u)}
                for (c, k), m, i, u in zip(self.rows, self.measured_hz, self.initial_hz,
                                           self.updated_hz, strict=True)
            ],
            "identifiability": self.identifiability.to_dict(),
            "solver": self.solver,
            "pairing": self.pairing,
            "units": self.units,
            "perturbations": self.perturbations,
        }

    @classmethod
    def from_dict(cls, doc: dict, source: str | None = None,
                  model: ParametricModel | None = None) -> UpdateResult:
        """The result :meth:`to_dict` wrote; with the study's ``model``, checked against
        it (same parameters, physical values) and ``model`` set to the updated one.

        Raises InputError naming ``source`` and the field for anything else.
        """
        r = reader(doc, cls.SCHEMA, source)
        names = [str(n) for n in r.raw("names", list)]
        values = r.mapping("parameters", lambda p, k: p.number(k))
        if model is not None:
            values = _checked_values(values, model, r)
        x = r.array("x")
        if x.size != len(names) or set(names) - set(values) or any(
                values[n] != v for n, v in zip(names, x.tolist(), strict=True)):
            raise r.fail("x", "must be the values of 'names' in 'parameters'")
        std = r.mapping("std", lambda p, k: p.number(k, optional=True, minimum=0.0))
        if set(std) != set(names):
            raise r.fail("std", "must give one value (or null) per name in 'names'")
        freq = r.items("frequencies")
        rows = [(f.str("configuration"), f.int("mode")) for f in freq]
        hz = np.array([[f.number(k, minimum=0.0) for k in ("measured_hz", "initial_hz",
                                                            "updated_hz")]
                       for f in freq]).reshape(len(freq), 3)
        jac = r.array("jac", 2)
        cov = r.array("cov", 2, optional=True)
        if jac.size and jac.shape[1] != len(names) or cov is not None and cov.shape != (
                len(names), len(names)):
            raise r.fail("cov" if cov is not None and jac.shape[1:] == (len(names),)
                         else "jac", "does not match the number of names")
        history = tuple(Iterate.from_dict(h) for h in r.items("history"))
        if model is not None and history:
            _check_start(history[0].parameters, model, r)
        return cls(
            x=x, names=names, success=r.bool("success"), status=r.int("status"),
            message=r.str("message"), nit=r.int("nit"), nfev=r.int("nfev"),
            cost=r.number("cost", minimum=0.0), fun=r.array("fun"), jac=jac, cov=cov,
            std=std, method=r.str("method"), parameters=values, history=history, rows=rows,
            measured_hz=hz[:, 0], initial_hz=hz[:, 1], updated_hz=hz[:, 2],
            identifiability=IdentifiabilityReport.from_dict(
                r.raw("identifiability", dict), source),
            model=None if model is None else model.with_values(values),
            solver=r.raw("solver", dict, optional=True), optimizer=r.str("optimizer"),
            pairing=r.raw("pairing", dict, optional=True),
            units={str(k): str(v) for k, v in (r.raw("units", dict, optional=True)
                                               or {}).items()},
            perturbations=_perturbations(r))


def _perturbations(r: Reader) -> dict[str, list]:
    """The ``perturbations`` document (optional: results written before it have none)."""
    doc = r.raw("perturbations", dict, optional=True) or {}
    out = {}
    for name, adds in doc.items():
        if not isinstance(adds, list) or not all(
                isinstance(a, list) and len(a) == 3 and all(
                    isinstance(x, int | float) and not isinstance(x, bool) for x in a)
                for a in adds):
            raise r.fail(f"perturbations.{name}", "must be a list of [coordinate, mass, "
                                                  "stiffness] lists")
        out[str(name)] = [[int(a[0]), float(a[1]), float(a[2])] for a in adds]
    return out


def _check_start(start: dict[str, float], model: ParametricModel, r: Reader) -> None:
    """The saved update started from the study's model: a result of an earlier version
    of the study (another initial value) was reported beside the edited study's initial
    values, its change % against values it never started from."""
    for p in model.parameters:
        v = start.get(p.name)
        if v is None or not math.isclose(v, p.value, rel_tol=1e-12, abs_tol=0.0):
            raise r.fail("history[1].parameters",
                         f"the saved update started from {p.name} = {v!r}, the study's model "
                         f"has {p.value!r}: a result of another version of the study; "
                         f"update again")


def _checked_values(values: dict[str, float], model: ParametricModel, r: Reader
                    ) -> dict[str, float]:
    """Every parameter of ``model`` in ``values``, none else, each physical."""
    unknown = set(values) - set(model.names)
    if unknown:
        raise r.fail("parameters", f"{sorted(unknown)} are not in the study's model")
    missing = [n for n in model.names if n not in values]
    if missing:
        raise r.fail("parameters", f"no value for {missing} (a result of another study?)")
    for p in model.parameters:
        v = values[p.name]
        if v < 0 or (v == 0 and p.value > 0):
            raise r.fail(f"parameters.{p.name}",
                         f"{v!r} is not a physical value (initial {p.value:g})")
    return {n: values[n] for n in model.names}
