"""Reading a NASTRAN deck as NASTRAN reads it, through pyNastran.

:func:`load_deck` expands every INCLUDE itself (:mod:`eigenupdate.io.nastran_include`: a
relative path is looked up in the directory of the file that includes it, then in the main
deck's, the job's directory where NASTRAN runs it; names and files as pre-processors
write them on Windows), hands
the text to pyNastran with its log silenced and stdout captured (no
``pyNastran_crash.bdf`` can be written: pyNastran never sees an INCLUDE), remembers where
each card starts (``file:line``) for the messages, and sorts the cards into

* supported: they define K, M or the set of coordinates and are assembled;
* skipped: they change neither K nor M (loads, tables, damping, eigenvalue methods,
  output, optimisation, aero, USET, DTI, MDLPRM, ...): listed in one note with counts;
* refused: everything else (a card that may change K or M): every such card with its
  count in one error.

pyNastran never parses a skipped card (it only counts it), so a skipped card that only
another NASTRAN writes (NASTRAN-95's ``EIGR`` with method DET or FEER) cannot stop the
reading; NASTRAN-95's executive-control ``APP`` statement (the approach: DISP, AERO),
which pyNastran does not know, is dropped as well.
"""

from __future__ import annotations

import contextlib
import io
import math
import re
import traceback
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from eigenupdate.budget import require
from eigenupdate.errors import EigenupdateWarning, InputError
from eigenupdate.io import nastran_genel as genel
from eigenupdate.io import nastran_solution
from eigenupdate.io.nastran_blame import (
    FIRST,
    blamed_card,
    card_in_traceback,
    card_starts,
    place,
    replication_line,
)
from eigenupdate.io.nastran_include import expand
from eigenupdate.io.nastran_plates95 import CARDS as PLATES95

