"""NASTRAN's reduction sets of a normal-modes deck and the reduction they ask for.

ASET/ASET1 (the a-set, with the SUPORT coordinates) or OMIT/OMIT1 (the o-set) make a
static (Guyan) reduction; QSET/QSET1 on SPOINTs (with ASET or alone: every coordinate
outside ASET and QSET is omitted, QRG QSET) add generalized coordinates, the lowest
fixed-interface modes of the o-set with the a-set held, one per q-set coordinate: the
dynamic (Craig-Bampton) reduction of MSC's SOL 103/SEMODES residual structure. Both are in
:mod:`eigenupdate.model.reduction`. MSC takes those modes from the EIGRL that METHOD
selects and uses the lowest as many as the q-set has (its warning 9145 truncates the
rest); with fewer modes than q-set coordinates it fills them with residual vectors,
which are not built here: such a deck is refused.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from eigenupdate.errors import InputError
from eigenupdate.io.nastran_deck import case_value, modal_subcases
from eigenupdate.model import reduction


@dataclass(frozen=True)
class Reduced:
    """K and M after the reduction, and what the model's coordinates became."""

    k: sp.csr_array
    m: sp.csr_array
    keep: np.ndarray  # the kept physical rows (indices into the assembled rows)
    gone: np.ndarray  # the omitted rows (indices into the unconstrained rows)
    modal: np.ndarray  # coordinates of the q-set SPOINTs (10 id + 1), in K's last rows
    fixed_hz: tuple = ()  # frequencies of the fixed-interface modes used


def set_rows(bdf, cards, where, label: str) -> list[int]:
    """Rows of ASET/ASET1/OMIT/OMIT1/SUPORT/QSET cards (point id, components); a scalar
    point's component is 0 or blank."""
    rows = []
    for card in cards:
        ids = getattr(card, "ids", None) or getattr(card, "nodes", [])
        comps = getattr(card, "components", None) or getattr(card, "Cs", None)
        comps = [comps] * len(ids) if isinstance(comps, str | None) else comps
        for n, c in zip(ids, comps, strict=True):
            if n not in where:
                raise InputError(f"{label}: GRID {n} is referenced but not defined")
            c = str(c or "").strip()
            rows += [6 * where[n] + int(x) - 1 for x in c if x != "0"]
            if n not in bdf.nodes and c in ("", "0"):
                rows.append(6 * where[n])
    return rows


def analysis_set(bdf, where, ndof: int) -> np.ndarray | None:
    """Mask of NASTRAN's a-set when ASET or OMIT cards ask for a reduction: the ASET
    coordinates (with the SUPORT ones), or all but the OMIT ones."""
    asets, omits = list(bdf.asets), list(bdf.omits)
    if not asets and not omits:
        return None
    if asets and omits:
        raise InputError("both ASET and OMIT cards: give one of them")
    if asets:
        mask = np.zeros(ndof, bool)
        mask[set_rows(bdf, asets, where, "ASET")] = True
        mask[set_rows(bdf, bdf.suport, where, "SUPORT")] = True
    else:
        mask = np.ones(ndof, bool)
        mask[set_rows(bdf, omits, where, "OMIT")] = False
    return mask


def q_set(bdf, where, n_grids: int) -> np.ndarray:
    """Rows of the QSET/QSET1 scalar points, ascending (empty without such cards)."""
    qsets = list(bdf.qsets)
    for card in qsets:
        if not card.ids:  # pyNastran keeps ``QSET1,0`` and ``QSET1,0,THRU,4`` as no point
            raise InputError(f"{card.type}: a card that names no SPOINT (a q-set card "
                             f"lists at least one point)")
        for n, c in zip(card.ids, _components(card), strict=True):
            if n in where and where[n] < n_grids:
                raise InputError(f"{card.type}: GRID {n}: the q-set (generalized "
                                 f"coordinates of the dynamic reduction) is read on SPOINTs "
                                 f"only")
            if n in where and str(c or "").strip() not in ("", "0"):
                raise InputError(f"{card.type}: component {c} of SPOINT {n} must be 0 or "
                                 f"blank")
            if n not in where:  # even in a THRU range, which pyNastran has expanded
                raise InputError(f"{card.type}: SPOINT {n} is referenced but not defined")
    return np.unique(np.array(set_rows(bdf, qsets, where, "QSET"), dtype=int))


def _components(card) -> list:
    comps = card.components
    return [comps] * len(card.ids) if isinstance(comps, str | None) else list(comps)


