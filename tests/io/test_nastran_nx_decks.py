"""Two NX decks of the published-deck survey (issue 20) that looked far off NX's printed
frequencies: what NX's numbers are, and which differences are the element formulations'.

nx_sine (NX 2022.1, SOL 111): its eigenvalue table holds 8 eigenvalues (EIGRL V2 = 2000 Hz)
and then 6 residual vectors, which SOL 111 adds by default (RESVEC; for a structure held
at a grid, one static shape per rigid-body acceleration: INRLOD). Rows 9-14 are therefore
Rayleigh-Ritz values of the augmented basis, not eigenvalues.

random_test_bar_plus_tri (NX 11.0, SOL 111, EIGRL ND = 20): true eigenvalues; the modes
that bend its one CQUAD4 and one CTRIA3 out of plane, and one mode that couples the CBARs'
in-plane rotation to the CQUAD4's drilling, differ with the shell formulation."""

from __future__ import annotations

import shutil
import warnings

import numpy as np
import pytest
import scipy.linalg
from bounds import eigenvalue_floor
from conftest import ROOT
from nastran_frames import need, opensees

from eigenupdate.errors import EigenupdateWarning
from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.io.nastran import read_nastran  # noqa: E402

DATA = ROOT / "tests" / "data" / "nastran_published"
SHELL_TOL = 0.01  # ref.json's tolerance for shells and solids: formulations differ


def _nx(name: str) -> np.ndarray:
    """NX's LAMA rows (Hz) from the csv beside the deck."""
    lines = (DATA / f"{name}.csv").read_text().splitlines()
    rows = [line for line in lines if line and not line.startswith(("#", "mode"))]
    return np.array([float(line.split(",")[1]) for line in rows])


def _model(path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EigenupdateWarning)
        return read_nastran(path).model


def _ritz_hz(K, M, basis) -> np.ndarray:
    q, _ = np.linalg.qr(basis)
    lam = scipy.linalg.eigh(q.T @ K @ q, q.T @ M @ q, eigvals_only=True)
    return np.sqrt(lam) / (2 * np.pi)


@pytest.fixture(scope="module")
def nx_sine(tmp_path_factory):
    """Our eigenvalues of nx_sine and the Ritz values of NX's augmented basis."""
    nx = _nx("nx_sine")
    model = _model(DATA / "nx_sine.bdf")
    eig = solve_elastic(model.stiffness(), model.mass(), nx.size, dense=True)
    # the same deck without its SPC card, to have the held grid 999's columns of K
    tmp = tmp_path_factory.mktemp("nx_sine")
    shutil.copy(DATA / "sample_model.inc", tmp)
    text = (DATA / "nx_sine.bdf").read_text()
    spc = ("SPC = 1\n", "SPC            1     999  123456     0.0\n")  # case, bulk
    assert all(text.count(line) == 1 for line in spc)
    (tmp / "free.bdf").write_text(text.replace(spc[0], "").replace(spc[1], ""))
    free = _model(tmp / "free.bdf")
    c = np.asarray(free.coordinates)
    held = np.isin(c, 9990 + np.arange(1, 7))
    K, M = free.stiffness().toarray(), free.mass().toarray()
    Kff, Mff, Kfs = K[np.ix_(~held, ~held)], M[np.ix_(~held, ~held)], K[np.ix_(~held, held)]
    assert np.array_equal(c[~held], np.asarray(model.coordinates))
    rigid = -np.linalg.solve(Kff, Kfs)  # unit motions of grid 999: rigid (one CBUSH holds all)
    inrlod = np.linalg.solve(Kff, Mff @ rigid)  # static shapes under rigid-body accelerations
    ritz = _ritz_hz(Kff, Mff, np.hstack([eig.modes[:, :8], inrlod]))
    return nx, eig.frequencies_hz, ritz


def test_nx_sine_eigenvalues_below_eigrl_v2_agree_with_nx(nx_sine):
    """Source: NX 2022.1's LAMA rows 1-8 (nx_sine.csv), the eigenvalues below EIGRL V2 =
    2000 Hz (our ninth is 3497 Hz: exactly 8 are below). Tolerance: 1 % (shells and
    solids); measured worst -0.23 % (mode 8, the 1 mm flap)."""
    nx, eig, _ = nx_sine
    assert eig[7] < 2000.0 < eig[8]
    assert np.all(np.abs(eig[:8] / nx[:8] - 1) <= SHELL_TOL), eig[:8] / nx[:8] - 1