# cards that define K, M or the coordinates and are assembled (io/nastran.py)
SUPPORTED = frozenset({
    "GRID", "GRDSET", "CORD1R", "CORD2R", "CORD1C", "CORD2C", "CORD1S", "CORD2S",
    "CBAR", "BAROR", "PBAR", "PBARL", "CBEAM", "PBEAM", "PBEAML", "CROD", "PROD", "CONROD",
    "CTUBE", "PTUBE",
    "CELAS1", "CELAS2", "PELAS", "CONM2", "CMASS1", "CMASS2", "PMASS", "MAT1",
    "SPC", "SPC1", "SPCADD", "ASET", "ASET1", "OMIT", "OMIT1", "SUPORT", "PARAM", "ENDDATA",
    "RBE1", "RBE2", "RBAR", "RROD", "RBE3", "MPC", "MPCADD", "CRIGD1", "CRIGD2", "CRIGD3",
    "CRIGDR",
    "SPOINT", "CELAS3", "CELAS4", "CMASS3", "CMASS4", "CONM1", "CBUSH", "PBUSH",
    "CQUAD4", "CTRIA3", "CQUAD8", "CTRIA6", "PSHELL", "PCOMP", "PCOMPG", "MAT8", "MAT2",
    "CHEXA", "CPENTA", "CTETRA", "CPYRAM", "PSOLID", "MAT9", "DMIG", "CSHEAR", "PSHEAR", "CQUADR",
    "CTRIAR", "QSET", "QSET1", "GENEL", *PLATES95,
})
# cards that change neither K nor M of a normal-modes analysis
SKIPPED = frozenset({
    # loads and enforced motion
    "FORCE", "FORCE1", "FORCE2", "MOMENT", "MOMENT1", "MOMENT2", "LOAD", "PLOAD", "PLOAD1",
    "PLOAD2", "PLOAD4", "PLOADX1", "GRAV", "RFORCE", "ACCEL", "ACCEL1", "TEMP", "TEMPD",
    "SPCD", "DLOAD", "RLOAD1", "RLOAD2", "TLOAD1", "TLOAD2", "LSEQ", "DAREA", "DPHASE",
    "DELAY", "SLOAD", "QBDY1", "QBDY2", "QBDY3", "QHBDY", "QVOL", "CLOAD", "PLOADX", "GMLOAD",
    "TEMPRB", "TEMPP1", "TEMPBC", "NOLIN1", "NOLIN2", "NOLIN3", "NOLIN4", "TIC", "BOLTFOR",
    # tables, damping, frequencies, time steps, eigenvalue methods
    "TABLED1", "TABLED2", "TABLED3", "TABLED4", "TABLEM1", "TABLEM2", "TABLEM3", "TABLEM4",
    "TABDMP1", "TABRND1", "TABLES1", "TABLEST", "TABLEH1", "TABLEHT", "FREQ", "FREQ1",
    "FREQ2", "FREQ3", "FREQ4", "FREQ5", "TSTEP", "TSTEPNL", "EIGRL", "EIGR", "EIGC", "EIGB",
    "EIGP", "NLPARM", "NLPCI", "RANDPS", "RANDT1", "TABRNDG", "TABLED5", "TSTEP1", "NLSTEP",
    "NLCNTL", "NLCNTL2", "NLCNTLG", "RVDOF", "RVDOF1",
    # damping (real modes ignore it) and extra points of dynamic response
    "CDAMP1", "CDAMP2", "CDAMP3", "CDAMP4", "CDAMP5", "PDAMP", "PDAMP5", "PDAMPT", "CVISC",
    "PVISC", "PBUSHT", "PELAST", "EPOINT", "TF",
    # heat transfer: thermal materials and boundary cards
    "MAT4", "MAT5", "CHBDYE", "CHBDYG", "CHBDYP", "PHBDY", "CONV", "PCONV", "RADBC",
    "RADM", "RADMT", "RADSET", "RADCAV", "RADLST", "RADMTX", "VIEW", "VIEW3D",
    # sets, output, bookkeeping (SUPORT1 is chosen by case control for rigid-body modes)
    "SUPORT1", "CBARAO", "SEQGP", "SEQSEP", "CNGRNT",
    "USET", "USET1", "DTI", "MDLPRM", "SET1", "SET2", "SET3", "ECHOON", "ECHOOFF", "OUTRCV",
    "PLOTEL", "PLOTEL3", "PLOTEL4", "PLOTEL6", "PLOTEL8", "PLOTTET", "PLOTPEN", "PLOTPYR",
    "PLOTHEX",
    "MONPNT1", "MONPNT2", "MONPNT3", "MONDSP1", "MONSUM", "MONSUM1",
    # aeroelasticity
    "AERO", "AEROS", "CAERO1", "CAERO2", "CAERO3", "CAERO4", "CAERO5", "PAERO1", "PAERO2",
    "PAERO3", "PAERO4", "PAERO5", "SPLINE1", "SPLINE2", "SPLINE3", "SPLINE4", "SPLINE5",
    "AESTAT", "AESURF", "AESURFS", "AELIST", "AEFACT", "AELINK", "AEPARM", "AECOMP",
    "AECOMPL", "TRIM", "TRIM2", "FLUTTER", "FLFACT", "MKAERO1", "MKAERO2", "DIVERG", "CSSCHD",
    "GUST",
    # optimisation
    "DESVAR", "DVPREL1", "DVPREL2", "DVMREL1", "DVMREL2", "DVCREL1", "DVCREL2", "DRESP1",
    "DRESP2", "DRESP3", "DCONSTR", "DCONADD", "DOPTPRM", "DTABLE", "DEQATN", "DLINK",
    "DVGRID", "DSCREEN", "DVPSURF", "GROUP",
    # direct matrices that only DMAP reads (aerodynamic WKK, W2GJ, FA2J...); the
    # structural ones, selected by K2GG and M2GG, are DMIG (io/nastran_dmig.py)
    "DMI",
})
# PARAMs that change K, M or the coordinates of line, spring, mass and rigid elements in
# normal modes, and are interpreted (SNORM: shells.SNORM); the others (nonlinear LGDISP,
# output and damping PARAMs) are skipped and listed
PARAMS_READ = frozenset({"WTMASS", "COUPMASS", "AUTOSPC", "K6ROT", "SNORM", "CK2", "CM2"})
# temperature-dependent tables of supported materials: used only when the case control
# selects a TEMPERATURE set (MATT1 remark 1), otherwise the MAT1/MAT8 values hold
TEMPERATURE_TABLES = frozenset({"MATT1", "MATT8"})
_TEMPERATURE = re.compile(r"^\s*TEMP", re.IGNORECASE)
_APPROACH = re.compile(r"^\s*APP\b", re.IGNORECASE)
# case control's ECHOON/ECHOOFF (MSC QRG: they turn the input echo on and off), which
# pyNastran takes for ECHO = ... and fails on (no '=')
_ECHO = re.compile(r"^\s*ECHO(ON|OFF)\b", re.IGNORECASE)
_ENDDATA = re.compile(r"^\s*ENDDATA\b", re.IGNORECASE)
_BEGIN_BULK = re.compile(r"^\s*BEGIN[\s,]+BULK\b", re.IGNORECASE)
_PLAIN_BEGIN_BULK = re.compile(r"^\s*BEGIN[\s,]+BULK\s*(\$|$)", re.IGNORECASE)  # no SUPER


