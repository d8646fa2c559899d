"""Reading back what earlier commands wrote: the parameters of ``update --save`` (JSON)
and the loss factors of ``extract --uff55`` (universal file, dataset 55)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from eigenupdate.budget import require_nesting
from eigenupdate.errors import InputError
from eigenupdate.io.uff import read_modes
from eigenupdate.model.parametric import ParametricModel


def read_updated_values(path: str | Path, model: ParametricModel) -> dict[str, float]:
    """Every parameter value of a saved update result, checked against ``model``.

    Raises InputError when the file is not such a result, belongs to another model
    (unknown or missing parameters) or holds a value that is not physical.
    """
    src = str(path)
    try:
        text = Path(path).read_text(encoding="utf-8")
        require_nesting(text, src)
        doc = json.loads(text)
        values = doc["parameters"]
        if not isinstance(values, dict):
            raise TypeError
    except InputError:  # too deeply nested
        raise
    except OSError as exc:
        raise InputError(f"cannot read result: {exc.strerror or exc}", source=src) from None
    except (ValueError, KeyError, TypeError):
        raise InputError("not a result of 'eigenupdate update --save' (no parameters table)",
                         source=src, field="parameters") from None
    unknown = set(values) - set(model.names)
    if unknown:
        raise InputError(f"parameters {sorted(unknown)} are not in the study's model",
                         source=src, field="parameters")
    missing = [n for n in model.names if n not in values]
    if missing:
        raise InputError(f"no value for {missing} (a result of another study?)",
                         source=src, field="parameters")
    for p in model.parameters:
        v = values[p.name]
        ok = isinstance(v, int | float) and not isinstance(v, bool) and np.isfinite(v)
        if not ok or v < 0 or (v == 0 and p.value > 0):
            raise InputError(f"{v!r} is not a physical value (initial {p.value:g})",
                             source=src, field=f"parameters.{p.name}")
    return values


def read_loss_factors(path: str | Path, configuration: str) -> list[float]:
    """Loss factors of elastic modes 1, 2, ... of a configuration from ``extract --uff55``."""
    modes = sorted((m.mode_number, m.loss_factor) for m in read_modes(path)
                   if m.label == configuration)
    if not modes or [k for k, _ in modes] != list(range(1, len(modes) + 1)):
        raise InputError(f"no loss factors of modes 1, 2, ... for configuration "
                         f"{configuration!r}", source=str(path))
    return [eta for _, eta in modes]
