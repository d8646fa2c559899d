"""Variable-node CQUAD8 (4 to 8 nodes) and CTRIA6 (3 to 6): blank mid-side nodes
(model/shells_transition.py). Rigid-body modes of every pattern, the identities that do
hold (a blank node is the full element's node tied to its corners' mean, but for the
shear; all blank: CTRIA3, CQUAD4's MITC4 bending and shear), patch tests on meshes mixing
full and transition elements, Navier's plate converging with no locking at a/h = 1e4
against the full element and CQUAD4 on the same mesh, thickness derivatives by finite
differences."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import scipy.sparse.linalg as spla
from bounds import BACKWARD, EPS, assert_thickness_derivatives, solve_floor
from plates import NU, RHO, E, constant_strain_state, navier, plate_fixed
from quadratic_meshes import plate_mesh, skewed_plate
from quadratic_meshes import transition_plate_frequency as _plate
from test_shells_quadratic import PATCH_QUADS, PATCH_TRIAS, _quadratic_patch, _rotation

from eigenupdate.model import shells
from eigenupdate.model import shells_quadratic as sq
from eigenupdate.model import shells_transition as st
from eigenupdate.model.assembly import node_dofs, scatter

MODULI = shells.pshell_moduli(E, NU)


def _element(k: int, pattern, curved: bool) -> np.ndarray:
    """One distorted element (k, 3) turned at random, mid-side nodes NaN where
    ``pattern`` is 0; CQUAD8 on a doubly curved surface when ``curved``."""
    xy = (np.array([[0, 0], [1.1, 0.1], [1.0, 0.9], [-0.1, 1.0]]) if k == 8
          else np.array([[0, 0], [1.1, 0.1], [0.2, 0.9]]))
    e = st.EDGES[k]
    x = np.column_stack([np.vstack([xy, (xy[e[:, 0]] + xy[e[:, 1]]) / 2]), np.zeros(k)])
    if curved:
        x[:, 2] = 0.3 * x[:, 0] ** 2 - 0.2 * x[:, 1] ** 2
    x = x @ _rotation(k + sum(pattern)).T
    x[k - len(e):][~np.array(pattern, bool)] = np.nan
    return x


def _patterns(k: int):
    return list(itertools.product([1, 0], repeat=len(st.EDGES[k])))


@pytest.mark.parametrize(("k", "curved"), [(8, False), (8, True), (6, False)],
                         ids=["quad-flat", "quad-curved", "tria"])
def test_every_pattern_has_six_rigid_modes_and_no_spurious_one(k, curved):
    """Source: a free elastic body has exactly six zero-energy motions u = t + theta x x;
    each must be stress-free to rounding (BACKWARD eps ||K|| ||u|| times the 48 terms of a
    row), and no other eigenvalue below 100 BACKWARD eps ||K|| (a spurious mode of the
    shear tying would be one: the smallest elastic ones, the drilling penalty, are 9e-8
    ||K|| and above). Every pattern of blank mid-side nodes of one element; the full flat
    CQUAD8 has its one known membrane mode (tests/model/test_shells_quadratic.py)."""
    for pattern in _patterns(k):
        x = _element(k, pattern, curved)
        K = sq.pshell_matrices(x[None], 0.02, *MODULI, rho=RHO)["K"][0]
        here = ~np.isnan(x).any(axis=1)
        d = node_dofs(np.flatnonzero(here)[:, None], 6).ravel()
        K = K[np.ix_(d, d)]
        lam = np.linalg.eigvalsh(K)
        norm = np.abs(lam).max()
        zero = 100 * BACKWARD * EPS * norm
        zeros = 7 if k == 8 and not curved and all(pattern) else 6
        assert np.sum(np.abs(lam) <= zero) == zeros, pattern
        assert np.all(lam[zeros:] > 100 * zero), pattern
        for t, theta in [(e, np.zeros(3)) for e in np.eye(3)] + \
                [(np.zeros(3), e) for e in np.eye(3)]:
            u = np.column_stack([t + np.cross(theta, x[here]),
                                 np.broadcast_to(theta, (here.sum(), 3))]).ravel()
            assert np.linalg.norm(K @ u) <= BACKWARD * EPS * norm * np.linalg.norm(u) * 48


@pytest.mark.parametrize("k", [8, 6])
def test_a_blank_node_is_the_full_elements_node_tied_to_its_corners(k):
    """Source: Bathe's transition functions (Finite Element Procedures, Fig. 5.4: a missing
    mid-side node's function dropped, half of it added to each corner's) are the full
    element's with that node's value the mean of its corners': membrane, bending and
    drilling stiffness and the consistent mass of the transition element equal C^T X C of
    the full element with the node at its edge's middle (C: shells_transition.tie), to
    rounding (1e-13 of the largest entry: a few products of O(1) factors), on a flat
    distorted element turned at random (on a curved CQUAD8 not: the transition element
    interpolates its corners' normals, the full one has its own at the node; 1 % of the
    bending there). The transverse
    shear is NOT that (tied to its corners under MITC8's or the stabilised shear the
    element locks): it is the tying of shells_transition, checked by the other tests."""
    for pattern in _patterns(k)[1:]:
        x = _element(k, pattern, False)
        full = st.fill(x[None])[0][0]
        C = st.tie(~np.isnan(x).any(axis=1)[None])[0]
        T6 = np.kron(C, np.eye(6))
        parts = {}
        for name, y in (("t", x), ("f", full)):
            R, p = sq.local_parts(y[None], *MODULI)
            parts[name] = {q: shells.combine(R, p, {q: np.ones(1)})[0]
                           for q in ("membrane", "bending", "drilling")}
            parts[name]["mass"] = sq.shell_mass(y[None], False)[0]
        for q, got in parts["t"].items():
            want = T6.T @ parts["f"][q] @ T6
            assert np.abs(got - want).max() <= 1e-13 * np.abs(want).max(), (pattern, q)


def test_all_blank_ctria6_is_ctria3():
    """Source: with G4-G6 blank the CTRIA6 is the linear triangle, and its shear tying is
    MITC3's (edge mid-points) with CTRIA3's stabilisation size (the longest edge): every
    stiffness part and both masses equal model/shells.py's CTRIA3 to rounding, on a
    triangle turned at random."""
    c = np.array([[0.1, 0.0, 0.0], [1.2, 0.2, 0.0], [0.3, 0.9, 0.0]]) @ _rotation(4).T
    x6 = np.vstack([c, np.full((3, 3), np.nan)])[None]
    R3, p3 = shells.local_parts(c[None], *MODULI)
    R6, p6 = sq.local_parts(x6, *MODULI)
    assert sq.stabilisation_size(x6) == pytest.approx(shells.stabilisation_size(c[None]),
                                                      rel=1e-15)
    for q in shells.STIFFNESS_PARTS:
        a = shells.combine(R3, p3, {q: np.ones(1)})[0]
        b = shells.combine(R6, p6, {q: np.ones(1)})[0][:18, :18]
        assert np.abs(a - b).max() <= 1e-13 * np.abs(a).max(), q
    for lumped in (False, True):
        a, b = shells.shell_mass(c[None], lumped)[0], sq.shell_mass(x6, lumped)[0][:18, :18]
        assert np.abs(a - b).max() <= 1e-13 * np.abs(a).max()


def test_all_blank_cquad8_bends_and_shears_as_cquad4_on_a_parallelogram():
    """Source: with G5-G8 blank the CQUAD8 is bilinear and its shear tying MITC4's (Dvorkin
    & Bathe), as CQUAD4's (model/shells.py): on a parallelogram (constant Jacobian, where
    3 x 3 and 2 x 2 Gauss points integrate both exactly) bending, shear and drilling
    parts and the consistent mass are equal to rounding. The membrane is not: CQUAD4's
    has incompatible modes, this element's is the plain bilinear one (stiffer in
    in-plane bending), as an isoparametric transition element's."""
    c = np.array([[0.0, 0, 0], [1.2, 0, 0], [1.5, 0.8, 0], [0.3, 0.8, 0]]) @ _rotation(6).T
    x8 = np.vstack([c, np.full((4, 3), np.nan)])[None]
    R4, p4 = shells.local_parts(c[None], *MODULI)
    R8, p8 = sq.local_parts(x8, *MODULI)
    for q in ("bending", "shear", "drilling"):
        a = shells.combine(R4, p4, {q: np.ones(1)})[0]
        b = shells.combine(R8, p8, {q: np.ones(1)})[0][:24, :24]
        assert np.abs(a - b).max() <= 1e-13 * np.abs(a).max(), q
    a, b = shells.shell_mass(c[None], False)[0], sq.shell_mass(x8, False)[0][:24, :24]
    assert np.abs(a - b).max() <= 1e-13 * np.abs(a).max()


