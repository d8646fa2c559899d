"""CQUAD4 (MITC4) and CTRIA3 (stabilised MITC3) shell elements: rigid-body modes, patch
tests, Navier's and Leissa's plates with mesh convergence, thin-plate locking, and the
thickness derivatives by finite differences."""

from __future__ import annotations

import numpy as np
import pytest
from bounds import BACKWARD, EPS, assert_thickness_derivatives, solve_floor
from plates import NU, RHO, E, constant_strain_state, navier, plate_frequency
from shell_patch import PATCH_QUADS, PATCH_TRIAS, PATCH_XY, assert_inner_nodes_follow

from eigenupdate.errors import InputError
from eigenupdate.model import shells
from eigenupdate.model.assembly import node_dofs, scatter


def _rotation(seed: int) -> np.ndarray:
    q, r = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    return q * np.sign(np.diag(r))


def _patch(elements, seed):
    """The patch turned to a random orientation: nodes (8, 3), rotation."""
    Q = _rotation(seed)
    xyz = np.column_stack([PATCH_XY, np.zeros(8)]) @ Q.T + np.array([1.0, -2.0, 0.5])
    return xyz, Q


def _stiffness(xyz, elements, h=0.001):
    moduli = shells.pshell_moduli(E, NU)
    K = shells.pshell_matrices(xyz[elements], h, *moduli, rho=RHO)["K"]
    return scatter(node_dofs(elements, 6), K, 6 * xyz.shape[0]).toarray()


@pytest.mark.parametrize("elements", [PATCH_QUADS, PATCH_TRIAS], ids=["quad4", "tria3"])
@pytest.mark.parametrize("seed", [0, 1])
def test_free_element_and_patch_have_six_rigid_body_modes(elements, seed):
    """Source: a free elastic body has exactly six zero-energy motions. The zero
    eigenvalues a backward-stable eigh returns are below BACKWARD eps ||K||; the
    smallest elastic one (the drilling penalty, 1e-6 K6ROT G T against E T) is ~1e-4
    ||K||, far above. The six rigid motions (translations, rotations about the basic axes,
    u = t + theta x x) are each stress-free."""
    xyz, _ = _patch(elements, seed)
    for el in (elements[:1], elements):
        used = np.unique(el)
        K = _stiffness(xyz, el, h=0.02)
        dofs = node_dofs(used[:, None], 6).ravel()
        K = K[np.ix_(dofs, dofs)]
        lam = np.linalg.eigvalsh(K)
        norm = np.abs(lam).max()
        zero = 1e3 * BACKWARD * EPS * norm
        assert np.sum(np.abs(lam) <= zero) == 6
        assert np.all(lam[6:] > 100 * zero)
        for t, theta in [(e, np.zeros(3)) for e in np.eye(3)] + \
                [(np.zeros(3), e) for e in np.eye(3)]:
            u = np.column_stack([t + np.cross(theta, xyz[used]),
                                 np.broadcast_to(theta, (used.size, 3))]).ravel()
            assert np.linalg.norm(K @ u) <= BACKWARD * EPS * norm * np.linalg.norm(u) * 24


@pytest.mark.parametrize("elements", [PATCH_QUADS, PATCH_TRIAS], ids=["quad4", "tria3"])
@pytest.mark.parametrize("which", ["membrane", "bending"])
def test_patch_test_reproduces_constant_strain_states(elements, which):
    """Source: the patch test (Irons; MacNeal & Harder's patch). Boundary nodes get the
    exact values of a constant-strain state; the solved inner nodes must carry the same
    state, within the solve's rounding floor (BACKWARD eps cond(K_ii)). The bending state
    has zero shear: MITC4's and MITC3's tied shear strains are exact for it (a quadratic's
    secant slope is its mid-edge slope), so the stabilisation of CTRIA3 does not enter."""
    xyz, Q = _patch(elements, 3)
    K = _stiffness(xyz, elements, h=0.01)
    local = constant_strain_state(PATCH_XY, which)
    # to global axes: translations and rotations turn with Q (element axes = patch axes)
    u = np.column_stack([local[:, :3] @ Q.T, local[:, 3:] @ Q.T]).ravel()
    assert_inner_nodes_follow(K, u)


