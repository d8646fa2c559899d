"""Membrane-bending coupling B of unsymmetric laminates on CQUAD4 (MITC4) and CTRIA3
(MITC3): rigid-body modes, the patch test with N = B kappa and M = B eps, and the
antisymmetric cross-ply [0/90] plate against the Navier solution of laminate theory
with coupling (Whitney; Reddy), with mesh convergence."""

from __future__ import annotations

import numpy as np
import pytest
from bounds import BACKWARD, EPS
from laminate_plates import RHO, element_stiffness, fe_plate, navier_coupled, stack
from plates import constant_strain_state
from shell_patch import PATCH_QUADS, PATCH_TRIAS, PATCH_XY, assert_inner_nodes_follow

from eigenupdate.model import shells
from eigenupdate.model.assembly import node_dofs, scatter

AREA = 0.24 * 0.12


def _patch_stiffness(elements, angles, t, z0, seed):
    q, r = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    Q = q * np.sign(np.diag(r))
    Q[:, 2] *= np.linalg.det(Q)  # a rotation (a reflection would turn rotations' sense)
    xyz = np.column_stack([PATCH_XY, np.zeros(8)]) @ Q.T + np.array([1.0, -2.0, 0.5])
    K = element_stiffness(xyz[elements], angles, t, z0, Q[:, 0])
    return scatter(node_dofs(elements, 6), K, 6 * 8).toarray(), Q


UNSYMMETRIC = [((0.0, 90.0), None), ((30.0, -45.0, 60.0), None), ((0.0,), 0.0)]
IDS = ["0-90", "30-45-60", "offset-Z0"]


@pytest.mark.parametrize("elements", [PATCH_QUADS, PATCH_TRIAS], ids=["quad4", "tria3"])
@pytest.mark.parametrize("angles,z0", UNSYMMETRIC, ids=IDS)
def test_free_unsymmetric_patch_has_six_rigid_body_modes(elements, angles, z0):
    """Source: a free elastic body has exactly six zero-energy motions, coupling or
    not (B couples strains, which rigid motions do not make). Zero eigenvalues of a
    backward-stable eigh are below BACKWARD eps ||K|| (100 of room, over the 48 rows);
    the smallest elastic one (a bending mode of the stiff fibre laminate, 6e-11 ||K||
    for one [0/90] CQUAD4, plies 0.01 thick) is above 10 times that. (A CQUAD4 coupling
    from compatible membrane strains only, against its condensed membrane, failed here:
    one negative eigenvalue, -1e4 against ||K|| = 3e9.)"""
    t = 0.01
    abdh = stack(angles, t, z0)
    assert np.abs(abdh[1]).max() > 1e-3 * np.abs(abdh[0]).max() * t  # B != 0 indeed
    for el in (elements[:1], elements):
        K, _ = _patch_stiffness(el, angles, t, z0, 1)
        used = np.unique(el)
        dofs = node_dofs(used[:, None], 6).ravel()
        K = K[np.ix_(dofs, dofs)]
        lam = np.linalg.eigvalsh(K)
        zero = 1e2 * BACKWARD * EPS * np.abs(lam).max()
        assert np.sum(np.abs(lam) <= zero) == 6, lam[:8]
        assert np.all(lam[6:] > 10 * zero), lam[:8]


def _state(xy, which, Q):
    local = constant_strain_state(xy, which)
    return np.column_stack([local[:, :3] @ Q.T, local[:, 3:] @ Q.T]).ravel()


# the constant states of plates.constant_strain_state in element (patch) axes
EPS_STATE = 1e-3 * np.array([2.0, 3.0, 1.5])  # u,x, v,y, u,y + v,x
KAPPA_STATE = 1e-3 * np.array([-4.0, -2.0, -3.0])  # ry,x, -rx,y, ry,y - rx,x


@pytest.mark.parametrize("elements", [PATCH_QUADS, PATCH_TRIAS], ids=["quad4", "tria3"])
@pytest.mark.parametrize("angles,z0", UNSYMMETRIC, ids=IDS)
def test_patch_test_gives_n_equal_b_kappa_and_m_equal_b_eps(elements, angles, z0):
    """Source: classical laminate theory, N = A eps + B kappa, M = B eps + D kappa
    (Jones 1999, eq. 4.22), and the patch test (Irons; MacNeal & Harder's patch).
    (1) Boundary nodes given a constant membrane-plus-curvature state, the solved inner
    nodes carry the same state within the solve's floor (BACKWARD eps cond(K_ii), x10).
    (2) The work of the FE forces of a constant curvature state on the unit membrane
    states, over the area, is N = B kappa (and that of a constant membrane state on the
    unit curvature states M = B eps), within the rounding of the products:
    24 eps |du|^T |K| |u| / area (24 = the terms of a row of K)."""
    t = 0.002
    abdh = stack(angles, t, z0)
    B = abdh[1][0]
    K, Q = _patch_stiffness(elements, angles, t, z0, 5)
    um, ub = _state(PATCH_XY, "membrane", Q), _state(PATCH_XY, "bending", Q)
    u = um + ub
    assert_inner_nodes_follow(K, u)
    # unit states: u = x (exx), v = y (eyy), u = y (gxy); ry = x (kx), rx = -y (ky),
    # ry = y (kxy); nodal translations and rotations turned to global axes by Q
    x, y = PATCH_XY[:, 0], PATCH_XY[:, 1]
    zero = np.zeros_like(x)

    def glob(tr, rot):
        return np.column_stack([np.column_stack(tr) @ Q.T,
                                np.column_stack(rot) @ Q.T]).ravel()

    unit_m = [glob((x, zero, zero), (zero,) * 3), glob((zero, y, zero), (zero,) * 3),
              glob((y, zero, zero), (zero, zero, -0.5 * np.ones_like(x)))]
    unit_b = [glob((zero, zero, -x**2 / 2), (zero, x, zero)),
              glob((zero, zero, -y**2 / 2), (-y, zero, zero)),
              glob((zero, zero, -x * y / 2), (-x / 2, y / 2, zero))]
    for units, state, expect in ((unit_m, ub, B @ KAPPA_STATE), (unit_b, um, B @ EPS_STATE)):
        for du, e in zip(units, expect, strict=True):
            work = du @ K @ state / AREA
            bound = 24 * EPS * (np.abs(du) @ np.abs(K) @ np.abs(state)) / AREA
            assert abs(work - e) <= bound, (work, e, bound)
        assert np.abs(expect).max() > 1e3 * bound  # the coupling is there to be seen


