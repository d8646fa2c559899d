"""NASTRAN-95's plates CQUAD1, CQUAD2, CTRIA1, CTRIA2 with PQUAD1, PQUAD2, PTRIA1, PTRIA2,
read as the CQUAD4/CTRIA3 and PSHELL they amount to (NASTRAN-95 User's Manual, bulk data).

pyNastran does not read NASTRAN-95's cards (its CQUAD1 is another card), so
:mod:`eigenupdate.io.nastran_deck` leaves them to pyNastran's rejected lines and
:func:`read_plates` turns each into pyNastran's CQUAD4, CTRIA3 or PSHELL object whose
``type`` is the deck's card: every later path (offsets, mass, COUPMASS, parameters,
checks) is the PSHELL one, and messages name the deck's card and id.

* PQUAD1, PTRIA1 (PID MID1 T1 MID2 I MID3 T3 NSM): PSHELL MID1, T = T1 (which also gives
  the structural mass, remark 3), MID2 with 12I/T^3 = 12 I / T1^3, MID3 with TS/T = T3 / T1,
  NSM. T3 = 0 or MID3 = 0 is rigid in transverse shear (remark 2), as PSHELL with MID3
  blank; I = 0 leaves out bending, as NASTRAN-95's KTRIQD skips the plate part.
* PQUAD2, PTRIA2 (one or two PID MID T NSM): MID1 = MID2 = MID3 = MID, T, I = T^3 / 12
  (12I/T^3 = 1) and transverse shear thickness T (remark 2): TS/T = 1, not PSHELL's 5/6
  (KTRIQD passes T as the plate's T2, and KTRBSC's shear stiffness is G T2).
* CQUAD1, CQUAD2, CTRIA1, CTRIA2 (EID PID G1.. TH): PID blank is EID; TH is the
  material angle from the G1-G2 side, as CQUAD4's THETA.
* Refused: a transverse shear material other than MAT1, and a MID1/MID2 MAT1 whose
  given G is not E / (2 (1 + NU)) (:func:`_plane_shear`).
"""

from __future__ import annotations

from eigenupdate.errors import InputError
from eigenupdate.io.nastran_fields import in_range
from eigenupdate.io.nastran_rejected import card_fields, card_name

# element card -> (its property card, corners, the card it is read as)
ELEMENTS = {"CQUAD1": ("PQUAD1", 4, "CQUAD4"), "CQUAD2": ("PQUAD2", 4, "CQUAD4"),
            "CTRIA1": ("PTRIA1", 3, "CTRIA3"), "CTRIA2": ("PTRIA2", 3, "CTRIA3")}
PROPERTIES = ("PQUAD1", "PQUAD2", "PTRIA1", "PTRIA2")
CARDS = frozenset(ELEMENTS) | frozenset(PROPERTIES)
READ_AS = {**{k: v[2] for k, v in ELEMENTS.items()}, **dict.fromkeys(PROPERTIES, "PSHELL")}


class _Card:
    """One rejected card's fields read with pyNastran's field parsers (NASTRAN's real
    numbers: ``3.0+7``, ``.5``), each failure one line naming the card."""

    def __init__(self, name: str, fields: list[str]):
        from pyNastran.bdf.bdf_interface import assign_type
        from pyNastran.bdf.bdf_interface.bdf_card import BDFCard

        self.name, self.label = name, f"{name} {fields[0] if fields else ''}".strip()
        self.card, self.assign = BDFCard([name, *fields]), assign_type

    def get(self, kind: str, i: int, what: str, *default):
        try:
            return getattr(self.assign, kind)(self.card, i, what, *default)
        except SyntaxError as exc:
            raise InputError(f"{self.label}: {str(exc).splitlines()[0]}") from None

    def blank(self, i: int) -> bool:
        return self.card.field(i) in (None, "")


