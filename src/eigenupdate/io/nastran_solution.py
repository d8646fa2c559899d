"""The deck's solution sequence, and the ones whose modes its K and M do not give.

The reader builds K and M as the bulk data defines them, which are the matrices of
NASTRAN's normal modes (MSC/NX SOL 103, SEMODES; NASTRAN-95 rigid format 3) and of the
sequences that start from them (dynamics, flutter, statics, buckling, optimisation).
Some sequences compute the modes of another stiffness or structure; their frequencies
would differ from what this reader gives, so such a deck is refused, naming the line:

* modes with differential stiffness (a preload): NASTRAN-95's rigid format 13, MSC/NX
  SOL 103 with STATSUB in the case control (in SOL 105 it selects the buckling load),
  SOL 106/129 with PARAM NMLOOP, SOL 400 modes after a nonlinear step (ANALYSIS = NLSTAT
  or NLTRAN), NX's SOL 401/402 modes after a static or transient subcase (sequential
  subcases: each starts from the state the previous one ended in; a subcase naming no
  ANALYSIS is taken as static, SOL 401's default), Autodesk Nastran's
  prestress solutions (``SOL LINEAR PRESTRESS MODAL``..., SOL 182-186, 188, 189; its 187
  is MSC's and NX's DDAM, whose modes are the structure's, so that number stays read);
* cyclic symmetry, where the bulk data is one segment: NASTRAN-95's rigid formats 14 and
  15, MSC/NX SOL 114-118 (CYCSTATX, CYCMODE, CYCBUCKL, CYCFREQ);
* heat transfer (APP HEAT, ANALYSIS = HEAT, SOL 153 and 159, Autodesk's ``... HEAT
  TRANSFER``): K is a conductance.

STATSUB in a subcase with ANALYSIS = BUCK (SOL 200) or written STATSUB(BUCKLING) selects
a buckling load, as in SOL 105: the deck's modes stay those of its K and M.
"""

from __future__ import annotations

import re
from pathlib import Path

from eigenupdate.errors import InputError

# a tab separates as a blank does (pyNastran reads ``SOL<tab>13`` and ``SOL 013`` as 13)
_SOL = re.compile(r"^\s*SOL(?:\s*,\s*|\s+)([A-Z0-9][A-Z0-9 \t]*)", re.IGNORECASE)
_APP = re.compile(r"^\s*APP\w*(?:\s*,\s*|\s+)(\w+)", re.IGNORECASE)
_STATSUB = re.compile(r"^\s*STATSUB\s*(\(\s*BUCK)?", re.IGNORECASE)
_SUBCASE = re.compile(r"^\s*SUBCASE\b", re.IGNORECASE)
_NMLOOP = re.compile(r"^\s*PARAM\s*[\s,*]\s*NMLOOP\b", re.IGNORECASE)
_ANALYSIS = re.compile(r"^\s*ANALYSIS\s*=\s*(\w+)", re.IGNORECASE)

_NAMES = {"SEMODES": "103", "MODES": "103", "SEBUCKL": "105", "NLSTATIC": "106",
          "CYCSTATX": "114", "CYCMODE": "115", "CYCBUCKL": "116", "CYCFREQ": "118",
          "NLTRAN": "129", "NLSCSH": "153", "NLTCSH": "159", "NONLIN": "400",
          "SEMFREQ": "111", "SEMTRAN": "112", "SEMCEIG": "110", "DESOPT": "200",
          # Autodesk Nastran's names (its solution numbers beside them)
          "LINEAR STATIC": "101", "MODAL": "103", "LINEAR BUCKLING": "105",
          "NONLINEAR STATIC": "106", "NONLINEAR TRANSIENT RESPONSE": "129",
          "NONLINEAR BUCKLING": "180", "PRESTRESS STATIC": "181"}
_PRESTRESS = {"182", "183", "184", "185", "186", "188", "189"}  # Autodesk's (not 187)
_SEQUENTIAL = {"401", "402"}  # NX: a subcase starts from the previous one's state
_CYCLIC = {"114", "115", "116", "118"}
_HEAT = {"153", "159"}
BUCKLING = {"105", "5", "180"}  # load factors, not frequencies (180: Autodesk's nonlinear)


def solution(lines: list[str], cend: int) -> tuple[str | None, int | None, int | None]:
    """(SOL as a number where it has one, its line index, the line index of NASTRAN's
    ``APP HEAT`` or None) from the executive control ``lines[:cend]``.

    >>> solution(["ID X", "APP DISPLACEMENT", "SOL   3,1", "CEND"], 3)
    ('3', 2, None)
    >>> solution(["SOL SEMODES", "CEND"], 1)
    ('103', 0, None)
    """
    sol, at, heat = None, None, None
    for i, text in enumerate(lines[:max(cend, 0)]):
        if (m := _SOL.match(text)) and sol is None:
            sol, at = _number(m.group(1)), i
        elif (m := _APP.match(text)) and m.group(1).upper() == "HEAT":
            heat = i
    return sol, at, heat