def test_tying_reproduces_its_polynomial_spaces():
    """Source: the construction. With every node, e_rt's assumed field is MITC8's, the
    polynomial in 1, r, s, rs, s^2 matching e_rt at the four points r = +-1/sqrt(3),
    s = +-1 and its mean: such a field is reproduced exactly from those values (weights
    from shells_transition.tying_weights); with no mid-side node, MITC4's 1, s from the
    edge mid-points; e_st the same with r, s swapped. Weights sum to one for every
    pattern (a constant strain is kept)."""
    rng = np.random.default_rng(0)
    mean_s2 = 1 / 3
    for present, basis in ((None, [(0, 0), (1, 0), (0, 1), (1, 1), (0, 2)]),
                           (np.array([[1, 1, 1, 1, 0, 0, 0, 0]], bool), [(0, 0), (0, 1)])):
        c = rng.normal(size=len(basis))

        def f(r, s, c=c, basis=basis):
            return sum(ci * r**i * s**j for ci, (i, j) in zip(c, basis, strict=True))
        mean = sum(ci * (mean_s2 if j == 2 else 1.0 if j == 0 else 0.0) * (i == 0)
                   for ci, (i, j) in zip(c, basis, strict=True))
        vals = np.array([f(r, s) for r, s in st.POINTS] + [mean])
        for p, q in rng.uniform(-1, 1, (5, 2)):
            w = st.tying_weights(present, p, q)[0]
            assert w[0] @ vals == pytest.approx(f(p, q), abs=1e-13)
            assert w[1] @ vals == pytest.approx(f(q, p), abs=1e-13)  # e_st, swapped
    for pattern in _patterns(8):
        present = np.array([[1, 1, 1, 1, *pattern]], bool)
        assert np.allclose(st.tying_weights(present, 0.3, -0.7).sum(axis=2), 1.0,
                           atol=1e-14)


