"""Writing a NASTRAN deck back with updated parameter values.

The deck is written as it was read (every INCLUDE expanded in place), line for line;
only the fields of updated parameters change. A field in free format gets the value with
12 significant digits; a card in large-field format gets it in its 16-character field;
a small-field (8-character) card that holds an updated value is written in large-field
format, every other field keeping its original text. A parameter whose value did not
change (fixed, or not updated) is not touched, so ``2500.`` stays ``2500.``.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from eigenupdate.errors import InputError
from eigenupdate.io.atomic import write_text
from eigenupdate.io.nastran import CardField, NastranModel

# data field (1 = NASTRAN field 2, 9 = field 2 of the first continuation) of each
# parameter; None: found by a flag or a pair (PBUSH "K", PELAS/PMASS pairs)
FIELD_INDEX = {
    ("MAT1", "E"): 2, ("MAT1", "RHO"): 5,
    **{("MAT8", f): k + 2 for k, f in enumerate(("E1", "E2", "NU12", "G12", "G1Z", "G2Z",
                                                 "RHO"))},
    ("PBAR", "A"): 3, ("PBAR", "I1"): 4, ("PBAR", "I2"): 5, ("PBAR", "J"): 6,
    ("PBEAM", "A"): 3, ("PBEAM", "I1"): 4, ("PBEAM", "I2"): 5, ("PBEAM", "J"): 7,
    ("PROD", "A"): 3, ("PROD", "J"): 4,
    ("CELAS2", "K"): 2, ("CELAS4", "K"): 2, ("CMASS2", "M"): 2, ("CMASS4", "M"): 2,
    ("CONM2", "M"): 4, ("PSHELL", "T"): 3, ("PSHEAR", "T"): 3,
    # PCOMP PID Z0 NSM SB FT TREF GE LAM, then MIDk Tk THETAk SOUTk a ply
    **{("PCOMP", f"T{k}"): 4 * k + 6 for k in range(1, 100)},
    # PBARL/PBEAML PID MID GROUP TYPE, then DIM1... on the continuation (one station)
    **{(c, f"DIM{k}"): 8 + k for c in ("PBARL", "PBEAML") for k in range(1, 11)},
}
_CONTINUATION = re.compile(r"^[+*, ]|^$")


@dataclass
class _Card:
    start: int  # line index of the first line
    lines: list[int]  # indices of its lines (comments excluded)
    kind: str  # "free", "small" or "large"
    fields: list[str]  # data fields (field 2 of the first line = fields[0])


def _split(text: str, kind: str) -> list[str]:
    """The data fields of one line (8 small or free, 4 large)."""
    body = text.split("$")[0].expandtabs(8) if kind != "free" else text.split("$")[0]
    if kind == "free":
        # field 10 (the 9th token) is the continuation field: a marker such as +P1
        # is not data (the rendered card continues with a leading comma instead)
        tokens = [t.strip() for t in body.split(",")[1:]]
        if len(tokens) > 9:
            raise InputError(f"free-field line with more than 8 data fields: {text.strip()}")
        return (tokens + [""] * 8)[:8]
    width, count = (16, 4) if kind == "large" else (8, 8)
    body = body[8:8 + width * count].ljust(width * count)
    return [body[i:i + width].strip() for i in range(0, width * count, width)]


def _cards(text: list[str], name: str) -> list[_Card]:
    """Every card ``name`` in the text, with its data fields as written."""
    out = []
    i = 0
    while i < len(text):
        line = text[i]
        head = line.split(",")[0].split("$")[0][:8].strip().upper()
        if head.rstrip("*") != name or line.startswith(("$", " ", "+", "*")):
            i += 1
            continue
        kind = "free" if "," in line[:10] else "large" if head.endswith("*") else "small"
        lines, fields = [i], _split(line, kind)
        j = i + 1
        while j < len(text):
            nxt = text[j]
            if nxt.startswith("$") or not nxt.strip():
                j += 1
                continue
            if not _CONTINUATION.match(nxt):
                break
            k = "free" if "," in nxt[:10] else "large" if nxt.startswith("*") else "small"
            if k == "large" and kind == "small" or k == "small" and kind == "large":
                raise InputError(f"card {name} mixes small and large fields")
            lines.append(j)
            fields += _split(nxt, k)
            j += 1
        out.append(_Card(i, lines, kind, fields))
        i = j
    return out


def _locate(cards: list[_Card], f: CardField) -> tuple[_Card, int]:
    """The card holding a parameter's field and the field's data index (0-based)."""
    for card in cards:
        ids = card.fields
        if (f.card, f.field) in FIELD_INDEX:
            if _int(ids[0]) == f.id:
                return card, FIELD_INDEX[(f.card, f.field)] - 1
        elif f.card in ("PELAS", "PMASS"):  # up to 2 (PELAS) or 4 (PMASS) pairs per card
            step = 4 if f.card == "PELAS" else 2
            for k in range(0, len(ids), step):
                if _int(ids[k]) == f.id:
                    return card, k + 1
        elif f.card in ("PQUAD2", "PTRIA2"):  # one or two PID MID T NSM sets per card
            for k in (0, 4):
                if _int(ids[k]) == f.id:
                    return card, k + 2
        elif f.card == "PBUSH" and _int(ids[0]) == f.id:
            flags = [k for k, x in enumerate(ids) if x.upper() == "K" and k % 8 == 1]
            if flags:
                return card, flags[0] + int(f.field[1])
        elif f.card == "CONM1" and _int(ids[0]) == f.id:
            i, j = int(f.field[1]) - 1, int(f.field[2]) - 1
            return card, 3 + i * (i + 1) // 2 + j
    raise InputError(f"{f.card} {f.id}: card not found in the deck's text to write back")


def _int(text: str) -> int | None:
    try:
        return int(text)
    except ValueError:
        return None


def _free_value(v: float) -> str:
    return repr(float(f"{v:.12g}"))


def _large_value(v: float) -> str:
    from pyNastran.bdf.field_writer_16 import print_float_16

    return print_float_16(v).strip()


def _render_large(name: str, fields: list[str]) -> list[str]:
    """A card in large-field format: 4 fields of 16 characters a line."""
    while fields and not fields[-1]:
        fields = fields[:-1]
    rows = [fields[k:k + 4] for k in range(0, max(len(fields), 1), 4)]
    out = []
    for n, row in enumerate(rows):
        lead = f"{name}*" if n == 0 else "*"
        out.append(lead.ljust(8) + "".join(x.rjust(16) for x in row))
    return out


def write_updated_bdf(nm: NastranModel, out: str | Path, values: dict[str, float],
                      comment: Sequence[str] = ()) -> None:
    """Write the deck with the parameters' new ``values`` in their fields and ``comment``
    lines at the top; atomically (a failure leaves ``out`` untouched)."""
    text = list(nm.text)
    initial = dict(zip(nm.model.names, nm.model.values, strict=True))
    changed: dict[int, tuple[_Card, dict[int, float]]] = {}
    found: dict[str, list[_Card]] = {}
    inherited: list = []
    for p, f in zip(nm.model.parameters, nm.fields, strict=True):
        if p.name not in values or float(values[p.name]) == initial[p.name]:
            continue
        if f.card == "PBEAML" and len(nm.bdf.properties[f.id].dim) > 1:
            raise InputError(f"PBEAML {f.id}: its {f.field} on several stations cannot be "
                             f"written back (give the section on one station)")
        if f.card not in found:
            found[f.card] = _cards(text, f.card)
        card, index = _locate(found[f.card], f)
        changed.setdefault(card.start, (card, {}))[1][index] = float(values[p.name])
        if f.card == "PCOMP":
            inherited.append((card, index, initial[p.name]))
    for card, index, old in inherited:
        # a blank T of the next ply is the previous ply's: keep the old value there
        nxt = index + 4
        ply = card.fields[nxt - 1:nxt + 3]
        if len(ply) == 4 and any(ply) and not ply[1]:
            changed[card.start][1].setdefault(nxt, old)
    replace: dict[int, list[str]] = {}
    for card, new in changed.values():
        name = text[card.start].split(",")[0][:8].strip().rstrip("*").upper()
        fields = list(card.fields)
        fields += [""] * (max(new) + 1 - len(fields))
        if card.kind == "free":
            for k, v in new.items():
                fields[k] = _free_value(v)
            rows = [fields[k:k + 8] for k in range(0, len(fields), 8)]
            lines = [",".join([name if n == 0 else "", *row]).rstrip(",")
                     for n, row in enumerate(rows)]
        else:
            for k, v in new.items():
                fields[k] = _large_value(v)
            lines = _render_large(name, fields)
        replace[card.start] = lines
        for k in card.lines[1:]:
            replace[k] = []
    body = []
    for k, line in enumerate(text):
        body += replace.get(k, [line])
    head = "".join(f"$ {line}\n" for line in comment)
    write_text(out, head + "\n".join(body) + "\n")


SIGNATURE = "eigenupdate: updated from"
"""The start of the comment block of ``update --save-bdf``: its own earlier output."""


def save_updated_bdf(study, result, out: str | Path) -> None:
    """Write a study's NASTRAN model back with the values of an update ``result``
    (:class:`~eigenupdate.identify.updating.UpdateResult`), a comment block saying what
    was updated, from which test and with which posterior std."""
    nm: NastranModel = study.nastran
    lines = [f"{SIGNATURE} {nm.path.name} by study {Path(study.path).name}",
             f"measured frequencies: {study.frequencies}",
             f"method: {result.method}, {result.message} after {result.nit} iteration(s)",
             "parameter                  card field        initial      updated   post. std"]
    initial = dict(zip(nm.model.names, nm.model.values, strict=True))
    for p, f in zip(nm.model.parameters, nm.fields, strict=True):
        std = result.std.get(p.name)
        lines.append(f"{p.name:<26} {f.card} {f.id} {f.field:<5} {initial[p.name]:12.6g} "
                     f"{result.parameters[p.name]:12.6g} "
                     f"{'fixed' if std is None else format(std, '11.4g')}")
    write_updated_bdf(nm, out, result.parameters, lines)