@dataclass
class Deck:
    """A deck read by pyNastran, with where each card starts and what was skipped."""

    path: Path
    bdf: Any
    lines: dict = field(default_factory=dict)  # (card, id) -> "file:line"
    skipped: str = ""  # the note: "FORCE x2, MDLPRM x1, PARAM POST"
    temperature: bool = False  # the case control selects a TEMPERATURE set
    text: list = field(default_factory=list)  # every line, INCLUDEs expanded
    included: list = field(default_factory=list)  # the files INCLUDEs read (resolved)
    bulk: int = 0  # index in ``text`` of the first line given to pyNastran

    def where(self, card: str, cid: int | None = None) -> str:
        """``file:line`` of a card, or the deck's name when it is not known."""
        return self.lines.get((card, cid), self.path.name)


def _quiet_bdf():
    try:
        from pyNastran.bdf.bdf import BDF
    except ImportError:
        raise InputError("NASTRAN models need pyNastran: pip install 'eigenupdate[nastran]' "
                         "(see the README)") from None
    from cpylog import SimpleLogger  # pyNastran's logger; errors are ours to report

    bdf = BDF(log=SimpleLogger(level="critical"))
    for card in SUPPORTED:
        if card in bdf._card_parser:
            bdf._card_parser[card] = (_Blanks(bdf._card_parser[card][0],
                                              _BLANKS.get(card, ())),
                                      bdf._card_parser[card][1])
    return bdf


# fields whose being blank changes what follows a parameter (pyNastran fills them in):
# MAT1 G or NU (which follows E), PCOMP Z0 (blank: -T/2, moving with the plies), GRID CP
# and CD (blank: GRDSET's, an explicit 0 is the basic system), MAT8 G1Z/G2Z (blank:
# NASTRAN's rigid transverse shear; pyNastran puts 1e8)
_BLANKS = {"MAT1": (("G", 3), ("NU", 4)), "PCOMP": (("Z0", 2),), "PCOMPG": (("Z0", 2),),
           "GRID": (("CP", 2), ("CD", 6)), "MAT8": (("G1Z", 6), ("G2Z", 7))}