def _number(text: str) -> str:
    """A SOL's number as a string: a name's (``SEMODES``: 103), digits without leading
    zeros (``013``: 13), ``SOL 3,1``'s 3; an unknown name as it is written.

    >>> _number("013"), _number("LINEAR  PRESTRESS MODAL"), _number("3")
    ('13', 'LINEAR PRESTRESS MODAL', '3')
    """
    words = text.upper().split()
    return str(int(words[0])) if words[0].isdigit() else _NAMES.get(" ".join(words),
                                                                      " ".join(words))


def check(lines: list[str], origin: list, cend: int, bulk: int, path: Path) -> str | None:
    """Refuse a deck whose solution's modes are not those of its K and M; its SOL.

    ``lines``, ``origin`` (file name, line) as the deck ``path`` reads, ``cend`` and
    ``bulk`` the indices of CEND and BEGIN BULK (-1 and len(lines) where it has none).
    """
    sol, at, heat = solution(lines, cend)

    def refuse(i: int, what: str) -> None:
        name, number = origin[i]
        where = f"line {number}" if name == path.name else f"{name}:{number}"
        raise InputError(f"{where}: {what}, not the modes of the deck's K and M that this "
                         f"reader builds", source=str(path))

    if heat is not None:
        refuse(heat, "APP HEAT makes it a heat transfer analysis")
    _refuse_sol(sol, at, refuse)
    for i in range(cend + 1, bulk) if cend >= 0 else range(0):
        if m := _SOL.match(lines[i]):  # misplaced after CEND: judged as if before it
            _refuse_sol(_number(m.group(1)), i, refuse, " (after CEND)")
    _case_control(lines, origin, range(cend + 1, bulk) if cend >= 0 else range(0), sol,
                  refuse)
    if sol in ("106", "129"):
        for i, text in enumerate(lines):
            if _NMLOOP.match(text):
                refuse(i, f"SOL {sol} with PARAM NMLOOP computes modes of the loaded, "
                          f"deformed structure")
    return sol


def _case_control(lines: list[str], origin: list, case: range, sol: str | None,
                  refuse) -> None:
    """The case control's refusals, subcase by subcase (a SUBCASE line opens one; the
    lines above the first give every subcase's defaults)."""
    blocks: list[tuple[int | None, list[int]]] = []  # (its SUBCASE line, its lines)
    for i in case:
        if _SUBCASE.match(lines[i]) or not blocks:
            blocks.append((i if _SUBCASE.match(lines[i]) else None, []))
        blocks[-1][1].append(i)
    default = None  # the ANALYSIS above the subcases
    loaded = None  # NX SOL 401/402: the first static or transient subcase (kind, line)
    for head, rows in blocks:
        kinds = [(i, m.group(1).upper()) for i in rows if (m := _ANALYSIS.match(lines[i]))]
        for i, kind in kinds:
            if kind == "HEAT":
                refuse(i, "ANALYSIS = HEAT is a heat transfer analysis")
            if sol == "400" and kind in ("NLSTAT", "NLTRAN"):
                refuse(i, "SOL 400 modes after a nonlinear step include its stiffness")
        if head is None:
            default = kinds[0][1] if kinds else None
        own = [k for _, k in kinds] or [default or ""]
        # STATSUB(BUCKLING), or STATSUB in a buckling subcase, selects a buckling load
        statsub = next((i for i in rows if (m := _STATSUB.match(lines[i]))
                        and m.group(1) is None), None)
        if statsub is not None and sol not in BUCKLING and not any(
                k.startswith("BUCK") for k in own):
            refuse(statsub, "STATSUB asks for the modes of a preloaded structure "
                            "(differential stiffness)")
        if sol in _SEQUENTIAL and head is not None:  # STATICS when a subcase names none
            kind, at = (kinds[0][1], kinds[0][0]) if kinds else (default or "STATICS", head)
            if kind == "MODES" and loaded is not None:
                refuse(at, f"SOL {sol} modes after the ANALYSIS = {loaded[0]} subcase of "
                           f"line {loaded[1]} include its preload (NX's sequential "
                           f"subcases)")
            if kind != "MODES" and loaded is None:
                loaded = (kind, origin[at][1])


def _refuse_sol(sol: str | None, at: int | None, refuse, where: str = "") -> None:
    """Refuse the solution sequences whose modes are not those of K and M."""
    if sol in _PRESTRESS or (sol is not None and "PRESTRESS" in sol):
        refuse(at, f"SOL {sol}{where} (Autodesk Nastran's prestress solution) computes "
                   f"the modes of a preloaded structure")
    if sol in _HEAT or (sol is not None and "HEAT TRANSFER" in sol):
        refuse(at, f"SOL {sol}{where} is a heat transfer analysis")
    if sol == "13":
        refuse(at, f"SOL 13{where} (NASTRAN-95's normal modes with differential stiffness) "
                   "computes the modes of a preloaded structure")
    if sol in _CYCLIC or sol in ("14", "15"):
        refuse(at, f"SOL {sol}{where} is a cyclic symmetry analysis of one segment")
