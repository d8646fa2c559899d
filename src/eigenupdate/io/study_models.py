"""The [model] table of a study: spring-mass, beam, matrices (Matrix Market) or
nastran (a BDF), with the parameters each names."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from eigenupdate.errors import InputError
from eigenupdate.io.matrix_market import read_matrix_model
from eigenupdate.io.study_table import TableReader
from eigenupdate.model.beam import beam_model, element_parameter_names
from eigenupdate.model.parameters import Parameter
from eigenupdate.model.parametric import ParametricModel
from eigenupdate.model.spring_mass import Mass, Spring, spring_mass_model


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


def _parameter(r: TableReader, seen: dict[str, str], default_value: Any = ...) -> Parameter:
    """A parameter table; ``seen`` maps the names read so far to where they were."""
    name = r.get("name", "str")
    if name in seen:
        raise r.error("name", f"duplicate parameter name {name!r} (also {seen[name]})")
    seen[name] = r._f("name")
    value = r.get("value", "float", default_value)
    std = r.get("std", "float", None)
    update = r.get("update", "bool", True)
    unit = r.get("unit", "str", "")
    if len(unit) > 40 or not unit.isprintable():
        raise r.error("unit", f"must be a short printable label such as \"N/m\", got {unit!r}")
    if value < 0:
        raise r.error("value", f"must be >= 0, got {value}")
    if std is not None and std <= 0:
        raise r.error("std", f"must be > 0, got {std}")
    return Parameter(name, value, std, update, unit.strip())


def _si(r: TableReader, p: Parameter, unit: str) -> None:
    """A unit label on a model whose values are SI must be the SI unit: ``unit = "g"`` on
    a 9.7 kg mass printed 9.7 g (labels are not converted)."""
    def norm(u: str) -> str:
        return u.translate(str.maketrans("\u00b2", "2", " *\u00b7^"))
    if p.unit and norm(p.unit) != norm(unit):
        raise r.error("unit", f"{p.unit!r} is not the unit of this value: the model's values "
                              f"are SI, {unit} here (a unit is a label, not converted); give "
                              f"the value in {unit} and unit = \"{unit}\" or no unit")


def _positive(r: TableReader, p: Parameter) -> None:
    if p.value <= 0:
        raise r.error("value", f"must be > 0, got {p.value}")


def _spring_mass(m: TableReader, _base: Path) -> ParametricModel:
    masses, springs, seen = [], [], {}
    for i, t in enumerate(m.get("mass", "tables", [])):
        r = TableReader(t, f"model.mass[{i + 1}]", m.source)
        p = _parameter(r, seen)
        _positive(r, p)
        _si(r, p, "kg")
        c = r.get("coordinate", "int")
        if c < 1:
            raise r.error("coordinate", f"must be >= 1, got {c}")
        r.finish()
        masses.append(Mass(p, c))
    for i, t in enumerate(m.get("spring", "tables", [])):
        r = TableReader(t, f"model.spring[{i + 1}]", m.source)
        p = _parameter(r, seen)
        _positive(r, p)
        _si(r, p, "N/m")
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


def _beam(m: TableReader, _base: Path) -> ParametricModel:
    nodes = m.floats("nodes")
    if not isinstance(nodes, list):
        raise m.error("nodes", "must be a list of node positions (m)")
    pms = []
    seen = {name: "an element parameter of the beam"
            for names in element_parameter_names(len(nodes) - 1) for name in names}
    for i, t in enumerate(m.get("point_mass", "tables", [])):
        r = TableReader(t, f"model.point_mass[{i + 1}]", m.source)
        p = _parameter(r, seen)
        pms.append((p, r.get("coordinate", "int")))
        if isinstance(pms[-1][1], int):  # odd: a translation; even: a rotary inertia
            _si(r, p, "kg" if pms[-1][1] % 2 else "kg m^2")
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


def _matrices(m: TableReader, base: Path) -> ParametricModel:
    k0 = base / m.get("K0", "str")
    m0 = base / m.get("M0", "str")
    params, seen = [], {}
    for i, t in enumerate(m.get("parameter", "tables")):
        r = TableReader(t, f"model.parameter[{i + 1}]", m.source)
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
        r = TableReader(t, f"model.term[{i + 1}]", m.source)
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


def _nastran(m: TableReader, base: Path):
    """[model] type = "nastran": a BDF and parameters named by card, id and field."""
    from eigenupdate.io.nastran import CardField, read_nastran

    bdf = base / m.get("bdf", "str")
    subcase = m.get("subcase", "int", None)
    params, seen = [], {}
    for i, t in enumerate(m.get("parameter", "tables", [])):
        r = TableReader(t, f"model.parameter[{i + 1}]", m.source)
        if "value" in t:
            raise r.error("value", "the value is the card's; edit the BDF to change it")
        p = _parameter(r, seen, default_value=0.0)
        where = CardField(r.get("card", "str").upper(), r.get("id", "int"),
                          r.get("field", "str").upper())
        r.finish()
        params.append((p, where))
    return read_nastran(bdf, params, subcase)
