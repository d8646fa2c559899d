"""3-D frame elements (bars, beams, rods) as NASTRAN forms them, vectorised over elements.

Local element coordinates follow NASTRAN's CBAR: x runs from end A to end B, the
orientation vector v lies in plane 1 (the local x-y plane), y is the part of v normal to
x and z = x cross y. Plane-1 bending (displacements v, rotations about z) uses I1,
plane-2 bending (w, rotations about y) uses I2. Element degrees of freedom are
``[u, v, w, rx, ry, rz]`` at end A, then at end B.

Every matrix is split into unit *parts* that are scaled by one section quantity each,
so that K = EA k_axial + GJ k_torsion + EI1 k_bend1 + EI2 k_bend2 and
M = (rho A + nsm) m_translation + i_x m_torsion (i_x the torsional mass inertia per
length). A parameter that scales one of those quantities linearly (E, rho, A, I1, I2, J)
then has an exact dK/ds and dM/ds.

Shear flexibility (NASTRAN's K1, K2 on PBAR, PBEAM and the PBARL/PBEAML sections) is
Timoshenko's, as NASTRAN applies it to the two-node element: with
phi = 12 E I / (K A G L^2) in each plane the bending stiffness is the Euler-Bernoulli one
with 12, 6L, 4L^2, 2L^2 replaced by 12, 6L, (4 + phi) L^2, (2 - phi) L^2, all over
(1 + phi) (Przemieniecki, Theory of Matrix Structural Analysis, 1968, Sec. 5.6).

Mass formulations (MSC/NX Nastran; PARAM COUPMASS > 0 selects the coupled one):
*coupled* uses the cubic Hermitian shape functions in bending and linear ones in axial
and torsion; *lumped* puts half the element's translational (and torsional) mass at each
end and leaves the bending rotations massless. A rod's coupled mass is NASTRAN's own,
axial [5 1; 1 5] / 12 and lumped transverse. The caller chooses i_x: NASTRAN's CBAR has
none, its CBEAM rho (I1 + I2) (+ NSI). With offsets the lumped end masses sit at the
offset ends and ``element_transform`` carries them rigidly to the grids, as NASTRAN-95's
conventional bar mass does (mis/bard.f: m [[1, -[w]x], [[w]x, |w|^2 1 - w w^T]]).
"""

from __future__ import annotations

import numpy as np

from eigenupdate.errors import InputError

STIFFNESS_PARTS = ("axial", "torsion", "bend1", "bend2")
MASS_PARTS = ("translation", "torsion")


def stiffness_parts(length: np.ndarray, phi1: np.ndarray | None = None,
                    phi2: np.ndarray | None = None) -> dict[str, np.ndarray]:
    """Local stiffness (n, 12, 12) per unit EA, GJ, EI1 and EI2.

    ``phi1``, ``phi2``: the shear parameters 12 E I / (K A G L^2) of planes 1 and 2
    (0 or None: Euler-Bernoulli).

    Examples
    --------
    >>> k = stiffness_parts(np.array([2.0]))
    >>> float(k["axial"][0, 0, 0]), float(k["bend1"][0, 1, 5]), float(k["bend2"][0, 2, 4])
    (0.5, 1.5, -1.5)
    """
    L = np.asarray(length, dtype=float)
    n = L.size
    out = {name: np.zeros((n, 12, 12)) for name in STIFFNESS_PARTS}
    bar = np.array([[1.0, -1.0], [-1.0, 1.0]])
    for name, dof in (("axial", 0), ("torsion", 3)):
        idx = np.ix_([dof, dof + 6], [dof, dof + 6])
        out[name][:, idx[0], idx[1]] = bar / L[:, None, None]
    for name, (t, r, sign), phi in (("bend1", (1, 5, 1.0), phi1),
                                    ("bend2", (2, 4, -1.0), phi2)):
        d = [t, r, t + 6, r + 6]
        s = np.array([1.0, sign, 1.0, sign])
        f = np.zeros(n) if phi is None else np.broadcast_to(np.asarray(phi, float), (n,))
        unit = np.array([[12, 6, -12, 6], [6, 4, -6, 2], [-12, -6, 12, -6], [6, 2, -6, 4]],
                        dtype=float)[None].repeat(n, 0)
        # shear: the rotation-rotation terms 4 and 2 become 4 + phi and 2 - phi
        unit[:, 1, 1] += f
        unit[:, 3, 3] += f
        unit[:, 1, 3] -= f
        unit[:, 3, 1] -= f
        # powers of L: translation rows/cols carry none, rotation ones one each
        p = np.array([0, 1, 0, 1])
        k = (unit * L[:, None, None] ** (p[:, None] + p[None, :])
             / (L[:, None, None] ** 3 * (1.0 + f)[:, None, None]))
        out[name][:, np.ix_(d, d)[0], np.ix_(d, d)[1]] = k * np.outer(s, s)
    return out


