"""Cards pyNastran does not read (NASTRAN-95's CRIGD1/2/3/R, CQUAD1...), as the raw
lines it leaves in ``bdf.reject_lines``: their name and fields as written."""

from __future__ import annotations


def card_name(line: str) -> str:
    """The card's name: field 1, tabs expanded (``CQUAD1<tab>2`` is a CQUAD1), a
    large-field ``*`` dropped.

    >>> card_name("crigd1\t1\t2"), card_name("CRIGDR,5,1,2,1"), card_name("PQUAD1* 1")
    ('CRIGD1', 'CRIGDR', 'PQUAD1')
    """
    return line.expandtabs(8)[:8].split(",")[0].strip().rstrip("*").upper()


def card_fields(lines: list[str]) -> list[str]:
    """Fields 2.. of a card and its continuations as written: 8-character small fields,
    16-character large ones (``CARD*``, ``*`` continuations) or free-field commas; a
    line's continuation field (10) is not data.

    >>> card_fields(["PTRIA1  200     400     2.5" + " " * 48 + "+PTRIA1*",
    ...              "+PTRIA1*1.51022 0.00"])[8:10]
    ['1.51022', '0.00']
    >>> card_fields(["PQUAD1* 7               400", "*       2.5"])[:5]
    ['7', '400', '', '', '2.5']"""
    out = []
    for k, line in enumerate(lines):
        body = line.split("$")[0].expandtabs(8)
        if "," in body[:10]:
            out += ([x.strip() for x in body.split(",")[1:9]] + [""] * 8)[:8]
            continue
        # large field: the card's name ends with '*', a continuation starts with it
        # (NASTRAN-95's d05011a continues with '+PTRIA1*': a small-field name)
        wide = body.startswith("*") or (k == 0 and body[:8].strip().endswith("*"))
        width = 16 if wide else 8
        body = body[8:72].ljust(64)
        out += [body[i:i + width].strip() for i in range(0, 64, width)]
    return out
