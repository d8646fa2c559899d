"""The files of ``eigenupdate extract``: the measurement CSV, the modes as UFF 55, the
whole extraction as JSON and a plot of every fit."""

from __future__ import annotations

import re
from collections.abc import Callable
from pathlib import Path

from eigenupdate.errors import InputError
from eigenupdate.io import uff
from eigenupdate.io.atomic import make_dir, write_text
from eigenupdate.measure.extraction import extraction_csv
from eigenupdate.measure.frf import FRF, dof_label
from eigenupdate.measure.modes import Mode
from eigenupdate.measure.survey import TestExtraction


def safe_name(name: str) -> str:
    """A configuration name as a file name."""
    return re.sub(r"[^A-Za-z0-9.-]+", "_", name).strip("_") or "configuration"


def write_extraction(res: TestExtraction, frfs: dict[str, list[FRF]], output: str | Path, *,
                     uff55: str | Path | None = None, save: str | Path | None = None,
                     plots: str | Path | None = None,
                     label: Callable[[tuple[int, int]], str] | None = None) -> None:
    """Write the extracted frequencies (``output``, a measurement CSV), and if asked the
    modes with loss factors (``uff55``), the extraction's JSON (``save``) and a plot of
    the fits of every FRF into ``plots``; ``label`` names an FRF's points. An extraction
    with problems (a used mode not found) is refused: InputError, nothing written."""
    from eigenupdate.report.text import dumps

    if res.problems:  # a failed extraction writes nothing; one line, the others counted
        more = len(res.problems) - 1
        raise InputError(res.problems[0] + (f" (and {more} more problem(s): "
                                            f"{'; '.join(res.problems[1:])})" if more else ""))
    if plots:
        from eigenupdate.plot.plots import plot_extraction_fit

        make_dir(plots)
        stems: set[str] = set()
        for ex in res.configurations:
            stem = safe_name(ex.configuration)
            while stem in stems:  # '0.35 kg at 1' and '0.35 kg at 1!' replaced one another
                stem += "_"
            stems.add(stem)
            for j, x in enumerate(frfs[ex.configuration]):
                shown = [m for m in ex.modes if m.fits[j] is not None]
                if not shown:
                    continue
                points = [(label or dof_label)(p) for p in (x.response, x.reference)]
                plot_extraction_fit(
                    Path(plots) / f"extract_{stem}_{j + 1}.png",
                    x.frequency_hz, x.receptance, [m.fits[j] for m in shown],
                    mode_numbers=[m.mode for m in shown],
                    title=f"{ex.configuration}: {points[0]} / {points[1]}")
    write_text(output, extraction_csv(res.modes))
    if save:
        write_text(save, dumps(res.to_dict()) + "\n")
    if uff55:
        uff.write_modes(uff55, [Mode(m.frequency_hz, loss_factor=m.loss_factor, mode_number=m.mode,
                                 label=m.configuration) for m in res.modes])
