"""Cards of published decks that change neither K nor M of a normal-modes analysis are
skipped, not refused (issue 20, tools/deck_sweep.py over pyNastran's models/): plot
elements, gust and random tables, SOL 400/401 steps and controls, nonlinear transient and
thermal loads, radiation exchange, initial conditions, residual-vector requests. The card
lines are copied from the pyNastran decks that were refused for them (pyNastran is
BSD-3-Clause): bwb/bwb_freq.bdf (PLOTEL3, PLOTEL4), other/sdbush01.bdf (TABRNDG),
msc/force_vector/nas102_ws21.dat (NOLIN1, NOLIN4), nx/sol401/sol401_tstep1.dat (TSTEP1),
nx/z402cdamp1_04.bdf (NLCNTLG), thermal/htflw47.bdf (QBDY3, TEMPBC), thermal/hd15901.bdf
(RADMTX), other/v12902.bdf (TIC), superelements/resvec23.bdf (RVDOF1),
nx/normalized_mass_density/s200tpgext1.dat (GROUP: a set for output and optimisation;
pyNastran's reader failed on its THRU).

Independent source: the same deck without these cards (they define no element, mass or
constraint), whose K and M must be identical, bit for bit.

Run for real in .venv-nastran (``make test``); skipped in the core environment."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from nastran_frames import need

from eigenupdate.errors import EigenupdateWarning, InputError

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.io.nastran import read_nastran  # noqa: E402

# a steel cantilever of 2 CBARs with a tip mass; grids 1-3 (the cards below name grids of
# their own decks: a skipped card is never cross-referenced)
BULK = ("GRID,1,,0.,0.,0.\nGRID,2,,.5,0.,0.\nGRID,3,,1.,0.,0.\n"
        "CBAR,1,1,1,2,0.,0.,1.\nCBAR,2,1,2,3,0.,0.,1.\n"
        "PBAR,1,1,1.e-3,2.e-7,8.e-7,5.e-7\nMAT1,1,2.e11,,0.3,7800.\n"
        "CONM2,10,3,,2.\nSPC1,1,123456,1\n")
CARDS = {
    "PLOTEL3": "PLOTEL3,10,2356,7996,20032\n",
    "PLOTEL4": "PLOTEL4,20,2356,7996,20032,10342\n",
    "TABRNDG": "TABRNDG 1       1       .2      6.\n",
    "NOLIN1": "NOLIN1, 100, 1, 2, 197.4, 101, 0, 111\n",
    "NOLIN4": "NOLIN4, 100, 1, 2, -0.3, 101, 10, 2.\n",
    "TSTEP1": ("TSTEP1*              1011.0000000000E+00               3             YES+\n"
               "*\n"),
    "NLCNTLG": "NLCNTLG  STRMEAS       0  STROUT       0\n",
    "QBDY3": "QBDY3,20,.1666666,,1,2,3,4,5,+QBY1\n+QBY1,6\n",
    "TEMPBC": "TEMPBC,10,STAT,0.0,10\n",
    "RADMTX": "RADMTX  1       1       0.      0.      0.      0.      0.      0.\n",
    "TIC": "TIC,1,2,1,0.0,1.0\n",
    "RVDOF1": "RVDOF1,3,2\n",
    "GROUP": ("GROUP        222     Top Surf                                           +\n"
              "+           ELEM       1    THRU     999\n"),
}


def _read(path):
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always", EigenupdateWarning)
        nm = read_nastran(path)
    return nm, [str(w.message) for w in got]


@pytest.fixture(scope="module")
def plain(tmp_path_factory):
    path = tmp_path_factory.mktemp("plain") / "plain.bdf"
    path.write_text("SOL 103\nCEND\nSPC = 1\nBEGIN BULK\n" + BULK + "ENDDATA\n")
    return _read(path)[0].model


@pytest.mark.parametrize("card", sorted(CARDS))
def test_card_that_changes_neither_k_nor_m_is_skipped(tmp_path, plain, card):
    """Source: the deck without the card; K and M identical (exact: the same cards
    assembled), the card named with its count in the one 'skipped' note."""
    path = tmp_path / "deck.bdf"
    path.write_text("SOL 103\nCEND\nSPC = 1\nBEGIN BULK\n" + BULK + CARDS[card] + "ENDDATA\n")
    nm, notes = _read(path)
    assert np.array_equal(nm.model.coordinates, plain.coordinates)
    assert (nm.model.stiffness() != plain.stiffness()).nnz == 0
    assert (nm.model.mass() != plain.mass()).nnz == 0
    assert any(f"{card} x1" in n for n in notes if "skipped" in n), notes


def test_bolt_and_contact_stay_refused(tmp_path):
    """A BOLT (NX SOL 401/402: it ties or preloads elements) and a glue set selected by
    BGSET change K: refused with their names (nx/bolt/s402bolt304.bdf, nx/glue/n401gsh01);
    BOLTFOR, its preload, is only a load and is skipped. Card lines from those decks."""
    path = tmp_path / "deck.bdf"
    path.write_text("SOL 103\nCEND\nSPC = 1\nBGSET = 100\nBEGIN BULK\n" + BULK
                    + "BOLT           1       3     100       3      18\n"
                    "               9      10      11      12      13      14\n"
                    "BOLTFOR        1    1.E5       1\n"
                    "BGSET        101       1       2     1.5             .01\nENDDATA\n")
    with pytest.raises(InputError, match=r"not supported: BGSET x1, BOLT x1$"):
        read_nastran(path)


def test_a_heat_transfer_material_is_named_as_such(tmp_path):
    """A thermal deck's PSOLID names a MAT4 (skipped: it changes neither K nor M): the
    refusal says the deck's MAT4 are heat-transfer materials (pyNastran's
    elements/time_thermal_elements.bdf was refused with 'material 15 is not defined')."""
    grids = "".join(f"GRID,{i + 1},,{x}.,{y}.,{z}.\n" for i, (x, y, z) in enumerate(
        [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1),
         (0, 1, 1)]))
    path = tmp_path / "thermal.bdf"
    bulk = ("CEND\nBEGIN BULK\n" + grids + "CHEXA,1,5,1,2,3,4,5,6\n,7,8\n"
            "PSOLID,5,15\nMAT4,15,200.,,7800.\nENDDATA\n")
    path.write_text("SOL 101\n" + bulk)
    with pytest.raises(InputError, match=r"PSOLID 5: material 15 is not defined \(the "
                       r"deck's MAT4 are heat-transfer materials, not read for K and M\)"):
        read_nastran(path)
    path.write_text("SOL 159\n" + bulk)  # a heat transfer solution says so first
    with pytest.raises(InputError, match=r"line 1: SOL 159 is a heat transfer analysis"):
        read_nastran(path)
