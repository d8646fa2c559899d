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
from eigenupdate.io.inputs import require_regular
from eigenupdate.io.measurements import read_measurements
from eigenupdate.io.study_models import (
    _beam,
    _matrices,
    _model_files,
    _nastran,
    _spring_mass,
)
from eigenupdate.io.study_table import TableReader
from eigenupdate.measure.measurement import Measurement
from eigenupdate.model.configurations import BASE, Addition, Configuration
from eigenupdate.model.parametric import ParametricModel

MODEL_TYPES = ("spring-mass", "beam", "matrices", "nastran")


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
        """Files a run reads: the study, its model files (a deck's INCLUDEd files too)
        and, if asked, its measurement CSV and FRF files (a run must not write over any
        of them)."""
        out = [self.path, *self.model_files,
               *(self.nastran.included if self.nastran is not None else [])]
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


def load_study(path: str | Path, *, require_model: bool = True) -> Study:
    """Parse and validate a study file.

    With ``require_model=False`` (``eigenupdate extract``) the [model] table may be
    missing: ``model`` is then None and the configurations are the perturbations (or,
    without any, the keys of [measurement.frf]).
    """
    path = Path(path)
    src = str(path)
    require_regular(path, "study file")
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
    top = TableReader(data, "", src)
    title = top.get("title", "str", path.stem)
    if "model" not in data and not require_model:
        return _study_without_model(path, top, title)
    if "model" not in data:
        raise InputError("[model] is required (only 'extract' runs without a model)",
                         source=src, field="model")
    m = TableReader(top.get("model", "table"), "model", src)
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
        _perturbation(TableReader(t, f"perturbation[{i + 1}]", src), nastran)
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

    up = TableReader(top.get("updating", "table", {}), "updating", src)
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
        design = _design(TableReader(top.get("design", "table"), "design", src), model, mtype,
                         modes, getattr(nastran, "modal", frozenset()))
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


def _measurement(top: TableReader, names: list[str] | None, path: Path
                 ) -> tuple[list[int], str | None, dict[str, list[Path]], dict[str, Any]]:
    """[measurement]: modes, frequencies, frf (by configuration), frf_options."""
    src = str(path)
    meas = TableReader(top.get("measurement", "table", {}), "measurement", src)
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
        for n in names:
            if config_name_problem(n):
                raise meas.error("frf", f"{n!r} {config_name_problem(n)}")
    frf = _frf_files(frf_table, names, path.parent, src)
    return modes, freq, frf, frf_options


def _study_without_model(path: Path, top: TableReader, title: str) -> Study:
    src = str(path)
    perts = [
        _perturbation(TableReader(t, f"perturbation[{i + 1}]", src))
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


def config_name_problem(name: str) -> str | None:
    """Why ``name`` cannot label a configuration's rows in a measurement CSV, or None.

    The CSV reader strips spaces, skips lines starting with '#' and splits lines at line
    breaks: such names were accepted here and written by ``simulate``, whose file then
    could not be read back ('base ' even read as the bare structure's second row)."""
    if not name:
        return "is empty"
    if name != name.strip():
        return "begins or ends with white space (the measurement CSV strips it)"
    if name.startswith("#"):
        return "begins with '#' (a comment line in the measurement CSV)"
    if not name.isprintable():
        return "holds a control or format character (a line break, tab, NUL, bidi mark)"
    return None


def _perturbation(r: TableReader, nastran=None) -> Configuration:
    adds = []
    if "add" in r.data and {"coordinate", "grid", "mass", "stiffness"} & set(r.data):
        raise r.error("add", "give either coordinate with mass/stiffness or add = [...], "
                             "not both")
    if "add" in r.data:
        for j, t in enumerate(r.get("add", "tables")):
            adds.append(_addition(TableReader(t, f"{r.where}.add[{j + 1}]", r.source),
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
    bad = config_name_problem(name)
    if bad:
        raise r.error("name", f"{name!r} {bad}")
    r.finish()
    return Configuration(name, tuple(adds))


def _addition(r: TableReader, finish: bool = True, nastran=None) -> Addition:
    if nastran is None:
        c = r.get("coordinate", "int")
    else:  # NASTRAN names a GRID and a component 1-6
        if "coordinate" in r.data:
            raise r.error("coordinate", "a NASTRAN model names grid = ... and component = 1-6")
        grid, component = r.get("grid", "int"), r.get("component", "int")
        try:
            c = nastran.grid_dof(grid, component)
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


def _design(r: TableReader, model: ParametricModel, model_type: str,
            study_modes: list[int], modal: frozenset = frozenset()) -> DesignSpec:
    """The [design] table of ``eigenupdate design`` (see :class:`DesignSpec`); ``modal``:
    a NASTRAN model's q-set coordinates (mode amplitudes, no place for a mass)."""
    coords = r.data.get("coordinates")
    if coords == "translational":
        r.used.add("coordinates")
        if model_type == "matrices":  # assembled matrices do not say which are rotations
            raise r.error("coordinates", "'translational' needs a model that says which "
                                         "coordinates are rotations; list the coordinates")
        coords = [c.number for c in model.coordinate_table.coordinates
                  if not c.rotation and c.number not in modal]
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
            if c in modal:
                raise r.error("coordinates", f"coordinate {c} is a q-set SPOINT (the amplitude "
                                             f"of a fixed-interface mode, QSET), not a point")

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
    for key, bad, need in (("min_shift_in_std", shift < 0, ">= 0"),
                           ("min_relative_gap", not 0 <= gap < 1, "from 0 to below 1"),
                           ("max_added_mass", limit is not None and limit <= 0, "> 0")):
        if bad:  # each named: max_added_mass = 0 was reported as min_shift_in_std
            raise r.error(key, f"must be {need}, got {r.data[key]!r}")
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
        min_relative_gap=gap, max_added_mass=limit, prior_draws=draws, max_exchange_risk=risk,
        # as the study names its own NASTRAN perturbations: grid-component
        labels=tuple((c, f"{c // 10}-{c % 10}") for c in coords) if model_type == "nastran"
        else ())