class _Blanks:
    """pyNastran's reader of one card, remembering which of ``fields`` (name, index) the
    card left blank, as ``obj.blank``: NASTRAN's rule for a blank field (e.g. MAT1's G
    follows E, a given G stays) cannot be read off the numbers pyNastran fills in.
    pyNastran's own failures on the card (a ZeroDivisionError on MAT1 NU = -1) are
    tagged with the card's name and id (``card=['MAT1', '1']``) for :func:`blamed_card`."""

    def __init__(self, cls, fields):
        self.cls, self.fields = cls, fields

    def add_card(self, card, comment=""):
        fields = [str(card.field(i) or "").strip().upper() for i in range(card.nfields)]
        for i in (i for i in range(1, len(fields) - 1) if fields[i] == "THRU"):
            a, b = fields[i - 1], fields[i + 1]
            if a.isdigit() and b.isdigit():  # else pyNastran's own message
                n = int(b) - int(a) + 1
                try:
                    if n < 1:  # pyNastran kept only the first id
                        raise InputError(f"{a} THRU {b}: the range must increase")
                    require("thru_ids", n, f"{a} THRU {b} is {n:,} ids (pyNastran lists them)")
                except InputError as exc:
                    raise ValueError(f"{exc}\ncard=['{fields[0]}', '{fields[1]}']") from None
        why = genel.field_problem(fields) if self.cls.type == "GENEL" else None
        if why:  # pyNastran would drop the field without a word
            raise ValueError(f"{why}\ncard=['{fields[0]}', '{fields[1]}']")
        try:
            obj = self.cls.add_card(card, comment=comment)
        except Exception as exc:
            lines = [x for x in str(exc).splitlines() if x.strip()]
            what = f"{type(exc).__name__}: {lines[0] if lines else ''}"
            if isinstance(exc, TypeError | AttributeError | IndexError):  # None in a sum
                what = f"pyNastran fails on the card ({what}); a blank or invalid field?"
            elif isinstance(exc, AssertionError) and not lines:  # PSHEAR T = 0: nothing said
                tb = traceback.extract_tb(exc.__traceback__)
                check = (tb[-1].line or "").removeprefix("assert ").split(", ")[0] if tb else ""
                what = (f"a field is out of range: pyNastran's check {check.replace('self.', '')!r}"
                        f" fails" if check else "a field is out of range (pyNastran's check)")
            if isinstance(exc, ZeroDivisionError) and self.cls.type == "MAT1":
                what = ("a division by zero in G = E / (2 (1 + NU)) (NU = -1, or G = 0 with "
                        "NU blank; NASTRAN needs -1 < NU <= 0.5)")
            raise ValueError(f"{what}\ncard=['{card.field(0)}', '{card.field(1)}']") from None
        obj.blank = frozenset(name for name, i in self.fields if card.field(i) in (None, ""))
        return obj