def _cquad4_plate(nx, h):
    xyz, el = plate_mesh(nx, 1.0, 1.0, False)
    m = shells.pshell_matrices(xyz[el[:, :4]], h, *MODULI, rho=RHO)
    d, n = node_dofs(el[:, :4], 6), 6 * xyz.shape[0]
    K, M = scatter(d, m["K"], n), scatter(d, m["M"], n)
    fixed = plate_fixed(xyz, 1.0, "ss")
    fixed[np.unique(el[:, 4:])] = True
    free = np.flatnonzero(~fixed.ravel())
    mu = spla.eigsh(M[free][:, free], 1, K[free][:, free], which="LA",
                    return_eigenvectors=False)
    return float(np.sqrt(1 / mu[0]))


def _mindlin(h):
    """Mindlin's (1, 1) frequency of the simply supported unit plate (no rotary inertia,
    kappa = 5/6), as tests/model/test_shells_quadratic.py."""
    return navier(1.0, h) / np.sqrt(1 + 2 * np.pi**2 * h**2 / (6 * 5 / 6 * (1 - NU)))


@pytest.mark.parametrize("triangles", [False, True], ids=["quad", "tria"])
def test_plate_with_transition_elements_converges_and_does_not_lock(triangles):
    """Source: Mindlin's simply supported square plate (its (1, 1) mode is exactly
    sin sin). Meshes 4, 8, 16 per side: CQUAD8 (CTRIA6 x 2) full for x < 1/2, linear
    (every mid-side blank) beyond, transition elements between. The linear region
    limits the rate to the mesh size squared (measured ratios 2.8, 3.5 quad; 3.6, 3.9
    tria): errors positive and falling by more than 2.5 each halving. Locking: at a/h
    = 1000 and 10000 the errors agree within 1 % on each mesh (measured 0.1 %; a
    locking element's grows as (a/h)^2: blank nodes tied to their corners under MITC8's
    tying gave 500 % at 4 x 4), and a/h = 100's within 10 % (measured 0.3 % quad, 7 %
    tria: the CTRIA6 shear stabilisation's T/h dependence). Against the
    same mesh all full and all linear: the mixed mesh's error lies between them (the
    full element's is the smaller), and the all-linear quad (MITC4) within five times
    CQUAD4's on that mesh (measured 4.0: no residual bending flexibility here)."""
    errs = {}
    for h in (1e-2, 1e-3, 1e-4):
        w = _mindlin(h)
        errs[h] = np.array([_plate(nx, h, triangles, "half") for nx in (4, 8, 16)]) / w - 1
    e = errs[1e-2]
    assert np.all(e > 0) and np.all(e[:-1] / e[1:] > 2.5), errs
    assert np.all(np.abs(errs[1e-4] / errs[1e-3] - 1) < 0.01), errs
    assert np.all(np.abs(errs[1e-3] / e - 1) < 0.1), errs
    h = 1e-4
    w = _mindlin(h)
    full = _plate(8, h, triangles, "none") / w - 1
    linear = _plate(8, h, triangles, "all") / w - 1
    assert 0 < full < errs[h][1] < linear, (full, errs[h][1], linear)
    if not triangles:
        assert linear < 5 * (_cquad4_plate(8, h) / w - 1)


