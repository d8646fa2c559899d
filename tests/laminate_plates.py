"""Laminated plates with membrane-bending coupling for the shell tests: a ply stack's
A, B, D, H turned to each element's axes, the elements' K built as the deck path does,
and the Navier solution of the simply supported cross-ply plate."""

from __future__ import annotations

import numpy as np
import scipy.sparse.linalg as spla
from plates import square_mesh

from eigenupdate.model import laminate, shells
from eigenupdate.model.assembly import node_dofs, scatter

# a graphite-epoxy ply (E1/E2 = 25, Reddy's material): SI units
E1, E2, NU12, G12, G13, G23, RHO = 175e9, 7e9, 0.25, 3.5e9, 3.5e9, 1.4e9, 1600.0


def stack(angles, t, z0=None, phi=(0.0,)):
    """A, B, D, H (each (n, ., .)) of plies of thickness t at ``angles`` (degrees) from
    the laminate's x axis, bottom at z0 (default -T/2), in the axes of n elements whose
    x axis is at -phi (n,) (radians) from the laminate's."""
    p = len(angles)
    q = np.stack([laminate.orthotropic_plane(E1, E2, NU12, G12)] * p)
    g = np.stack([np.diag([G13, G23])] * p)
    T = p * t
    return laminate.abd(q, g, np.full(p, t), -T / 2 if z0 is None else z0,
                        np.radians(angles)[None, :] + np.asarray(phi)[:, None])


def element_stiffness(xyz_e, angles, t, z0=None, x_lam=(1.0, 0.0, 0.0)):
    """K (n, 6k, 6k) of elements with the laminate of :func:`stack` whose x axis is
    ``x_lam`` (global), turned to each element's axes (CTRIA3's x runs G1-G2, so it
    differs between elements) as the deck path does, moduli per thickness power and
    factors T, T^3, T^2, s(T)."""
    R, _ = shells.shell_axes(xyz_e)
    phi = np.arctan2(R[:, 1] @ np.asarray(x_lam), R[:, 0] @ np.asarray(x_lam))
    A, B, D, H = stack(angles, t, z0, phi)
    T = len(angles) * t
    R, parts = shells.local_parts(xyz_e, A / T, D / T**3, H / T,
                                  coupling=B / T**2 if np.any(B) else None)
    size = shells.stabilisation_size(xyz_e)
    f = {"membrane": T, "drilling": T, "bending": T**3,
         "shear": shells.shear_thickness(T, size)}
    if shells.COUPLING in parts:
        f[shells.COUPLING] = T**2
    n = xyz_e.shape[0]
    return shells.combine(R, parts, {q: np.full(n, v) if np.ndim(v) == 0 else v
                                     for q, v in f.items()})


def navier_coupled(a, abdh, rho_h):
    """Lowest omega of a simply supported (S2: w, the tangential in-plane displacement
    and the rotation about the edge's normal held) square antisymmetric cross-ply plate,
    mode (1, 1), first-order shear deformation theory with coupling: u = U cos ax sin ay,
    v = V sin ax cos ay, w = W sin ax sin ay, ry = Ry cos ax sin ay, rx = Rx sin ax cos ay
    (a = pi / a) satisfy the edge conditions and, as A16 = A26 = B12 = B16 = B26 = B66 =
    D16 = D26 = 0, the equations of motion (Whitney 1987, sec. 5.4; Reddy, Mechanics of
    Laminated Composite Plates and Shells, 2004, sec. 6.3): the 5 x 5 stiffness is the
    energy's, each squared sine/cosine product integrating to a^2 / 4; no rotary inertia
    (as the elements). Rotations condensed, then the 3 x 3 eigenproblem in U, V, W."""
    A, B, D, H = (m[0] for m in abdh)
    al = np.pi / a
    C = np.block([[A, B], [B, D]])
    # rows: eps_x, eps_y, g_xy, k_x, k_y, k_xy; columns U, V, W, Rx, Ry
    Ps, Pc = np.zeros((6, 5)), np.zeros((6, 5))
    Ps[0, 0], Ps[1, 1], Ps[3, 4], Ps[4, 3] = -al, -al, -al, al  # times sin sin
    Pc[2, 0], Pc[2, 1], Pc[5, 4], Pc[5, 3] = al, al, al, -al  # times cos cos
    gx = np.array([0, 0, al, 0, 1.0])  # w,x + ry, times cos sin
    gy = np.array([0, 0, al, -1.0, 0])  # w,y - rx, times sin cos
    K = a**2 / 4 * (Ps.T @ C @ Ps + Pc.T @ C @ Pc + H[0, 0] * np.outer(gx, gx)
                    + H[1, 1] * np.outer(gy, gy))
    Kc = K[:3, :3] - K[:3, 3:] @ np.linalg.solve(K[3:, 3:], K[3:, :3])
    lam = np.linalg.eigvalsh(Kc / (rho_h * a**2 / 4))
    return float(np.sqrt(lam[0]))


