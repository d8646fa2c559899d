"""The designed plan as a ready study file: the input study with its ``[[perturbation]]``
tables replaced, ``measurement.modes`` set to the designed modes, and every relative path
rewritten so that it still resolves from the output file's folder.

The measurement files of the input study (``measurement.frequencies``, ``measurement.frf``)
describe the old configurations, so they are left out: the plan is for a test not yet made.
"""

from __future__ import annotations

import os
import tomllib
from collections.abc import Sequence
from pathlib import Path

import tomli_w

from eigenupdate.model.configurations import Configuration

_MODEL_PATHS = ("K0", "M0", "bdf")
SIGNATURE = "# eigenupdate design: plan from"
"""The first line of ``design -o``: its own earlier output, which it may replace."""


def plan_study_text(study_path: str | Path, configurations: Sequence[Configuration],
                    modes: Sequence[int], output: str | Path) -> str:
    """TOML text of the study at ``study_path`` with the plan's perturbations.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from eigenupdate.model.configurations import mass_at
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (d / "s.toml").write_text('[model]\\ntype = "matrices"\\nK0 = "K.mtx"\\n')
    >>> print(plan_study_text(d / "s.toml", [mass_at(3, 0.5)], [1, 2], d / "sub" / "p.toml"))
    # eigenupdate design: plan from s.toml
    [model]
    type = "matrices"
    K0 = "../K.mtx"
    <BLANKLINE>
    [[perturbation]]
    name = "0.5 kg at 3"
    add = [
        { coordinate = 3, mass = 0.5 },
    ]
    <BLANKLINE>
    [measurement]
    modes = [
        1,
        2,
    ]
    <BLANKLINE>
    """
    study_path = Path(study_path)
    doc = tomllib.loads(study_path.read_bytes().decode("utf-8-sig"))
    src, dst = study_path.parent, Path(output).parent

    def moved(p: str) -> str:
        full = src / p
        if Path(p).is_absolute():
            return p
        try:
            return Path(os.path.relpath(full.resolve(), dst.resolve())).as_posix()
        except ValueError:  # another drive on Windows
            return str(full.resolve())

    model = doc.get("model", {})
    for key in _MODEL_PATHS:
        if isinstance(model.get(key), str):
            model[key] = moved(model[key])
    for par in [*model.get("parameter", []), *model.get("term", [])]:
        for key in ("K", "M"):
            if isinstance(par.get(key), str):
                par[key] = moved(par[key])
    meas = doc.pop("measurement", {})
    for key in ("frequencies", "frf", "frf_options"):
        meas.pop(key, None)
    meas["modes"] = [int(k) for k in modes]
    doc.pop("perturbation", None)
    rest = {k: doc.pop(k) for k in list(doc) if k in ("updating", "design")}
    # a NASTRAN study names grid and component (coordinate 10 * grid + component)
    nastran = model.get("type") == "nastran"
    doc["perturbation"] = [
        {"name": c.name,
         "add": [{**({"grid": a.coordinate // 10, "component": a.coordinate % 10} if nastran
                     else {"coordinate": a.coordinate}),
                  **({"mass": a.mass} if a.mass else {}),
                  **({"stiffness": a.stiffness} if a.stiffness else {})}
                 for a in c.additions]}
        for c in configurations
    ]
    doc["measurement"] = meas
    doc.update(rest)
    return f"{SIGNATURE} {study_path.name}\n" + tomli_w.dumps(doc)