def load_deck(path: str | Path) -> Deck:
    """Read a deck (executive and case control optional) and sort its cards.

    Raises
    ------
    InputError
        The file cannot be read, pyNastran refuses a card, or the deck holds cards that
        would change K or M and are not supported (all of them, with their counts).
    """
    path = Path(path)
    lines: list[str] = []
    origin: list[tuple[str, int]] = []
    included: list[Path] = []
    expand(path.resolve(), lines, origin, (path.resolve(),), included)
    text = list(lines)
    upper = [x.upper() for x in lines]
    has_cend = any(x.strip().startswith("CEND") for x in upper)
    begins = [i for i, x in enumerate(upper) if _BEGIN_BULK.match(x)]
    # a plain one again (not MSC's partitioned BEGIN BULK SUPER = n): an INCLUDEd bulk
    # file that holds its own, whose reading NASTRAN does not document
    at = [place(":".join(map(str, origin[i])), path.name) for i in begins
          if _PLAIN_BEGIN_BULK.match(upper[i])]
    if len(at) > 1:
        raise InputError(f"{at[1]}: BEGIN BULK a second time (first at {at[0]}); an "
                         f"INCLUDEd bulk data file must not repeat it: remove one",
                         source=str(path))
    begin = begins[0] if begins else None
    first = 0
    if not has_cend and begin is not None:  # bulk data only, after BEGIN BULK
        nastran_solution.check(lines, origin, begin, begin, path)  # a SOL line before it
        first = begin + 1
        lines, origin = lines[first:], origin[first:]
    cend = next((i for i, x in enumerate(lines) if x.upper().strip().startswith("CEND")), -1)
    bulk = next((i for i, x in enumerate(lines) if _BEGIN_BULK.match(x)), len(lines))
    temperature = cend >= 0 and any(_TEMPERATURE.match(x) for x in lines[cend + 1:bulk])
    nastran_solution.check(lines, origin, cend, bulk, path)
    # a comment keeps the line numbers
    lines = ["$" + x if (i < cend and _APPROACH.match(x)) or (cend < i < bulk and _ECHO.match(x))
             else x for i, x in enumerate(lines)]
    start = bulk + 1 if bulk < len(lines) else (len(lines) if cend >= 0 else 0)
    lines, origin = _to_enddata(lines, origin, start, path.name)
    lines, origin = _one_per_card(lines, origin)
    lines[start:] = [_small_field_marker(x) for x in lines[start:]]
    _free_field_overflow(lines[start:], origin[start:], path)
    _blank_ids(lines[start:], origin[start:], path.name)
    bdf = _quiet_bdf()
    qset = any(re.match(r"QSET1?[\s,*]", x, re.IGNORECASE) for x in lines[start:])
    # EPOINT: kept apart from SPOINT; a QSET deck's EIGRL gives its fixed-interface modes
    bdf.disable_cards((SKIPPED | PLATES95) - {"EPOINT", "EIGRL" if qset else "EPOINT"})
    sink = io.StringIO()
    try:
        with contextlib.redirect_stdout(sink), contextlib.redirect_stderr(sink):
            bdf.read_bdf(io.StringIO("\n".join(lines) + "\n"), xref=False,
                         punch=not has_cend, validate=True)
    except Exception as exc:  # pyNastran raises many kinds on malformed cards
        msg = [x for x in str(exc).strip().splitlines() if x.strip()]
        blamed = blamed_card(str(exc), lines, origin, path.name) or card_in_traceback(
            exc, lines, origin, path.name)
        first = msg[0] if msg else type(exc).__name__
        if re.match(r"nodes=\[", first):  # pyNastran's validate(): a grid given twice
            first = f"a grid appears twice among its nodes {first[6:].split(';')[0]}"
        elif first == "Invalid Dependent DOFs":  # pyNastran's RROD validate()
            first = ("CMA, CMB must name one translational component (1, 2 or 3) at one end "
                     "(the Lagrange-multiplier form with both blank is not supported)")
        elif re.match(r"CORD1[RCS]\*?\s", first):  # its assert only echoes the card
            first = "G1, G2 and G3 must be three different grids (QRG CORD1R/C/S)"
        elif re.search(r"GENEL \d+$", blamed or "") and genel.parse_error(exc):
            first = genel.parse_error(exc)
        elif type(exc).__name__ == "ReplicationError":  # its message names no line
            blamed = replication_line(lines, origin, path.name)
            first = ("free-field replication ('=' card): pyNastran expands at most two '=' "
                     "cards in a row ('=n' repeats are read); write the cards out")
        elif isinstance(exc, TypeError | AttributeError | IndexError):  # its own failure
            first = (f"pyNastran fails on the card ({type(exc).__name__}: {first}); a "
                     f"blank or invalid field?")
        if blamed:
            raise InputError(f"{blamed}: {first}", source=str(path)) from None
        raise InputError(f"pyNastran cannot read the deck: {type(exc).__name__}: {first}",
                         source=str(path)) from None
    _grdset_defaults(bdf)
    _implicit_spoints(bdf)
    deck = Deck(path, bdf, card_starts(lines, origin), text=text, included=included,
                bulk=first, temperature=temperature)
    _sort_cards(deck)
    return deck


def _to_enddata(lines: list[str], origin: list, start: int, main: str) -> tuple[list, list]:
    """The lines up to the bulk data's ENDDATA (QRG ENDDATA: the end of the Bulk Data
    Section; NASTRAN and pyNastran read nothing after it), with a warning naming what
    follows it where that holds data (a bulk file INCLUDEd with its own ENDDATA ends the
    deck there: the main deck's cards after the INCLUDE are not read)."""
    end = next((i for i in range(start, len(lines)) if _ENDDATA.match(lines[i])), None)
    if end is None:
        return lines, origin
    after = [i for i in range(end + 1, len(lines)) if lines[i].strip() and not  # a second
             lines[i].lstrip().startswith("$") and not _ENDDATA.match(lines[i])]  # ENDDATA
    if after:
        warnings.warn(f"{place(':'.join(map(str, origin[end])), main)}: ENDDATA ends the "
                      f"bulk data: {len(after)} line(s) after it are not read, from "
                      f"{place(':'.join(map(str, origin[after[0]])), main)} "
                      f"({lines[after[0]].strip()[:24]!r})", EigenupdateWarning, stacklevel=3)
    return lines[:end + 1], origin[:end + 1]


