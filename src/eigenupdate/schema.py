"""Versioned JSON documents of the result classes.

Every result class writes one document with a ``"schema"`` key (``"eigenupdate.update/2"``
and the like) from ``to_dict`` and reads it back with ``from_dict``; :class:`Reader` is
how ``from_dict`` checks a document it did not write itself (a file edited by hand,
another command's file, an older version's), one field at a time, each error naming the
file and the field. Like ``errors`` and ``budget``, importable from every layer.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from eigenupdate.errors import InputError

__all__ = ["Reader", "finite_or_none", "reader"]


def finite_or_none(v: float | None) -> float | None:
    """A float for JSON: None for None, NaN and infinities (JSON has no such numbers)."""
    return None if v is None or not math.isfinite(v) else float(v)


def _is_number(v: Any) -> bool:
    return isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)


class Reader:
    """Typed access to one JSON object; ``field`` is where it sits in the document."""

    def __init__(self, doc: Any, source: str | None, field: str = "") -> None:
        if not isinstance(doc, dict):
            raise InputError(f"must be a JSON object, got {type(doc).__name__}",
                             source=source, field=field or None)
        self.doc, self.source, self.field = doc, source, field

    def _where(self, key: str | int) -> str:
        part = f"[{key}]" if isinstance(key, int) else key
        return f"{self.field}{'' if isinstance(key, int) or not self.field else '.'}{part}"

    def fail(self, key: str | int, why: str) -> InputError:
        return InputError(why, source=self.source, field=self._where(key))

    def has(self, key: str) -> bool:
        return self.doc.get(key) is not None

    def raw(self, key: str, kind: type | tuple[type, ...], *, optional: bool = False) -> Any:
        if key not in self.doc or (optional and self.doc[key] is None):
            if optional:
                return None
            raise self.fail(key, "missing")
        v = self.doc[key]
        if not isinstance(v, kind) or (isinstance(v, bool) and kind in (int, float)):
            raise self.fail(key, f"has the wrong type {type(v).__name__}")
        return v

    def str(self, key: str, *, optional: bool = False) -> str | None:
        return self.raw(key, str, optional=optional)

    def bool(self, key: str) -> bool:
        return self.raw(key, bool)

    def int(self, key: str, *, optional: bool = False) -> int | None:
        return self.raw(key, int, optional=optional)

    def number(self, key: str, *, optional: bool = False, minimum: float | None = None
               ) -> float | None:
        """A finite number (None where ``optional`` and null), at least ``minimum``."""
        v = self.raw(key, (int, float), optional=optional)
        if v is None:
            return None
        if not _is_number(v) or (minimum is not None and v < minimum):
            raise self.fail(key, f"{v!r} is not a finite number"
                                 + (f" >= {minimum:g}" if minimum is not None else ""))
        return float(v)

    def array(self, key: str, ndim: int = 1, *, optional: bool = False,
              nulls: bool = False) -> np.ndarray | None:
        """A list of numbers (``ndim`` 2: a list of equal-length lists); null entries
        become NaN where ``nulls``."""
        v = self.raw(key, list, optional=optional)
        if v is None:
            return None
        try:
            a = np.array([np.nan if nulls and x is None else x for x in v] if ndim == 1 else
                         [[np.nan if nulls and x is None else x for x in r] for r in v],
                         dtype=float)
        except (TypeError, ValueError):
            raise self.fail(key, f"must be {'a list' if ndim == 1 else 'a list of lists'} "
                                 "of numbers") from None
        if a.ndim != ndim and not (a.size == 0 and ndim == 2):
            raise self.fail(key, f"must have {ndim} dimension(s), got {a.ndim}")
        if not np.all(np.isfinite(a[~np.isnan(a)] if nulls else a)):
            raise self.fail(key, "must hold finite numbers")
        return a.reshape(0, 0) if a.size == 0 and ndim == 2 else a

    def child(self, key: str, *, optional: bool = False) -> Reader | None:
        v = self.raw(key, dict, optional=optional)
        return None if v is None else Reader(v, self.source, self._where(key))

    def items(self, key: str, *, optional: bool = False) -> list[Reader]:
        """A list of objects, each as a Reader."""
        v = self.raw(key, list, optional=optional)
        return [Reader(x, self.source, f"{self._where(key)}[{i}]")
                for i, x in enumerate(v or [])]

    def mapping(self, key: str, value: Callable[[Reader, str], Any]) -> dict[str, Any]:
        """An object whose values ``value(self_of_it, name)`` reads, by name."""
        r = self.child(key)
        return {k: value(r, k) for k in r.doc}


def reader(doc: Any, schema: str, source: str | None = None) -> Reader:
    """The document's Reader once its ``schema`` key says it is a ``schema`` document."""
    r = Reader(doc, source)
    got = doc.get("schema")
    if got != schema:
        what = schema.split(".", 1)[1].split("/")[0]
        raise InputError(f"is {got!r}, expected {schema!r} (not an eigenupdate {what} "
                         f"result, or one written by an older version: write it again)",
                         source=source, field="schema")
    return r
