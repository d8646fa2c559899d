"""Files the report reads besides the study and the results of the other commands: an
extraction CSV and the JSON summaries of a test design or a Monte Carlo run.

Each is validated here, once, and handed on as plain typed data; every error names the
file and the field.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from eigenupdate.errors import InputError
from eigenupdate.io.measurements import read_measurements
from eigenupdate.io.results import read_json

PathLike = str | Path


def _is_number(v: Any) -> bool:
    return isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)


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
    doc = read_json(path)
    if not isinstance(doc, dict) or not doc:
        raise InputError("must be a non-empty JSON object {key: value, ...}", source=str(path))
    return doc