# NASTRAN-95's scalar elements that may define two elements on one card (User's Manual,
# CELAS3 remark 3: "one or two scalar springs may be defined on a single card")
_TWO_PER_CARD = ("CELAS3", "CELAS4", "CMASS3", "CMASS4", "CDAMP3", "CDAMP4")


def _one_per_card(lines: list[str], origin: list) -> tuple[list[str], list]:
    """A small-field or free-field card of _TWO_PER_CARD with fields 6-9 given, as two
    cards (pyNastran reads one), both at the original line."""
    out, where = [], []
    for text, at in zip(lines, origin, strict=True):
        name = text[:8].split(",")[0].strip().upper()
        if name in _TWO_PER_CARD:
            fields = ([x.strip() for x in text.split(",")] if "," in text[:10]
                      else [text[i:i + 8].strip() for i in range(0, 72, 8)])
            if any(fields[5:9]):
                out += [",".join(fields[:5]), ",".join([name, *fields[5:9]])]
                where += [at, at]
                continue
        out.append(text)
        where.append(at)
    return out, where


def _small_field_marker(line: str) -> str:
    """A small-field line whose continuation field (columns 73-80) holds a ``*`` (the
    marker of a large-field continuation that follows, NASTRAN-95's d11011a), with ``+``
    there: pyNastran reads any line with a ``*`` anywhere as large field (16-column fields:
    ``UD_1 = '1       3'``); NASTRAN takes field 1 alone to say so.

    >>> _small_field_marker("+2      UD              1       1" + " " * 40 + "*30").strip()[-3:]
    '+30'
    """
    if "*" not in line[72:80] or "*" in line[:72] or "," in line or "\t" in line:
        return line
    return line[:72] + line[72:80].replace("*", "+") + line[80:]


_NUMBER = re.compile(r"^[-+]?(\d+\.?\d*|\.\d+)([eEdD]?[-+]?\d+)?$")


def param(bdf, name: str, default):
    """PARAM ``name``'s value (``default`` where the deck sets none): a finite number
    unless ``default`` is text; SNORM an angle of at most 180 degrees."""
    p = bdf.params.get(name)
    if p is None:
        return default
    v = p.values[0]
    if isinstance(default, str):
        return v
    v = float(v)
    if not math.isfinite(v):  # pyNastran reads "nan", which no "> 0" test stops
        raise InputError(f"PARAM {name}: {v} is not a finite number")
    if name == "SNORM" and v > 180:  # cos(radians(380)) is cos(20 degrees)
        raise InputError(f"PARAM {name}: {v:g} degrees is more than 180, the largest angle "
                         f"between two normals")
    return v


def _kinds(kind: str, cards: str) -> dict[str, str]:
    return dict.fromkeys(cards.split(), kind)


# cards whose field 1 is their own id, which NASTRAN requires (QRG), and what it numbers;
# pyNastran's "eid = None (field #1)" named neither the card nor the line (nor the
# INCLUDEd file: the main deck was blamed)
_ID_FIELD = {
    "GRID": "grid",
    **_kinds("element (EID)", "CBAR CBEAM CROD CONROD CTUBE CELAS1 CELAS2 CELAS3 CELAS4 "
                              "CMASS1 CMASS2 CMASS3 CMASS4 CONM1 CONM2 CBUSH GENEL CQUAD4 CTRIA3 "
                              "CQUAD8 CTRIA6 CHEXA CPENTA CTETRA CPYRAM CSHEAR RBE2 RBAR RBE3 "
                              "CRIGD1 CRIGD2 CRIGD3 CRIGDR CQUAD1 CQUAD2 CTRIA1 CTRIA2"),
    **_kinds("property (PID)", "PBAR PBARL PBEAM PBEAML PROD PTUBE PELAS PMASS PBUSH PSHELL "
                               "PCOMP PCOMPG PSOLID PSHEAR PQUAD1 PQUAD2 PTRIA1 PTRIA2"),
    **_kinds("material (MID)", "MAT1 MAT2 MAT8 MAT9"),
    **_kinds("set (SID)", "SPC SPC1 SPCADD MPC MPCADD EIGRL EIGR"),
    **_kinds("coordinate system (CID)", "CORD1R CORD1C CORD1S CORD2R CORD2C CORD2S"),
}