def reduce(bdf, where, n_grids: int, ndof: int, k: sp.csr_array, m: sp.csr_array,
           keep: np.ndarray, rows_ind: np.ndarray, restrained: np.ndarray,
           nids: np.ndarray, parameters: bool) -> Reduced:
    """The reduction the deck's ASET/OMIT/QSET cards ask for, of K and M on the free
    rows ``keep`` (indices into ``rows_ind``, the rows left by rigid elements and MPCs;
    ``restrained`` in the same numbering); none without such cards."""
    analysis, q = analysis_set(bdf, where, ndof), q_set(bdf, where, n_grids)
    none = np.zeros(0, int)
    if analysis is None and q.size == 0:
        return Reduced(k, m, keep, none, none)
    what = "QSET (Craig-Bampton reduction)" if q.size else "ASET/OMIT (Guyan reduction)"
    if parameters:
        raise InputError(f"{what}: K and M of the reduced model are not linear in the "
                         f"parameters; remove the ASET/OMIT/QSET cards to update the full "
                         f"model")
    if q.size and list(bdf.omits):
        raise InputError("OMIT with QSET: with a q-set NASTRAN omits every coordinate not in "
                         "the ASET or QSET; give the boundary by ASET")
    if analysis is None:  # QSET alone: every physical coordinate omitted (QRG QSET)
        analysis = np.zeros(ndof, bool)
        analysis[set_rows(bdf, bdf.suport, where, "SUPORT")] = True
    ids = nids[q // 6]
    if analysis[q].any():
        n = ids[np.flatnonzero(analysis[q])[0]]
        raise InputError(f"QSET: SPOINT {n} is also in the a-set (ASET): NASTRAN's sets "
                         f"are exclusive")
    _check_q(q, ids, keep, rows_ind, restrained)
    analysis = analysis[rows_ind]
    kept = analysis[keep]
    gone = rows_ind[keep[~kept]]
    if q.size == 0:
        k, m = reduction.guyan(k, m, np.flatnonzero(kept))
        return Reduced(k, m, keep[kept], gone, none)
    if q.size > gone.size:
        raise InputError(f"QSET: {q.size} q-set coordinates (SPOINTs {_ids(ids)}) but "
                         f"{gone.size} omitted coordinates, each fixed-interface mode "
                         f"being one q-set coordinate: give at most {gone.size}")
    v1, v2 = _eigrl(bdf, q.size)
    k, m, lam = reduction.craig_bampton(k, m, np.flatnonzero(kept), q.size)
    hz = np.sqrt(np.maximum(lam, 0.0)) / (2 * math.pi)
    outside = np.flatnonzero((hz < v1) | (hz > v2))
    if outside.size:
        j = int(outside[0])
        raise InputError(f"QSET: fixed-interface mode {j + 1} ({hz[j]:.6g} Hz) is outside "
                         f"the EIGRL range V1 {v1:g} to V2 {v2:g} Hz: NASTRAN would fill "
                         f"the q-set with residual vectors, which are not built")
    return Reduced(k, m, keep[kept], gone, 10 * ids + 1, tuple(hz.tolist()))


def _check_q(q: np.ndarray, ids: np.ndarray, keep: np.ndarray, rows_ind: np.ndarray,
             restrained: np.ndarray) -> None:
    """The q-set SPOINTs must be free and unconnected: their rows carry the modes."""
    position = np.minimum(np.searchsorted(rows_ind, q), rows_ind.size - 1)
    for j, n in enumerate(ids):
        if rows_ind[position[j]] != q[j]:
            raise InputError(f"QSET: SPOINT {n} is dependent (an MPC or rigid element)")
        if position[j] in restrained:
            raise InputError(f"QSET: SPOINT {n} is restrained (SPC): a q-set SPOINT holds "
                             f"a fixed-interface mode")
        if position[j] in keep:
            raise InputError(f"QSET: SPOINT {n} carries stiffness or mass of an element: a "
                             f"q-set SPOINT holds a fixed-interface mode only")


def _eigrl(bdf, n_q: int) -> tuple[float, float]:
    """V1, V2 (Hz) of the EIGRL that the modes subcases' METHOD selects."""
    methods = {int(v) for sub in modal_subcases(bdf)
               if (v := case_value(sub, "METHOD")) is not None}
    if len(methods) != 1:
        got = f"METHODs {sorted(methods)}" if methods else "no METHOD"
        raise InputError(f"QSET: the fixed-interface modes are those of the EIGRL that the "
                         f"case control's METHOD selects; it has {got}")
    sid = methods.pop()
    card = bdf.methods.get(sid)
    if card is None or card.type != "EIGRL":  # EIGR is never parsed: it names no EIGRL
        raise InputError(f"QSET: METHOD {sid} names no EIGRL card (the fixed-interface "
                         f"modes are read through an EIGRL; EIGR is not)")
    nd = card.nd
    if nd is not None and nd < n_q:
        raise InputError(f"EIGRL {sid}: ND {nd} is below the {n_q} q-set coordinates: "
                         f"NASTRAN would fill the rest with residual vectors, which are not "
                         f"built")
    for value, what in ((card.v1, "V1"), (card.v2, "V2")):
        if value is not None and not math.isfinite(float(value)):  # pyNastran reads nan
            raise InputError(f"EIGRL {sid}: {what} = {float(value):g} bounds the "
                             f"fixed-interface modes of the QSET reduction: give a number")
    v1 = -math.inf if card.v1 is None else float(card.v1)
    v2 = math.inf if card.v2 is None else float(card.v2)
    return v1, v2


def _ids(ids: np.ndarray) -> str:
    ids = ids.tolist()
    return ", ".join(map(str, ids)) if len(ids) <= 4 else f"{ids[0]} ... {ids[-1]}"
