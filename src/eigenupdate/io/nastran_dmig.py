"""Direct matrix input: the DMIG matrices the case control adds to K and M.

NASTRAN adds a DMIG matrix to the structure only where the case control selects it
(MSC QRG, K2GG remark 1: "DMIG matrices will not be used unless selected"):

* ``K2GG = name`` and ``M2GG = name`` add it to the g-set stiffness and mass, before the
  constraints, scaled by PARAM CK2 and CM2 (default 1.0) and by a factor written in the
  selection (``M2GG = 1.25*MAX, MBX``). M2GG is not scaled by PARAM WTMASS (QRG M2GG
  remark: its input must be in consistent mass units or scaled by CM2). Both must be
  symmetric (DMIG IFO = 6), real, and give an off-diagonal term on one side of the
  diagonal only (DMIG remark: a term given both above and below it is fatal).
* ``B2GG``, ``B2PP``, ``K42GG`` select damping, which real modes ignore.
* ``K2PP``, ``M2PP`` add to the p-set after the constraints (extra points included):
  refused, not modelled.

A DMIG's rows and columns are (grid, component 1-6) in the grid's displacement system
(CD), or (scalar point, 0): the g-set coordinates the rest of the deck assembles into.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from eigenupdate.errors import InputError
from eigenupdate.io.nastran_deck import case_value, modal_subcases
from eigenupdate.io.nastran_fields import in_range

ADDED = {"K2GG": "CK2", "M2GG": "CM2"}
"""Selections that add a DMIG to K or M, with the PARAM that scales them."""
AFTER_CONSTRAINTS = ("K2PP", "M2PP")


def selections(bdf) -> dict[str, list[tuple[float, str]]]:
    """{K2GG or M2GG: [(factor, DMIG name), ...]} that the case control selects; every
    subcase must select the same (one model)."""
    found: dict[str, set] = {}
    # a subcase that selects none while another selects one is a different model too
    for sub in modal_subcases(bdf):
        for key in (*ADDED, *AFTER_CONSTRAINTS):
            value = case_value(sub, key)
            if value is None:
                found.setdefault(key, set()).add(None)
                continue
            if key in AFTER_CONSTRAINTS:
                if _on_extra_points(bdf, value):
                    continue  # extra points are outside the real eigenvalue problem
                raise InputError(f"case control {key} (a direct input matrix added after the "
                                 f"constraints, in the p-set) is not supported; K2GG and "
                                 f"M2GG are (and K2PP, M2PP on extra points only)")
            found.setdefault(key, set()).add(_named(value, key))
    out = {}
    for key, chosen in found.items():
        if len(chosen) > 1:
            raise InputError(f"case control selects different {key} matrices in different "
                             f"subcases (or none in some): one model needs one")
        if chosen != {None}:
            out[key] = list(chosen.pop())
    return out


def _on_extra_points(bdf, chosen) -> bool:
    """True when every DMIG ``chosen`` (the case control's value) exists and its every
    term is on EPOINTs: a K2PP or M2PP there changes the dynamic response only, not the
    real modes (NASTRAN leaves extra points out of the eigenvalue problem; fmondsp's
    K2PP = STIFF is one)."""
    epoints = set(getattr(bdf, "epoints", {}) or {})
    if not epoints:
        return False
    items = chosen.split(",") if isinstance(chosen, str) else chosen
    for item in items:  # "name", "1.25*name" or pyNastran's (factor, ..., name)
        name = (item.rpartition("*")[2] if isinstance(item, str) else str(item[-1]))
        dmig = bdf.dmig.get(name.strip().upper())
        if dmig is None:
            return False
        points = {int(g) for g, _ in np.reshape(np.asarray(dmig.GCj), (-1, 2))}
        points |= {int(g) for g, _ in np.reshape(np.asarray(dmig.GCi), (-1, 2))}
        if not points <= epoints - set(bdf.nodes) - set(bdf.spoints):
            return False
    return True


def idle_note(bdf) -> str:
    """The DMIG matrices no K2GG or M2GG selects, for the skipped cards' note."""
    chosen = {n for sel in selections(bdf).values() for _, n in sel}
    idle = sorted(set(bdf.dmig) - chosen)
    return f"DMIG {', '.join(idle)} (not selected by K2GG or M2GG)" if idle else ""


def _named(value, key: str) -> tuple[tuple[float, str], ...]:
    """pyNastran's K2GG/M2GG value ([(factor, name), ...], or the text) as
    ((factor, NAME), ...)."""
    items = value.split(",") if isinstance(value, str) else value
    out = []
    for item in items:
        if isinstance(item, str):
            factor, _, name = item.rpartition("*")
            item = (factor or 1.0, name)
        try:
            factor, name = item
            out.append((float(factor), str(name).strip().upper()))
        except (TypeError, ValueError):
            raise InputError(f"case control {key} = {value}: expected names, each with an "
                             f"optional factor (1.25*KAX)") from None
    return tuple(out)


def assemble_dmig(bdf, point: Callable[[int, str, int], int], params: Callable, k0, m0
                  ) -> None:
    """Add the selected DMIG matrices to the triplets ``k0`` (K2GG) and ``m0`` (M2GG).

    ``point(id, label, component)`` gives a grid component's or scalar point's row;
    ``params(name, default)`` reads a PARAM."""
    for key, chosen in selections(bdf).items():
        scale = params(ADDED[key], 1.0)
        in_range(scale, f"PARAM {ADDED[key]}")
        target = k0 if key == "K2GG" else m0
        for factor, name in chosen:
            dmig = bdf.dmig.get(name)
            if dmig is None:
                raise InputError(f"case control {key} = {name}: no DMIG {name} in the deck")
            rows, cols, vals = _terms(dmig, point)
            v = scale * factor * vals
            off = rows != cols
            target.add(np.concatenate([rows, cols[off]]), np.concatenate([cols, rows[off]]),
                       np.concatenate([v, v[off]]))


def _terms(dmig, point) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(row, column, value) of one triangle of a symmetric real DMIG."""
    label = f"DMIG {dmig.name}"
    if int(dmig.matrix_form) != 6:
        raise InputError(f"{label}: IFO = {dmig.matrix_form}; K2GG and M2GG need a symmetric "
                         f"matrix (IFO = 6)")
    if int(dmig.tin) not in (1, 2):
        raise InputError(f"{label}: TIN = {dmig.tin} (complex) is not supported; K2GG and "
                         f"M2GG matrices are real (TIN 1 or 2)")
    gj, gi = np.asarray(dmig.GCj, dtype=int), np.asarray(dmig.GCi, dtype=int)
    if gj.size == 0:
        return (np.zeros(0, int),) * 2 + (np.zeros(0),)
    cols = np.array([point(int(g), label, int(c)) for g, c in gj.reshape(-1, 2)])
    rows = np.array([point(int(g), label, int(c)) for g, c in gi.reshape(-1, 2)])
    vals = np.array([in_range(x, f"{label}: term") for x in np.ravel(dmig.Real)])
    seen: dict[tuple[int, int], tuple] = {}
    for r, c, a, b in zip(rows, cols, gi.reshape(-1, 2), gj.reshape(-1, 2), strict=True):
        pair = (min(r, c), max(r, c))
        if pair in seen:
            twice = "both above and below the diagonal" if r != c and seen[pair][0] != r \
                else "twice"
            raise InputError(f"{label}: the term of row GRID {a[0]} component {a[1]}, column "
                             f"GRID {b[0]} component {b[1]} is given {twice}")
        seen[pair] = (r, c)
    return rows, cols, vals
