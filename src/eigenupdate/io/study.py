"""Study files: one TOML file describes the model, the perturbed configurations, the
measurements and the updating options. Paths inside it are relative to the file.

Every error names the file and the field (``model.mass[2].value``); unknown keys are
errors too, so a misspelt option is not silently ignored.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from eigenupdate.budget import require_nesting
from eigenupdate.choices import ESTIMATORS, FRF_KINDS, OPTIMIZERS
from eigenupdate.design.spec import CRITERIA, DesignSpec
from eigenupdate.errors import InputError
from eigenupdate.io.matrix_market import read_matrix_model
from eigenupdate.io.measurements import read_measurements
from eigenupdate.measure.measurement import Measurement
from eigenupdate.model.beam import beam_model, element_parameter_names
from eigenupdate.model.configurations import BASE, Addition, Configuration
from eigenupdate.model.parameters import Parameter
from eigenupdate.model.parametric import ParametricModel
from eigenupdate.model.spring_mass import Mass, Spring, spring_mass_model

MODEL_TYPES = ("spring-mass", "beam", "matrices", "nastran")
LIMIT = 1e100
"""Numbers of a study are 0 or of magnitude 1/LIMIT to LIMIT: beyond, products of a few
of them (K = EI/L^3, lambda = k/m, (2 pi f)^2) leave the floating-point range."""


@dataclass
class Study:
    """A parsed study file."""

    path: Path
    title: str
    model_type: str
    model: ParametricModel | None  # None only from load_study(require_model=False)
    configurations: list[Configuration]
    modes: list[int]
    frequencies: Path | None = None
    method: str = "least-squares"
    optimizer: str = "trust-region"
    max_iterations: int = 20
    tolerance: float = 1e-8
    frf: dict[str, list[Path]] = field(default_factory=dict)
    bands_hz: dict[str, list[list[float]]] = field(default_factory=dict)
    """[measurement.frf_options] bands_hz by configuration (validated; empty: automatic)."""
    exclude_below_hz: float | None = None
    frf_kinds: dict[Path, str] = field(default_factory=dict)
    """[measurement.frf_options] kind by FRF file, for files whose header does not say."""
    design: DesignSpec | None = None
    nastran: Any = None  # io.nastran.NastranModel of a type = "nastran" model (write-back)
    model_files: list[Path] = field(default_factory=list)

    def configuration(self, name: str | None = None) -> Configuration:
        """The configuration called ``name``; the bare structure if None."""
        if name is None:
            return self.configurations[0]
        for c in self.configurations:
            if c.name == name:
                return c
        raise InputError(f"no configuration {name!r} (have "
                         f"{[c.name for c in self.configurations]})", source=str(self.path))

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


def load_study(path: str | Path, *, require_model: bool = True) -> Study:
    """Parse and validate a study file.

    With ``require_model=False`` (``eigenupdate extract``) the [model] table may be
    missing: ``model`` is then None and the configurations are the perturbations (or,
    without any, the keys of [measurement.frf]).
    """
    path = Path(path)
    src = str(path)
    try:
        # utf-8-sig: editors on Windows start the file with a byte-order mark
        text = path.read_bytes().decode("utf-8-sig")
        require_nesting(text, src)  # before the recursive parser meets it
        data = tomllib.loads(text)
    except InputError:  # too deeply nested
        raise
    except OSError as exc:
        raise InputError(f"cannot read study file: {exc.strerror or exc}", source=src) from None
    except UnicodeDecodeError as exc:
        raise InputError(f"not UTF-8 text: {exc}", source=src) from None
    except ValueError as exc:  # TOMLDecodeError, or an integer of over 4300 digits
        raise InputError(f"invalid TOML: {exc}", source=src) from None
    top = _Reader(data, "", src)
    title = top.get("title", "str", path.stem)
    if "model" not in data and not require_model:
        return _study_without_model(path, top, title)
    if "model" not in data:
        raise InputError("[model] is required (only 'extract' runs without a model)",
                         source=src, field="model")
    m = _Reader(top.get("model", "table"), "model", src)
    mtype = m.get("type", "str")
    builders = {"spring-mass": _spring_mass, "beam": _beam, "matrices": _matrices,
                "nastran": _nastran}
    if mtype not in builders:
        raise m.error("type", f"unknown model type {mtype!r}; expected one of {list(MODEL_TYPES)}")
    try:
        model = builders[mtype](m, path.parent)
    except InputError as exc:
        if exc.source:
            raise
        raise InputError(str(exc), source=src) from None
    m.finish()
    nastran, model = (model, model.model) if mtype == "nastran" else (None, model)

    perts = [
        _perturbation(_Reader(t, f"perturbation[{i + 1}]", src), nastran)
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

    modes, freq, frf, frf_options = _measurement(top, names, path)

    up = _Reader(top.get("updating", "table", {}), "updating", src)
    method = up.get("method", "str", "least-squares")
    if method not in ESTIMATORS:
        raise up.error("method", f"unknown method {method!r}; expected one of {list(ESTIMATORS)}")
    optimizer = up.get("optimizer", "str", "trust-region")
    if optimizer not in OPTIMIZERS:
        raise up.error("optimizer", f"unknown optimizer {optimizer!r}; expected one of "
                                    f"{list(OPTIMIZERS)}")
    max_it = up.get("max_iterations", "int", 20)
    if not 1 <= max_it <= 10_000:
        raise up.error("max_iterations", f"must be 1 to 10000, got {max_it}")
    tol = up.get("tolerance", "float", 1e-8)
    if not 0 < tol <= 1e-2:  # the largest relative parameter change still called converged
        raise up.error("tolerance", f"{tol!r} must be > 0 and <= 0.01 (a relative step)")
    up.finish()
    design = None
    if "design" in top.data:
        design = _design(_Reader(top.get("design", "table"), "design", src), model, mtype, modes)
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
        optimizer=optimizer,
        max_iterations=max_it,
        tolerance=tol,
        frf=frf,
        **_frf_settings(frf_options, names, frf, path.parent, src),
        design=design,
        nastran=nastran,
        model_files=_model_files(data["model"], path.parent, mtype),
    )


def _frf_settings(options: dict, names: list[str], frf: dict[str, list[Path]], base: Path,
                  src: str) -> dict[str, Any]:
    """[measurement.frf_options]: bands_hz (list, or table by configuration), exclude_below_hz,
    kind (one FRF kind for files whose header does not say, or a table by file name)."""
    opts = dict(options)
    field_ = "measurement.frf_options"
    bands = opts.pop("bands_hz", None)
    low = opts.pop("exclude_below_hz", None)
    kind = opts.pop("kind", None)
    if opts:
        raise InputError(f"unknown key(s) {sorted(opts)}", source=src, field=field_)
    if bands is None:
        table = {}
    elif isinstance(bands, list):
        table = {n: bands for n in names}
    elif isinstance(bands, dict):
        unknown = set(bands) - set(names)
        if unknown:
            raise InputError(f"unknown configuration(s) {sorted(unknown)}", source=src,
                             field=f"{field_}.bands_hz")
        table = bands
    else:
        raise InputError("must be a list of [low, high] pairs or a table of them", source=src,
                         field=f"{field_}.bands_hz")
    for name, b in table.items():
        ok = isinstance(b, list) and all(
            isinstance(x, list) and len(x) == 2 and all(isinstance(v, int | float) for v in x)
            and 0 <= x[0] < x[1] for x in b)
        if not ok:
            raise InputError(f"{name!r}: bands must be [low, high] pairs in Hz, 0 <= low < high",
                             source=src, field=f"{field_}.bands_hz")
    if low is not None and not (isinstance(low, int | float) and low >= 0):
        raise InputError("must be a number >= 0", source=src, field=f"{field_}.exclude_below_hz")
    files = {p for ps in frf.values() for p in ps}
    if kind is None:
        kinds = {}
    elif isinstance(kind, str):
        kinds = {p: kind for p in files}
    elif isinstance(kind, dict):
        kinds = {base / k: v for k, v in kind.items()}
    else:
        raise InputError("must be an FRF kind or a table of them by file", source=src,
                         field=f"{field_}.kind")
    for p, k in kinds.items():
        if k not in FRF_KINDS or p not in files:
            what = f"{k!r} is not one of {list(FRF_KINDS)}" if k not in FRF_KINDS else \
                f"{p.relative_to(base)} is not a file of [measurement.frf]"
            raise InputError(what, source=src, field=f"{field_}.kind")
    return {"bands_hz": table, "exclude_below_hz": low, "frf_kinds": kinds}


def _measurement(top: _Reader, names: list[str] | None, path: Path
                 ) -> tuple[list[int], str | None, dict[str, list[Path]], dict[str, Any]]:
    """[measurement]: modes, frequencies, frf (by configuration), frf_options."""
    src = str(path)
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
    if names is None:  # no model and no perturbations: the FRF table names them
        names = sorted(frf_table, key=lambda n: n != BASE)
    frf = _frf_files(frf_table, names, path.parent, src)
    return modes, freq, frf, frf_options


def _study_without_model(path: Path, top: _Reader, title: str) -> Study:
    src = str(path)
    perts = [
        _perturbation(_Reader(t, f"perturbation[{i + 1}]", src))
        for i, t in enumerate(top.get("perturbation", "tables", []))
    ]
    names = [BASE, *[c.name for c in perts]] if perts else None
    modes, freq, frf, frf_options = _measurement(top, names, path)
    if not frf:
        raise InputError("a study without [model] needs [measurement.frf] files",
                         source=src, field="measurement.frf")
    configs = ([Configuration(BASE), *perts] if perts
               else [Configuration(n) for n in sorted(frf, key=lambda n: n != BASE)])
    top.used.add("updating")
    top.finish()
    return Study(path=path, title=title, model_type="", model=None, configurations=configs,
                 modes=sorted(modes), frequencies=None if freq is None else path.parent / freq,
                 frf=frf, **_frf_settings(frf_options, [c.name for c in configs], frf,
                                          path.parent, src))


def _model_files(table: dict, base: Path, model_type: str) -> list[Path]:
    """The files of a (validated) matrices or nastran model."""
    if model_type == "nastran":
        return [base / table["bdf"]]
    if model_type != "matrices":
        return []
    files = [table["K0"], table["M0"]]
    files += [t[k] for key in ("parameter", "term") for t in table.get(key, [])
              for k in ("K", "M") if k in t]
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
        if kf is None and mf is None and not any(
                isinstance(x, dict) and p.name in (x.get("powers") or {})
                for x in m.data.get("term", [])):
            raise r.error("K", "a parameter needs a K and/or an M file, or a "
                               "[[model.term]] whose powers name it")
        r.finish()
        params.append((p, None if kf is None else base / kf, None if mf is None else base / mf))
    index = {p.name: j for j, (p, _, _) in enumerate(params)}
    terms = []
    for i, t in enumerate(m.get("term", "tables", [])):
        r = _Reader(t, f"model.term[{i + 1}]", m.source)
        kf, mf = r.get("K", "str", None), r.get("M", "str", None)
        if kf is None and mf is None:
            raise r.error("K", "a term needs a K and/or an M file")
        powers = r.get("powers", "table")
        if not powers:
            raise r.error("powers", "must name at least one parameter, e.g. { t = 3 }")
        pw = []
        for name, a in powers.items():
            if name not in index:
                raise r.error("powers", f"unknown parameter {name!r} (parameters: "
                                        f"{sorted(index)})")
            if isinstance(a, bool) or not isinstance(a, int | float) or a == 0 \
                    or not abs(a) <= 100:
                raise r.error(f"powers.{name}", f"must be a non-zero number of magnitude up "
                                                f"to 100, got {a!r}")
            pw.append((index[name], float(a)))
        coef = r.get("coefficient", "float", 1.0)
        r.finish()
        terms.append((tuple(pw), coef, None if kf is None else base / kf,
                      None if mf is None else base / mf))
    return read_matrix_model(k0, m0, params, terms)


def _nastran(m: _Reader, base: Path):
    """[model] type = "nastran": a BDF and parameters named by card, id and field."""
    from eigenupdate.io.nastran import CardField, read_nastran

    bdf = base / m.get("bdf", "str")
    params, seen = [], {}
    for i, t in enumerate(m.get("parameter", "tables", [])):
        r = _Reader(t, f"model.parameter[{i + 1}]", m.source)
        if "value" in t:
            raise r.error("value", "the value is the card's; edit the BDF to change it")
        p = _parameter(r, seen, default_value=0.0)
        where = CardField(r.get("card", "str").upper(), r.get("id", "int"),
                          r.get("field", "str").upper())
        r.finish()
        params.append((p, where))
    return read_nastran(bdf, params)


def _perturbation(r: _Reader, nastran=None) -> Configuration:
    adds = []
    if "add" in r.data and {"coordinate", "grid", "mass", "stiffness"} & set(r.data):
        raise r.error("add", "give either coordinate with mass/stiffness or add = [...], "
                             "not both")
    if "add" in r.data:
        for j, t in enumerate(r.get("add", "tables")):
            adds.append(_addition(_Reader(t, f"{r.where}.add[{j + 1}]", r.source),
                                  nastran=nastran))
    if "coordinate" in r.data or "grid" in r.data:
        adds.append(_addition(r, finish=False, nastran=nastran))
    if not adds:
        raise r.error("coordinate", "a perturbation needs a coordinate (or add = [...])")
    a0 = adds[0]
    at = a0.coordinate if nastran is None else f"{a0.coordinate // 10}-{a0.coordinate % 10}"
    default = f"{a0.mass:g} kg at {at}" if a0.mass else f"{a0.stiffness:g} N/m at {at}"
    name = r.get("name", "str", default if len(adds) == 1 else ...)
    if name == BASE:
        raise r.error("name", f"{BASE!r} is the bare structure; choose another name")
    r.finish()
    return Configuration(name, tuple(adds))


def _addition(r: _Reader, finish: bool = True, nastran=None) -> Addition:
    if nastran is None:
        c = r.get("coordinate", "int")
    else:  # NASTRAN names a GRID and a component 1-6
        if "coordinate" in r.data:
            raise r.error("coordinate", "a NASTRAN model names grid = ... and component = 1-6")
        try:
            c = nastran.grid_dof(r.get("grid", "int"), r.get("component", "int"))
        except InputError as exc:
            raise r.error("grid", str(exc)) from None
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


def _design(r: _Reader, model: ParametricModel, model_type: str,
            study_modes: list[int]) -> DesignSpec:
    """The [design] table of ``eigenupdate design`` (see :class:`DesignSpec`)."""
    coords = r.data.get("coordinates")
    if coords == "translational":
        r.used.add("coordinates")
        if model_type == "matrices":  # assembled matrices do not say which are rotations
            raise r.error("coordinates", "'translational' needs a model that says which "
                                         "coordinates are rotations; list the coordinates")
        coords = [c.number for c in model.coordinate_table.coordinates if not c.rotation]
    else:
        coords = r.get("coordinates", "list")
        if not coords or not all(isinstance(c, int) and not isinstance(c, bool) for c in coords):
            raise r.error("coordinates", f"must be a list of coordinates or 'translational', "
                                         f"got {coords!r}")
        if len(set(coords)) != len(coords):
            raise r.error("coordinates", f"repeated coordinate in {coords}")
        for c in coords:
            try:
                model.index(c)
            except InputError as exc:
                raise r.error("coordinates", str(exc)) from None

    def positive_list(key: str, default: Any = ...) -> tuple[float, ...]:
        v = r.floats(key, default)
        v = [] if v is None else (v if isinstance(v, list) else [v])
        if any(x <= 0 or not math.isfinite(x) for x in v):
            raise r.error(key, f"must be finite numbers > 0, got {v}")
        return tuple(v)

    masses = positive_list("masses", None)
    springs = positive_list("stiffnesses", None)
    if not masses and not springs:
        raise r.error("masses", "is required (or stiffnesses = [...], N/m)")
    n_conf = r.get("configurations", "int")
    additions = r.get("additions", "int", 1)
    if n_conf < 1 or additions < 1:
        raise r.error("configurations", "configurations and additions must be >= 1")
    modes = r.get("modes", "list", None)
    fmax = r.get("max_frequency_hz", "float", None)
    if modes is not None and fmax is not None:
        raise r.error("modes", "give modes or max_frequency_hz, not both")
    if modes is None and fmax is None:
        modes = study_modes
        if not modes:
            raise r.error("modes", "is required (or max_frequency_hz, or measurement.modes)")
    if modes is not None:
        if not modes or any(isinstance(k, bool) or not isinstance(k, int) or k < 1 for k in modes):
            raise r.error("modes", f"must be elastic mode numbers >= 1, got {modes}")
        if len(set(modes)) != len(modes):
            raise r.error("modes", f"repeated mode number in {modes}")
        modes = tuple(sorted(modes))
    elif fmax <= 0:
        raise r.error("max_frequency_hz", f"must be > 0, got {fmax}")
    std_hz = positive_list("frequency_std_hz", None) or None
    rel = r.get("frequency_std_relative", "float", None)
    if (std_hz is None) == (rel is None):
        raise r.error("frequency_std_hz", "give frequency_std_hz (Hz, one value or one per mode) "
                                          "or frequency_std_relative, exactly one")
    if rel is not None and not 0 < rel < 1:
        raise r.error("frequency_std_relative", f"must be between 0 and 1, got {rel}")
    if std_hz is not None and len(std_hz) > 1 and (modes is None or len(std_hz) != len(modes)):
        raise r.error("frequency_std_hz", f"{len(std_hz)} values: give one, or one per mode of "
                                          f"design.modes")
    criterion = r.data.get("criterion", "A")
    r.used.add("criterion")
    if isinstance(criterion, list):
        updated = [model.names[j] for j in model.updated]
        bad = [c for c in criterion if c not in updated]
        if not criterion or bad:
            raise r.error("criterion", f"unknown or fixed parameter(s) {bad}; updated "
                                       f"parameters are {updated}")
        criterion = tuple(criterion)
    elif criterion not in CRITERIA:
        raise r.error("criterion", f"must be one of {list(CRITERIA)} or a list of parameter "
                                   f"names, got {criterion!r}")
    shift = r.get("min_shift_in_std", "float", 3.0)
    gap = r.get("min_relative_gap", "float", 0.02)
    limit = r.get("max_added_mass", "float", None)
    if shift < 0 or not 0 <= gap < 1 or (limit is not None and limit <= 0):
        raise r.error("min_shift_in_std", "min_shift_in_std >= 0, 0 <= min_relative_gap < 1 and "
                                          "max_added_mass > 0 are required")
    draws = r.get("prior_draws", "int", 64)
    if not 0 <= draws <= 10_000:
        raise r.error("prior_draws", f"must be from 0 to 10000, got {draws}")
    risk = r.get("max_exchange_risk", "float", 0.05)
    if not 0 <= risk <= 1:
        raise r.error("max_exchange_risk", f"must be between 0 and 1, got {risk}")
    r.finish()
    return DesignSpec(
        coordinates=tuple(coords), masses=masses, stiffnesses=springs, configurations=n_conf,
        additions=additions, modes=modes, max_frequency_hz=fmax, frequency_std_hz=std_hz,
        frequency_std_relative=rel, criterion=criterion, min_shift_in_std=shift,
        min_relative_gap=gap, max_added_mass=limit, prior_draws=draws, max_exchange_risk=risk)
