"""Extraction of every configuration of a test, numbered against the model if there is one,
and the table a user reads (accepted, rejected, missing and unexpected modes).

:func:`extract_test` is the library function behind ``eigenupdate extract``: it takes
FRFs already read (io/), so a notebook user calls it the same way.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

from eigenupdate.measure.extraction import (
    ConfigurationExtraction,
    ExtractedMode,
    extract_resonances,
    missing_used_modes,
)
from eigenupdate.measure.frf import FRF
from eigenupdate.measure.numbering import interlacing_bounds, number_resonances
from eigenupdate.model.configurations import BASE, Configuration
from eigenupdate.model.parametric import ParametricModel

__all__ = ["TestExtraction", "extract_test", "extraction_doc", "extraction_text"]


@dataclass(frozen=True)
class TestExtraction:
    """Every configuration's extraction; ``numbered_by`` is "model" or "order";
    ``problems`` are one-line errors (a used mode not found, an ambiguous number)."""

    __test__ = False  # not a pytest test class despite its name

    configurations: list[ConfigurationExtraction]
    numbered_by: str
    used_modes: list[int]
    problems: list[str]

    @property
    def modes(self) -> list[ExtractedMode]:
        return [m for c in self.configurations for m in c.modes]


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
                          problems)


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


def extraction_doc(result: TestExtraction) -> dict:
    """The table as a JSON-ready document."""
    def mode(m: ExtractedMode) -> dict:
        return {"mode": m.mode, "frequency_hz": m.frequency_hz, "std_hz": m.std_hz,
                "loss_factor": m.loss_factor, "loss_factor_std": m.loss_factor_std,
                "fit_quality": m.fit_quality, "check_frequency_hz": m.check_hz,
                "check_difference_std": m.disagreement, "under_resolved": m.under_resolved,
                "model_hz": m.model_hz, "band_hz": list(m.band_hz)}

    return {
        "numbered_by": result.numbered_by,
        "used_modes": result.used_modes,
        "problems": result.problems,
        "configurations": [{
            "name": ex.configuration,
            "line_spacing_hz": ex.line_spacing_hz,
            "notes": ex.notes,
            "modes": [mode(m) for m in ex.modes],
            "rejected": [{"frequency_hz": r.frequency_hz, "band_hz": list(r.band_hz),
                          "reason": r.reason} for r in ex.rejected],
            "unexpected": [{k: v for k, v in mode(m).items() if k != "mode"}
                           for m in ex.unexpected],
            "missing": [{"mode": k, "model_hz": f} for k, f in ex.missing],
        } for ex in result.configurations],
    }


def extraction_text(result: TestExtraction) -> str:
    """Per configuration: accepted modes, rejected candidates, missing/unexpected modes."""
    from eigenupdate.report.text import table

    blocks = []
    for ex in result.configurations:
        lines = [f"{ex.configuration} ({ex.line_spacing_hz:.4g} Hz lines; "
                 + "; ".join(ex.notes) + ")"]
        if not ex.modes:
            lines.append("  no validated resonance")
        else:
            lines.append(table(
                ["mode", "f Hz", "std Hz", "loss factor", "std", "fit R2", "check diff/std",
                 "model Hz", "note"],
                [[m.mode, m.frequency_hz, m.std_hz, m.loss_factor, m.loss_factor_std,
                  m.fit_quality, m.disagreement, m.model_hz,
                  "under-resolved" if m.under_resolved else ""] for m in ex.modes]))
        for r in ex.rejected:
            lines.append(f"  rejected {r.frequency_hz:.6g} Hz (band {r.band_hz[0]:.5g}-"
                         f"{r.band_hz[1]:.5g} Hz): {r.reason}")
        for k, f in ex.missing:
            lines.append(f"  missing: model mode {k} ({f:.6g} Hz) expected, not found")
        for m in ex.unexpected:
            lines.append(f"  unexpected: {m.frequency_hz:.6g} Hz matches no model mode")
        blocks.append("\n".join(lines))
    return "\n\n".join(blocks)

