"""Typed access to one table of a study's TOML file, with the dotted field name
(``model.mass[2].value``) for errors; unknown keys are errors too."""

from __future__ import annotations

from typing import Any

from eigenupdate.errors import InputError

LIMIT = 1e100
"""Numbers of a study are 0 or of magnitude 1/LIMIT to LIMIT: beyond, products of a few
of them (K = EI/L^3, lambda = k/m, (2 pi f)^2) leave the floating-point range."""


def in_limits(x: float) -> bool:
    """0 or of magnitude 1/LIMIT to LIMIT (NaN and inf are not); no float(x): ints may be
    huge. The rule for every number the package reads (study, command line, NASTRAN deck).

    >>> in_limits(0), in_limits(2e-7), in_limits(float("inf")), in_limits(10**400)
    (True, True, False, False)
    """
    return x == 0 or 1 / LIMIT <= abs(x) <= LIMIT


class TableReader:
    """Typed access to one TOML table, with the dotted field name for errors."""

    def __init__(self, data: dict, where: str, source: str):
        if not isinstance(data, dict):
            raise InputError("must be a table", source=source, field=where)
        self.data, self.where, self.source = data, where, source
        self.used: set[str] = set()

    def _f(self, key: str) -> str:
        return f"{self.where}.{key}" if self.where else key

    def error(self, key: str, msg: str) -> InputError:
        return InputError(msg, source=self.source, field=self._f(key))

    def get(
        self,
        key: str,
        kind: str,
        default: Any = ...,
    ) -> Any:
        self.used.add(key)
        if key not in self.data:
            if default is ...:
                raise self.error(key, "is required")
            return default
        v = self.data[key]
        check = {
            "str": lambda x: isinstance(x, str),
            "int": lambda x: isinstance(x, int) and not isinstance(x, bool) and abs(x) < 2**31,
            "float": lambda x: (
                isinstance(x, int | float) and not isinstance(x, bool)
                and in_limits(x)
            ),
            "bool": lambda x: isinstance(x, bool),
            "list": lambda x: isinstance(x, list),
            "table": lambda x: isinstance(x, dict),
            "tables": lambda x: isinstance(x, list) and all(isinstance(i, dict) for i in x),
        }[kind]
        if not check(v):
            names = {
                "str": "a string",
                "int": "an integer of magnitude below 2**31",
                "float": f"0 or a number of magnitude {1 / LIMIT:g} to {LIMIT:g}",
                "bool": "true or false",
                "list": "a list",
                "table": "a table",
                "tables": "an array of tables",
            }
            raise self.error(key, f"must be {names[kind]}, got {v!r}")
        return float(v) if kind == "float" else v

    def floats(self, key: str, default: Any = ...) -> float | list[float] | None:
        """A number or a list of numbers."""
        v = (
            self.get(key, "list", default)
            if isinstance(self.data.get(key), list)
            else self.get(key, "float", default)
        )
        if isinstance(v, list):
            bad = [x for x in v if isinstance(x, bool) or not isinstance(x, int | float)
                   or not in_limits(x)]
            if bad or not v:
                raise self.error(key, "must be a number or a non-empty list of numbers (0 or "
                                      f"of magnitude {1 / LIMIT:g} to {LIMIT:g})")
            return [float(x) for x in v]
        return v

    def finish(self) -> None:
        extra = sorted(set(self.data) - self.used)
        if extra:
            raise InputError(
                f"unknown key(s) {extra}", source=self.source, field=self.where or None
            )
