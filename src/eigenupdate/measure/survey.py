"""Extraction of every configuration of a test, numbered against the model if there is one,
and the table a user reads (accepted, rejected, missing and unexpected modes).

:func:`extract_test` is the library function behind ``eigenupdate extract``: it takes
FRFs already read (io/), so a notebook user calls it the same way.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field, replace
from typing import ClassVar

from eigenupdate.measure.extraction import (
    ConfigurationExtraction,
    ExtractedMode,
    Rejected,
    extract_resonances,
    missing_used_modes,
)
from eigenupdate.measure.frf import FRF, dof_label
from eigenupdate.measure.modal_fit import ModalFit
from eigenupdate.measure.numbering import interlacing_bounds, number_resonances
from eigenupdate.model.configurations import BASE, Configuration
from eigenupdate.model.parametric import ParametricModel
from eigenupdate.schema import Reader, reader

__all__ = ["TestExtraction", "extract_test"]


@dataclass(frozen=True)
class TestExtraction:
    """Every configuration's extraction; ``numbered_by`` is "model" or "order";
    ``problems`` are one-line errors (a used mode not found, an ambiguous number);
    ``frfs`` identifies the FRFs of each configuration, in the order of every mode's
    ``fits`` (file name, points, :meth:`FRF.fingerprint`): a saved extraction is shown
    only over the FRFs it was fitted to."""

    __test__ = False  # not a pytest test class despite its name

    configurations: list[ConfigurationExtraction]
    numbered_by: str
    used_modes: list[int]
    problems: list[str]
    frfs: dict[str, list[dict[str, str]]] = field(default_factory=dict)

    SCHEMA: ClassVar[str] = "eigenupdate.extraction/2"

    @property
    def modes(self) -> list[ExtractedMode]:
        return [m for c in self.configurations for m in c.modes]

    def to_dict(self) -> dict:
        """JSON-ready document (``eigenupdate extract --json``), fits included; read back
        by :meth:`from_dict`."""
        return {"schema": self.SCHEMA, "numbered_by": self.numbered_by,
                "used_modes": self.used_modes, "problems": self.problems,
                "configurations": [_configuration_doc(ex) for ex in self.configurations],
                "frfs": self.frfs}

    def require_frfs(self, frfs: dict[str, Sequence[FRF]], source: str | None = None
                     ) -> None:
        """InputError unless every configuration's fits were fitted to ``frfs`` (the
        study's files, read now), FRF by FRF: with two files swapped in
        ``[measurement.frf]`` the report drew the saved fits over the wrong FRFs."""
        from eigenupdate.errors import InputError

        for i, ex in enumerate(self.configurations):
            now = [frf_id(f) for f in frfs.get(ex.configuration, [])]
            saved = self.frfs.get(ex.configuration)
            if saved is None or [x["sha256"] for x in saved] != [x["sha256"] for x in now]:
                def names(ids):
                    return ", ".join(f"{x['file']} {x['points']}" for x in ids) or "none"
                raise InputError(
                    f"{ex.configuration!r} was fitted to FRFs "
                    f"{'not recorded' if saved is None else names(saved)}; the study's "
                    f"files give other FRFs ({names(now)}): an extraction of other files "
                    f"or another order; extract again", source=source,
                    field=f"frfs.{ex.configuration}" if saved is not None
                    else f"configurations[{i}]")
            if any(len(m.fits) != len(now) for m in [*ex.modes, *ex.unexpected]):
                raise InputError(f"a mode of {ex.configuration!r} has not one fit per FRF "
                                 f"({len(now)})", source=source, field=f"configurations[{i}]")

    @classmethod
    def from_dict(cls, doc: dict, source: str | None = None) -> TestExtraction:
        """The extraction :meth:`to_dict` wrote; InputError naming the field otherwise."""
        r = reader(doc, cls.SCHEMA, source)
        numbered = r.str("numbered_by")
        if numbered not in ("model", "order"):
            raise r.fail("numbered_by", f"{numbered!r} is not 'model' or 'order'")
        frfs = {}
        for name, ids in r.raw("frfs", dict).items():
            if not isinstance(ids, list) or not all(
                    isinstance(x, dict) and all(isinstance(x.get(k), str) for k in _FRF_ID)
                    for x in ids):
                raise r.fail(f"frfs.{name}", f"must be a list of objects with {_FRF_ID}")
            frfs[name] = [{k: x[k] for k in _FRF_ID} for x in ids]
        return cls([_configuration(c) for c in r.items("configurations")], numbered,
                   [int(k) for k in r.array("used_modes")],
                   [str(p) for p in r.raw("problems", list)], frfs)


def extract_test(
    frfs: dict[str, Sequence[FRF]],
    *,
    model: ParametricModel | None = None,
    configurations: Sequence[Configuration] | None = None,
    used_modes: Sequence[int] = (),
    bands_hz: dict[str, Sequence[tuple[float, float]]] | None = None,
    exclude_below_hz: float | None = None,
    progress=None,
) -> TestExtraction:
    """Extract, validate and number the modes of every configuration.

    Parameters
    ----------
    frfs : the FRFs of each configuration, by name (the bare structure first).
    model, configurations : the initial model and the study's configurations; with them
        every resonance is numbered by the model mode it belongs to, else by order.
    used_modes : the elastic modes the study uses; each must be found in every
        configuration (else a problem).
    bands_hz : explicit bands (band k = mode k) by configuration name.
    exclude_below_hz : ignore peaks below this frequency.
    progress : called with a one-line message per configuration.
    """
    bands_hz = bands_hz or {}
    out = []
    for i, (name, these) in enumerate(frfs.items(), 1):
        if progress:
            progress(f"[{i}/{len(frfs)}] {name}: {len(these)} FRF(s)")
        out.append(extract_resonances(these, name, bands_hz=bands_hz.get(name),
                                      exclude_below_hz=exclude_below_hz))
    problems: list[str] = []
    by_model = model is not None and configurations is not None and not bands_hz
    if by_model:
        out = _number_by_model(out, model, list(configurations), problems)
        _pair_by_shapes(out, frfs, model, list(configurations), problems)
    else:
        for ex in out:
            ex.notes.append("numbered by order: " + ("bands given" if bands_hz else "no model"))
    for ex in out:
        if not ex.modes:
            problems.append(f"configuration {ex.configuration!r}: no validated resonance")
            continue
        text = missing_used_modes(ex, used_modes)
        if text:
            problems.append(text)
    return TestExtraction(out, "model" if by_model else "order", sorted(used_modes),
                          problems, {name: [frf_id(f) for f in these]
                                     for name, these in frfs.items()})


_FRF_ID = ("file", "points", "sha256")


def frf_id(f: FRF) -> dict[str, str]:
    """What identifies an FRF in a saved extraction (``TestExtraction.frfs``)."""
    return {"file": os.path.basename(f.source), "points":
            f"{dof_label(f.response)}/{dof_label(f.reference)}", "sha256": f.fingerprint()}


def _pair_by_shapes(out: list[ConfigurationExtraction], frfs: dict[str, Sequence[FRF]],
                    model: ParametricModel, configurations: list[Configuration],
                    problems: list[str]) -> None:
    """Measured shapes against the model's and the bare structure's
    (:mod:`eigenupdate.measure.shapes`): an exchanged mode is a problem, a crossing the
    model shares a note."""
    from eigenupdate.measure.shapes import measured_shape, shape_pairing

    shapes = {}
    for ex in out:
        got = [measured_shape(ex.configuration, m.mode, m.frequency_hz, m.fits,
                              frfs[ex.configuration]) for m in ex.modes]
        shapes[ex.configuration] = [s for s in got if s is not None]
    pairing = shape_pairing(shapes, model, configurations)
    problems.extend(pairing.problems)
    for ex in out:
        ex.notes.extend(n for n in pairing.notes if n.startswith(
            f"configuration {ex.configuration!r}:"))


def _number_by_model(out: list[ConfigurationExtraction], model: ParametricModel,
                     configurations: list[Configuration], problems: list[str]
                     ) -> list[ConfigurationExtraction]:
    from eigenupdate.errors import InputError
    from eigenupdate.solve.jacobian import solve_configurations

    configs = {c.name: c for c in configurations}
    top = max(ex.frequency_range_hz[1] for ex in out)
    n, sols = max(len(ex.modes) for ex in out) + 3, None
    while True:  # enough model modes to pass the highest measured frequency
        try:
            sols = solve_configurations(model, [configs[ex.configuration] for ex in out], n)
        except InputError:
            if sols is None and n > 1:  # more modes than the model has: ask for fewer
                n -= 1
                continue
            if sols is None:
                raise
            break
        if min(s.frequencies_hz[-1] for s in sols) > top * 1.1:
            break
        n *= 2
    bare: dict[int, float] = {}
    numbered = []
    order = sorted(range(len(out)), key=lambda i: out[i].configuration != BASE)
    for i in order:
        ex, sol = out[i], sols[i]
        c = configs[ex.configuration]
        model_hz = [float(v) for v in sol.frequencies_hz]
        masses = sum(1 for a in c.additions if a.mass > 0 and a.stiffness == 0)
        springs = sum(1 for a in c.additions if a.stiffness > 0 and a.mass == 0)
        bounds = (interlacing_bounds(bare, len(model_hz), masses, springs)
                  if c.additions and bare and masses + springs == len(c.additions) else None)
        r = number_resonances([m.frequency_hz for m in ex.modes], model_hz,
                              range_hz=ex.frequency_range_hz, bounds_hz=bounds)
        modes = [replace(m, mode=k, model_hz=model_hz[k - 1])
                 for m, k in zip(ex.modes, r.numbers, strict=True) if k is not None]
        unexpected = [m for m, k in zip(ex.modes, r.numbers, strict=True) if k is None]
        if not c.additions:
            bare = {m.mode: m.frequency_hz for m in modes}
        for a in r.ambiguous:
            problems.append(f"configuration {ex.configuration!r}: ambiguous mode number: {a}")
        numbered.append((i, replace(
            ex, modes=modes, unexpected=unexpected,
            missing=[(k, model_hz[k - 1]) for k in r.missing],
            notes=[*ex.notes, "numbered against the initial model"
                   + (" and interlacing with the bare modes" if bounds else "")])))
    return [ex for _, ex in sorted(numbered, key=lambda t: t[0])]


# ------------------------------------------------ the JSON of TestExtraction, field by field


def _fit_doc(f: ModalFit | None) -> dict | None:
    if f is None:
        return None
    c = complex(f.modal_constant)
    return {**asdict(f), "modal_constant": [c.real, c.imag], "band_hz": list(f.band_hz)}


def _fit(r: Reader) -> ModalFit:
    band, const = r.array("band_hz"), r.array("modal_constant")
    if band.size != 2 or const.size != 2:
        raise r.fail("band_hz" if band.size != 2 else "modal_constant",
                     "must be two numbers")
    return ModalFit(r.number("frequency_hz", minimum=0.0), r.number("loss_factor"),
                    complex(*const), r.number("frequency_std_hz", minimum=0.0),
                    r.number("loss_factor_std", minimum=0.0), (band[0], band[1]),
                    r.str("method"))


def _mode_doc(m: ExtractedMode) -> dict:
    return {**{k: v for k, v in asdict(m).items() if k not in ("fits", "band_hz")},
            "band_hz": list(m.band_hz), "fits": [_fit_doc(f) for f in m.fits]}


def _mode(r: Reader) -> ExtractedMode:
    band = r.array("band_hz")
    if band.size != 2:
        raise r.fail("band_hz", "must be two numbers")
    fits = r.raw("fits", list)
    opt = {k: r.number(k, optional=True) for k in ("check_hz", "check_std_hz", "fit_quality",
                                                    "model_hz")}
    return ExtractedMode(
        r.str("configuration"), r.int("mode"), r.number("frequency_hz", minimum=0.0),
        r.number("std_hz", minimum=0.0), r.number("loss_factor"),
        r.number("loss_factor_std", minimum=0.0), (band[0], band[1]),
        tuple(None if f is None else _fit(Reader(f, r.source, f"{r.field}.fits[{i}]"))
              for i, f in enumerate(fits)),
        under_resolved=r.bool("under_resolved"), **opt)


def _configuration_doc(ex: ConfigurationExtraction) -> dict:
    return {"name": ex.configuration, "line_spacing_hz": ex.line_spacing_hz,
            "frequency_range_hz": list(ex.frequency_range_hz), "notes": ex.notes,
            "modes": [_mode_doc(m) for m in ex.modes],
            "rejected": [{**asdict(x), "band_hz": list(x.band_hz)} for x in ex.rejected],
            "unexpected": [_mode_doc(m) for m in ex.unexpected],
            "missing": [{"mode": k, "model_hz": f} for k, f in ex.missing]}


def _configuration(r: Reader) -> ConfigurationExtraction:
    span = r.array("frequency_range_hz")
    if span.size != 2:
        raise r.fail("frequency_range_hz", "must be two numbers")
    rejected = []
    for x in r.items("rejected"):
        band = x.array("band_hz")
        if band.size != 2:
            raise x.fail("band_hz", "must be two numbers")
        rejected.append(Rejected(x.str("configuration"), x.number("frequency_hz"),
                                 (band[0], band[1]), x.str("reason"), x.bool("narrow")))
    return ConfigurationExtraction(
        r.str("name"), [_mode(m) for m in r.items("modes")], rejected,
        r.number("line_spacing_hz", minimum=0.0), (span[0], span[1]),
        [_mode(m) for m in r.items("unexpected")],
        [(m.int("mode"), m.number("model_hz")) for m in r.items("missing")],
        [str(n) for n in r.raw("notes", list)])