@pytest.mark.parametrize("triangles", [False, True], ids=["quad4", "tria3"])
def test_navier_plate_converges_and_thin_plate_does_not_lock(triangles):
    """Source: Navier's closed form omega_11 = 2 pi^2 / a^2 sqrt(D / (rho h)) of a simply
    supported square plate. Meshes 8, 16, 32 per side (x 2 triangles). Bilinear/linear
    elements' frequency errors fall as the mesh size squared: each halving divides the
    error by 3..5, and the Richardson extrapolation (4 f_32 - f_16) / 3 is within the
    change between successive extrapolations plus the Mindlin-Kirchhoff difference at
    a/h = 1000 (pi^2 (h/a)^2 (1 + 2 / (kappa (1 - nu))) = 4.4e-5, taken as 5e-5).
    Locking: a/h = 10000 and a/h = 1000 give the same error within 10 % on each mesh
    (the Mindlin difference, 5e-5, is under 5 % of the errors; a locking element's error
    grows with a/h: plain MITC3 is 5.7 % off at a/h = 1000, 32 x 32)."""
    a = 1.0
    errs = {}
    for h in (a / 1000, a / 10000):
        w = navier(a, h)
        f = np.array([plate_frequency(nx, a, h, "ss", triangles) for nx in (8, 16, 32)])
        errs[h] = f / w - 1
    e = errs[a / 1000]
    assert np.all(e > 0) and np.all(np.diff(e) < 0)
    assert np.all((e[:-1] / e[1:] > 3) & (e[:-1] / e[1:] < 5)), e
    r1, r2 = (4 * e[1] - e[0]) / 3, (4 * e[2] - e[1]) / 3
    assert abs(r2) <= abs(r2 - r1) + 5e-5, (r1, r2)
    for k in (1, 2):
        assert abs(errs[a / 10000][k] / errs[a / 1000][k] - 1) < 0.1, errs


@pytest.mark.parametrize("triangles", [False, True], ids=["quad4", "tria3"])
def test_clamped_plate_converges_to_leissa(triangles):
    """Source: Leissa, Vibration of Plates (NASA SP-160, 1969), clamped square plate,
    lambda = omega a^2 sqrt(rho h / D) = 35.99 (+-0.005, its last digit). a/h = 1000;
    meshes 8, 16, 32; the Richardson extrapolation of 16 and 32 is within the change
    between successive extrapolations plus Leissa's rounding."""
    a, h = 1.0, 1e-3
    D = E * h**3 / (12 * (1 - NU**2))
    lam = np.array([plate_frequency(nx, a, h, "clamped", triangles) for nx in (8, 16, 32)])
    lam *= a**2 * np.sqrt(RHO * h / D)
    # monotone: CTRIA3 from above; CQUAD4 from below (its residual bending flexibility
    # softens coarse meshes: 35.40, 35.75, 35.91, 35.96 at 4 to 32)
    step = np.diff(lam)
    assert np.all(step < 0) if triangles else np.all(step > 0), lam
    r1, r2 = (4 * lam[1] - lam[0]) / 3, (4 * lam[2] - lam[1]) / 3
    assert abs(r2 - 35.99) <= abs(r2 - r1) + 0.005, (r1, r2)


@pytest.mark.parametrize("k", [3, 4])
@pytest.mark.parametrize("lumped", [False, True])
def test_thickness_derivatives_match_finite_differences(k, lumped):
    """Source: central finite differences of pshell_matrices' K(T), M(T). Truncation
    error is estimated from steps h and 2h (|D_h - D_2h| is 3/4 of D_2h's error, four
    times D_h's), rounding by 4 eps ||K|| / h; the exact derivative must be within."""
    xyz = np.column_stack([PATCH_XY, np.zeros(8)])[PATCH_QUADS[:, :k] if k == 4
                                                    else PATCH_TRIAS]
    xyz = xyz @ _rotation(7).T
    moduli = shells.pshell_moduli(E, NU, shear_ratio=0.8)
    T = np.linspace(0.002, 0.02, xyz.shape[0])

    def mats(t):
        return shells.pshell_matrices(xyz, t, *moduli, rho=RHO, nsm=1.5, lumped=lumped)

    assert_thickness_derivatives(mats, T)


def test_bad_shell_geometry_is_named():
    """Source: NASTRAN refuses such elements; here the message names the element."""
    sq = np.array([[0.0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]])
    moduli = shells.pshell_moduli(E, NU)
    cases = {
        "zero area": np.array([[0.0, 0, 0], [1, 0, 0], [2, 0, 0]]),
        "not convex": np.array([[0.0, 0, 0], [1, 0, 0], [0.3, 0.3, 0], [0, 1, 0]]),
        "warped": sq + np.array([[0, 0, 0], [0, 0, 0.5], [0, 0, 0], [0, 0, 0.5]]),
    }
    for what, xyz in cases.items():
        with pytest.raises(InputError, match=f"CQUAD4 7: {what}|CTRIA3 7: {what}"):
            label = "CQUAD4 7" if len(xyz) == 4 else "CTRIA3 7"
            shells.shell_stiffness_parts(xyz[None], *moduli, labels=[label])


