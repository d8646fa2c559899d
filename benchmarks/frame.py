"""A 3-D steel space frame of Euler-Bernoulli beam elements, as a ParametricModel.

Six coordinates per node, in the order (ux, uy, uz, rx, ry, rz); node i (0-based) has
user coordinates 6 i + 1 ... 6 i + 6. The frame is a rectangular grid of columns
(along Z) and floor beams (along X and Y) with non-uniform bays and storeys, every
member split into ``n_sub`` elements. Base joints are clamped (their coordinates are
removed) unless ``supports="free"``.

Element matrices (local x along the member, local z the "vertical" principal axis):
axial EA/L, torsion GJ/L with G = E / (2 (1 + nu)), bending in the local x-y plane
(EI_z) and the local x-z plane (EI_y); consistent mass rho A for translations and
rho (I_y + I_z) for torsion (rotary inertia of bending neglected, as in the planar
:mod:`eigenupdate.model.beam`). Stiffness is linear in E and mass linear in rho, so each
group's E (Pa) and rho (kg/m^3) are parameters: K = sum_g E_g K_g, M = sum_g rho_g M_g,
with K_g, M_g the group's matrices for E = 1, rho = 1.

Everything is vectorised over elements; the only Python loop is over the groups.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from eigenupdate.model.parameters import Parameter
from eigenupdate.model.parametric import ParametricModel

E_STEEL = 210e9
RHO_STEEL = 7850.0
NU = 0.3


@dataclass(frozen=True)
class Section:
    """Cross-section: area (m^2), second moments about local y and z (m^4), torsion J (m^4)."""

    A: float
    Iy: float
    Iz: float
    J: float


# HEB 300 columns and IPE 400 floor beams (strong axis = local y, bending in local x-z).
COLUMN = Section(A=1.491e-2, Iy=2.517e-4, Iz=8.563e-5, J=1.850e-6)
BEAM = Section(A=8.446e-3, Iy=2.313e-4, Iz=1.318e-5, J=5.110e-7)

# Sizes: (bays in X, bays in Y, storeys, elements per member).
SIZES = {
    "full": (7, 5, 18, 8),  # 103,464 coordinates: benchmark (a)
    "small": (4, 3, 6, 4),  # 6,228 coordinates: (a) of the quick run
    "b-full": (2, 2, 5, 4),  # 2,160 coordinates: benchmark (b)
    "b-small": (1, 1, 5, 3),  # 600 coordinates: (b) of the quick run
    # the full frame with 2, 4 and 16 elements per member: scaling of one iteration
    "mesh2": (7, 5, 18, 2),  # 19,224 coordinates
    "mesh4": (7, 5, 18, 4),  # 47,304
    "mesh16": (7, 5, 18, 16),  # 215,784
    "small-mesh2": (4, 3, 6, 2),  # quick run
    "stop": (5, 4, 8, 4),  # 12,816 coordinates: stopping on time (issue 21 item 5)
}

X_BAYS = np.array([6.0, 7.2, 5.4, 8.1, 6.6, 5.7, 7.5, 6.3])  # m, cycled
Y_BAYS = np.array([5.1, 6.3, 5.7, 6.9, 4.8, 6.0])
STOREY = 3.5  # m; the ground storey is 4.2 m


def element_matrices(L, A, Iy, Iz, J, nu=NU):
    """Local 12x12 stiffness (E = 1) and consistent mass (rho = 1) for arrays of elements.

    DOF order (u1, v1, w1, tx1, ty1, tz1, u2, ..., tz2) in local axes.
    Returns arrays of shape (n, 12, 12).
    """
    L, A, Iy, Iz, J = (np.broadcast_to(np.asarray(a, float), np.shape(L)) for a in
                       (L, A, Iy, Iz, J))
    n = L.size
    k = np.zeros((n, 12, 12))
    m = np.zeros((n, 12, 12))
    G = 1.0 / (2.0 * (1.0 + nu))

    def put(out, idx, coef, mat):
        # out[:, idx, idx] += coef[:, None, None] * mat[e] (mat may depend on L per element)
        ii = np.asarray(idx)
        out[:, ii[:, None], ii[None, :]] += coef[:, None, None] * mat

    bar = np.array([[1.0, -1.0], [-1.0, 1.0]])
    bar_m = np.array([[2.0, 1.0], [1.0, 2.0]]) / 6.0
    put(k, [0, 6], A / L, bar)
    put(k, [3, 9], G * J / L, bar)
    put(m, [0, 6], A * L, bar_m)
    put(m, [3, 9], (Iy + Iz) * L, bar_m)

    o = np.ones_like(L)
    kb = np.stack([
        np.stack([12 * o, 6 * L, -12 * o, 6 * L], -1),
        np.stack([6 * L, 4 * L**2, -6 * L, 2 * L**2], -1),
        np.stack([-12 * o, -6 * L, 12 * o, -6 * L], -1),
        np.stack([6 * L, 2 * L**2, -6 * L, 4 * L**2], -1),
    ], -2) / (L**3)[:, None, None]
    mb = np.stack([
        np.stack([156 * o, 22 * L, 54 * o, -13 * L], -1),
        np.stack([22 * L, 4 * L**2, 13 * L, -3 * L**2], -1),
        np.stack([54 * o, 13 * L, 156 * o, -22 * L], -1),
        np.stack([-13 * L, -3 * L**2, -22 * L, 4 * L**2], -1),
    ], -2) * (L / 420.0)[:, None, None]
    # bending in the local x-y plane (v, theta_z), about z: EI_z
    put(k, [1, 5, 7, 11], Iz, kb)
    put(m, [1, 5, 7, 11], A, mb)
    # bending in the local x-z plane (w, theta_y), about y: EI_y; w' = -theta_y flips signs
    flip = np.array([1.0, -1.0, 1.0, -1.0])
    put(k, [2, 4, 8, 10], Iy, kb * flip[:, None] * flip[None, :])
    put(m, [2, 4, 8, 10], A, mb * flip[:, None] * flip[None, :])
    return k, m


def rotations(xyz_a, xyz_b, up):
    """Rows: local x (member axis), y, z in global axes; local z is ``up`` made normal to x."""
    ex = xyz_b - xyz_a
    L = np.linalg.norm(ex, axis=1)
    ex = ex / L[:, None]
    ez = up - np.einsum("ij,ij->i", up, ex)[:, None] * ex
    ez /= np.linalg.norm(ez, axis=1)[:, None]
    ey = np.cross(ez, ex)
    return np.stack([ex, ey, ez], axis=1), L


def assemble(xyz, elements, up, sections, groups, n_groups, restrained=None):
    """Per-group unit stiffness and mass matrices (CSR), and the kept coordinates.

    xyz : (nodes, 3); elements : (ne, 2) node indices; up : (ne, 3) reference vector for
    local z; sections : (ne, 4) columns A, Iy, Iz, J; groups : (ne,) group of each element;
    restrained : boolean mask over the 6 * nodes coordinates (removed rows/columns).
    """
    n_all = 6 * xyz.shape[0]
    R, L = rotations(xyz[elements[:, 0]], xyz[elements[:, 1]], up)
    kl, ml = element_matrices(L, *sections.T)
    T = np.zeros((len(L), 12, 12))
    for b in range(4):
        T[:, 3 * b:3 * b + 3, 3 * b:3 * b + 3] = R
    kg = np.einsum("eji,ejk,ekl->eil", T, kl, T, optimize=True)
    mg = np.einsum("eji,ejk,ekl->eil", T, ml, T, optimize=True)

    keep = np.ones(n_all, bool) if restrained is None else ~restrained
    row_of = np.full(n_all, -1)
    row_of[keep] = np.arange(keep.sum())
    dofs = (6 * elements[:, :, None] + np.arange(6)).reshape(-1, 12)
    r = row_of[dofs]
    rr = np.broadcast_to(r[:, :, None], kg.shape)
    cc = np.broadcast_to(r[:, None, :], kg.shape)
    ok = (rr >= 0) & (cc >= 0)
    n = int(keep.sum())
    order = np.argsort(groups, kind="stable")
    bounds = np.searchsorted(groups[order], np.arange(n_groups + 1))
    k_terms, m_terms = [], []
    for g in range(n_groups):
        sel = order[bounds[g]:bounds[g + 1]]
        o = ok[sel]
        ij = (rr[sel][o], cc[sel][o])
        k_terms.append(sp.coo_array((kg[sel][o], ij), shape=(n, n)).tocsr())
        m_terms.append(sp.coo_array((mg[sel][o], ij), shape=(n, n)).tocsr())
    return k_terms, m_terms, np.flatnonzero(keep) + 1


@dataclass(frozen=True)
class Frame:
    """A built frame: the model, the truth values, and where the joints are."""

    model: ParametricModel  # with the initial (perturbed) parameter values
    truth: np.ndarray  # true parameter values
    xyz: np.ndarray  # node coordinates (m)
    joints: np.ndarray  # (nx+1, ny+1, ns+1) node index of each beam-column joint
    total_mass: float  # kg, at the true values
    n_elements: int


def _chains(a, b, xyz, n_sub, next_id):
    """Split members a-b into n_sub elements: new internal nodes and element node pairs."""
    t = np.arange(1, n_sub) / n_sub
    inner = xyz[a][:, None, :] + t[None, :, None] * (xyz[b] - xyz[a])[:, None, :]
    ids = next_id + np.arange(a.size * (n_sub - 1)).reshape(a.size, n_sub - 1)
    chain = np.concatenate([a[:, None], ids, b[:, None]], axis=1)
    elements = np.stack([chain[:, :-1], chain[:, 1:]], axis=-1).reshape(-1, 2)
    return inner.reshape(-1, 3), elements


def build_frame(
    nbx: int,
    nby: int,
    n_storeys: int,
    n_sub: int,
    *,
    supports: str = "clamped",
    n_bands: int = 5,
    truth_spread: float = 0.03,
    initial_error: float = 0.05,
    seed: int = 1,
) -> Frame:
    """Space frame with ``nbx`` x ``nby`` bays and ``n_storeys`` storeys.

    Elements form 3 * n_bands groups: (storey band) x (columns, X beams, Y beams), with
    the storeys split into ``n_bands`` contiguous bands. Each group has parameters
    ``E_<g>`` (Pa) and ``rho_<g>`` (kg/m^3). True values: steel nominal times
    1 +- ``truth_spread`` (random); initial values: truth times 1 +- between half and
    all of ``initial_error`` (random sign).
    """
    if supports not in ("clamped", "free"):
        raise ValueError(f"supports must be 'clamped' or 'free', not {supports!r}")
    if n_storeys < n_bands:
        raise ValueError("need at least as many storeys as bands")
    x = np.concatenate([[0.0], np.cumsum(np.resize(X_BAYS, nbx))])
    y = np.concatenate([[0.0], np.cumsum(np.resize(Y_BAYS, nby))])
    z = np.concatenate([[0.0, 4.2], 4.2 + STOREY * np.arange(1, n_storeys)])
    X, Y, Z = np.meshgrid(x, y, z, indexing="ij")
    joints = np.arange(X.size).reshape(X.shape)
    xyz = np.stack([X.ravel(), Y.ravel(), Z.ravel()], axis=1)

    band_of_storey = np.repeat(np.arange(n_bands),
                               [len(a) for a in np.array_split(np.arange(n_storeys), n_bands)])
    members = []  # (a, b, kind, storey, up)
    # columns: storey k from level k to k + 1
    a, b = joints[:, :, :-1], joints[:, :, 1:]
    st = np.broadcast_to(np.arange(n_storeys), a.shape)
    members.append((a.ravel(), b.ravel(), 0, st.ravel(), (0.0, 1.0, 0.0)))
    # X beams and Y beams at levels 1 .. n_storeys (storey index = level - 1)
    a, b = joints[:-1, :, 1:], joints[1:, :, 1:]
    st = np.broadcast_to(np.arange(n_storeys), a.shape)
    members.append((a.ravel(), b.ravel(), 1, st.ravel(), (0.0, 0.0, 1.0)))
    a, b = joints[:, :-1, 1:], joints[:, 1:, 1:]
    st = np.broadcast_to(np.arange(n_storeys), a.shape)
    members.append((a.ravel(), b.ravel(), 2, st.ravel(), (0.0, 0.0, 1.0)))

    pts, els, grp, ups, secs = [xyz], [], [], [], []
    next_id = xyz.shape[0]
    for a, b, kind, st, up in members:
        inner, e = _chains(a, b, xyz, n_sub, next_id)
        next_id += inner.shape[0]
        pts.append(inner)
        els.append(e)
        g = 3 * band_of_storey[st] + kind
        grp.append(np.repeat(g, n_sub))
        ups.append(np.broadcast_to(np.array(up), e.shape[:1] + (3,)))
        sec = COLUMN if kind == 0 else BEAM
        secs.append(np.broadcast_to(np.array([sec.A, sec.Iy, sec.Iz, sec.J]), (e.shape[0], 4)))
    xyz = np.concatenate(pts)
    elements = np.concatenate(els)
    groups = np.concatenate(grp)
    n_groups = 3 * n_bands

    restrained = None
    if supports == "clamped":
        restrained = np.zeros(6 * xyz.shape[0], bool)
        base = joints[:, :, 0].ravel()
        restrained[(6 * base[:, None] + np.arange(6)).ravel()] = True
    k_terms, m_terms, coords = assemble(
        xyz, elements, np.concatenate(ups), np.concatenate(secs), groups, n_groups, restrained
    )

    rng = np.random.default_rng(seed)
    nominal = np.concatenate([np.full(n_groups, E_STEEL), np.full(n_groups, RHO_STEEL)])
    truth = nominal * (1 + truth_spread * rng.uniform(-1, 1, nominal.size))
    err = initial_error * rng.uniform(0.5, 1.0, nominal.size) * rng.choice([-1, 1], nominal.size)
    initial = truth * (1 + err)
    kinds = ("col", "bx", "by")
    labels = [f"{kinds[g % 3]}{g // 3 + 1}" for g in range(n_groups)]
    params = tuple([Parameter(f"E_{s}", v) for s, v in zip(labels, initial[:n_groups],
                                                             strict=True)]
                   + [Parameter(f"rho_{s}", v) for s, v in zip(labels, initial[n_groups:],
                                                               strict=True)])
    n = coords.size
    zero = sp.csr_array((n, n))
    model = ParametricModel(
        zero, zero, params,
        tuple(k_terms) + (None,) * n_groups,
        (None,) * n_groups + tuple(m_terms),
        coordinates=coords,
    )
    # total structural mass at the true densities: sum of rho A L over the elements
    lengths = np.linalg.norm(xyz[elements[:, 1]] - xyz[elements[:, 0]], axis=1)
    area_length = np.bincount(groups, np.concatenate(secs)[:, 0] * lengths, n_groups)
    mass = float(truth[n_groups:] @ area_length)
    return Frame(model, truth, xyz, joints, mass, elements.shape[0])


def mass_sites(frame: Frame, count: int, seed: int = 2) -> list[int]:
    """``count`` distinct translational user coordinates at beam-column joints above the
    base, spread over storeys and plan positions, alternating X and Y directions (a vertical
    mass hardly changes the lateral modes of a frame)."""
    j = frame.joints[:, :, 1:]
    nx, ny, nz = j.shape
    rng = np.random.default_rng(seed)
    levels = np.linspace(nz - 1, 0, count).round().astype(int)  # top to bottom
    out: list[int] = []
    seen = set()
    for i, lev in enumerate(levels):
        for _ in range(100):
            node = int(j[rng.integers(nx), rng.integers(ny), lev])
            direction = i % 2
            c = 6 * node + direction + 1
            if c not in seen:
                break
        seen.add(c)
        out.append(c)
    return out


def cantilever(n_el: int, length: float, section: Section, axis=(1.0, 0.0, 0.0)):
    """Clamped-free straight cantilever along ``axis`` (E = rho = 1 unit matrices).

    Returns (K, M) for E = 1 and rho = 1 with node 0 clamped.
    """
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    xyz = np.arange(n_el + 1)[:, None] * (length / n_el) * axis[None, :]
    elements = np.stack([np.arange(n_el), np.arange(1, n_el + 1)], axis=1)
    up = np.array([0.0, 0.0, 1.0]) if abs(axis[2]) < 0.9 else np.array([0.0, 1.0, 0.0])
    restrained = np.zeros(6 * (n_el + 1), bool)
    restrained[:6] = True
    k, m, _ = assemble(
        xyz, elements, np.broadcast_to(up, (n_el, 3)),
        np.broadcast_to(np.array([section.A, section.Iy, section.Iz, section.J]), (n_el, 4)),
        np.zeros(n_el, int), 1, restrained,
    )
    return k[0], m[0]
