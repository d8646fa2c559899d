"""Writing a NASTRAN deck back with updated parameter values (pyNastran's writer).

The model is read and assembled by :mod:`eigenupdate.io.nastran`; here the updated
values go into their cards and the deck is written with a comment block saying what was
updated, from which test and with which posterior std.
"""

from __future__ import annotations

import copy
import io
from collections.abc import Sequence
from pathlib import Path

from eigenupdate.io.atomic import write_text
from eigenupdate.io.nastran import FIELDS, NastranModel, _stores, _tied, set_field


def write_updated_bdf(nm: NastranModel, out: str | Path, values: dict[str, float],
                      comment: Sequence[str] = ()) -> None:
    """Write the BDF with the parameters' values in their cards (pyNastran's writer) and
    ``comment`` lines at the top; atomically (a failure leaves ``out`` untouched)."""
    bdf = copy.deepcopy(nm.bdf)  # nm stays as read
    for mat in bdf.materials.values():
        if mat.type == "MAT1" and _tied(mat):
            mat.g = None  # G was blank: keep it blank, it follows E
    for p, f in zip(nm.model.parameters, nm.fields, strict=True):
        v = float(values[p.name])
        card = _stores(bdf)[f.card][f.id]
        set_field(card, FIELDS[f.card][f.field], v)
        # some cards (CELAS2) always print 8-character fields: force 16 for updated ones
        card.write_card = _large_field_writer(card)
    buf = io.StringIO()
    # 16-character fields: the updated values keep 10-12 significant digits
    bdf.write_bdf(buf, size=16, close=False, enddata=True)
    head = "".join(f"$ {line}\n" for line in comment)
    write_text(out, head + buf.getvalue())



def _large_field_writer(card):
    from pyNastran.bdf.field_writer_16 import print_card_16

    def write_card(size: int = 16, is_double: bool = False) -> str:
        return card.comment + print_card_16(card.repr_fields())

    return write_card


def save_updated_bdf(study, result, out: str | Path) -> None:
    """Write a study's NASTRAN model back with the values of an update ``result``
    (:class:`~eigenupdate.identify.updating.UpdateResult`), a comment block saying what
    was updated, from which test and with which posterior std."""
    nm: NastranModel = study.nastran
    lines = [f"eigenupdate: updated from {nm.path.name} by study {Path(study.path).name}",
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
