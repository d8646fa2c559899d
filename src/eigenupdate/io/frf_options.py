"""The study's ``[measurement.frf_options]``: validated once for ``extract`` and ``report``."""

from __future__ import annotations

from eigenupdate.errors import InputError
from eigenupdate.io.study import Study


def frf_options(study: Study) -> tuple[dict, float | None]:
    """(bands_hz by configuration name, exclude_below_hz) of the study's FRF extraction.

    ``bands_hz`` may be one list of [low, high] pairs for every configuration or a table
    of them by configuration; configurations without bands get automatic peak picking.
    """
    opts = dict(study.frf_options)
    src, field = str(study.path), "measurement.frf_options"
    bands = opts.pop("bands_hz", None)
    low = opts.pop("exclude_below_hz", None)
    if opts:
        raise InputError(f"unknown key(s) {sorted(opts)}", source=src, field=field)
    names = [c.name for c in study.configurations]
    if bands is None:
        table = {}
    elif isinstance(bands, list):
        table = {n: bands for n in names}
    elif isinstance(bands, dict):
        unknown = set(bands) - set(names)
        if unknown:
            raise InputError(f"unknown configuration(s) {sorted(unknown)}", source=src,
                             field=f"{field}.bands_hz")
        table = bands
    else:
        raise InputError("must be a list of [low, high] pairs or a table of them", source=src,
                         field=f"{field}.bands_hz")
    for name, b in table.items():
        ok = isinstance(b, list) and all(
            isinstance(x, list) and len(x) == 2 and all(isinstance(v, int | float) for v in x)
            and 0 <= x[0] < x[1] for x in b)
        if not ok:
            raise InputError(f"{name!r}: bands must be [low, high] pairs in Hz, 0 <= low < high",
                             source=src, field=f"{field}.bands_hz")
    if low is not None and not (isinstance(low, int | float) and low >= 0):
        raise InputError("must be a number >= 0", source=src, field=f"{field}.exclude_below_hz")
    return table, low
