"""NASTRAN's general element GENEL: a stiffness (K) or flexibility (Z) matrix between
independent coordinates UI, tied to dependent ones UD by the rigid-body matrix S.

NASTRAN-95 User's Manual, bulk data card GENEL (Autodesk Nastran's reference says the same):
with K = Z^-1 in the flexibility approach, the element's stiffness on (u_i, u_d) is ::

    [  K      -K S   ]
    [ -S^T K   S^T K S ]

K or Z is given by its lower triangle, column by column from the diagonal, in the order of
the UI list; S (m x n) row by row. "If {ud} is input but [S] is omitted, [S] is internally
calculated. In this case, {ud} must have six and only six degrees of freedom": S then maps
the six UD coordinates' rigid-body motion to the UI coordinates (NASTRAN-95's TA1CA,
S = D_i D_d^-1 with D the grids' rigid-body rows). NASTRAN-95's code also computes an S
for fewer than six UD under K (a partial rigid body, TA1CA's DMFGR branch), which its
manual does not state: refused, as is S omitted with a scalar point. GENEL has no mass.
Coordinates are in the grids' displacement systems (CD), as the model's.
"""

from __future__ import annotations

import re

import numpy as np
import scipy.linalg

from eigenupdate.budget import require
from eigenupdate.errors import InputError
from eigenupdate.io.nastran_fields import in_range
from eigenupdate.io.numbers import eigenvalues_with_slack, printed_half_unit
from eigenupdate.model.constraints import rigid_equations


def assemble_genel(bdf, grid, point, xyz, frames, k0) -> None:
    """Add every GENEL's stiffness to ``k0`` (COO triplets on the model's rows).

    ``point(n, label, c)`` is the row of grid ``n``'s component ``c`` (a scalar point's
    with ``c`` 0), ``grid(n, label)`` a grid's index in ``xyz`` and ``frames``.
    """
    for eid, e in sorted(bdf.elements.items()):
        if e.type != "GENEL":
            continue
        label = f"GENEL {eid}"
        ui = [(int(g), int(c)) for g, c in np.reshape(e.ul, (-1, 2))]
        ud = [(int(g), int(c)) for g, c in np.reshape(e.ud, (-1, 2))]
        if not ui:
            raise InputError(f"{label}: no UI coordinates (fields 4-9 and on: grid, component)")
        rows = [point(g, label, c) for g, c in ui + ud]
        seen: dict = {}
        for (g, c), r in zip(ui + ud, rows, strict=True):
            if r in seen:
                raise InputError(f"{label}: coordinate {g}-{c} is listed twice in UI/UD "
                                 f"(as {seen[r][0]}-{seen[r][1]} before)")
            seen[r] = (g, c)
        k = _stiffness(e, label, len(ui))
        s = _rigid_matrix(e, label, ui, ud, grid, xyz, frames)
        t = np.hstack([np.eye(len(ui)), -s])  # u_i - S u_d: the element's deformation
        dofs = np.asarray(rows)
        k0.add(np.repeat(dofs, dofs.size), np.tile(dofs, dofs.size), t.T @ k @ t)


def parse_error(exc: BaseException) -> str | None:
    """pyNastran's failure on a GENEL card (its first line: ``AssertionError: n_K=...``,
    re-raised as a ValueError) in NASTRAN's terms; None when it is none of these."""
    text = str(exc).strip().split("\n")[0]
    if re.match(r"AssertionError: n_(K|Z|S|UD)=", text):
        return "one of the words UD, K, Z, S appears twice"
    if text.startswith("AssertionError: ["):  # its "assert k is None, k" on a Z
        return "both K and Z are given; one of them defines the element"
    if "cannot reshape" in text:
        return ("a UI or UD grid without its component (a blank field ends the list: a "
                "scalar point's component is 0)")
    if re.search(r"'[KZS]' is not in list", text):
        return "write the words UD, K, Z, S in capitals"
    return None


_WORDS = ("UD", "K", "Z", "S")


def field_problem(fields: list[str]) -> str | None:
    """What pyNastran's GENEL reader would pass over without a word, in a GENEL's fields
    (text, upper case, "" for blank; index 0 the card's name): field 3 or the field after
    UD not blank (the QRG's layout leaves them blank; pyNastran skips them), or a value
    after a blank inside a list (pyNastran ends the list at its first blank and drops the
    rest, where the count of a UI or UD list is not checked against anything else).

    >>> field_problem(["GENEL", "2", "", "1", "0", "", "", "2", "0", "K", "1.E4"])
    "the UI list has '2' after a blank field: write the list without gaps"
    """
    if len(fields) > 2 and fields[2] and fields[2] not in _WORDS:
        return f"field 3 holds {fields[2]!r}; it is blank (UI1 is in field 4)"
    where = [(i, w) for i, w in enumerate(fields) if w in _WORDS]
    for i, w in where:
        if w == "UD" and i + 1 < len(fields) and fields[i + 1]:
            return (f"the field after UD holds {fields[i + 1]!r}; it is blank (UD1 is two "
                    f"fields after UD)")
    lists = [(3, "UI")] + [(i + (2 if w == "UD" else 1), w) for i, w in where]
    for start, name in lists:
        end = next((j for j in range(start, len(fields)) if fields[j] in _WORDS), len(fields))
        gap = next((j for j in range(start, end) if not fields[j]), end)
        extra = [x for x in fields[gap:end] if x]
        if extra and name in ("UI", "UD") and (gap - start) % 2:
            return (f"a UI or UD grid without its component ({name} grid {fields[gap - 1]}; a "
                    f"blank field ends the list: a scalar point's component is 0)")
        if extra:
            return (f"the {name} list has {extra[0]!r} after a blank field: write the list "
                    f"without gaps")
    return None


