"""Universal file dataset 55: real normal modes (analysis type 2) as
:class:`~eigenupdate.measure.modes.Mode`. Every real number is stored with 6 significant
digits (``%13.5e``)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import numpy as np
import pyuff

from eigenupdate.errors import InputError
from eigenupdate.io.atomic import atomic_write
from eigenupdate.io.uff._pyuff import PathLike, _open_uff, _quiet, _read_set
from eigenupdate.measure.modes import Mode

__all__ = ["read_modes", "write_modes"]


MODE_ID = "eigenupdate normal mode"
"""ID line 1 of every mode written: what makes a file an earlier ``extract --uff55``."""


def write_modes(path: PathLike, modes: Sequence[Mode]) -> None:
    """Write normal modes as datasets 55 (analysis type 2) to a universal file.

    Fields written per mode: ``freq`` = frequency_hz, ``modal_m`` = modal_mass,
    ``modal_damp_vis`` = damping_ratio, ``modal_damp_his`` = loss_factor, ``mode_n`` =
    mode_number (or the 1-based position when 0), ``load_case`` = 1, ``node_nums`` and
    ``r1``..``r3`` (``r1``..``r6`` with data characteristic 3 for 6-column shapes),
    specific data type 8 (displacement).  Values get 6 significant digits.  The file is
    replaced atomically.

    Raises
    ------
    ValueError
        If ``modes`` is empty.
    """
    if len(modes) == 0:
        raise ValueError(f"{path}: no modes to write")
    dsets = []
    for k, mode in enumerate(modes, start=1):
        shape = np.asarray(mode.shape)
        six = shape.shape[1] == 6
        cols = {f"r{j + 1}": shape[:, j].copy() for j in range(shape.shape[1])}
        dsets.append(
            pyuff.prepare_55(
                id1=MODE_ID,
                id2=f"mode {mode.mode_number or k}",
                id3=mode.label[:80] or "NONE",
                id4="NONE",
                id5="NONE",
                model_type=1,
                analysis_type=2,
                data_ch=3 if six else 2,
                spec_data_type=8,
                data_type=2,
                n_data_per_node=6 if six else 3,
                load_case=1,
                mode_n=int(mode.mode_number or k),
                freq=float(mode.frequency_hz),
                modal_m=float(mode.modal_mass),
                modal_damp_vis=float(mode.damping_ratio),
                modal_damp_his=float(mode.loss_factor),
                node_nums=np.asarray(mode.node_nums, dtype=np.int64),
                **cols,
            )
        )

    def _write(tmp: str) -> None:
        with _quiet():
            pyuff.UFF(tmp).write_sets(dsets, mode="add")

    atomic_write(path, _write)


def read_modes(path: PathLike) -> list[Mode]:
    """Read all normal-mode datasets (type 55, analysis type 2) of a universal file.

    The inverse of :func:`write_modes`; other datasets are skipped.

    Returns
    -------
    list of Mode
        In file order, with ``source=str(path)``.

    Raises
    ------
    InputError
        If the file cannot be read, holds no normal-mode dataset, or a dataset cannot be
        parsed or has complex or non-finite values.
    """
    src = str(path)
    uff, types = _open_uff(path)
    modes: list[Mode] = []
    other: set[int] = set()
    for index, set_type in enumerate(types):
        if set_type != 55:
            continue
        dset = _read_set(uff, index, set_type, src)
        analysis = int(dset.get("analysis_type", -1))
        if analysis != 2:
            other.add(analysis)
            continue
        where = f"dataset {index + 1}"
        if int(dset.get("data_type", 2)) != 2:
            raise InputError(
                f"{where}: complex mode shape data (data type {dset.get('data_type')}) in a "
                "normal-mode dataset is not supported",
                source=src,
                field="data_type",
            )
        ncol = 6 if "r4" in dset else 3
        try:
            shape = np.column_stack(
                [np.asarray(dset[f"r{j + 1}"], dtype=np.float64) for j in range(ncol)]
            )
            mode = Mode(
                frequency_hz=dset["freq"],
                loss_factor=dset.get("modal_damp_his", 0.0),
                damping_ratio=dset.get("modal_damp_vis", 0.0),
                modal_mass=dset.get("modal_m", 0.0),
                node_nums=np.asarray(dset["node_nums"], dtype=np.int64),
                shape=shape,
                mode_number=int(dset.get("mode_n", 0)),
                label="" if str(dset.get("id3", "NONE")).strip() == "NONE"
                else str(dset.get("id3", "")).strip(),
            )
        except (KeyError, TypeError, ValueError) as exc:  # InputError is a ValueError
            err = InputError(f"{where}: {exc}", source=src)
            err.field = getattr(exc, "field", None)
            raise err from None
        modes.append(replace(mode, source=src))
    if not modes:
        extra = (
            f"; the type-55 datasets have analysis types {sorted(other)}"
            if other
            else f"; found dataset types {sorted(set(types))}"
            if types
            else "; no universal-file datasets found"
        )
        raise InputError(
            f"no normal-mode dataset (type 55, analysis type 2) in file{extra}", source=src
        )
    return modes
