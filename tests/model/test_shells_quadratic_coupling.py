"""Membrane-bending coupling on CQUAD8 and CTRIA6 (model/shells_quadratic.py local_parts
with ``coupling``; the mass off the reference surface: model/shells_quadratic_mass.py).
Independent references: the laminate's energy [eps, kappa] [[A, B], [B, D]] [eps, kappa]
times the area in constant strain and curvature states (the patch test), equilibrium
(rigid motions store no energy) and positive energy of a single element, and a point
mass's rigid-body inertia at its height."""

from __future__ import annotations

import numpy as np
import pytest
from laminate_plates import stack
from shell_patch import rigid_motions as _rigid

from eigenupdate.model import shells, shells_quadratic_mass
from eigenupdate.model import shells_quadratic as quadratic

ABDH = [m[0] for m in stack((0.0, 90.0), 0.005)]  # [0/90] graphite-epoxy, T = 0.01
T = 0.01
# a parallelogram CQUAD8 (straight sides, mid-side nodes halfway: an affine map, so
# quadratic fields in x, y are exact) and a straight-sided CTRIA6, turned out of xy
Q8 = np.array([[0.0, 0, 0], [1.2, 0.1, 0], [1.5, 0.9, 0], [0.3, 0.8, 0]])
Q8 = np.vstack([Q8, (Q8 + np.roll(Q8, -1, axis=0)) / 2])
T6 = np.array([[0.0, 0, 0], [1.1, 0.2, 0], [0.4, 0.9, 0]])
T6 = np.vstack([T6, (T6 + np.roll(T6, -1, axis=0)) / 2])
AREAS = {8: 1.2 * 0.8 - 0.1 * 0.3, 6: abs(1.1 * 0.9 - 0.2 * 0.4) / 2}


def _parts(xyz, coupling=True):
    """K of one element with the [0/90] laminate whose x is the global x, turned to the
    element's axes (a CQUAD8's x bisects its xi and eta lines) as the deck path does."""
    R, _ = quadratic.material_axes(xyz[None])
    phi = np.arctan2(R[:, 1, 0], R[:, 0, 0])  # global x in the element's axes
    A, B, D, H = (m[0] for m in stack((0.0, 90.0), T / 2, phi=phi))
    _, parts = quadratic.local_parts(xyz[None], A / T, D / T**3, H / T,
                                     coupling=B[None] / T**2 if coupling else None)
    f = {"membrane": T, "bending": T**3, "shear": T, "drilling": T}
    if coupling:
        f[shells.COUPLING] = T**2
    return shells.combine(np.eye(3)[None], parts, {q: np.array([v]) for q, v in f.items()})[0]


def _state(xyz, e, k):
    """Grid displacements (6 per node) of constant membrane strain e and curvature k
    (engineering shear; fibre rotation beta = theta x z, strain at z = e + z k), no
    transverse shear and no drilling mismatch."""
    out = np.zeros((len(xyz), 6))
    for i, (x, y, _) in enumerate(xyz):
        bx, by = k[0] * x + k[2] * y / 2, k[1] * y + k[2] * x / 2
        out[i, :3] = [e[0] * x + e[2] * y / 2, e[1] * y + e[2] * x / 2,
                      -(k[0] * x * x + k[2] * x * y + k[1] * y * y) / 2]
        out[i, 3:5] = [-by, bx]  # beta = (theta_y, -theta_x)
    return out.ravel()


