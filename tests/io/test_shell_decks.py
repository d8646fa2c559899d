"""Shell and solid decks of ../shared/data/nastran/ against MSC Nastran's printed
frequencies (ref.json), read through the normal path (read_nastran: CQUAD4 + PSHELL,
RBE2 rings, CONM2, COUPMASS, WTMASS; CTETRA10 + PSOLID). Skipped when the shared data are
not on this machine (failed under CI=true, as tests/io/test_nastran_decks.py)."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest
import scipy.sparse.linalg as spla
from nastran_frames import need
from test_nastran_decks import _errors, _ref

from eigenupdate.errors import EigenupdateWarning
from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.io.nastran import read_nastran  # noqa: E402


def _with_normals_errors(tmp_path_factory) -> tuple[np.ndarray, dict]:
    """dakota_cylinder's errors with grid normals asked for (PARAM SNORM 20, MSC's default
    since V2001: "What's New in MSC.Nastran 2004", section 12; MSC 70.7, which printed
    the reference, had none, as a deck without PARAM SNORM reads here)."""
    deck, ref = _ref("dakota_cylinder")
    copy = tmp_path_factory.mktemp("dakota") / deck.name
    copy.write_text(deck.read_text().replace("BEGIN BULK\n", "BEGIN BULK\nPARAM,SNORM,20.\n",
                                             1))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EigenupdateWarning)
        model = read_nastran(copy).model
    n = ref["compare_modes"]
    got = solve_elastic(model.stiffness(), model.mass(), n).frequencies_hz
    return got / np.array(ref["elastic_hz"][:n]) - 1, ref


@pytest.fixture(scope="module")
def cylinder():
    return _errors("dakota_cylinder")


def test_cylinder_with_grid_normals_is_stiffer_than_msc_707(tmp_path_factory):
    """With grid normals (PARAM SNORM 20: the drilling tied on curved facets) this coarse
    (16 round), thick (T/R = 0.2) cylinder's n = 2 modes are above MSC 70.7's, which had
    none: measured +0.17 % and +1.02 % (modes 4-5, 7-8), where plain facets (the deck as
    given) give -0.36 % and -0.56 %. On a fine mesh the tied facets converge to the
    curved shell (a cylinder at R/T = 50: tests/io/test_nastran_curved_facets.py); the
    plain ones do not."""
    err, _ = _with_normals_errors(tmp_path_factory)
    assert np.all(err[[3, 4, 6, 7]] > 0), err


def test_cylinder_beam_axial_and_torsion_modes_agree_with_msc(cylinder):
    """Source: MSC Nastran 70.7's frequencies (ref.json), tolerance 1 % (ref.json's for
    shells: formulations differ between codes). Modes 1-2 and 9-10 (the cylinder bending
    as a beam), 3 and 6: measured 4e-5 .. 1.1e-3. The six rigid-body modes are found and
    excluded (the deck is free-free)."""
    err, ref = cylinder
    assert np.all(np.abs(err[[0, 1, 2, 5, 8, 9]]) <= ref["tolerance"]), err


def test_cylinder_shell_modes_agree_with_msc(cylinder):
    """Source: as above; all ten compared modes within 1 % (the deck has no PARAM SNORM:
    no grid normals, as MSC 70.7 ran it).

    The n = 2 shell modes (4-5, 7-8) were +2.55/+2.22 % above MSC with plain MITC4, as
    OpenSees' ShellMITC4 and ShellDKGQ on the same mesh (+3.0/+3.8 %, +3.0/+3.4 %):
    MSC's QUAD4 is softer on this coarse (16 x 20), thick (T/R = 0.2) cylinder. With
    MacNeal's residual bending flexibility (model/shells.py RBF_ALPHA, from MacNeal's
    QUAD4 paper, not tuned on this deck's numbers beyond choosing the shortest edge as
    the element's size: the mean edge gives -1.2/-1.3 %, the longest -2.1 %) they are
    -0.36/-0.56 %."""
    err, ref = cylinder
    assert np.all(np.abs(err) <= ref["tolerance"]), err


@pytest.mark.xfail(strict=True, reason="open: MSC 2005's lumped CTETRA10 mass is not "
                   "HRZ: -10..-23 % with it (consistent: +9..+40 %)")
def test_tet10_deck_agrees_with_msc():
    """Source: MSC Nastran 2005's frequencies of pyn_tet10 (ref.json), tolerance 1 %.

    What is known (stiffness: the 5-point rule, test above; numbers from
    tools/tet10_mass.py): a diagonal mass, the same in x, y, z at a grid, with zero at
    every corner grid and 6 free masses at the 6 free mid-edge grids reproduces all ten
    of MSC's frequencies to 2.3e-7 (10 data, 6 unknowns), so MSC 2005 lumps a CTETRA10's
    mass onto its mid-edge nodes only. The six masses sum to rho (V1 + V2 / 2) within
    3e-6 (the fit's noise: 1e-6), V the isoparametric volumes: element 1 puts the mass of
    its curved volume (14 % above its straight-edged one) on its mid-edge nodes, element
    2 exactly half of its mass on its three free ones (the edges of face G1-G2-G4). The
    deck fixes only these six nodal sums; how the three grids shared by the elements
    split is a 2-parameter family. Neither element is split evenly: element 1's unshared
    edges 1-2, 3-1, 1-4 get 0.192, 0.117, 0.206 of its mass. If element 1's straight
    opposite-edge pairs (1-2/3-4, 3-1/2-4) get equal masses, element 2's pairs (1-2/3-4,
    2-3/1-4, 3-1/2-4) get 0.1899, 0.1865, 0.1236 each, within 3e-4 of 1 / sin of the
    angle between opposite edges (0.1899, 0.1862, 0.1239); but that rule gives element 1
    0.221 and 0.100 where 0.192 and 0.117 are needed (4.6 % on the frequencies with both
    elements), so it is not MSC's rule as it stands. Largest frequency errors of rules
    tried on both elements (mid-edge nodes only, each element's mass conserved): equal
    sixths, HRZ diagonal, row sums 11.6 %; edge length 20 %, its square root 2.4 %, its
    square 63 %; Voronoi regions of the mid-edge nodes 4.5 %; corners' row sums moved to
    their edges (equally, by length, by 1/length^2, to the shortest) 2.4 .. 17 %; corner
    unknowns condensed by the element's Laplacian or elastic stiffness 5.2 .. 7.1 %;
    nearest mid-edge node of each integration point (4 .. 64 points) 5.8 .. 118 %.
    Not built until the rule is known."""
    err, ref = _errors("pyn_tet10")
    assert np.all(np.abs(err) <= ref["tolerance"]), err



def test_lumped_tet10_mass_is_said_to_differ_from_msc(tmp_path):
    """Source: the xfail above (MSC 2005 lumps a CTETRA10 on its mid-edge grids, we use
    HRZ): a deck that asks for lumped mass on CTETRA10 is told so once, naming the count
    and the first element; PARAM,COUPMASS,1 (coupled mass, which every NASTRAN shares)
    silences it."""
    deck, _ = _ref("pyn_tet10")
    with pytest.warns(EigenupdateWarning) as got:
        read_nastran(deck)
    said = [str(w.message) for w in got if "HRZ" in str(w.message)]
    assert len(said) == 1 and said[0].startswith("2 CTETRA10 (the first CTETRA 1)")
    coupled = tmp_path / deck.name
    coupled.write_text(deck.read_text().replace("BEGIN BULK", "BEGIN BULK\nPARAM,COUPMASS,1", 1))
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        read_nastran(coupled)
    assert not [w for w in got if "HRZ" in str(w.message)]

# MSC 2005's static displacements of pyn_tet10 under its unit FX at grid 2154 (SOL 111,
# FREQUENCY = 0, after augmentation with residual vectors, so K^-1 f exactly): pyNastran's
# models/complex/tet10/simple_example.f06 (commit 1d25a92, page 16), T1 T2 T3 per grid.
TET10_STATIC = {
    2136: (1.258036e-05, 7.695964e-07, 1.294139e-05),
    2154: (4.340456e-05, -1.289517e-05, 4.163720e-05),
    2161: (1.790950e-06, 3.298141e-06, -2.531172e-06),
    2191: (8.735060e-06, -2.023279e-06, 1.029112e-05),
    2259: (-4.626278e-08, -8.466152e-07, -2.370280e-06),
    2485: (-1.601899e-06, -2.378052e-06, 4.837875e-06),
    2486: (4.112244e-06, 1.731911e-06, 4.172349e-06),
    2487: (2.421974e-05, -4.759638e-06, 2.368923e-05),
    2503: (-1.301535e-06, -4.054202e-06, -7.301098e-07),
    2534: (3.151078e-06, -6.841077e-06, 1.593433e-05),
}


def test_tet10_stiffness_reproduces_msc_static_displacements():
    """Source: MSC Nastran 2005's printed displacements of pyn_tet10 (TET10_STATIC).
    Seven printed digits are 5e-7 relative per entry; K is well conditioned here (MSC
    prints a factor-diagonal ratio of 56), so the solution's error is below 1e-5 of its
    norm. Integrating CTETRA10's stiffness exactly instead (the element has one curved
    edge, 2.7 % of its length off the straight line) gives 6e-3; the 8-point degree-1
    rule 0.23: this pins down the 5-point rule."""
    deck, _ = _ref("pyn_tet10")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EigenupdateWarning)
        model = read_nastran(deck).model
    f = np.zeros(model.n)
    f[model.index(21541)] = 1.0
    u = spla.spsolve(model.stiffness().tocsc(), f)
    want = np.zeros(model.n)
    for g, t in TET10_STATIC.items():
        for c in range(3):
            want[model.index(10 * g + c + 1)] = t[c]
    assert np.linalg.norm(u - want) <= 1e-5 * np.linalg.norm(want)


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
