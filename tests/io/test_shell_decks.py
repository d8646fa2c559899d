"""Shell and solid decks of ../shared/data/nastran/ against MSC Nastran's printed
frequencies (ref.json), read through the normal path (read_nastran: CQUAD4 + PSHELL,
RBE2 rings, CONM2, COUPMASS, WTMASS; CTETRA10 + PSOLID). Skipped when the shared data are
not on this machine (failed under CI=true, as tests/io/test_nastran_decks.py)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from nastran_frames import need
from test_nastran_decks import _errors, _ref

pytestmark = pytest.mark.nastran
need("pyNastran")


@pytest.fixture(scope="module")
def cylinder():
    return _errors("dakota_cylinder")


def test_cylinder_beam_axial_and_torsion_modes_agree_with_msc(cylinder):
    """Source: MSC Nastran 70.7's frequencies (ref.json), tolerance 1 % (ref.json's for
    shells: formulations differ between codes). Modes 1-2 and 9-10 (the cylinder bending
    as a beam), 3 and 6: measured 4e-5 .. 5.7e-4. The six rigid-body modes are found and
    excluded (the deck is free-free)."""
    err, ref = cylinder
    assert np.all(np.abs(err[[0, 1, 2, 5, 8, 9]]) <= ref["tolerance"]), err


@pytest.mark.xfail(strict=True, reason="open: modes 4-5 and 7-8 (the circumferential "
                   "n = 2 shell modes) are 2.2-2.5 % above MSC 70.7's")
def test_cylinder_shell_modes_agree_with_msc(cylinder):
    """Source: as above; all ten compared modes within 1 %."""
    err, ref = cylinder
    assert np.all(np.abs(err) <= ref["tolerance"]), err


@pytest.mark.xfail(strict=True, reason="open: two CTETRA10 with lumped mass are 7-23 % "
                   "below MSC 2005's (consistent mass: 9-40 % above)")
def test_tet10_deck_agrees_with_msc():
    """Source: MSC Nastran 2005's frequencies of pyn_tet10 (ref.json), tolerance 1 %."""
    err, ref = _errors("pyn_tet10")
    assert np.all(np.abs(err) <= ref["tolerance"]), err


def test_frequencies_command_on_the_mixed_deck(run_cli, tmp_path):
    """Source: MSC Nastran 2005's frequencies of pyn_solid_shell_bar (ref.json, 1 %),
    through the user's path: a study naming the deck, ``eigenupdate frequencies --json``
    (measured 0.30, 0.18, 0.82 %)."""
    deck, ref = _ref("pyn_solid_shell_bar")
    study = tmp_path / "study.toml"
    study.write_text(f'[model]\ntype = "nastran"\nbdf = "{deck}"\n')
    n = ref["compare_modes"]
    code, out, _ = run_cli("frequencies", study, "--modes", n, "--json")
    assert code == 0
    got = np.array(json.loads(out)["configurations"][0]["frequencies_hz"])
    assert np.all(np.abs(got / np.array(ref["elastic_hz"][:n]) - 1) <= ref["tolerance"])
