"""Reading back what earlier commands wrote: their JSON results (``update --save``,
``design --json``, ``montecarlo -o``, ``extract --json``), each through its class's
``from_dict``, and the loss factors of ``extract --uff55`` (universal file, dataset 55)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from eigenupdate.budget import require_nesting
from eigenupdate.errors import InputError
from eigenupdate.identify.updating import UpdateResult
from eigenupdate.io.inputs import require_regular
from eigenupdate.io.uff import read_modes
from eigenupdate.model.parametric import ParametricModel


def read_json(path: str | Path) -> Any:
    """A JSON file's document; InputError naming the file when it cannot be read."""
    src = str(path)
    require_regular(path, "JSON file")
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


def read_result(path: str | Path, model: ParametricModel | None = None) -> UpdateResult:
    """The result of ``eigenupdate update --save``, checked against the study's ``model``
    when given (see :meth:`UpdateResult.from_dict`)."""
    return UpdateResult.from_dict(read_json(path), str(path), model)


def read_loss_factors(path: str | Path, configuration: str) -> list[float]:
    """Loss factors of elastic modes 1, 2, ... of a configuration from ``extract --uff55``."""
    modes = sorted((m.mode_number, m.loss_factor) for m in read_modes(path)
                   if m.label == configuration)
    if not modes or [k for k, _ in modes] != list(range(1, len(modes) + 1)):
        raise InputError(f"no loss factors of modes 1, 2, ... for configuration "
                         f"{configuration!r}", source=str(path))
    return [eta for _, eta in modes]


def may_replace(path: str | Path) -> bool:
    """True if ``path`` does not exist or holds a result saved with success false: only
    those may be replaced by an unconverged result (without ``--force``)."""
    try:
        doc = json.loads(Path(path).read_text(encoding="utf-8"))
    except FileNotFoundError:
        return True
    except (OSError, ValueError, RecursionError):
        return False
    return isinstance(doc, dict) and doc.get("success") is False