def test_nx_sine_rows_above_v2_are_residual_vector_ritz_values(nx_sine):
    """Source: NX 2022.1's LAMA rows 9-14 (nx_sine.csv) and the Poincare separation
    theorem: the k-th Ritz value of any subspace is at or above the k-th eigenvalue.

    Rows 9-14 lie 9.6-51.6 % above our eigenvalues 9-14 (within the 1 % of shells they
    must not lie below them). The Rayleigh-Ritz values of our K, M on NX's basis (our 8
    modes and K^-1 M R, R the six rigid-body motions of the structure about its held
    grid) reproduce rows 9, 11, 13, the modes of the CONM2s on the CBUSH and composite
    plate, within 1 % (measured +0.27, +0.11, -0.21 %; they moved at most 0.4 % when the
    shells' shear stabilisation was changed). Rows 10, 12, 14 are the 1 mm flap's
    residual beyond its first mode, which depends on the shell formulation (row 10 moved
    from -11 to -23 % with the same changes): there the Ritz value is only asserted to be
    nearer NX's row than our eigenvalue is (measured -13.5 vs -39.6 %, -0.99 vs -24.4 %,
    +7.1 vs -51.6 %)."""
    nx, eig, ritz = nx_sine
    assert np.all(eig[8:] <= nx[8:] * (1 + SHELL_TOL)), eig[8:] / nx[8:] - 1
    rows = np.array([9, 11, 13]) - 1
    assert np.all(np.abs(ritz[rows] / nx[rows] - 1) <= SHELL_TOL), ritz / nx - 1
    rows = np.array([10, 12, 14]) - 1
    assert np.all(np.abs(ritz[rows] / nx[rows] - 1) < np.abs(eig[rows] / nx[rows] - 1))


@pytest.fixture(scope="module")
def random_test():
    """Our elastic modes 1-17 of random_test_bar_plus_tri and NX's (rows 4-20)."""
    nx = _nx("random_test_bar_plus_tri")
    model = _model(DATA / "random_test_bar_plus_tri.bdf")
    sol = solve_elastic(model.stiffness(), model.mass(), 17, dense=True)
    return sol, nx


def test_random_test_modes_that_bend_no_shell_agree_with_nx(random_test):
    """Source: NX 11.0's LAMA (random_test_bar_plus_tri.csv): rows 1-3 rigid (3 below
    1e-6 Hz, as ours), rows 4-20 our elastic modes 1-17. Compared: the modes whose strain
    energy is in the bars (bending, torsion, axial) and the shells' membrane, not shell
    bending nor the bar-to-shell drilling coupling (modes 4-7 and 9, see the xfail below):
    1, 2, 3, 8, 10-17. Tolerance 1 % (shells); measured worst -0.47 % (mode 8), modes
    11-17 within 1e-4."""
    sol, nx = random_test
    assert sol.n_rigid == 3 and np.all(nx[:3] < 1e-6)
    err = sol.frequencies_hz / nx[3:] - 1
    keep = np.array([1, 2, 3, 8, 10, 11, 12, 13, 14, 15, 16, 17]) - 1
    assert np.all(np.abs(err[keep]) <= SHELL_TOL), err


def _opensees_random_test() -> np.ndarray:
    """Eigenvalues of random_test_bar_plus_tri built by hand in OpenSees: the CBARs as
    ElasticTimoshenkoBeam (shear areas K1 A, K2 A), the CQUAD4 and CTRIA3 as ASDShellQ4
    and ASDShellT3, NASTRAN's lumped masses (half of each bar's, a quarter of the quad's,
    a third of the triangle's, the CONM2) times WTMASS, grid 1 held in 456."""
    ops = opensees()
    E, nu, rho, wtmass, T = 2.0e6, 0.33, 0.098, 0.00259, 0.1
    A, inertia, J, k = 0.01445, 1.74e-5, 2.9382e-5, 0.8501176
    xyz = {1: (0, 0, 0), 2: (0, 1, 0), 3: (0, 2, 0), 4: (0, 3, 0), 5: (0, 4, 0),
           6: (1, 2, 0), 7: (1, 3, 0)}
    mass = dict.fromkeys(xyz, 0.0)
    mass[1] = 1.0e4 * wtmass
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    for n, p in xyz.items():
        ops.node(n, *map(float, p))
    ops.fix(1, 0, 0, 0, 1, 1, 1)
    ops.geomTransf("Linear", 1, 1.0, 0.0, 0.0)  # CBAR's v = (1, 0, 0); I1 = I2
    for e, (i, j) in enumerate([(1, 2), (2, 3), (3, 4), (4, 5)]):
        ops.element("ElasticTimoshenkoBeam", e + 1, i, j, E, E / (2 * (1 + nu)), A, J,
                    inertia, inertia, k * A, k * A, 1)
        for n in (i, j):
            mass[n] += rho * A * wtmass / 2
    ops.section("ElasticMembranePlateSection", 1, E, nu, T, 0.0)
    ops.element("ASDShellQ4", 10, 3, 6, 7, 4, 1)
    ops.element("ASDShellT3", 11, 5, 4, 7, 1)
    for n in (3, 6, 7, 4):
        mass[n] += rho * T * wtmass / 4
    for n in (5, 4, 7):
        mass[n] += rho * T * wtmass * 0.5 / 3
    for n, m in mass.items():
        ops.mass(n, m, m, m, 0.0, 0.0, 0.0)
    lam = np.sort(np.array(ops.eigen("-fullGenLapack", 24)))
    ops.wipe()
    return lam[lam > 1.0]


