"""Warped CQUAD4 (and CQUADR): computed on the mean plane, rigidly linked to the grids
(model/rigid_links.py). Checked by rigid-body motion of a free warped element (exact with
the links, not without), MacNeal and Harder's twisted beam (every element warped), and
the warning and refusal levels.

Run for real in .venv-nastran (``make test``); skipped in the core environment."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import scipy.sparse.linalg as spla
from nastran_frames import need

from eigenupdate.errors import EigenupdateWarning, InputError
from eigenupdate.model import rigid_links, shells

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.io.nastran import read_nastran  # noqa: E402

STEEL = "MAT1,1,2.e11,,0.3,7850.\n"
# a unit square with grids 2 and 4 lifted: heights +-0.075 about the mean plane, warp 0.075
WARPED = "GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.15\nGRID,3,,1.,1.,0.\nGRID,4,,0.,1.,0.15\n"


def _deck(tmp_path, body: str, name="deck.bdf"):
    path = tmp_path / name
    path.write_text("BEGIN BULK\nPARAM,AUTOSPC,NO\n" + body + "ENDDATA\n")
    return path


def _read(path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EigenupdateWarning)
        return read_nastran(path).model


# a 2 x 2 patch on the hyperbolic paraboloid z = 0.6 x y: every element warped by 0.075
HYPAR = "".join(f"GRID,{3 * i + j + 1},,{0.5 * i!r},{0.5 * j!r},{0.6 * 0.25 * i * j!r}\n"
                for i in range(3) for j in range(3))


@pytest.mark.parametrize("card", ["CQUAD4", "CQUADR"])
def test_free_warped_patch_has_six_rigid_modes(tmp_path, card):
    """Source: rigid-body motion stores no energy. A free 2 x 2 patch of warped elements
    (warp 0.075) has exactly six zero eigenvalues of K (below 1e-10 of the largest) and a
    gap of 1e3 to the seventh (CQUAD4's K6ROT drilling is 1e-6 of the membrane). The
    parts on the mean plane without the links strain under a rigid rotation about an
    in-plane axis: shown on one element below, so the test can fail."""
    quads = "".join(f"{card},{k + 1},1,{a},{a + 3},{a + 4},{a + 1}\n"
                    for k, a in enumerate((1, 2, 4, 5)))
    model = _read(_deck(tmp_path, HYPAR + quads + "PSHELL,1,1,.01,1,,1\n" + STEEL
                        + "PARAM,K6ROT,100.\n"))
    w = np.linalg.eigvalsh(model.stiffness().toarray())
    zero = np.abs(w[:6]).max()
    assert zero <= 1e-10 * w[-1] and w[6] > 1e3 * zero, w[:8] / w[-1]

    xyz = np.array([[[0.0, 0, 0], [1, 0, 0.15], [1, 1, 0], [0, 1, 0.15]]])
    R, linked = shells.local_parts(xyz, *shells.pshell_moduli(2e11, 0.3))
    unlinked = rigid_links.offset_parts(linked, rigid_links.warp_heights(xyz, R[:, 2]))
    rot = np.zeros(24)  # rotation about the element's own x axis, in element axes
    local = np.einsum("ij,kj->ki", R[0], xyz[0] - xyz[0].mean(axis=0))
    rot[1::6], rot[2::6], rot[3::6] = -local[:, 2], local[:, 1], 1.0

    def energy(parts):
        return sum(float(rot[c] @ b[0] @ rot[c]) for c, b in parts.values())

    assert abs(energy(linked)) <= 1e-12 * abs(energy(unlinked)) and energy(unlinked) > 0


def _twisted_beam(nx: int, ny: int) -> str:
    """MacNeal and Harder's twisted beam (Finite Elements in Analysis and Design 1, 1985,
    test 7): L = 12, width 1.1, T = 0.32, E = 29e6, NU = 0.22, 90 degrees of twist,
    clamped at x = 0; the tip grids tied by an RBE2 to a tip grid loaded there."""
    lines, gid = [], {}
    for i in range(nx + 1):
        x = 12.0 * i / nx
        th = 0.5 * np.pi * i / nx
        for j in range(ny + 1):
            s = -0.55 + 1.1 * j / ny
            gid[i, j] = len(gid) + 1
            lines.append(f"GRID,{gid[i, j]},,{x!r},{s * np.cos(th)!r},{s * np.sin(th)!r}")
    for i in range(nx):
        for j in range(ny):
            lines.append(f"CQUAD4,{i * ny + j + 1},1,{gid[i, j]},{gid[i + 1, j]},"
                         f"{gid[i + 1, j + 1]},{gid[i, j + 1]}")
    lines += [f"SPC1,1,123456,{gid[0, j]}" for j in range(ny + 1)]
    lines.append("GRID,9999,,12.,0.,0.")
    tip = [str(gid[nx, j]) for j in range(ny + 1)]  # 5 on the first line, 8 on the next
    lines.append("RBE2,9999,9999,123456," + ",".join(tip[:5]))
    lines += ["," + ",".join(tip[k:k + 8]) for k in range(5, len(tip), 8)]
    return ("\n".join(lines) + "\nPSHELL,1,1,0.32,1,,1\nMAT1,1,29.e6,,0.22\n"
            "PARAM,K6ROT,100.\n")


@pytest.mark.parametrize("direction, reference", [(3, 5.424e-3), (2, 1.754e-3)],
                         ids=["in-plane", "out-of-plane"])
def test_twisted_beam_agrees_with_macneal_harder(tmp_path, direction, reference):
    """Source: MacNeal and Harder's twisted beam, tip deflection under a unit tip load in
    the tip's plane (z) 5.424e-3, normal to it (y) 1.754e-3 (their reference solution, 4
    digits). Every element is warped (7.5 degrees of twist across each at 12 x 2): the
    mean-plane links and the warped elements' own corner normals (no PARAM SNORM) give
    12 x 2 and 24 x 4 within 1 % (NASTRAN's QUAD4 in their table: 0.993 and 0.985 at
    12 x 2), whatever K6ROT (0 or 1e4 move it by less than 0.2 %). Plain facets hinged
    about their normals: 3.9 times too soft at 12 x 2."""
    out = {}
    for nx, ny, k6rot in ((12, 2, "100."), (24, 4, "100."), (12, 2, "0."), (12, 2, "1.e4")):
        deck = _twisted_beam(nx, ny).replace("PARAM,K6ROT,100.", f"PARAM,K6ROT,{k6rot}")
        nm = read_nastran(_deck(tmp_path, deck, f"b{nx}{k6rot}.bdf"))
        K = nm.model.stiffness().tocsc()
        f = np.zeros(K.shape[0])
        at = nm.model.index(nm.grid_dof(9999, direction))
        f[at] = 1.0
        out[nx, k6rot] = spla.spsolve(K, f)[at] / reference
    assert abs(out[12, "100."] - 1) <= 0.01 and abs(out[24, "100."] - 1) <= 0.01, out
    assert abs(out[12, "0."] / out[12, "1.e4"] - 1) <= 2e-3, out


def test_warp_warned_then_refused(tmp_path):
    """NASTRAN's GEOMCHECK warns of a CQUAD4 warped beyond 0.05; here beyond
    shells.MAX_WARP it is refused in one line naming the element."""
    body = "CQUAD4,7,1,1,2,3,4\nPSHELL,1,1,.01,1,,1\n" + STEEL
    with pytest.warns(EigenupdateWarning, match="CQUAD4 7: warped by up to 0.075"):
        read_nastran(_deck(tmp_path, WARPED + body, "a.bdf"))
    steep = WARPED.replace("0.15", "0.5")  # heights +-0.25: warp 0.25
    with pytest.raises(InputError, match="CQUAD4 7: warped by 0.25"):
        read_nastran(_deck(tmp_path, steep + body, "b.bdf"))
