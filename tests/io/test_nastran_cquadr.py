"""CQUADR and CTRIAR read from a deck (model/shells_drilling.py; PSHELL, PCOMP).

Sources: Navier's simply supported plate, and the same deck with CQUAD4/CTRIA3 (a flat
plate's bending modes do not involve the membrane, whose formulation alone differs);
central finite differences of K, M for PSHELL T, MAT1 E and RHO; the deck re-read at
changed values; OpenSees' ShellDKGQ (a drilling membrane too: Long & Xu's GQ12) on the
same in-plane cantilever mesh, and ASDShellQ4.

NASTRAN's own frequencies: none of the decks with CQUADR/CTRIAR we have is usable. In
the pyNastran mirror, models/elements/modes_elements (MSC) prints three eigenvalues, all
near zero (1e-9..2e-8 Hz: mechanisms of a free test assembly); models/other/trncomp12
(NX, SOL 112, modes 0.77, 1.25, 2.04 ... Hz; CQUAD8/CTRIA6 with blank mid-side grids
beside the CQUADR/CTRIAR, read since model/shells_transition.py; six elements, its
frequencies 10 % to twice off the refined deck's, ours -8 to +30 % off its) constrains
the CQUADR's rz (PS = 6), which NASTRAN's remark 5 says gives inaccurate results;
dbxdra2 (complex modes) holds CTRIAX6, RBE1 and others not supported."""

from __future__ import annotations

import numpy as np
import pytest
from bounds import assert_matrix_derivatives
from nastran_frames import need, opensees
from plates import square_mesh

from eigenupdate.errors import InputError
from eigenupdate.model.parameters import Parameter
from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")
from plates import (  # noqa: E402
    INIT,
    NU,
    RHO,
    E,
    two_region_deck,  # noqa: E402
)
from plates import card_specs as _spec  # noqa: E402
from plates import read_deck as _read  # noqa: E402

from eigenupdate.io.nastran import CardField  # noqa: E402


def plate(path, v=INIT, nx=8, a=1.0, triangles=False, drilling=True, nsm=0.5, held="12"):
    """The two-region plate (tests/plates.py), w held on its edges and ``held`` everywhere
    (u, v: the drilling rotation stays free, as NASTRAN's remark 5 asks)."""
    card = {(False, True): "CQUADR", (False, False): "CQUAD4", (True, True): "CTRIAR",
            (True, False): "CTRIA3"}[triangles, drilling]
    return two_region_deck(path, v, nx, a, card, nsm, held)


@pytest.mark.parametrize("triangles", [False, True], ids=["CQUADR", "CTRIAR"])
def test_plate_bending_is_cquad4s_and_converges_to_navier(tmp_path, triangles):
    """Source: Navier's omega_11 of a simply supported thin plate (a/h = 1000), and the
    same deck with CQUAD4 (CTRIA3): bending and shear are theirs and a flat plate's
    bending modes leave the membrane unstrained, so the lowest four frequencies agree to
    the eigen-solver's rounding (1e-9 relative here), whatever the drilling
    formulation; the first converges toward Navier as the CQUAD4's does."""
    t = 1e-3
    v = {"t1": t, "t2": t, "E": E, "rho": RHO}
    f = {}
    for nx in (8, 16):
        for drilling in (True, False):
            m = _read(plate(tmp_path / f"p{nx}{drilling}.bdf", v, nx, triangles=triangles,
                            drilling=drilling, nsm=0.0)).model
            f[nx, drilling] = solve_elastic(m.stiffness(), m.mass(), 4).frequencies_hz
        assert np.abs(f[nx, True] / f[nx, False] - 1).max() <= 1e-9
    D = E * t**3 / (12 * (1 - NU**2))
    exact = np.pi * np.sqrt(D / (RHO * t))  # 2 pi^2 / a^2 sqrt(D / rho h) / (2 pi)
    f8, f16 = f[8, True][0], f[16, True][0]
    # as test_nastran_shell_thickness.py's CQUAD4: the support holds w only, the error
    # falls about as h^(1/2..1) (measured -1.0, -0.64 %): order 1/2 allowed
    assert abs(f16 - exact) <= abs(f16 - f8) / (np.sqrt(2) - 1) + 1e-4 * exact


@pytest.mark.parametrize("triangles", [False, True], ids=["CQUADR", "CTRIAR"])
def test_thickness_E_rho_derivatives_match_central_differences(tmp_path, triangles):
    """PSHELL T (membrane, drilling ~ T, bending ~ T^3, shear s(T)), MAT1 E, RHO on
    CQUADR/CTRIAR: dK/dp, dM/dp against central differences (tests/bounds.py); the
    drilling rotation free, so its part is in K."""
    model = _read(plate(tmp_path / "a.bdf", triangles=triangles), _spec()).model
    assert model.nonlinear
    assert_matrix_derivatives(model)