@pytest.mark.parametrize("k6rot", [0.0, shells.K6ROT])
def test_quad4_membrane_bends_in_plane_without_parasitic_shear(k6rot):
    """Source: Euler-Bernoulli pure bending, tip deflection M L^2 / (2 E I), I = T h^3 / 12,
    which is a linear-strain plane-stress field: CQUAD4's incompatible membrane modes
    represent it exactly on rectangles (the bilinear membrane alone gives 9 % of the
    deflection here: one element across, aspect 5). A couple F h at the tip, root free
    to contract (u fixed, v at one node); within the solve's rounding floor, plus the
    drilling penalty's energy (1e-6 K6ROT G T against E T, rz free: a relative 1e-3
    bound)."""
    L, h, T, nel = 5.0, 0.2, 0.05, 5
    x = np.linspace(0, L, nel + 1)
    xyz = np.array([[xi, yi, 0.0] for xi in x for yi in (0.0, h)])
    el = np.array([[2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1] for i in range(nel)])
    moduli = shells.pshell_moduli(E, NU)
    K = scatter(node_dofs(el, 6), shells.shell_stiffness_parts(xyz[el], *moduli, k6rot=k6rot)
                ["membrane"] * T + T * shells.shell_stiffness_parts(
                    xyz[el], *moduli, k6rot=k6rot)["drilling"], 6 * len(xyz)).toarray()
    fixed = [0, 1, 6]  # u, v of the bottom root node, u of the top one
    fixed += [6 * i + c for i in range(len(xyz)) for c in (2, 3, 4)]
    if k6rot == 0.0:
        fixed += [6 * i + 5 for i in range(len(xyz))]
    free = np.setdiff1d(np.arange(K.shape[0]), fixed)
    F = 1e3
    f = np.zeros(K.shape[0])
    f[6 * (2 * nel)] = F  # bottom tip node, +x
    f[6 * (2 * nel + 1)] = -F  # top tip node, -x: moment -F h about z
    u = np.zeros_like(f)
    Kff = K[np.ix_(free, free)]
    u[free] = np.linalg.solve(Kff, f[free])
    exact = F * h * L**2 / (2 * E * T * h**3 / 12)
    tip = 0.5 * (u[6 * (2 * nel) + 1] + u[6 * (2 * nel + 1) + 1])
    bound = 10 * solve_floor(Kff) + (1e-3 if k6rot else 0.0)
    assert abs(tip / exact - 1) <= bound, tip / exact


def _laminate_a(t):
    """A of a [0/45/90] stack of a carbon ply (E1 140 GPa, E2 10 GPa, nu12 0.3, G12
    5 GPa) with ply thicknesses t."""
    from eigenupdate.model import laminate
    e1, e2, nu, g = 1.4e11, 1.0e10, 0.3, 5.0e9
    d = 1 - nu**2 * e2 / e1
    q = np.array([[e1 / d, nu * e2 / d, 0], [nu * e2 / d, e2 / d, 0], [0, 0, g]])
    return sum(ti * laminate.rotate_plane(q, np.radians(a))
               for ti, a in zip(t, (0, 45, 90), strict=True))


def test_quad4_membrane_condensed_with_fixed_moduli_is_linear_and_second_order():
    """CQUAD4's incompatible modes condensed as under A0 (``condense_with``): the exact
    Schur complement at A = A0; linear in A (the sum of the parts of A's entries is the
    part of A); and at other A stiffer than the exact condensation (a Ritz
    approximation: the difference is positive semi-definite) by an amount of second
    order in the change (the error ratio for halved changes tends to 4). Source: the
    Schur complement itself, on a badly distorted element."""
    xyz = np.array([[[0, 0, 0], [1.3, 0.1, 0], [1.0, 1.2, 0], [-0.2, 0.7, 0]]], float)
    cb, cs = np.eye(3)[None], np.eye(2)[None]
    a0 = _laminate_a([1.0, 1.0, 1.0])[None]

    def membrane(a, with_a0=True):
        kw = {"condense_with": a0} if with_a0 else {}
        return shells.local_parts(xyz, a, cb, cs, **kw)[1]["membrane"][1][0]

    k0 = membrane(a0, False)
    assert np.abs(membrane(a0) - k0).max() <= 1e-14 * np.abs(k0).max()
    a = _laminate_a([1.2, 1.0, 0.85])[None]
    parts = sum(a[0, i, j] * membrane(_unit(i, j))
                for i in range(3) for j in range(i, 3))
    assert np.abs(parts - membrane(a)).max() <= 1e-13 * np.abs(k0).max()
    errors = []
    for f in (0.2, 0.1, 0.05):
        a = _laminate_a([1 + f, 1.0, 1 - 0.75 * f])[None]
        d = membrane(a) - membrane(a, False)
        assert np.linalg.eigvalsh(d).min() >= -1e-13 * np.abs(k0).max()
        errors.append(np.abs(d).max() / np.abs(k0).max())
    assert errors[0] <= 3.2e-5  # the bound the NASTRAN test cites
    assert 3.5 <= errors[0] / errors[1] <= 4.5 and 3.5 <= errors[1] / errors[2] <= 4.5


def _unit(i, j):
    u = np.zeros((1, 3, 3))
    u[0, i, j] = u[0, j, i] = 1.0
    return u
