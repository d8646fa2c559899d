"""Files the report reads besides the study: a saved update result, an extraction CSV and
the JSON summaries of a test design or a Monte Carlo run.

Each is validated here, once, and handed on as plain typed data; every error names the
file and the field.
"""

from __future__ import annotations

import csv
import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from eigenupdate.budget import require_nesting
from eigenupdate.errors import InputError
from eigenupdate.io.measurements import read_measurements
from eigenupdate.io.results import read_updated_values
from eigenupdate.model.parametric import ParametricModel

PathLike = str | Path


def _json(path: PathLike) -> Any:
    src = str(path)
    try:
        text = Path(path).read_text(encoding="utf-8-sig")
        require_nesting(text, src)
        return json.loads(text)
    except InputError:  # too deeply nested
        raise
    except OSError as exc:
        raise InputError(f"cannot read: {exc.strerror or exc}", source=src) from None
    except (UnicodeDecodeError, ValueError) as exc:
        raise InputError(f"not a JSON file: {exc}", source=src) from None


def _is_number(v: Any) -> bool:
    return isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)


def read_result(path: PathLike, model: ParametricModel) -> dict[str, Any]:
    """A result of ``eigenupdate update --save``, checked against the study's ``model``.

    Returns the document with the keys the report uses: ``method``, ``converged``,
    ``message``, ``iterations``, ``parameters``, ``std``, ``history`` (parameter values
    of every iterate), ``steps`` (objective, step, note) and ``frequencies`` (rows of
    configuration, mode, measured_hz, initial_hz, updated_hz). ``std`` values may be
    None (undefined), as the update writes them.
    """
    src = str(path)
    doc = _json(path)
    if not isinstance(doc, dict):
        raise InputError("must be a JSON object", source=src)

    def need(key: str, kind: type | tuple[type, ...]) -> Any:
        if key not in doc:
            raise InputError("missing (not a result of 'eigenupdate update --save')",
                             source=src, field=key)
        if not isinstance(doc[key], kind) or isinstance(doc[key], bool) and kind is int:
            raise InputError(f"has the wrong type {type(doc[key]).__name__}", source=src,
                             field=key)
        return doc[key]

    need("parameters", dict)
    values = read_updated_values(path, model)
    names = list(model.names)
    std = need("std", dict)
    for k, v in std.items():
        if k not in values or not (v is None or _is_number(v) and v >= 0):
            raise InputError(f"{v!r} for {k!r} is not a standard deviation of a parameter",
                             source=src, field=f"std.{k}")
    history = need("history", list)
    for i, h in enumerate(history):
        if not (isinstance(h, dict) and set(h) == set(names)
                and all(_is_number(x) for x in h.values())):
            raise InputError("must give a number for every parameter", source=src,
                             field=f"history[{i}]")
    steps = doc.get("steps", [])
    if not isinstance(steps, list) or len(steps) not in (0, len(history)) or not all(
            isinstance(s, dict) and (s.get("objective") is None or _is_number(s["objective"]))
            for s in steps):
        raise InputError("must be one {objective, step, note} per history entry", source=src,
                         field="steps")
    rows = need("frequencies", list)
    for i, r in enumerate(rows):
        ok = (isinstance(r, dict) and isinstance(r.get("configuration"), str)
              and isinstance(r.get("mode"), int)
              and all(_is_number(r.get(k)) and r[k] > 0
                      for k in ("measured_hz", "initial_hz", "updated_hz")))
        if not ok:
            raise InputError("needs configuration, mode, measured_hz, initial_hz, updated_hz "
                             "(positive numbers)", source=src, field=f"frequencies[{i}]")
    converged = doc.get("converged")
    if not isinstance(converged, bool):
        raise InputError("must be true or false", source=src, field="converged")
    return {
        "method": str(doc.get("method", "")),
        "converged": converged,
        "message": str(doc.get("message", "")),
        "iterations": doc.get("iterations", max(len(history) - 1, 0)),
        "parameters": {n: float(values[n]) for n in names},
        "std": {k: None if v is None else float(v) for k, v in std.items()},
        "history": history,
        "steps": steps,
        "frequencies": rows,
    }


@dataclass(frozen=True)
class ExtractedRow:
    """One row of an extraction CSV (``eigenupdate extract -o``); None where empty."""

    configuration: str
    mode: int
    frequency_hz: float
    std_hz: float | None
    loss_factor: float | None = None
    loss_factor_std: float | None = None
    check_hz: float | None = None
    check_std_hz: float | None = None

    @property
    def disagreement(self) -> float | None:
        """|frequency - cross-check| in combined standard deviations."""
        if self.check_hz is None or self.std_hz is None:
            return None
        s = math.hypot(self.std_hz, self.check_std_hz or 0.0)
        return abs(self.frequency_hz - self.check_hz) / s if s > 0 else None


_EXTRA = {"loss_factor": "loss_factor", "loss_factor_std": "loss_factor_std",
          "check_frequency_hz": "check_hz", "check_std_hz": "check_std_hz"}


def read_extracted(path: PathLike, configurations: list[str]) -> list[ExtractedRow]:
    """Rows of an extraction CSV, in file order.

    The first four columns are read (and validated) as the measurement CSV they are; the
    loss factors and the rational-fraction cross-check are optional columns.
    """
    src = str(path)
    core = read_measurements(path, configurations)
    text = Path(path).read_text(encoding="utf-8-sig")
    lines = [ln for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
    extra: dict[tuple[str, int], dict[str, float | None]] = {}
    for i, row in enumerate(csv.DictReader(lines), 2):
        key = (row["configuration"].strip(), int(row["mode"]))
        vals: dict[str, float | None] = {}
        for col, attr in _EXTRA.items():
            cell = (row.get(col) or "").strip()
            try:
                vals[attr] = float(cell) if cell else None
            except ValueError:
                raise InputError(f"row {i}: {cell!r} is not a number", source=src,
                                 field=col) from None
            if vals[attr] is not None and not (math.isfinite(vals[attr]) and vals[attr] >= 0):
                raise InputError(f"row {i}: {cell!r} must be a finite number >= 0",
                                 source=src, field=col)
        extra[key] = vals
    return [ExtractedRow(m.configuration, m.mode, m.frequency_hz, m.std_hz, **extra[key])
            for key, m in core.items()]


def read_summary(path: PathLike) -> dict[str, Any]:
    """A test-design plan or Monte Carlo summary: any JSON object (rendered generically)."""
    doc = _json(path)
    if not isinstance(doc, dict) or not doc:
        raise InputError("must be a non-empty JSON object {key: value, ...}", source=str(path))
    return doc