@pytest.mark.parametrize("triangles", [False, True], ids=["CQUADR", "CTRIAR"])
def test_model_at_new_values_is_the_hand_edited_deck(tmp_path, triangles):
    """Source: the deck with its T, E, RHO changed in the text and read again; the same
    element matrices times the same factors summed in another order (a few ulps)."""
    nm = _read(plate(tmp_path / "a.bdf", triangles=triangles), _spec())
    new = dict(zip(INIT, np.array(list(INIT.values())) * [1.1, 0.93, 1.05, 0.97], strict=True))
    ref = _read(plate(tmp_path / "b.bdf", new, triangles=triangles)).model
    s = np.array(list(new.values()))
    for a, b in ((nm.model.stiffness(s), ref.stiffness()), (nm.model.mass(s), ref.mass())):
        assert abs(a - b).max() <= 1e-12 * abs(b).max()


def test_unsymmetric_laminate_is_refused(tmp_path):
    """An unsymmetric PCOMP ([0/90] of MAT8) on a CQUADR: one line naming the card
    (the membrane-bending coupling is not built for these elements)."""
    path = tmp_path / "u.bdf"
    path.write_text("BEGIN BULK\nGRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nGRID,3,,1.,1.,0.\n"
                    "GRID,4,,0.,1.,0.\nCQUADR,1,7,1,2,3,4\nPCOMP,7\n,2,0.001,0.\n"
                    ",2,0.001,90.\nMAT8,2,1.4e11,1.e10,0.3,5.e9,5.e9,5.e9,1600.\n"
                    "ENDDATA\n")
    with pytest.raises(InputError, match="PCOMP 7: membrane-bending coupling.*CQUADR"):
        _read(path)


def _strip(nx: int, ny: int, L=1.0, w=0.1, t=0.005):
    """Nodes and quadrilaterals of an L x w strip in z = 0."""
    xs, ys = np.linspace(0, L, nx + 1), np.linspace(0, w, ny + 1)
    xyz = np.array([(a, b, 0.0) for a in xs for b in ys])
    at = np.arange(xyz.shape[0]).reshape(nx + 1, ny + 1)
    quads = np.column_stack([at[:-1, :-1].ravel(), at[1:, :-1].ravel(), at[1:, 1:].ravel(),
                             at[:-1, 1:].ravel()])
    return xyz, quads, t


def _ours(tmp_path, nx, ny):
    xyz, quads, t = _strip(nx, ny)
    lines = [f"GRID,{i + 1},,{x!r},{y!r},0.,,345" for i, (x, y, _) in enumerate(xyz)]
    lines += [f"CQUADR,{k + 1},1," + ",".join(str(n + 1) for n in q) for k, q in enumerate(quads)]
    lines += [f"SPC1,1,126,{i + 1}" for i, p in enumerate(xyz) if p[0] == 0.0]
    path = tmp_path / f"s{nx}.bdf"
    path.write_text("BEGIN BULK\nPARAM,COUPMASS,1\n"
                    f"PSHELL,1,1,{t!r},1,,1\nMAT1,1,{E!r},,{NU!r},{RHO!r}\n"
                    + "\n".join(lines) + "\nENDDATA\n")
    m = _read(path).model
    return solve_elastic(m.stiffness(), m.mass(), 3).frequencies_hz


def _opensees(nx, ny, element):
    xyz, quads, t = _strip(nx, ny)
    ops = opensees()
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    for i, p in enumerate(xyz):
        ops.node(i + 1, *map(float, p))
        ops.fix(i + 1, *([1, 1, 1, 1, 1, 1] if p[0] == 0.0 else [0, 0, 1, 1, 1, 0]))
    ops.section("ElasticMembranePlateSection", 1, E, NU, t, RHO)
    for k, q in enumerate(quads):
        ops.element(element, k + 1, *[int(n) + 1 for n in q], 1)
    lam = np.sort(np.array(ops.eigen("-fullGenLapack", 3)))
    ops.wipe()
    return np.sqrt(lam) / (2 * np.pi)


@pytest.mark.parametrize("element", ["ShellDKGQ", "ASDShellQ4"])
def test_in_plane_modes_agree_with_opensees(tmp_path, element):
    """Source: OpenSees' ShellDKGQ (Long & Xu's GQ12 membrane with drilling rotations)
    and ASDShellQ4 (Hughes-Brezzi drilling with an enhanced-strain membrane): other
    formulations converging to the same limit, on the same meshes of a clamped 1 x 0.1
    strip, in-plane modes alone (w, rx, ry held): first three frequencies (two bending,
    one axial). Each code's own discretisation error at 40 x 4 is bounded by its change
    from 20 x 2 (both converge at order >= 1 here: that change over 2^1 - 1); the two
    may differ by the sum of those bounds, plus 0.5 % for the mass formulations.
    Measured (Hz) at 40 x 4: ours 81.320, 488.673, 1263.972; ShellDKGQ 81.306, 488.451,
    1263.647; ASDShellQ4 81.023, 486.069, 1263.535 (at 20 x 2: 82.120, 495.593,
    1264.795; 82.117, 495.429, 1263.964; 81.004, 485.534, 1263.682): ours is ShellDKGQ's
    to 3e-4, ASDShellQ4 is nearer its limit on coarse meshes; Euler's beam 81.53."""
    a = {n: _ours(tmp_path, 10 * n, n) for n in (2, 4)}
    b = {n: _opensees(10 * n, n, element) for n in (2, 4)}
    bound = np.abs(a[4] / a[2] - 1) + np.abs(b[4] / b[2] - 1) + 0.005
    rel = np.abs(a[4] / b[4] - 1)
    assert np.all(rel <= bound), (a, b, rel, bound)


