"""CQUAD4 against OpenSees' ShellMITC4 on the same mesh (second code).

OpenSees' ShellMITC4 is Bathe & Dvorkin's MITC4 with an ElasticMembranePlateSection
(shear factor 5/6, consistent translational mass, no rotary inertia); its membrane has
its own drilling formulation, so only out-of-plane modes of a flat plate (uncoupled from
the membrane) are compared, against the consistent-mass CQUAD4. Run in the nastran
environment (openseespy), like the frame comparisons.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla
from bounds import eigenvalue_floor
from nastran_frames import opensees
from plates import NU, RHO, E, plate_matrices, square_mesh

pytestmark = pytest.mark.nastran


@pytest.mark.parametrize("skew", [0.0, 0.3])
def test_quad4_plate_bending_matches_opensees_shellmitc4(skew, monkeypatch):
    """Source: OpenSees ShellMITC4, clamped 6 x 6 plate (a/h = 50) of squares or of
    parallelograms (x += skew y), first 6 modes. Both are MITC4 with consistent
    translational mass: they agree within the rounding floors of both eigen-solutions
    (bounds.eigenvalue_floor, x 2); the drilling penalty does not enter out-of-plane
    modes of a flat plate. (With randomly moved inner nodes the two codes differ by
    1e-4..1e-3: they tie the shear strains of a non-parallelogram differently; ours
    passes the constant-curvature patch test on such elements, test_shells.py.) Our
    CQUAD4 adds MacNeal's residual bending flexibility to MITC4 (shells.RBF_ALPHA; its
    eigenvalues 15-51 % below MITC4's here, 6 elements across at a/h 50): removed for
    this comparison of the MITC4 core."""
    from eigenupdate.model import shells

    monkeypatch.setattr(shells, "RBF_ALPHA", 0.0)
    ops = opensees()
    a, h, nx = 1.0, 0.02, 6
    xyz, el = square_mesh(nx, a, triangles=False)
    inner = ~(np.isclose(xyz[:, 0], 0) | np.isclose(xyz[:, 0], a)
              | np.isclose(xyz[:, 1], 0) | np.isclose(xyz[:, 1], a))
    xyz[:, 0] += skew * xyz[:, 1]
    edge = ~inner
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    for i, p in enumerate(xyz):
        ops.node(i + 1, *map(float, p))
        fix = [1, 1, 0, 0, 0, 1] if inner[i] else [1, 1, 1, 1, 1, 1]
        ops.fix(i + 1, *fix)
    ops.section("ElasticMembranePlateSection", 1, E, NU, h, RHO)
    for e, nodes in enumerate(el):
        ops.element("ShellMITC4", e + 1, *[int(n) + 1 for n in nodes], 1)
    lam_ops = np.sort(np.array(ops.eigen("-fullGenLapack", 6)))
    ops.wipe()

    K, M = plate_matrices(xyz, el, h, lumped=False)
    fixed = np.zeros((xyz.shape[0], 6), bool)
    fixed[:, [0, 1, 5]] = True
    fixed[edge] = True
    # rotations are massless: condense them (eigh needs M > 0) by solving on w only
    free = np.flatnonzero(~fixed.ravel())
    Kf, Mf = K.toarray()[np.ix_(free, free)], M.toarray()[np.ix_(free, free)]
    w = np.flatnonzero(free % 6 == 2)
    r = np.flatnonzero(free % 6 != 2)
    Kc = Kf[np.ix_(w, w)] - Kf[np.ix_(w, r)] @ np.linalg.solve(Kf[np.ix_(r, r)], Kf[np.ix_(r, w)])
    Mc = Mf[np.ix_(w, w)]
    lam, X = sla.eigh(Kc, Mc, subset_by_index=[0, 5])
    floor = eigenvalue_floor(Kc, Mc, lam, X)
    rel = np.abs(lam_ops / lam - 1)
    assert np.all(rel <= 2 * floor), (rel, floor)