def _pshell(c: _Card, base: int):
    """The PSHELL a PQUAD1/PTRIA1 or one PID MID T NSM set of a PQUAD2/PTRIA2 amounts to."""
    from pyNastran.bdf.cards.properties.shell import PSHELL

    pid = c.get("integer", base, "PID")
    c.label = f"{c.name} {pid}"
    _positive(c, pid, "PID")
    if c.name in ("PQUAD2", "PTRIA2"):
        mid = c.get("integer", base + 1, "MID")
        t = c.get("double", base + 2, "T")
        nsm = c.get("double_or_blank", base + 3, "NSM", 0.0)
        _positive(c, t, "T")
        return PSHELL(pid, mid1=mid, t=t, mid2=mid, twelveIt3=1.0, mid3=mid, tst=1.0,
                      nsm=nsm)
    mid1 = c.get("integer", 2, "MID1")
    t1 = c.get("double", 3, "T1")
    mid2 = c.get("integer_or_blank", 4, "MID2", 0)
    inertia = c.get("double_or_blank", 5, "I", 0.0)
    mid3 = c.get("integer_or_blank", 6, "MID3", 0)
    t3 = c.get("double_or_blank", 7, "T3", 0.0)
    nsm = c.get("double_or_blank", 8, "NSM", 0.0)
    _positive(c, t1, "T1")
    for value, what in ((inertia, "I"), (t3, "T3")):
        if not value >= 0:
            raise InputError(f"{c.label}: {what} = {value:g} must be >= 0")
        in_range(value, f"{c.label}: {what}")  # 12 I / T1^3 and T3 / T1 stay finite
    if inertia > 0 and mid2 <= 0:
        raise InputError(f"{c.label}: I = {inertia:g} needs MID2 (bending material)")
    bending = inertia > 0  # I = 0: no plate part (NASTRAN-95's KTRIQD)
    shear = bending and mid3 > 0 and t3 > 0  # else rigid in transverse shear (remark 2)
    return PSHELL(pid, mid1=mid1, t=t1, mid2=mid2 if bending else None,
                  twelveIt3=12.0 * inertia / t1**3 if bending else 1.0,
                  mid3=mid3 if shear else None, tst=t3 / t1 if shear else 0.833333, nsm=nsm)


def _positive(c: _Card, value: float, what: str) -> None:
    if not value > 0:
        raise InputError(f"{c.label}: {what} = {value:g} must be > 0")
    in_range(value, f"{c.label}: {what}")  # T1^3 neither overflows nor underflows to 0


def _plane_shear(c: _Card, bdf, p) -> None:
    """Refuse a MID1/MID2 MAT1 whose given G is not E / (2 (1 + NU)): NASTRAN-95's MAT
    routine gives these plates that G as in-plane shear modulus (premat.f, G33 = G),
    CQUAD4 and CTRIA3 E / (2 (1 + NU)). 1e-5 accepts a G consistent to an 8-character
    field's digits (each rounded by at most 5e-7)."""
    for mid in {p.mid1, p.mid2} - {None, 0}:
        m = bdf.materials.get(mid)
        if m is None or m.type != "MAT1" or not (m.e or 0) > 0 or not (m.g or 0) > 0:
            continue
        g = m.e / (2 * (1 + (m.nu or 0.0)))
        if abs(m.g - g) > 1e-5 * m.g:
            raise InputError(f"{c.label}: MAT1 {mid}'s G = {m.g:g} is not E / (2 (1 + NU)) "
                             f"= {g:g}: NASTRAN-95 takes that G for in-plane shear, which "
                             f"the plate read as CQUAD4/CTRIA3 does not (not supported)")


# the last field of each card's layout (PQUAD1/PTRIA1: Z1, Z2 on the continuation)
_LAST = {"CQUAD1": 7, "CQUAD2": 7, "CTRIA1": 6, "CTRIA2": 6, "PQUAD1": 10, "PTRIA1": 10,
         "PQUAD2": 8, "PTRIA2": 8}


def _no_extra_fields(c: _Card) -> None:
    """Refuse data beyond the card's layout (an MSC-style ZOFFS, a third property): it
    would be dropped without a word."""
    extra = [i for i in range(_LAST[c.name] + 1, c.card.nfields) if not c.blank(i)]
    if extra:
        raise InputError(f"{c.label}: field {extra[0] + 1} = {c.card.field(extra[0])!r} is "
                         f"beyond the card's fields (NASTRAN-95 User's Manual {c.name})")