@pytest.mark.parametrize("triangles", [False, True], ids=["quad", "tria"])
@pytest.mark.parametrize("seed", [0, 1])
def test_random_blank_nodes_do_not_lock(triangles, seed):
    """Source: Mindlin's plate (as above) on an 8 x 8 mesh whose mid-side nodes are each blank
    with probability 1/2 (every pattern of transition element, shared edges consistent). A
    locking element's error grows as (a/h)^2; here a/h = 1e4's stays within twice a/h =
    100's plus 1e-4 (measured: quad 2.6e-4 against 1.9e-4, 2.23e-3 against 2.18e-3; tria
    5.8e-3 against 5.6e-3, 8.7e-3 against 8.6e-3), and below the all-linear mesh's error at
    a/h = 1e4 (1.7 %, 3.6 % for quad and tria)."""
    got = [_plate(8, h, triangles, "random", seed) / _mindlin(h) - 1 for h in (1e-2, 1e-4)]
    assert abs(got[1]) <= 2 * abs(got[0]) + 1e-4, got
    assert abs(got[1]) < _plate(8, 1e-4, triangles, "all") / _mindlin(1e-4) - 1, got


def _patch(corners, blank):
    """The quadratic patch of test_shells_quadratic with the mid-side nodes of the
    patch's edges ``blank`` ((a, b) corner pairs) blank."""
    xy, el, on = _quadratic_patch(corners)
    k = el.shape[1]
    nc = k - len(st.EDGES[k])
    gone = [el[i, nc + j] for i in range(len(el)) for j, (a, b) in enumerate(st.EDGES[k])
            if {el[i, a], el[i, b]} in [set(p) for p in blank]]
    return xy, el, on, np.unique(gone)


@pytest.mark.parametrize(("corners", "which"), [(PATCH_QUADS, "membrane"),
                                                (PATCH_TRIAS, "membrane"),
                                                (PATCH_TRIAS, "bending")],
                         ids=["quad-membrane", "tria-membrane", "tria-bending"])