@pytest.mark.parametrize("k", [8, 6], ids=["CQUAD8", "CTRIA6"])
def test_constant_strain_and_curvature_store_the_laminate_energy(k):
    """Source: the patch test. In a state of constant eps and kappa the element stores
    area [eps, kappa] C [eps, kappa] (u^T K u), C the [0/90] laminate's [[A, B], [B, D]]
    (Whitney 1987 sec. 2): each of membrane, coupling and bending is exact on its rule
    (constant integrands), and B enters with the sign of the strain at z = eps + z kappa.
    Rounding of sums of a few hundred products: 1e-11."""
    xyz = Q8 if k == 8 else T6
    K = _parts(xyz)
    A, B, D, _ = ABDH
    C = np.block([[A, B], [B, D]])
    rng = np.random.default_rng(5)
    for _ in range(3):
        z = rng.standard_normal(6) * np.array([1e-4] * 3 + [1e-2] * 3)
        u = _state(xyz, z[:3], z[3:])
        want = AREAS[k] * z @ C @ z
        assert u @ K @ u == pytest.approx(want, rel=1e-11)
    # B's sign: the coupling's share of a stretch with bending, alone
    z = np.array([1e-4, 0, 0, 1e-2, 0, 0])
    u = _state(xyz, z[:3], z[3:])
    share = u @ (K - _parts(xyz, coupling=False)) @ u
    assert share == pytest.approx(2 * AREAS[k] * z[:3] @ B @ z[3:], rel=1e-9)




def _curved():
    """A CQUAD8 on a cylinder of radius 1 (30 degrees by 0.5)."""
    a = np.radians([0.0, 30.0, 30.0, 0.0, 15.0, 30.0, 15.0, 0.0])
    z = np.array([0.0, 0.0, 0.5, 0.5, 0.0, 0.25, 0.5, 0.25])
    return np.column_stack([np.cos(a), np.sin(a), z])


@pytest.mark.parametrize("name", ["CQUAD8", "CTRIA6", "curved CQUAD8"])
def test_coupled_element_is_positive_and_annihilates_rigid_motions(name):
    """Source: equilibrium and the laminate's positive energy. K (coupling included)
    annihilates the six rigid motions (1e-10 of |K| per unit length: the curvature terms
    vanish for u = t + theta x x on any surface) and has no negative eigenvalue (below
    -1e-12 |K|): the split D - B A^-1 B / B A^-1 B keeps the energy a sum of squares,
    and a state of no membrane energy on the membrane's points (a flat CQUAD8's
    spurious mode) does no coupling work. Its zero eigenvalues are the uncoupled
    element's (the same count)."""
    xyz = {"CQUAD8": Q8, "CTRIA6": T6, "curved CQUAD8": _curved()}[name]
    K = _parts(xyz)
    assert np.abs(K @ _rigid(xyz)).max() <= 1e-10 * np.abs(K).max() * 2
    w, w0 = np.linalg.eigvalsh(K), np.linalg.eigvalsh(_parts(xyz, coupling=False))
    assert w.min() >= -1e-12 * w.max()
    assert np.sum(w <= 1e-10 * w.max()) == np.sum(w0 <= 1e-10 * w0.max())


@pytest.mark.parametrize("lumped", [False, True], ids=["consistent", "lumped"])
@pytest.mark.parametrize("k", [8, 6], ids=["CQUAD8", "CTRIA6"])
def test_mass_off_the_reference_surface_has_its_rigid_body_inertia(k, lumped):
    """Source: rigid-body statics of a mass m (per area, on the area S) at height h above
    a flat element, ZOFFS z under it: r^T M r has the total m S on the translations,
    the first moments m S H (u with ry, -v with rx, H = z + h) and the second m S H^2
    plus the in-plane spread on rx, ry, at any split of H between ZOFFS and h; 1e-12."""
    xyz = Q8 if k == 8 else T6
    r = _rigid(xyz)
    S = AREAS[k]
    for z, h in ((0.0, 0.004), (0.003, 0.002), (0.005, 0.0)):
        m0, m1, m2 = shells_quadratic_mass.unit_masses(xyz[None], lumped, None,
                                                       np.array([z]))
        H = z + h
        M = (m0 + H * m1 + H * H * m2)[0]  # moments about the grids: m, m H, m H^2
        Mr = r.T @ M @ r
        assert Mr[0, 0] == pytest.approx(S, rel=1e-12)
        assert Mr[0, 4] == pytest.approx(S * H, rel=1e-12)
        assert Mr[1, 3] == pytest.approx(-S * H, rel=1e-12)
        flat = r.T @ quadratic.shell_mass(xyz[None], lumped)[0] @ r
        assert Mr[3, 3] - flat[3, 3] == pytest.approx(S * H * H, rel=1e-10)
