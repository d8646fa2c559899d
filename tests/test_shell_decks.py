"""CQUAD4 against MSC Nastran's printed frequencies of a shared deck (dakota_cylinder).

The deck (320 CQUAD4 + PSHELL, two RBE2 end rings, a CONM2, PARAM COUPMASS 1 and WTMASS)
is read here with pyNastran directly and assembled with the element library, the RBE2
rings eliminated as rigid links: a check of the elements on a curved shell until the deck
reader calls them. Skipped when the shared data are not on this machine.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg as sla
from nastran_frames import need

from eigenupdate.model import shells
from eigenupdate.model.assembly import node_dofs, scatter

pytestmark = pytest.mark.nastran
DECK = Path(__file__).resolve().parents[2] / "shared" / "data" / "nastran" / "dakota_cylinder"


def _skew(v):
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


@pytest.fixture(scope="module")
def cylinder():
    """Elastic frequencies (Hz) of the deck with coupled mass, and MSC's."""
    if not (DECK / "modal.bdf").exists():
        pytest.skip("shared NASTRAN decks not on this machine")
    bdf = need("pyNastran.bdf.bdf").read_bdf(str(DECK / "modal.bdf"), debug=None)
    ref = json.loads((DECK / "ref.json").read_text())
    nids = sorted(bdf.nodes)
    idx = {n: i for i, n in enumerate(nids)}
    xyz = np.array([bdf.nodes[n].get_position() for n in nids])
    quads = [e for e in bdf.elements.values() if e.type == "CQUAD4"]
    assert len(quads) == len(bdf.elements) == 320
    el = np.array([[idx[n] for n in e.node_ids] for e in quads])
    (prop,) = bdf.properties.values()
    (mat,) = bdf.materials.values()
    moduli = shells.pshell_moduli(mat.e, mat.nu, G3=mat.g, bending_ratio=prop.twelveIt3,
                                  shear_ratio=prop.tst)
    m = shells.pshell_matrices(xyz[el], prop.t, *moduli, rho=mat.rho, nsm=prop.nsm,
                               lumped=bdf.params["COUPMASS"].values[0] <= 0)
    n = 6 * len(nids)
    d = node_dofs(el, 6)
    K, M = scatter(d, m["K"], n).toarray(), scatter(d, m["M"], n).toarray()
    for conm in bdf.masses.values():
        i = 6 * idx[conm.nid]
        M[i:i + 3, i:i + 3] += conm.mass * np.eye(3)
    M *= bdf.params["WTMASS"].values[0]
    # RBE2: each dependent grid moves rigidly with the independent one
    T, dependent = np.eye(n), []
    for rbe in bdf.rigid_elements.values():
        gi = 6 * idx[rbe.gn]
        for nid in rbe.Gmi:
            j = 6 * idx[nid]
            link = np.eye(6)
            link[:3, 3:] = -_skew(xyz[j // 6] - xyz[gi // 6])
            T[j:j + 6] = 0.0
            T[j:j + 6, gi:gi + 6] = link
            dependent += range(j, j + 6)
    T = T[:, np.setdiff1d(np.arange(n), dependent)]
    K, M = T.T @ K @ T, T.T @ M @ T
    # free-free, rotations massless: largest mu of M x = mu (K + sigma M) x
    sigma = (2 * np.pi * 1000.0) ** 2
    mu = sla.eigh(M, K + sigma * M, eigvals_only=True)[::-1][:16]
    f = np.sqrt(np.abs(1 / mu - sigma)) / (2 * np.pi)
    return f, ref


def test_cylinder_has_six_rigid_body_modes(cylinder):
    """Source: the deck is free-free (MSC: 6 modes below 1e-3 Hz); ours are below 1e-6
    of the first elastic frequency's square, the shift's rounding floor."""
    f, ref = cylinder
    assert ref["n_rigid"] == 6
    assert np.all(f[:6] ** 2 <= 1e-6 * f[6] ** 2)


def test_cylinder_beam_axial_and_torsion_modes_agree_with_msc(cylinder):
    """Source: MSC Nastran 70.7's frequencies (ref.json), tolerance 1 % (the shared
    decks' tolerance for shells: formulations differ between codes). Modes 1-2 and 9-10
    (the cylinder bending as a beam), 3 and 6: measured 1.5e-4 .. 5.7e-4."""
    f, ref = cylinder
    elastic = f[6:16] / np.array(ref["elastic_hz"][:10]) - 1
    assert np.all(np.abs(elastic[[0, 1, 2, 5, 8, 9]]) <= 0.01), elastic


@pytest.mark.xfail(strict=True, reason="open: modes 4-5 and 7-8 (the circumferential "
                   "n = 2 shell modes) are 2.2-2.5 % above MSC 70.7's, mass or bending "
                   "formulation not matched")
def test_cylinder_shell_modes_agree_with_msc(cylinder):
    """Source: as above; all ten compared modes within 1 %."""
    f, ref = cylinder
    elastic = f[6:16] / np.array(ref["elastic_hz"][:10]) - 1
    assert np.all(np.abs(elastic) <= 0.01), elastic