def _blank_ids(lines: list[str], origin: list, main: str) -> None:
    """A card of _ID_FIELD whose id is blank, named by its file and line."""
    for text, (name, number) in zip(lines, origin, strict=True):
        m = FIRST.match(text)
        kind = _ID_FIELD.get(m.group(1).upper()) if m else None
        if kind is None:
            continue
        body = text.split("$")[0].expandtabs(8)  # a tab moves to the next field, as pyNastran
        if "," in body[:10]:
            ident = (body.split(",") + [""])[1]
        else:
            ident = body[8:24] if m.group(2) else body[8:16]
        if not ident.strip():
            raise InputError(f"{place(f'{name}:{number}', main)}: {m.group(1).upper()}: the "
                             f"id (field 1) is blank; every {kind.split(' (')[0]} needs an id"
                             + (f" ({kind.split(' (')[1]}" if " (" in kind else ""))


def _free_field_overflow(lines: list[str], origin: list, path: Path) -> None:
    """Refuse data beyond a free-field line's continuation field (its 10th field, the 6th
    of a large-field ``*`` one): pyNastran drops such data without a word (an SPC1 listing
    nine grids on one free-field line lost the last three). A fixed-field line is read to
    column 80 by NASTRAN and pyNastran alike: text beyond it is only warned about (a
    ZAERO deck keeps its continuation markers there). A number alone in a continuation
    field that continues nothing is warned about (``GRID*,2,,1.,2.,3.`` loses z)."""
    card = ""
    data = [i for i, x in enumerate(lines) if x.strip() and not x.startswith("$")]
    follows = {i: lines[j][:1] in ("+", "*", ",", " ")
               for i, j in zip(data, data[1:], strict=False)}
    for i, (text, (name, number)) in enumerate(zip(lines, origin, strict=True)):
        body = text.split("$")[0].rstrip()
        if not body.strip():
            continue
        at = f"line {number}" if name == path.name else f"{name}:{number}"
        if "," in body[:10]:
            fields = [f.strip() for f in body.split(",")]
            while len(fields) > 1 and not fields[-1]:
                fields.pop()
            last = 6 if fields[0].startswith("*") or fields[0].endswith("*") else 10
            lost = fields[last:]
            cont = fields[last - 1] if len(fields) == last else ""
            where = f"field {last} of a free-field line"
        else:  # fixed field: 80 columns, 73-80 the continuation field
            fields = [body[:8].strip()]
            lost = []
            cont = body[72:80].strip()
            where = "columns 73-80 of a fixed-field line"
            if len(body) > 80:  # NASTRAN reads 80 columns and so does pyNastran: no misreading
                warnings.warn(f"{path.name}: {at}: columns 81-{len(body)} are not read "
                              f"({body[80:].strip()[:20]!r})", EigenupdateWarning, stacklevel=2)
        if fields[0][:1].isalpha():
            card = fields[0].upper().rstrip("*")
        if lost:
            raise InputError(
                f"{at}: {card or 'card'}: data beyond the continuation field ({where}): "
                f"NASTRAN does not read {', '.join(repr(f) for f in lost)}; continue the "
                f"card on the next line", source=str(path))
        if cont and not follows.get(i, False) and _NUMBER.match(cont):
            warnings.warn(f"{path.name}: {at}: {card}: {cont!r} is in the continuation "
                          f"field ({where}), which NASTRAN does not read as data: it is "
                          f"ignored", EigenupdateWarning, stacklevel=2)