def bending_coupling_part(length: np.ndarray) -> np.ndarray:
    """Local stiffness (n, 12, 12) per unit E I12 (I12 = int y z dA, an unsymmetric
    section): the energy E I12 int v'' w'' dx couples plane 1 (v, rz) with plane 2
    (w, ry), Euler-Bernoulli, as NASTRAN-95's KBAR builds it (which ignores K1, K2 when
    I12 != 0).

    Examples
    --------
    KBAR's v_A-w_A term 12 E I12 / L^3 and rz_A-ry_A term -4 E I12 / L:

    >>> k = bending_coupling_part(np.array([2.0]))[0]
    >>> float(k[1, 2]), float(k[5, 4]), float(k[2, 1]), bool((k == k.T).all())
    (1.5, -2.0, 1.5, True)
    """
    L = np.asarray(length, dtype=float)
    unit = np.array([[12, 6, -12, 6], [6, 4, -6, 2], [-12, -6, 12, -6], [6, 2, -6, 4]],
                    dtype=float)
    p = np.array([0, 1, 0, 1])
    k = unit[None] * L[:, None, None] ** (p[:, None] + p[None, :]) / L[:, None, None] ** 3
    k = k * np.outer([1.0, 1.0, 1.0, 1.0], [1.0, -1.0, 1.0, -1.0])  # ry = -w'
    out = np.zeros((L.size, 12, 12))
    d1, d2 = [1, 5, 7, 11], [2, 4, 8, 10]
    out[:, np.ix_(d1, d2)[0], np.ix_(d1, d2)[1]] = k
    out[:, np.ix_(d2, d1)[0], np.ix_(d2, d1)[1]] = np.transpose(k, (0, 2, 1))
    return out


def release(parts: dict[str, np.ndarray], released: np.ndarray) -> None:
    """Pin flags: condense the ``released`` (n, 12) local end components out of each
    element's stiffness parts, in place (K_rr - K_rp K_pp^+ K_pr; a part's released rows
    and columns become zero). Each local component belongs to one part (u axial, rx
    torsion, v and rz plane 1, w and ry plane 2), so K stays linear in EA, GJ, EI1, EI2.

    Examples
    --------
    A unit beam released in rotation about z at end A: end B's plane-1 translation
    against a fixed end A has stiffness 3 EI / L^3 (a propped cantilever's).

    >>> k = stiffness_parts(np.array([1.0]))
    >>> pin = np.zeros((1, 12), bool); pin[0, 5] = True
    >>> release(k, pin)
    >>> float(k["bend1"][0, 7, 7]), float(k["bend1"][0, 5, 5])
    (3.0, 0.0)
    """
    for e in np.flatnonzero(released.any(axis=1)):
        for k in parts.values():
            ke = k[e]
            p = np.flatnonzero(released[e] & (np.abs(np.diag(ke)) > 0))
            if p.size == 0:
                continue
            ke = ke - ke[:, p] @ np.linalg.pinv(ke[np.ix_(p, p)]) @ ke[p, :]
            ke[p, :] = 0.0
            ke[:, p] = 0.0
            k[e] = 0.5 * (ke + ke.T)


def mass_parts(length: np.ndarray, consistent: bool) -> dict[str, np.ndarray]:
    """Local mass (n, 12, 12) per unit mass per length (translation) and per unit
    torsional mass inertia per length (torsion).

    Examples
    --------
    Either formulation keeps the element's total mass, rho A L:

    >>> for c in (True, False):
    ...     m = mass_parts(np.array([2.0]), c)["translation"][0]
    ...     print(float(m[np.ix_([0, 6], [0, 6])].sum()), float(m[np.ix_([1, 7], [1, 7])].sum()))
    2.0 2.0
    2.0 2.0
    """
    L = np.asarray(length, dtype=float)
    n = L.size
    tr = np.zeros((n, 12, 12))
    tor = np.zeros((n, 12, 12))
    if not consistent:
        for d in (0, 1, 2, 6, 7, 8):
            tr[:, d, d] = L / 2
        for d in (3, 9):
            tor[:, d, d] = L / 2
        return {"translation": tr, "torsion": tor}
    lin = np.array([[2.0, 1.0], [1.0, 2.0]]) / 6.0
    ax = np.ix_([0, 6], [0, 6])
    tr[:, ax[0], ax[1]] = lin * L[:, None, None]
    tq = np.ix_([3, 9], [3, 9])
    tor[:, tq[0], tq[1]] = lin * L[:, None, None]
    unit = np.array([[156, 22, 54, -13], [22, 4, 13, -3], [54, 13, 156, -22], [-13, -3, -22, 4]],
                    dtype=float) / 420.0
    p = np.array([0, 1, 0, 1])
    m = unit[None] * L[:, None, None] ** (p[:, None] + p[None, :] + 1)
    for t, r, sign in ((1, 5, 1.0), (2, 4, -1.0)):
        d = [t, r, t + 6, r + 6]
        s = np.array([1.0, sign, 1.0, sign])
        i = np.ix_(d, d)
        tr[:, i[0], i[1]] = m * np.outer(s, s)
    return {"translation": tr, "torsion": tor}


