"""Limits on what one run may build, checked on an estimate before anything is built.

A small input can ask for a huge computation: a Matrix Market header declaring 3e6 x 3e6,
a beam of 10,000 nodes (20,000 parameter matrices of 20,000 rows each), a [design] table
whose combinations run to billions, a TOML or JSON file nested thousands deep, a Monte
Carlo of 1e9 trials. Each is
estimated from the input's own numbers and refused beyond a default limit, with the
estimate and the environment variable that raises the limit.

>>> require("candidates", 25, "the [design] table asks for 25 candidate configurations")
>>> try:
...     require("candidates", 10**12, "the [design] table asks for 1e12 candidates")
... except InputError as exc:
...     print(str(exc).split("; ")[1])
the limit is 20,000 (set EIGENUPDATE_MAX_CANDIDATES to raise it)
"""

from __future__ import annotations

import os

from eigenupdate.errors import InputError

LIMITS: dict[str, tuple[str, int]] = {
    # a sparse factorisation of K - sigma M takes some kB per coordinate
    "coordinates": ("EIGENUPDATE_MAX_COORDINATES", 500_000),
    # the parameter matrices (one sparse n x n matrix per parameter), MB
    "memory_mb": ("EIGENUPDATE_MAX_MEMORY_MB", 2_000),
    # each candidate is one perturbed eigen-solution, about 1-10 ms on the paper's models
    "candidates": ("EIGENUPDATE_MAX_CANDIDATES", 20_000),
    # arrays and tables inside each other in a TOML or JSON file
    "nesting": ("EIGENUPDATE_MAX_NESTING", 64),
    # Monte Carlo trials (--trials, --validate): one seed and one result kept per trial
    # (--trials 1000000000 spawned its seeds until memory ran out)
    "trials": ("EIGENUPDATE_MAX_TRIALS", 100_000),
    # an input file read whole (a study, a deck and each INCLUDE, a UFF or JSON file), MB:
    # a sparse 10 GB study file was read until memory ran out, naming no file
    "input_mb": ("EIGENUPDATE_MAX_INPUT_MB", 1_000),
    # ids in one NASTRAN "A THRU B" range, which pyNastran expands into a list (SPC1
    # 1 THRU 100000000 ran out of memory)
    "thru_ids": ("EIGENUPDATE_MAX_THRU_IDS", 10_000_000),
}
"""name -> (environment variable, default limit)."""


def limit(name: str) -> int:
    """The limit called ``name``: its environment variable if set, else the default."""
    env, default = LIMITS[name]
    text = os.environ.get(env)
    if text is None or not text.strip():
        return default
    try:
        value = int(text)
    except ValueError:
        value = -1
    if value < 1:
        raise InputError(f"must be an integer >= 1, got {text!r}", source="environment",
                         field=env)
    return value


def check_environment() -> None:
    """Raise InputError for a limit set to something that is not a limit (the command
    line calls this first, so a bad setting stops every command at once)."""
    for name in LIMITS:
        limit(name)


def require(name: str, value: float, what: str, *, source: str | None = None,
            field: str | None = None) -> None:
    """Raise InputError if ``value`` exceeds the limit ``name``; ``what`` says what was
    estimated (it is the start of the message)."""
    env, _ = LIMITS[name]
    lim = limit(name)
    if value > lim:
        raise InputError(f"{what}; the limit is {lim:,} (set {env} to raise it)",
                         source=source, field=field)


def parameter_matrices_mb(n_parameters: int, n_coordinates: int, nnz: int = 0) -> float:
    """Memory of ``n_parameters`` sparse n x n matrices (CSR: row pointers of n + 1
    integers each, plus 12 bytes per stored entry), MB."""
    return (8.0 * n_parameters * (n_coordinates + 1) + 12.0 * nnz) / 1e6


def require_model_size(n_coordinates: int, n_parameters: int, field: str = "model"
                       ) -> None:
    """Refuse a model beyond the coordinate limit, or whose parameter matrices would
    take more memory than the limit, before it is assembled."""
    require("coordinates", n_coordinates, f"the model has {n_coordinates:,} coordinates",
            field=field)
    mb = parameter_matrices_mb(n_parameters, n_coordinates)
    require("memory_mb", mb, f"its {n_parameters:,} parameter matrices of {n_coordinates:,} "
                             f"rows would take {mb:,.0f} MB", field=field)


def nesting_depth(text: str) -> int:
    """Deepest nesting of ``[``/``{`` in TOML or JSON text, outside strings and comments
    (a header line ``[[a.b]]`` counts 2, as a table header is not nested).

    >>> nesting_depth('a = [[1, 2], {b = "[[["}]  # [[[')
    2
    """
    depth = best = 0
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if c in "\"'":
            triple = text.startswith(c * 3, i)
            end = c * 3 if triple else c
            j = i + len(end)
            while j < n and not text.startswith(end, j):
                if c == '"' and text[j] == "\\":
                    j += 1
                elif not triple and text[j] == "\n":
                    break
                j += 1
            i = j + len(end)
            continue
        if c == "#":
            j = text.find("\n", i)
            i = n if j < 0 else j
            continue
        if c in "[{":
            depth += 1
            best = max(best, depth)
        elif c in "]}":
            depth = max(depth - 1, 0)
        i += 1
    return best


def require_nesting(text: str, source: str) -> None:
    """Refuse TOML or JSON text nested deeper than the limit, before a recursive parser
    meets it."""
    if text.count("[") + text.count("{") <= limit("nesting"):
        return  # cannot be deeper: no scan
    depth = nesting_depth(text)
    require("nesting", depth, f"nested {depth} levels deep", source=source)