def fe_plate(nx, a, angles, t, rho_h, triangles):
    """Lowest omega of the FE plate with the S2 support of :func:`navier_coupled`:
    w everywhere on the edges, v and rx on x = 0, a; u and ry on y = 0, a."""
    xyz, el = square_mesh(nx, a, triangles)
    n = 6 * xyz.shape[0]
    d = node_dofs(el, 6)
    K = scatter(d, element_stiffness(xyz[el], angles, t), n)
    M = scatter(d, rho_h * shells.shell_mass(xyz[el], False), n)
    x, y = xyz[:, 0], xyz[:, 1]
    on_x = np.isclose(x, 0) | np.isclose(x, a)
    on_y = np.isclose(y, 0) | np.isclose(y, a)
    fixed = np.zeros((xyz.shape[0], 6), bool)
    fixed[on_x | on_y, 2] = True
    fixed[on_x, 1] = fixed[on_x, 3] = True
    fixed[on_y, 0] = fixed[on_y, 4] = True
    free = np.flatnonzero(~fixed.ravel())
    K, M = K[free][:, free], M[free][:, free]
    mu = spla.eigsh(M, 1, K, which="LA", return_eigenvectors=False)
    return float(np.sqrt(1.0 / mu[0]))


def fe_quadratic_plate(nx, a, abdh_of, T, rho_h, triangles):
    """Lowest omega of nx x nx CQUAD8 (2 nx x nx CTRIA6) on an a x a plate with the S2
    support of :func:`navier_coupled`, symmetric section (B = 0): ``abdh_of(phi)`` gives
    A, B, D, H in the axes of elements whose x is at -phi from the laminate's (as
    :func:`stack`), moduli per thickness power and CTRIA6's stabilisation scaled by
    :func:`~eigenupdate.model.shells_quadratic.stabilisation_ratio`, as the deck path."""
    from quadratic_meshes import plate_mesh

    from eigenupdate.model import shells_quadratic as sq

    xyz, el = plate_mesh(nx, a, a, triangles)
    xe = xyz[el]
    R, _ = sq.material_axes(xe)
    A, _, D, H = abdh_of(np.arctan2(R[:, 1, 0], R[:, 0, 0]))
    n = len(el)
    cb, cs = D / T**3, H / T
    _, parts = sq.local_parts(xe, A / T, cb, cs)
    size = sq.stabilisation_size(xe) * np.sqrt(sq.stabilisation_ratio(cb, cs))
    f = {"membrane": np.full(n, T), "drilling": np.full(n, T), "bending": np.full(n, T**3),
         "shear": shells.shear_thickness(T, size)}
    K = shells.combine(np.broadcast_to(np.eye(3), (n, 3, 3)), parts, f)
    d, N = node_dofs(el, 6), 6 * len(xyz)
    K, M = scatter(d, K, N), scatter(d, rho_h * sq.shell_mass(xe, False), N)
    x, y = xyz[:, 0], xyz[:, 1]
    on_x = np.isclose(x, 0) | np.isclose(x, a)
    on_y = np.isclose(y, 0) | np.isclose(y, a)
    fixed = np.zeros((len(xyz), 6), bool)
    fixed[on_x | on_y, 2] = True
    fixed[on_x, 1] = fixed[on_x, 3] = True
    fixed[on_y, 0] = fixed[on_y, 4] = True
    free = np.flatnonzero(~fixed.ravel())
    mu = spla.eigsh(M[free][:, free], 1, K[free][:, free], which="LA",
                    return_eigenvectors=False)
    return float(np.sqrt(1.0 / mu[0]))
