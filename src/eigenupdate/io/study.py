"""Study files: one TOML file describes the model, the perturbed configurations, the
measurements and the updating options. Paths inside it are relative to the file.

Every error names the file and the field (``model.mass[2].value``); unknown keys are
errors too, so a misspelt option is not silently ignored.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from eigenupdate.errors import InputError
from eigenupdate.identify.updating import METHODS
from eigenupdate.io.matrix_market import matrix_model
from eigenupdate.io.measurements import Measurement, read_measurements
from eigenupdate.model.beam import beam_model, element_parameter_names
from eigenupdate.model.configurations import BASE, Addition, Configuration
from eigenupdate.model.parameters import Parameter
from eigenupdate.model.parametric import ParametricModel
from eigenupdate.model.spring_mass import Mass, Spring, spring_mass_model

MODEL_TYPES = ("spring-mass", "beam", "matrices")
LIMIT = 1e100
"""Numbers of a study are 0 or of magnitude 1/LIMIT to LIMIT: beyond, products of a few
of them (K = EI/L^3, lambda = k/m, (2 pi f)^2) leave the floating-point range."""


@dataclass
class Study:
    """A parsed study file."""

    path: Path
    title: str
    model_type: str
    model: ParametricModel
    configurations: list[Configuration]
    modes: list[int]
    frequencies: Path | None = None
    method: str = "least-squares"
    max_iterations: int = 20
    tolerance: float = 1e-8
    frf: dict[str, list[Path]] = field(default_factory=dict)
    frf_options: dict[str, Any] = field(default_factory=dict)
    model_files: list[Path] = field(default_factory=list)

    def inputs(self, *, measurements: bool = False, frf: bool = False) -> list[Path]:
        """Files a run reads: the study, its model files and, if asked, its measurement
        CSV and FRF files (a run must not write over any of them)."""
        out = [self.path, *self.model_files]
        if measurements and self.frequencies is not None:
            out.append(self.frequencies)
        if frf:
            out += [f for files in self.frf.values() for f in files]
        return out

    def measurements(self) -> dict[tuple[str, int], Measurement]:
        """Read the measurement CSV; configuration names must be those of the study."""
        if self.frequencies is None:
            raise InputError(
                "no measurement file given", source=str(self.path), field="measurement.frequencies"
            )
        return read_measurements(self.frequencies, [c.name for c in self.configurations])

    def require_modes(self) -> list[int]:
        if not self.modes:
            raise InputError("no modes given", source=str(self.path), field="measurement.modes")
        return self.modes


class _Reader:
    """Typed access to one TOML table, with the dotted field name for errors."""

    def __init__(self, data: dict, where: str, source: str):
        if not isinstance(data, dict):
            raise InputError("must be a table", source=source, field=where)
        self.data, self.where, self.source = data, where, source
        self.used: set[str] = set()

    def _f(self, key: str) -> str:
        return f"{self.where}.{key}" if self.where else key

    def error(self, key: str, msg: str) -> InputError:
        return InputError(msg, source=self.source, field=self._f(key))

    def get(
        self,
        key: str,
        kind: str,
        default: Any = ...,
    ) -> Any:
        self.used.add(key)
        if key not in self.data:
            if default is ...:
                raise self.error(key, "is required")
            return default
        v = self.data[key]
        check = {
            "str": lambda x: isinstance(x, str),
            "int": lambda x: isinstance(x, int) and not isinstance(x, bool) and abs(x) < 2**31,
            "float": lambda x: (
                isinstance(x, int | float) and not isinstance(x, bool)
                and (x == 0 or 1 / LIMIT <= abs(x) <= LIMIT)  # no float(x): ints may be huge
            ),
            "bool": lambda x: isinstance(x, bool),
            "list": lambda x: isinstance(x, list),
            "table": lambda x: isinstance(x, dict),
            "tables": lambda x: isinstance(x, list) and all(isinstance(i, dict) for i in x),
        }[kind]
        if not check(v):
            names = {
                "str": "a string",
                "int": "an integer of magnitude below 2**31",
                "float": f"0 or a number of magnitude {1 / LIMIT:g} to {LIMIT:g}",
                "bool": "true or false",
                "list": "a list",
                "table": "a table",
                "tables": "an array of tables",
            }
            raise self.error(key, f"must be {names[kind]}, got {v!r}")
        return float(v) if kind == "float" else v

    def floats(self, key: str, default: Any = ...) -> float | list[float] | None:
        """A number or a list of numbers."""
        v = (
            self.get(key, "list", default)
            if isinstance(self.data.get(key), list)
            else self.get(key, "float", default)
        )
        if isinstance(v, list):
            bad = [x for x in v if isinstance(x, bool) or not isinstance(x, int | float)
                   or (x != 0 and not 1 / LIMIT <= abs(x) <= LIMIT)]
            if bad or not v:
                raise self.error(key, "must be a number or a non-empty list of numbers (0 or "
                                      f"of magnitude {1 / LIMIT:g} to {LIMIT:g})")
            return [float(x) for x in v]
        return v

    def finish(self) -> None:
        extra = sorted(set(self.data) - self.used)
        if extra:
            raise InputError(
                f"unknown key(s) {extra}", source=self.source, field=self.where or None
            )


def load_study(path: str | Path) -> Study:
    """Parse and validate a study file."""
    path = Path(path)
    src = str(path)
    try:
        # utf-8-sig: editors on Windows start the file with a byte-order mark
        data = tomllib.loads(path.read_bytes().decode("utf-8-sig"))
    except OSError as exc:
        raise InputError(f"cannot read study file: {exc.strerror or exc}", source=src) from None
    except UnicodeDecodeError as exc:
        raise InputError(f"not UTF-8 text: {exc}", source=src) from None
    except ValueError as exc:  # TOMLDecodeError, or an integer of over 4300 digits
        raise InputError(f"invalid TOML: {exc}", source=src) from None
    top = _Reader(data, "", src)
    title = top.get("title", "str", path.stem)
    m = _Reader(top.get("model", "table"), "model", src)
    mtype = m.get("type", "str")
    builders = {"spring-mass": _spring_mass, "beam": _beam, "matrices": _matrices}
    if mtype not in builders:
        raise m.error("type", f"unknown model type {mtype!r}; expected one of {list(MODEL_TYPES)}")
    try:
        model = builders[mtype](m, path.parent)
    except InputError as exc:
        if exc.source:
            raise
        raise InputError(str(exc), source=src) from None
    m.finish()

    perts = [
        _perturbation(_Reader(t, f"perturbation[{i + 1}]", src))
        for i, t in enumerate(top.get("perturbation", "tables", []))
    ]
    configs = [Configuration(BASE), *perts]
    names = [c.name for c in configs]
    for i, c in enumerate(configs):
        if c.name in names[:i]:
            raise InputError(
                f"duplicate configuration name {c.name!r}",
                source=src,
                field=f"perturbation[{i}].name",
            )
        try:
            c.rows(model)
        except InputError as exc:
            raise InputError(str(exc), source=src, field=f"perturbation[{i}]") from None

    meas = _Reader(top.get("measurement", "table", {}), "measurement", src)
    modes = meas.get("modes", "list", [])
    if any(isinstance(k, bool) or not isinstance(k, int) or not 1 <= k < 2**31 for k in modes):
        raise meas.error("modes", f"must be elastic mode numbers >= 1, got {modes}")
    if len(set(modes)) != len(modes):
        raise meas.error("modes", f"repeated mode number in {modes}")
    freq = meas.get("frequencies", "str", None)
    frf_table = meas.get("frf", "table", {})
    frf_options = meas.get("frf_options", "table", {})
    meas.finish()
    frf = _frf_files(frf_table, names, path.parent, src)

    up = _Reader(top.get("updating", "table", {}), "updating", src)
    method = up.get("method", "str", "least-squares")
    if method not in METHODS:
        raise up.error("method", f"unknown method {method!r}; expected one of {list(METHODS)}")
    max_it = up.get("max_iterations", "int", 20)
    if not 1 <= max_it <= 10_000:
        raise up.error("max_iterations", f"must be 1 to 10000, got {max_it}")
    tol = up.get("tolerance", "float", 1e-8)
    if not 0 < tol <= 1e-2:  # the largest relative parameter change still called converged
        raise up.error("tolerance", f"{tol!r} must be > 0 and <= 0.01 (a relative step)")
    up.finish()
    top.finish()
    return Study(
        path=path,
        title=title,
        model_type=mtype,
        model=model,
        configurations=configs,
        modes=sorted(modes),
        frequencies=None if freq is None else path.parent / freq,
        method=method,
        max_iterations=max_it,
        tolerance=tol,
        frf=frf,
        frf_options=frf_options,
        model_files=_model_files(data["model"], path.parent) if mtype == "matrices" else [],
    )


def _model_files(table: dict, base: Path) -> list[Path]:
    """The Matrix Market files of a (validated) matrices model."""
    files = [table["K0"], table["M0"]]
    files += [t[k] for t in table.get("parameter", []) for k in ("K", "M") if k in t]
    return [base / f for f in files]


def _parameter(r: _Reader, seen: dict[str, str], default_value: Any = ...) -> Parameter:
    """A parameter table; ``seen`` maps the names read so far to where they were."""
    name = r.get("name", "str")
    if name in seen:
        raise r.error("name", f"duplicate parameter name {name!r} (also {seen[name]})")
    seen[name] = r._f("name")
    value = r.get("value", "float", default_value)
    std = r.get("std", "float", None)
    update = r.get("update", "bool", True)
    if value < 0:
        raise r.error("value", f"must be >= 0, got {value}")
    if std is not None and std <= 0:
        raise r.error("std", f"must be > 0, got {std}")
    return Parameter(name, value, std, update)


def _positive(r: _Reader, p: Parameter) -> None:
    if p.value <= 0:
        raise r.error("value", f"must be > 0, got {p.value}")


def _spring_mass(m: _Reader, _base: Path) -> ParametricModel:
    masses, springs, seen = [], [], {}
    for i, t in enumerate(m.get("mass", "tables", [])):
        r = _Reader(t, f"model.mass[{i + 1}]", m.source)
        p = _parameter(r, seen)
        _positive(r, p)
        c = r.get("coordinate", "int")
        if c < 1:
            raise r.error("coordinate", f"must be >= 1, got {c}")
        r.finish()
        masses.append(Mass(p, c))
    for i, t in enumerate(m.get("spring", "tables", [])):
        r = _Reader(t, f"model.spring[{i + 1}]", m.source)
        p = _parameter(r, seen)
        _positive(r, p)
        cs = r.get("coordinates", "list")
        if len(cs) != 2 or cs[0] == cs[1] or not all(
                isinstance(c, int) and not isinstance(c, bool) and c >= 0 for c in cs):
            raise r.error(
                "coordinates", f"must be two different coordinates (0 = ground), got {cs}"
            )
        stray = sorted(set(cs) - {0} - {x.coordinate for x in masses})
        if stray:
            raise r.error("coordinates", f"coordinate(s) {stray} have no mass (every "
                          "coordinate of a spring-mass model needs one)")
        r.finish()
        springs.append(Spring(p, (cs[0], cs[1])))
    if not masses:
        raise m.error("mass", "a spring-mass model needs at least one [[model.mass]]")
    if not springs:  # K = 0: every mode is a rigid-body mode at 0 Hz
        raise m.error("spring", "a spring-mass model needs at least one [[model.spring]]")
    # coordinates are 1..n with a mass at each: n is the number of distinct coordinates,
    # so a typo (coordinate = 100000) is found without building anything of its size
    n = len({x.coordinate for x in masses})
    for i, x in enumerate(masses):
        if x.coordinate > n:
            raise InputError(
                f"{x.coordinate} is beyond the {n} coordinates of this model (coordinates are "
                f"1..{n}, each with a mass)", source=m.source,
                field=f"model.mass[{i + 1}].coordinate")
    return spring_mass_model(masses, springs, n)


def _beam(m: _Reader, _base: Path) -> ParametricModel:
    nodes = m.floats("nodes")
    if not isinstance(nodes, list):
        raise m.error("nodes", "must be a list of node positions (m)")
    pms = []
    seen = {name: "an element parameter of the beam"
            for names in element_parameter_names(len(nodes) - 1) for name in names}
    for i, t in enumerate(m.get("point_mass", "tables", [])):
        r = _Reader(t, f"model.point_mass[{i + 1}]", m.source)
        p = _parameter(r, seen)
        pms.append((p, r.get("coordinate", "int")))
        r.finish()
    restrained = m.get("restrained", "list", [])
    if not all(isinstance(c, int) and not isinstance(c, bool) for c in restrained):
        raise m.error("restrained", f"must be a list of coordinates, got {restrained}")
    return beam_model(
        nodes,
        m.floats("EI"),
        m.floats("mass_per_length"),
        EI_std=m.floats("EI_std", None),
        mass_per_length_std=m.floats("mass_per_length_std", None),
        point_masses=pms,
        restrained=restrained,
        update_EI=m.get("update_EI", "bool", True),
        update_mass_per_length=m.get("update_mass_per_length", "bool", True),
    )


def _matrices(m: _Reader, base: Path) -> ParametricModel:
    k0 = base / m.get("K0", "str")
    m0 = base / m.get("M0", "str")
    params, seen = [], {}
    for i, t in enumerate(m.get("parameter", "tables")):
        r = _Reader(t, f"model.parameter[{i + 1}]", m.source)
        p = _parameter(r, seen)
        kf, mf = r.get("K", "str", None), r.get("M", "str", None)
        if kf is None and mf is None:
            raise r.error("K", "a parameter needs a K and/or an M file")
        r.finish()
        params.append((p, None if kf is None else base / kf, None if mf is None else base / mf))
    return matrix_model(k0, m0, params)


def _perturbation(r: _Reader) -> Configuration:
    adds = []
    if "add" in r.data and {"coordinate", "mass", "stiffness"} & set(r.data):
        raise r.error("add", "give either coordinate with mass/stiffness or add = [...], "
                             "not both")
    if "add" in r.data:
        for j, t in enumerate(r.get("add", "tables")):
            adds.append(_addition(_Reader(t, f"{r.where}.add[{j + 1}]", r.source)))
    if "coordinate" in r.data:
        adds.append(_addition(r, finish=False))
    if not adds:
        raise r.error("coordinate", "a perturbation needs a coordinate (or add = [...])")
    a0 = adds[0]
    default = (
        f"{a0.mass:g} kg at {a0.coordinate}"
        if a0.mass
        else f"{a0.stiffness:g} N/m at {a0.coordinate}"
    )
    name = r.get("name", "str", default if len(adds) == 1 else ...)
    if name == BASE:
        raise r.error("name", f"{BASE!r} is the bare structure; choose another name")
    r.finish()
    return Configuration(name, tuple(adds))


def _addition(r: _Reader, finish: bool = True) -> Addition:
    c = r.get("coordinate", "int")
    mass = r.get("mass", "float", 0.0)
    k = r.get("stiffness", "float", 0.0)
    if mass < 0 or k < 0 or (mass == 0 and k == 0):
        raise r.error(
            "mass", f"needs mass > 0 and/or stiffness > 0, got mass={mass}, stiffness={k}"
        )
    if finish:
        r.finish()
    return Addition(c, mass=mass, stiffness=k)


def _frf_files(table: dict, names: list[str], base: Path, src: str) -> dict[str, list[Path]]:
    out = {}
    for key, v in table.items():
        if key not in names:
            raise InputError(
                f"configuration {key!r} is not in the study",
                source=src,
                field=f"measurement.frf.{key}",
            )
        files = [v] if isinstance(v, str) else v
        if not isinstance(files, list) or not files or not all(isinstance(f, str) for f in files):
            raise InputError(
                "must be a file path or a list of paths", source=src, field=f"measurement.frf.{key}"
            )
        out[key] = [base / f for f in files]
    return out