def _implicit_spoints(bdf) -> None:
    """Scalar points named only by scalar elements (QRG SPOINT: a scalar point on the
    connection entry of a scalar element need not be on an SPOINT entry): CELAS3/4 and
    CMASS3/4 connect scalar points only, CELAS1/2 and CMASS1/2 where a component is 0
    or blank."""
    named = set()
    for e in [*bdf.elements.values(), *bdf.masses.values()]:
        if e.type in ("CELAS3", "CELAS4", "CMASS3", "CMASS4"):
            named.update(n for n in e.nodes if n)
        elif e.type in ("CELAS1", "CELAS2", "CMASS1", "CMASS2"):
            named.update(n for n, c in zip(e.nodes, (e.c1, e.c2), strict=True)
                         if n and not c)
    new = sorted(named - set(bdf.nodes) - set(bdf.spoints) - set(bdf.epoints))
    if new:
        bdf.add_spoint(new)


def _grdset_defaults(bdf) -> None:
    """GRDSET's CP and CD into every GRID that left the field blank (QRG GRDSET: its
    fields are the defaults of blank GRID fields; PS is merged where the SPCs are read)."""
    gs = bdf.grdset
    if gs is None:
        return
    for g in bdf.nodes.values():
        blank = getattr(g, "blank", frozenset())
        if gs.cp and "CP" in blank:
            g.cp = gs.cp
        if gs.cd and "CD" in blank:
            g.cd = gs.cd


def _unused_properties(bdf) -> set[str]:
    """Property card types no element names: they cannot change K or M."""
    used = {getattr(e, "pid", None) for e in [*bdf.elements.values(), *bdf.masses.values()]}
    kinds: dict = {}
    for pid, p in [*bdf.properties.items(), *bdf.properties_mass.items()]:
        kinds.setdefault(p.type, set()).add(pid)
    return {k for k, pids in kinds.items() if not pids & used}


def _sort_cards(deck: Deck) -> None:
    bdf = deck.bdf
    counts = dict(bdf.card_count)  # rejected cards are counted here too
    unused = SKIPPED if deck.temperature else SKIPPED | TEMPERATURE_TABLES
    skipped = {k: v for k, v in counts.items() if k in unused  # QSET's modes are EIGRL's
               and not (k == "EIGRL" and counts.keys() & {"QSET", "QSET1"})}
    refused = {k: v for k, v in counts.items() if k not in unused and k not in SUPPORTED}
    unused_props = [f"{k} x{refused.pop(k)} (no element uses it)"
                    for k in sorted(refused.keys() & _unused_properties(bdf))]
    params = []
    for name in sorted(bdf.params):
        if name not in PARAMS_READ:
            params.append(f"PARAM {name}")
    if refused:
        listing = ", ".join(f"{k} x{v}" for k, v in sorted(refused.items()))
        if refused.keys() & TEMPERATURE_TABLES:
            listing += " (the case control selects a TEMPERATURE set)"
        raise InputError(f"cards that would change K or M and are not supported: {listing}",
                         source=str(deck.path))
    parts = [f"{k} x{v}" for k, v in sorted(skipped.items())] + unused_props + params
    deck.skipped = ", ".join(parts)


def modal_subcases(bdf) -> list:
    """The subcases whose selections (SPC, MPC, K2GG, M2GG) make the normal-modes model:
    those with ANALYSIS = MODES where a multi-analysis deck has any (NX's SOL 111 with a
    modes subcase and a base-excitation one holding another SPC set), else all of them;
    the global subcase 0 only where there is no other (pyNastran copies its selections
    into the others, which may replace them); only the one the study names where it
    names one (``bdf.eigenupdate_subcase``, set by read_nastran)."""
    cc = bdf.case_control_deck
    if cc is None:
        return []
    chosen = getattr(bdf, "eigenupdate_subcase", None)  # the study's [model] subcase
    if chosen is not None:
        if chosen not in cc.subcases or chosen < 1:
            raise InputError(f"subcase {chosen} is not in the case control (its subcases: "
                             f"{sorted(i for i in cc.subcases if i > 0) or 'none'})",
                             field="model.subcase")
        return [cc.subcases[chosen]]
    subs = [s for i, s in cc.subcases.items() if i > 0] or list(cc.subcases.values())
    modes = [s for s in subs if str(case_value(s, "ANALYSIS") or "").upper() == "MODES"]
    return modes or subs


def case_value(sub, key: str):
    """A case control command's value in a subcase, None where it has none."""
    try:
        return sub.get_parameter(key)[0]
    except KeyError:
        return None