@pytest.mark.parametrize("triangles", [False, True], ids=["CQUADR", "CTRIAR"])
def test_free_offset_plate_keeps_its_rigid_modes_and_frequencies(tmp_path, triangles):
    """Source: exact invariance (as test_nastran_offsets.py's CQUAD4): the grids' and the
    reference plane's coordinates are related by an invertible map under which the
    offset plate's K and rigidly moved M are the plate's without offset, so a free
    plate (1 x 1 x 0.004, 8 x 8, ZOFFS T/2) keeps its first ten elastic frequencies to
    the eigen-solver's rounding (1e-9 with room) and its six rigid modes. The offset
    couples the drilling membrane with bending here, so this exercises it too."""
    xyz, el = square_mesh(8, 1.0, triangles)
    card = "CTRIAR" if triangles else "CQUADR"
    hz, ks = [], []
    for z in (0.0, 0.002):
        lines = [f"GRID,{i + 1},,{x!r},{y!r},0." for i, (x, y, _) in enumerate(xyz)]
        lines += [f"{card},{k + 1},1," + ",".join(str(n + 1) for n in e)
                  + (f",,{z!r}" if z else "") for k, e in enumerate(el)]  # THETA, ZOFFS
        path = tmp_path / f"z{z}.bdf"
        path.write_text("BEGIN BULK\nPARAM,COUPMASS,1\nPSHELL,1,1,0.004,1,,1,,0.5\n"
                        f"MAT1,1,{E!r},,{NU!r},{RHO!r}\n" + "\n".join(lines) + "\nENDDATA\n")
        m = _read(path).model
        sol = solve_elastic(m.stiffness(), m.mass(), 10)
        assert sol.n_rigid == 6
        hz.append(sol.frequencies_hz)
        ks.append(m.stiffness())
    assert abs(ks[1] - ks[0]).max() > 1e-3 * abs(ks[0]).max()  # the offset was read
    assert np.max(np.abs(hz[1] / hz[0] - 1)) <= 1e-9, hz


@pytest.mark.parametrize("triangles", [False, True], ids=["CQUADR", "CTRIAR"])
def test_ply_thickness_and_angle_on_a_laminate(tmp_path, triangles):
    """PCOMP (LAM = SYM [0/45]s of MAT8, THETA 30 on the element) with two ply
    thicknesses as parameters: dK/dt, dM/dt against central differences
    (tests/bounds.py); the membrane is linear in the plies' moduli (nothing condensed),
    so the derivative is exact, and the deck re-read with the thicknesses changed gives
    the model's K at those values to a few ulps."""
    xyz, el = square_mesh(4, 1.0, triangles)
    card = "CTRIAR" if triangles else "CQUADR"

    def write(path, t1, t2):
        lines = [f"GRID,{i + 1},,{x!r},{y!r},0." for i, (x, y, _) in enumerate(xyz)]
        lines += [f"{card},{k + 1},1," + ",".join(str(n + 1) for n in e) + ",30."
                  for k, e in enumerate(el)]
        lines += [f"SPC1,1,123,{i + 1}" for i, (x, y, _) in enumerate(xyz) if x == 0.0]
        path.write_text("BEGIN BULK\nPARAM,COUPMASS,1\n"
                        f"PCOMP,1,,0.5,,,,,SYM\n,1,{t1!r},0.,,1,{t2!r},45.\n"
                        "MAT8,1,1.4e11,1.0e10,0.3,5.0e9,5.0e9,3.0e9,1600.\n"
                        + "\n".join(lines) + "\nENDDATA\n")
        return path

    spec = [(Parameter(n, 0.0), CardField("PCOMP", 1, f)) for n, f in (("a", "T1"),
                                                                       ("b", "T2"))]
    model = _read(write(tmp_path / "a.bdf", 1e-3, 2e-3), spec).model
    assert_matrix_derivatives(model)
    ref = _read(write(tmp_path / "b.bdf", 1.2e-3, 1.7e-3)).model
    s = np.array([1.2e-3, 1.7e-3])
    for a, b in ((model.stiffness(s), ref.stiffness()), (model.mass(s), ref.mass())):
        assert abs(a - b).max() <= 1e-12 * abs(b).max()