def _stiffness(e, label: str, m: int) -> np.ndarray:
    """K, or Z^-1, as a full symmetric matrix, checked: K positive semi-definite to within
    the rounding of its printed digits (a stiffness with rigid-body modes, rounded, has
    small negative eigenvalues); Z positive definite, its inverse computable."""
    flexible = e.k is None
    name = "Z" if flexible else "K"
    if flexible and (e.z is None or np.ndim(e.z) == 0):  # pyNastran's asarray(None)
        raise InputError(f"{label}: neither K nor Z is given")
    values = np.ravel(np.asarray(e.z if flexible else e.k, dtype=float))
    need = m * (m + 1) // 2
    if values.size != need:
        raise InputError(f"{label}: {name} lists {values.size} values; {m} UI coordinates need "
                         f"{need} (the lower triangle by columns; a blank field ends the list)")
    # dense m x m matrices: K (or Z), its rounding, and the eigen-solve's work copy
    mb = 3 * 8.0 * m * m / 1e6
    require("memory_mb", mb, f"{label}: {name} of {m:,} UI coordinates would take {mb:,.0f} "
            f"MB as dense matrices")
    for x in values:
        in_range(x, f"{label}: {name} entry")
    a, half = np.zeros((m, m)), np.zeros((m, m))
    # the lower triangle by columns is the upper one by rows: triu's order
    i, j = np.triu_indices(m)
    a[i, j] = a[j, i] = values
    half[i, j] = half[j, i] = [printed_half_unit(x) for x in values]
    if flexible:
        lam, tiny = eigenvalues_with_slack(a)
        if lam[0] < -tiny:
            raise InputError(f"{label}: Z is not positive definite (smallest eigenvalue "
                             f"{lam[0]:.4g})")
        if lam[0] <= tiny:
            raise InputError(f"{label}: Z is singular (smallest eigenvalue {lam[0]:.3g} of "
                             f"{lam[-1]:.4g}): K = Z^-1 does not exist")
        # the computed inverse errs by about m eps cond(Z) relative (Higham, Accuracy and
        # Stability of Numerical Algorithms, 2002, 14.1): beyond half a unit of the six
        # digits frequencies are printed to, the numbers would not be the deck's
        cond = lam[-1] / lam[0]
        if m * np.finfo(float).eps * cond > 5e-7:
            raise InputError(f"{label}: Z's condition number {cond:.3g} is too large to invert "
                             f"(K = Z^-1 would err by up to {m * np.finfo(float).eps * cond:.1g} "
                             f"relative, beyond 5e-7); give K")
        return scipy.linalg.cho_solve(scipy.linalg.cho_factor(a), np.eye(m))
    # the printed entries are within half a unit of the true ones
    lam, slack = eigenvalues_with_slack(a, half)
    if lam[0] < -slack:
        raise InputError(f"{label}: K is not positive semi-definite (smallest eigenvalue "
                         f"{lam[0]:.4g}, beyond the rounding of its printed digits {slack:.2g})")
    return a


def _rigid_matrix(e, label: str, ui: list, ud: list, grid, xyz, frames) -> np.ndarray:
    """S (m x n): given row by row, else computed from the grids' geometry for six UD."""
    m, n = len(ui), len(ud)
    given = e.s is not None and np.size(e.s) > 0
    if not given:
        if n == 0:
            return np.zeros((m, 0))
        if n != 6:
            raise InputError(f"{label}: S is omitted and UD lists {n} coordinates: NASTRAN "
                             f"computes S only for six UD coordinates (GENEL remarks); give S")
        idx = {}
        for g, _ in ui + ud:
            try:
                idx[g] = grid(g, label)
            except InputError:  # point() has found it: a scalar point
                raise InputError(f"{label}: S is omitted and {g} is a scalar point, which "
                                 f"has no rigid-body motion to compute S from; give S") from None
        try:
            eqs = rigid_equations(xyz, frames, [(idx[g], c) for g, c in ud],
                                  [(idx[g], c) for g, c in ui], label)
        except InputError:
            raise InputError(f"{label}: S is omitted and the six UD coordinates do not fix "
                             f"the element's rigid-body motion (a translation or rotation is "
                             f"left free); give S") from None
        s = np.zeros((m, n))
        where = {(idx[g], c): j for j, (g, c) in enumerate(ud)}
        for i, (_, terms) in enumerate(eqs):
            for key, v in terms:
                s[i, where[key]] = v
        return s
    if n == 0:
        raise InputError(f"{label}: S is given without a UD list (S maps the UD coordinates)")
    values = np.ravel(np.asarray(e.s, dtype=float))
    if values.size != m * n:
        raise InputError(f"{label}: S lists {values.size} values; {m} UI by {n} UD "
                         f"coordinates need {m * n} (row by row; a blank field ends the list)")
    for x in values:
        in_range(x, f"{label}: S entry")
    return values.reshape(m, n)