def rod_mass_part(length: np.ndarray, consistent: bool) -> np.ndarray:
    """Local translational mass (n, 12, 12) of a rod per unit mass per length, as
    MSC/NX Nastran's CROD: coupled, axial [5 1; 1 5] / 12 (the mean of the lumped and
    the linear consistent matrix) and half the mass on each end transversely; lumped,
    halves in all three directions."""
    L = np.asarray(length, dtype=float)
    out = np.zeros((L.size, 12, 12))
    for d in range(3):
        if consistent and d == 0:
            m = np.array([[5.0, 1.0], [1.0, 5.0]]) / 12.0
        else:
            m = np.eye(2) / 2.0
        i = np.ix_([d, d + 6], [d, d + 6])
        out[:, i[0], i[1]] = m * L[:, None, None]
    return out


def local_axes(xa: np.ndarray, xb: np.ndarray, v: np.ndarray,
               labels: list[str] | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Lengths (n,) and rotations (n, 3, 3) whose rows are the local x, y, z axes.

    ``labels`` name the elements in the errors (zero length, v parallel to the axis).

    Examples
    --------
    >>> L, R = local_axes(np.array([[0., 0, 0]]), np.array([[0., 0, 3]]), np.array([[1., 1, 0]]))
    >>> float(L[0]), np.round(R[0], 4).tolist()
    (3.0, [[0.0, 0.0, 1.0], [0.7071, 0.7071, 0.0], [-0.7071, 0.7071, 0.0]])
    """
    d = np.asarray(xb, float) - np.asarray(xa, float)
    L = np.linalg.norm(d, axis=1)
    scale = max(float(np.max(np.abs(np.concatenate([xa, xb])), initial=0.0)), 1.0)
    short = np.flatnonzero(L <= 1e-12 * scale)
    if short.size:
        what = labels[short[0]] if labels else f"element {short[0]}"
        # a huge coordinate or offset elsewhere makes a sound element relatively zero
        far = f" (length {L[short[0]]:g} against coordinates up to {scale:g})" \
            if L[short[0]] > 0 else ""
        raise InputError(f"{what}: zero-length element{far}")
    ex = d / L[:, None]
    v = np.asarray(v, float)
    vy = v - np.sum(v * ex, axis=1)[:, None] * ex
    nv = np.linalg.norm(vy, axis=1)
    vn = np.linalg.norm(v, axis=1)
    bad = np.flatnonzero(~(nv > 1e-8 * np.maximum(vn, 1e-300)))
    if bad.size:
        what = labels[bad[0]] if labels else f"element {bad[0]}"
        raise InputError(f"{what}: orientation vector is zero or parallel to the element axis")
    ey = vy / nv[:, None]
    ez = np.cross(ex, ey)
    return L, np.stack([ex, ey, ez], axis=1)


def any_normal(axis: np.ndarray) -> np.ndarray:
    """A vector not parallel to each row of ``axis`` (orientation of rods)."""
    a = np.abs(np.asarray(axis, float))
    out = np.zeros_like(a)
    out[np.arange(a.shape[0]), np.argmin(a, axis=1)] = 1.0
    return out


def skew(w: np.ndarray) -> np.ndarray:
    """(n, 3, 3) cross-product matrices: skew(w) @ x = w cross x."""
    w = np.asarray(w, float)
    s = np.zeros((w.shape[0], 3, 3))
    s[:, 0, 1], s[:, 0, 2] = -w[:, 2], w[:, 1]
    s[:, 1, 0], s[:, 1, 2] = w[:, 2], -w[:, 0]
    s[:, 2, 0], s[:, 2, 1] = -w[:, 1], w[:, 0]
    return s


def node_transform(rotation: np.ndarray, offset: np.ndarray | None,
                   frame: np.ndarray) -> np.ndarray:
    """(n, 6, 6) map from a grid's 6 displacements in its own frame to the element end's
    6 displacements in local axes.

    ``frame`` (n, 3, 3): rows are the grid's displacement axes in basic (NASTRAN's CD).
    ``offset`` (n, 3): vector from the grid to the element end in basic (rigid link:
    u_end = u_grid + theta x offset).
    """
    n = rotation.shape[0]
    to_basic = np.transpose(frame, (0, 2, 1))
    t = np.zeros((n, 6, 6))
    t[:, :3, :3] = rotation @ to_basic
    t[:, 3:, 3:] = rotation @ to_basic
    if offset is not None:
        t[:, :3, 3:] = rotation @ (-skew(offset)) @ to_basic
    return t


def element_transform(rotation, offset_a, offset_b, frame_a, frame_b) -> np.ndarray:
    """(n, 12, 12) map from the two grids' displacements to local end displacements."""
    n = rotation.shape[0]
    t = np.zeros((n, 12, 12))
    t[:, :6, :6] = node_transform(rotation, offset_a, frame_a)
    t[:, 6:, 6:] = node_transform(rotation, offset_b, frame_b)
    return t


def to_global(local: np.ndarray, transform: np.ndarray) -> np.ndarray:
    """T^T k T for every element."""
    return np.transpose(transform, (0, 2, 1)) @ local @ transform