@pytest.mark.parametrize("triangles", [False, True], ids=["quad4", "tria3"])
@pytest.mark.parametrize("angles", [(0.0, 90.0), (0.0, 90.0, 90.0, 0.0)],
                         ids=["antisymmetric-0-90", "symmetric-0-90s"])
def test_cross_ply_plate_converges_to_navier_with_coupling(triangles, angles):
    """Source: the Navier solution ``navier_coupled`` (tests/laminate_plates.py: first-order
    shear deformation laminate theory, the elements' own H = 5/6 sum G t, so no modelling
    difference remains), a = 1, a/h = 100. Meshes 8, 16, 32: the error falls at least as
    h^2 (each halving at least by 3), and the 32-mesh's error is at most the change from
    16 to 32 (h^2: a third of it; room 3). For [0/90] the coupling lowers the frequency
    far more than that bound (the same formula with B = 0 is checked to differ), and
    [0/90]s (B = 0: no coupling part is formed) converges to it too. Measured: [0/90]
    Navier 202.6 rad/s (317.9 with B = 0), CQUAD4 -1.78, -0.46, -0.12 %, CTRIA3 +1.98,
    +0.50, +0.12 %; [0/90]s 317.6, CQUAD4 -9.0, -2.6, -0.67 %, CTRIA3 -3.8, -1.0, -0.27 %."""
    a, t = 1.0, 0.01 / len(angles)
    abdh = stack(angles, t)
    rho_h = RHO * 0.01
    exact = navier_coupled(a, abdh, rho_h)
    f = np.array([fe_plate(nx, a, angles, t, rho_h, triangles) for nx in (8, 16, 32)])
    e = np.abs(f / exact - 1)
    assert np.all(e[:-1] / e[1:] > 3), e
    assert e[2] <= abs(f[2] - f[1]) / exact, (f, exact)
    uncoupled = navier_coupled(a, (abdh[0], 0 * abdh[1], abdh[2], abdh[3]), rho_h)
    if len(angles) == 2:
        assert abs(uncoupled / exact - 1) > 10 * e[2], (uncoupled, exact, f)
    else:
        assert uncoupled == exact


def test_navier_reference_is_classical_laminate_theory_when_shear_rigid():
    """Source: the classical (Kirchhoff) Navier solution of an antisymmetric cross-ply
    square plate (Reddy 2004, sec. 5.3.2; Jones 1999, sec. 5.5): with alpha = pi / a,
    c11 = (A11 + A66) alpha^2, c12 = (A12 + A66) alpha^2, c22 = (A66 + A22) alpha^2,
    c13 = -B11 alpha^3, c23 = -B22 alpha^3, c33 = (D11 + 2 (D12 + 2 D66) + D22) alpha^4,
    omega^2 the least eigenvalue of c / (rho h). The test's first-order reference with H
    times 1e8 is within 1e-6 of it (its shear term ~ D alpha^2 / H ~ 1e-11, plus the
    rounding of the 3 x 3 solve)."""
    abdh = stack((0.0, 90.0), 0.005)
    A, B, D, H = (m[0] for m in abdh)
    al = np.pi
    c = np.array([[(A[0, 0] + A[2, 2]) * al**2, (A[0, 1] + A[2, 2]) * al**2, -B[0, 0] * al**3],
                  [0, (A[2, 2] + A[1, 1]) * al**2, -B[1, 1] * al**3],
                  [0, 0, (D[0, 0] + 2 * (D[0, 1] + 2 * D[2, 2]) + D[1, 1]) * al**4]])
    c = np.triu(c) + np.triu(c, 1).T
    clt = np.sqrt(np.linalg.eigvalsh(c / (RHO * 0.01))[0])
    rigid = navier_coupled(1.0, (A[None], B[None], D[None], 1e8 * H[None]), RHO * 0.01)
    assert abs(rigid / clt - 1) <= 1e-6, (rigid, clt)
    assert abs(navier_coupled(1.0, abdh, RHO * 0.01) / clt - 1) > 1e-4  # shear does show


@pytest.mark.parametrize("elements", [PATCH_QUADS, PATCH_TRIAS], ids=["quad4", "tria3"])
def test_coupling_leaves_the_other_parts_bit_identical(elements):
    """Source: construction. The coupling part is added beside the others: membrane,
    drilling, bending and shear are the same bits with or without it (B = 0 forms none)."""
    xyz = np.column_stack([PATCH_XY, np.zeros(8)])[elements]
    A, B, D, H = stack((0.0, 90.0), 0.002)
    _, plain = shells.local_parts(xyz, A[0], D[0], H[0])
    _, coupled = shells.local_parts(xyz, A[0], D[0], H[0], coupling=B[0])
    assert set(coupled) - set(plain) == {shells.COUPLING} and shells.COUPLING not in plain
    for name, (cols, block) in plain.items():
        assert np.array_equal(cols, coupled[name][0]) and np.array_equal(block, coupled[name][1])
