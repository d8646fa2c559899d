"""Where in a deck a card starts, and which card and line a pyNastran failure names.

pyNastran reads the deck as one text without line numbers; these map its messages (a
card quoted as ``card=['GRID', '2', ...]``, a card object in the traceback, a THRU range)
back to ``line N: CARD id`` of the deck, or ``file:N`` in an included file.
"""

from __future__ import annotations

import re

FIRST = re.compile(r"^([A-Za-z][A-Za-z0-9]*)(\*?)")


def card_starts(lines: list[str], origin: list[tuple[str, int]]) -> dict:
    """(card, first integer field) -> "file:line" of the card's first line."""
    out: dict = {}
    for text, (name, number) in zip(lines, origin, strict=True):
        m = FIRST.match(text)
        if m is None:
            continue
        card = m.group(1).upper()
        if "," in text[:10]:
            fields = text.split(",")
            second = fields[1] if len(fields) > 1 else ""
        elif m.group(2):  # large field: 8 then 16 characters
            second = text[8:24]
        else:
            second = text[8:16]
        try:
            cid = int(second.strip())
        except ValueError:  # a name (DMIG KX) or blank
            cid = second.strip().upper() or None
        out.setdefault((card, cid), f"{name}:{number}")
        out.setdefault((card, None), f"{name}:{number}")
    return out


def blamed_card(text: str, lines: list[str], origin, main: str) -> str:
    """``line N: CARD id`` (``file:N`` in an included file) of the card pyNastran's message
    quotes (``card=['GRID', '2', ...]``), or "" when it quotes none."""
    m = re.search(r"card=\[\s*'([A-Za-z0-9]+)\*?'\s*,\s*'\s*(\d+)\s*'", text)
    named = re.search(r"card=\[\s*'(PARAM)\*?'\s*,\s*'\s*([A-Za-z][A-Za-z0-9_]*)\s*'", text)
    if named is not None:  # a PARAM is known by its name (SNORM = 'YES')
        return _located("PARAM", named.group(2).upper(), lines, origin, main)
    if m is None:  # validate()'s messages name the card (PSHELL pid=1) or print it
        m = re.match(r"([A-Z][A-Z0-9]*) [a-z]+=(-?\d+)\b", text) or (re.search(
            r"^([A-Z][A-Z0-9]*)\*?(?: +|\s*,\s*)(-?\d+)\b", text.split("\n", 1)[-1],
            re.MULTILINE) if "\n" in text else None)
    if m is None:
        return ""
    at = _thru_line(text, lines, origin, main)
    if at is not None:
        return f"{at}: {m.group(1).upper()} {int(m.group(2))}"
    return _located(m.group(1).upper(), int(m.group(2)), lines, origin, main)


def card_in_traceback(exc: BaseException, lines: list[str], origin, main: str) -> str:
    """``line N: CARD id`` of the card object pyNastran was building or checking when it
    raised without quoting it (a card's validate(): ``AssertionError: mass=-150.0``), from
    the innermost frame whose ``self`` is a card; or ""."""
    tb, found = exc.__traceback__, None
    while tb is not None:
        card = tb.tb_frame.f_locals.get("self")
        kind = getattr(card, "type", None)
        ident = next((getattr(card, a) for a in ("eid", "pid", "mid", "nid", "sid", "cid")
                      if isinstance(getattr(card, a, None), int)), None)
        if ident is None and kind in ("DMIG", "DMI"):  # named, not numbered
            ident = str(getattr(card, "name", "")).upper() or None
        if isinstance(kind, str) and kind.isupper() and ident is not None:
            found = (kind, ident)
        tb = tb.tb_next
    return "" if found is None else _located(*found, lines, origin, main)


def _located(card: str, cid: int | str, lines: list[str], origin, main: str) -> str:
    """``line N: CARD id`` (``file:N`` in an included file; ``CARD id`` if not found)."""
    hit = card_starts(lines, origin).get((card, cid))
    return f"{card} {cid}" if hit is None else f"{place(hit, main)}: {card} {cid}"


def place(hit: str, main: str) -> str:
    """``line N`` for a ``file:N`` of the deck ``main`` itself, else ``file:N``."""
    name, line = hit.rsplit(":", 1)
    return f"line {line}" if name == main else hit


def _thru_line(text: str, lines: list[str], origin, main: str) -> str | None:
    """``line N`` of the line holding the range an ``A THRU B`` message names (a set's
    cards share its id, so the card's first line may be another card's)."""
    m = re.match(r"(\d+) THRU (\d+)", text)
    if m is None:
        return None
    rng = re.compile(rf"(^|[\s,]){m.group(1)}[\s,]+THRU[\s,]+{m.group(2)}([\s,]|$)",
                     re.IGNORECASE)
    for line, (name, number) in zip(lines, origin, strict=True):
        if rng.search(line[8:] if "," not in line[:10] else line.split(",", 1)[-1]):
            return place(f"{name}:{number}", main)
    return None


def replication_line(lines: list[str], origin, main: str) -> str:
    """``line N`` of the first free-field replication card (``=`` in field 1) that is the
    third in a row (pyNastran expands a replication of a replication, no further), else of
    the first one; "" if the deck has none."""
    first, run = "", 0
    for text, (name, number) in zip(lines, origin, strict=True):
        if not text or text[0] in " \t+*,$":  # continuation, comment or blank line
            continue
        run = run + 1 if text.startswith("=") else 0
        if run == 3:
            return place(f"{name}:{number}", main)
        first = first or (place(f"{name}:{number}", main) if run else "")
    return first