def test_random_test_out_of_plane_modes_match_opensees(monkeypatch):
    """Source: OpenSees on the same mesh (_opensees_random_test, cards transcribed by
    hand): a second code for the deck's reading (PBAR K1/K2 shear, J, WTMASS, the large
    mass, lumped masses, PSHELL's moduli). Our CQUAD4 without MacNeal's residual bending
    flexibility is MITC4, as ASDShellQ4; the modes whose kinetic energy is all in z
    (out of plane: 2, 3, 5, 6, 7, 10 then) agree within the rounding floors of both
    eigen-solutions (bounds.eigenvalue_floor, x 2; measured 1e-10..3e-8). The in-plane
    modes are not compared: OpenSees' membranes have their own drilling formulation."""
    from eigenupdate.model import shells

    monkeypatch.setattr(shells, "RBF_ALPHA", 0.0)
    model = _model(DATA / "random_test_bar_plus_tri.bdf")
    K, M = model.stiffness().toarray(), model.mass().toarray()
    sol = solve_elastic(K, M, 17, dense=True)
    z = np.asarray(model.coordinates) % 10 == 3
    kinetic = sol.modes * (M @ sol.modes)
    out = kinetic[z].sum(axis=0) > 0.99
    assert np.count_nonzero(out) == 6
    theirs = _opensees_random_test()
    lam = sol.eigenvalues[out]
    nearest = theirs[np.argmin(np.abs(theirs[:, None] / lam - 1), axis=0)]
    floor = eigenvalue_floor(K, M, lam, sol.modes[:, out])
    rel = np.abs(nearest / lam - 1)
    assert np.all(rel <= 2 * floor), (rel, floor)


@pytest.mark.xfail(strict=True, reason="open: shell formulation on one CQUAD4 and one "
                   "CTRIA3 at a/h = 10: modes 6, 7, 9 -2.2, -8.7, -8.5 %, mode 4 -1.04 %")
def test_random_test_all_modes_agree_with_nx(random_test):
    """Source: as above, all 17 elastic modes within 1 %.

    What is known. Modes 5, 6, 7, 9 bend the shells out of plane (z carries all their
    kinetic energy; 19, 87, 53, 16 % of their strain energy is the shells'): with the
    CQUAD4's residual bending flexibility off they are +1.4, +5.8, +2.0, +3.7 %, with the
    CTRIA3's shear stabilisation off +1.3, +1.6, -6.2, -7.7 %; OpenSees' ShellDKGQ and
    ShellDKGT (Kirchhoff) on this mesh give +0.2, +6.0, +0.4 % on 5, 6, 7. The deck is
    read right (the test above), and NX's QUAD4/TRIA3 sit inside the spread of
    formulations of one element across a span. The in-plane modes 1, 4, 8, 10
    depend on the CQUAD4's drilling penalty only (PARAM K6ROT 100 in the deck; the bars'
    end rotations load it): ours at K6ROT = 1600 gives -0.00, -0.01, -0.01, -0.00 %
    (at 100: -0.13, -1.04, -0.47, -0.01 %), as does a drilling-only matrix
    1e-7 K6ROT G [3 -1 -1 -1; ...] / 3 on rz (NASTRAN_CoFE's Cquad4.m, reverse-engineered
    from MSC): -0.01, -0.08, -0.04, +0.00 %. One deck (T = 0.1, A = 1) cannot tell
    how NX's penalty scales with T and area, so the constant is not changed."""
    sol, nx = random_test
    err = sol.frequencies_hz / nx[3:] - 1
    assert np.all(np.abs(err) <= SHELL_TOL), err
