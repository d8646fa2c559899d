"""An unsymmetric PCOMP (membrane-bending coupling B) off its grids, by ZOFFS or by a
stack shift Z0 != -T/2: the rigid offset must move the coupling part too. Independent
reference: the same plate with its reference plane's grids placed at the offset and
tied to the grids by RBE2 (the rigid link NASTRAN's offset stands for). Runs in
.venv-nastran (pyNastran)."""

from __future__ import annotations

import warnings

import pytest
from bounds import assert_eigenvalues_agree
from nastran_frames import need

from eigenupdate.errors import EigenupdateWarning
from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.io.nastran import read_nastran  # noqa: E402

# [0/30/-45/90], two materials: B != 0
PCOMP = ("PCOMP,1,{z0},{nsm}\n,2,0.004,0.,,2,0.006,30.\n,1,0.003,-45.,,2,0.004,90.\n"
         "MAT8,2,1.4e11,9.e9,0.3,5.e9,5.e9,5.e9,1600.\nMAT1,1,7.e10,,0.33,2700.\n")
T = 0.017
NX = 4
TRIANGLES = {1, 6}  # these quads split in two CTRIA3
FLIPPED = {3, 6, 9}  # node order reversed: normal -z, ZOFFS given with the other sign


def _deck(path, z, z0="", linked=False, coupmass=1, nsm="0.5", flipped=FLIPPED):
    """Unit plate, u, v, w held on the edge grids (so the offset matters); ZOFFS ``z`` along +z
    (each element's field carries its normal's sign). ``linked``: no ZOFFS, the elements
    on grids 1000 + i at height z, each tied to grid i by an RBE2."""
    n = NX + 1
    lines = []
    for j in range(n):
        for i in range(n):
            g = j * n + i + 1
            lines.append(f"GRID,{g},,{i / NX!r},{j / NX!r},0.")
            if g in {1, n, n * n} or i in (0, NX) or j in (0, NX):
                lines.append(f"SPC1,1,123,{g}")
            if linked:
                lines += [f"GRID,{g + 1000},,{i / NX!r},{j / NX!r},{z!r}",
                          f"RBE2,{g + 5000},{g},123456,{g + 1000}"]
    eid = 0
    for j in range(NX):
        for i in range(NX):
            k = j * NX + i
            q = [j * n + i + 1, j * n + i + 2, (j + 1) * n + i + 2, (j + 1) * n + i + 1]
            if linked:
                q = [g + 1000 for g in q]
            sign = -1 if k in flipped else 1
            for nodes in ([q[:3], [q[0], q[2], q[3]]] if k in TRIANGLES else [q]):
                eid += 1
                nodes = nodes[::sign]
                card = "CQUAD4" if len(nodes) == 4 else "CTRIA3"
                off = "" if linked else f",,{sign * z!r}"
                lines.append(f"{card},{eid},1," + ",".join(map(str, nodes)) + off)
    path.write_text(f"SOL 103\nCEND\nSPC = 1\nBEGIN BULK\nPARAM,COUPMASS,{coupmass}\n"
                    + PCOMP.format(z0=z0, nsm=nsm) + "\n".join(lines) + "\nENDDATA\n")
    return path


def _solve(path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EigenupdateWarning)
        m = read_nastran(path).model
    K, M = m.stiffness(), m.mass()
    return solve_elastic(K, M, 8), K, M


@pytest.mark.parametrize("coupmass", [1, -1], ids=["coupled", "lumped"])
@pytest.mark.parametrize("z", [0.01, -0.004])
def test_unsymmetric_pcomp_with_zoffs_is_the_rigidly_linked_plate(tmp_path, z, coupmass):
    """Source: the rigid link the offset stands for (RBE2 from each grid to a grid at
    the reference plane; NASTRAN-95 TLDRD's u + z ry, v - z rx). Both models are the
    same K and M in the same independent coordinates, so their eigenvalues agree within
    the two solvers' rounding floors. Before the fix the coupling part was not moved:
    K was indefinite (negative eigenvalues about 3e-5 of the largest)."""
    got, _, _ = _solve(_deck(tmp_path / "o.bdf", z, coupmass=coupmass))
    ref, K, M = _solve(_deck(tmp_path / "r.bdf", z, linked=True, coupmass=coupmass))
    assert_eigenvalues_agree(got.eigenvalues, ref, K, M)
    plain, _, _ = _solve(_deck(tmp_path / "p.bdf", 0.0, coupmass=coupmass))
    assert abs(got.frequencies_hz[0] / plain.frequencies_hz[0] - 1) > 0.01  # seen


def test_unsymmetric_pcomp_shifted_by_z0_is_the_rigidly_linked_plate(tmp_path):
    """Source: as above. Z0 = 0 puts the stack's bottom on the grids (NASTRAN's PCOMP
    Z0, along the element's normal): the stack about its mid-plane T/2 above them, i.e.
    the plate on grids at T/2 tied by RBE2, with Z0 = -T/2 there. No element is flipped
    (Z0 follows each one's normal) and NSM is 0 (it lies on the reference plane, which
    Z0 does not move)."""
    got, _, _ = _solve(_deck(tmp_path / "o.bdf", 0.0, z0="0.", nsm="0.", flipped=()))
    ref, K, M = _solve(_deck(tmp_path / "r.bdf", T / 2, linked=True, nsm="0.",
                             flipped=()))
    assert_eigenvalues_agree(got.eigenvalues, ref, K, M)