def test_patch_test_with_transition_elements(corners, which):
    """Source: the patch test (Irons; MacNeal & Harder's distorted patch, as
    test_shells_quadratic) with the mid-side nodes of one inner edge, two boundary edges and
    (triangles) two diagonals blank: full and transition elements mixed. The constant-strain
    state's exact values on the boundary; the solved inner nodes carry it within the solve's
    rounding floor (BACKWARD eps cond(K_ii)). The Kirchhoff bending state is in the
    transition triangle's space with zero tied shear (a quadratic w's chord slope is its
    tangent at the edge's middle, MITC3's tying point); CQUAD8's bending patch needs
    parallelograms (the next test)."""
    blank = [(4, 5), (0, 1), (2, 3)] + ([(0, 5), (2, 7)] if corners is PATCH_TRIAS else [])
    xy, el, on, gone = _patch(corners, blank)
    Q = _rotation(3)
    xyz = np.column_stack([xy, np.zeros(len(xy))]) @ Q.T + np.array([1.0, -2.0, 0.5])
    x = xyz[el].copy()
    x[np.isin(el, gone)] = np.nan
    assert 0 < np.isnan(x[:, :, 0]).any(axis=1).sum() < len(el)
    _assert_patch(x, el, xyz, xy, Q, on, gone, which)


def test_parallelogram_patch_with_transition_quads_bends_exactly():
    """Source: the bending patch test on parallelograms (a skewed 3 x 3 grid of unequal
    cells, as test_shells_quadratic's), the mid-side nodes of the middle row's and
    column's edges blank: full, 7-, 6- and 5-node elements. The Kirchhoff state's w is
    quadratic: exact along edges with their mid-side node, and along a straight linear
    edge its chord slope is the tangent at the middle, the tying point. Within the
    solve's rounding floor."""
    xyz, el, xy, on = skewed_plate()
    mids = np.unique(el[:, 4:])
    gone = mids[(np.abs(xyz[mids, 0] - 0.5) < 1 / 6) | (np.abs(xyz[mids, 1] - 0.5) < 1 / 6)]
    Q = _rotation(5)
    xyz = np.column_stack([xy, np.zeros(len(xy))]) @ Q.T
    x = xyz[el].copy()
    x[np.isin(el, gone)] = np.nan
    _assert_patch(x, el, xyz, xy, Q, on, gone, "bending")


@pytest.mark.parametrize("k", [8, 6])
@pytest.mark.parametrize("lumped", [False, True])
def test_transition_thickness_derivatives_match_finite_differences(k, lumped):
    """Source: central finite differences of pshell_matrices' K(T), M(T) (as
    test_shells_quadratic's: truncation from steps h and 2h, rounding 4 eps ||K|| / h),
    one element of every pattern of blank mid-side nodes (CQUAD8 curved)."""
    xyz = np.stack([_element(k, p, k == 8) for p in _patterns(k)])
    moduli = shells.pshell_moduli(E, NU, shear_ratio=0.8)
    T = np.linspace(0.002, 0.02, xyz.shape[0])

    def mats(t):
        return sq.pshell_matrices(xyz, t, *moduli, rho=RHO, nsm=1.5, lumped=lumped)

    assert_thickness_derivatives(mats, T)


def _assert_patch(x, el, xyz, xy, Q, on, gone, which: str) -> None:
    """The patch's inner nodes solved from the constant-strain state ``which`` on its
    boundary (elements' nodes x, blank ones NaN; turned by Q) reproduce that state within
    the solve's rounding floor."""
    d, n = node_dofs(el, 6), 6 * len(xyz)
    K = scatter(d, sq.pshell_matrices(x, 0.01, *MODULI, rho=RHO)["K"], n).toarray()
    local = constant_strain_state(xy, which)
    u = np.column_stack([local[:, :3] @ Q.T, local[:, 3:] @ Q.T]).ravel()
    keep = np.setdiff1d(np.arange(len(xy)), gone)
    inner = node_dofs(np.intersect1d(np.flatnonzero(~on), keep)[:, None], 6).ravel()
    outer = node_dofs(np.intersect1d(np.flatnonzero(on), keep)[:, None], 6).ravel()
    Kii = K[np.ix_(inner, inner)]
    got = np.linalg.solve(Kii, -K[np.ix_(inner, outer)] @ u[outer])
    err = np.linalg.norm(got - u[inner]) / np.linalg.norm(u[inner])
    assert err <= solve_floor(Kii) * 10, err