def _element(c: _Card):
    from pyNastran.bdf.cards.elements.shell import CQUAD4, CTRIA3

    prop, n, _ = ELEMENTS[c.name]
    eid = c.get("integer", 1, "EID")
    c.label = f"{c.name} {eid}"
    _positive(c, eid, "EID")
    pid = c.get("integer_or_blank", 2, "PID", eid)  # blank: EID (User's Manual)
    _positive(c, pid, "PID")
    nids = [c.get("integer", 3 + k, f"G{k + 1}") for k in range(n)]
    theta = c.get("double_or_blank", 3 + n, "TH", 0.0)
    in_range(theta, f"{c.label}: TH")  # pyNastran's parser reads nan, CQUAD4's does not
    cls = CQUAD4 if n == 4 else CTRIA3
    return cls(eid, pid, nids, theta_mcid=theta), prop


def read_plates(deck) -> None:
    """Add the deck's NASTRAN-95 plates (pyNastran's rejected lines) to its BDF as
    CQUAD4/CTRIA3 and PSHELL objects typed with the deck's card; refuse a missing or
    wrong property, a blank or invalid field, T or T1 <= 0 and a repeated id."""
    bdf = deck.bdf
    cards = []
    for raw in getattr(bdf, "reject_lines", []):
        lines = [x for x in raw if x.strip() and not x.startswith("$")]
        name = card_name(lines[0]) if lines else ""
        if name in CARDS:
            cards.append(_Card(name, card_fields(lines)))
            _no_extra_fields(cards[-1])
    counted = {n: bdf.card_count.get(n, 0) for n in CARDS}
    for n, count in counted.items():  # a card not recognised above would be lost
        if count != sum(c.name == n for c in cards):
            raise InputError(f"{n}: {count} cards in the deck but "
                             f"{sum(c.name == n for c in cards)} read (an unusual form of "
                             f"the card's name field?)")
    props: dict = {}
    for c in (c for c in cards if c.name in PROPERTIES):
        two = c.name in ("PQUAD2", "PTRIA2") and any(not c.blank(i) for i in (5, 6, 7, 8))
        bases = [1, 5] if two else [1]
        for base in bases:
            if base > 1:  # the second property on the card: its line is the card's
                first, second = (str(c.card.field(i) or "").strip() for i in (1, base))
                if first.isdigit() and second.isdigit():
                    deck.lines.setdefault((c.name, int(second)),
                                          deck.lines.get((c.name, int(first))))
            p = _pshell(c, base)
            p.type = c.name
            if p.pid in props or p.pid in bdf.properties or p.pid in bdf.properties_mass:
                other = props.get(p.pid) or bdf.properties.get(p.pid) or \
                    bdf.properties_mass[p.pid]
                raise InputError(f"{c.label}: property id {p.pid} is also {other.type} "
                                 f"{p.pid}'s")
            _plane_shear(c, bdf, p)
            shear = bdf.materials.get(p.mid3) if p.mid3 else None
            if shear is not None and shear.type != "MAT1":
                raise InputError(f"{c.label}: transverse shear material {shear.type} "
                                 f"{p.mid3}: only MAT1 is read here (NASTRAN-95's "
                                 f"anisotropic shear convention is not checked)")
            props[p.pid] = p
    elements: dict = {}
    for c in (c for c in cards if c.name in ELEMENTS):
        e, want = _element(c)
        e.type = c.name
        p = props.get(e.pid) or bdf.properties.get(e.pid)
        if p is None or p.type != want:
            have = f" (property {e.pid} is a {p.type})" if p is not None else ""
            raise InputError(f"{c.label}: {want} {e.pid} is not defined{have}")
        others = (elements, bdf.elements, bdf.masses, bdf.rigid_elements)
        other = next((d[e.eid] for d in others if e.eid in d), None)
        if other is not None:
            raise InputError(f"{c.label}: element id {e.eid} is also {other.type} {e.eid}'s")
        elements[e.eid] = e
    bdf.properties.update(props)
    bdf.elements.update(elements)
