"""Lumped (NASTRAN's default) mass of CBAR and CBEAM with offsets WA/WB.

NASTRAN's convention (NASTRAN-95 ``mis/bard.f``, its conventional-mass branch): half the
bar's mass, (rho A + NSM) L / 2 with L the length between the offset ends, is a point
mass at each offset end, carried rigidly to its grid:
[[m 1, -m [w]x], [m [w]x, m (|w|^2 1 - w w^T)]] in the grid's displacement system; the
CBEAM adds its torsional inertia rho (I1 + I2) L / 2 about the element axis at each end
(rotations are not changed by a rigid offset). Checked here against NASTRAN-95's printed
grid point weight generator output for its offset-bar ring (D02-01-1A), against the same
model built with RBE2s to grids at the offset ends, and against closed-form rigid-body
mass properties.

Run for real in .venv-nastran (``make test``); skipped in the core environment."""

from __future__ import annotations

import re
import warnings

import numpy as np
import pytest
from conftest import ROOT
from nastran_frames import need

from eigenupdate.errors import EigenupdateWarning
from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.io.nastran import read_nastran  # noqa: E402
from eigenupdate.io.nastran_write import write_updated_bdf  # noqa: E402

DATA = ROOT / "tests" / "data" / "nastran_published"


def _skew(r) -> np.ndarray:
    return np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])


def _rigid_body_mass(model, positions: dict, frames: dict, ref) -> np.ndarray:
    """D^T M D, D the unit rigid-body motions about ``ref`` in basic (NASTRAN's MO), built
    here from the grids' positions and displacement frames (rows: axes in basic)."""
    D = np.zeros((model.n, 6))
    for g, x in positions.items():
        d = np.block([[np.eye(3), -_skew(np.asarray(x) - ref)], [np.zeros((3, 3)), np.eye(3)]])
        f = frames.get(g, np.eye(3))
        t = np.block([[f, np.zeros((3, 3))], [np.zeros((3, 3)), f]]) @ d
        for c in range(6):
            if 10 * g + c + 1 in set(model.coordinates.tolist()):
                D[model.index(10 * g + c + 1)] = t[c]
    return D.T @ model.mass().toarray() @ D


# NASTRAN-95's printed "MO - RIGID BODY MASS MATRIX IN BASIC COORDINATE SYSTEM" about
# GRID 19 (demoout/d02011a.out of nasa/NASTRAN-95 commit 65e29e9, 1995 ed.)
D02011A_MO = np.array([
    [3.13262851e04, -5.68434189e-14, 0.0, 0.0, 0.0, 1.47353916e-03],
    [5.68434189e-14, 3.13262851e04, 0.0, 0.0, 0.0, 3.44589147e05],
    [0.0, 0.0, 3.13262858e04, -5.75844994e-04, -3.44589146e05, 0.0],
    [0.0, 0.0, -5.75845012e-04, 1.56631423e06, 1.42182534e-03, 0.0],
    [0.0, 0.0, -3.44589146e05, 1.42182531e-03, 5.35679491e06, 0.0],
    [1.47353917e-03, 3.44589147e05, 0.0, 0.0, 0.0, 6.92310919e06]])


def test_nastran95_offset_ring_grid_point_weight(tmp_path):
    """Source: NASTRAN-95's grid point weight generator (PARAM GRDPNT 19) for its
    demonstration problem D02-01-1A (deck inp/d02011a.inp, output demoout/d02011a.out,
    nasa/NASTRAN-95 commit 65e29e9, NASA Open Source Agreement 1.3): 24 CBARs on a ring of
    radius 11 in cylindrical CP/CD 2, each offset WA = WB = (-1, 0, 0) (radially inward),
    lumped mass (no COUPMASS). The mass is the offset polygon's, 24 (2 10 sin 7.5 deg) 1000
    0.5, and its inertia about the ring's axis m 10^2 (at the offset ends), not m 11^2 (at
    the grids): NASTRAN-95 puts the end masses at the offset ends. It prints 9 digits from
    single-precision grid coordinates (its mass is 3.3e-8 below the exact one): 1e-6 of
    the largest entry. Read without GRID 25 and its RFORCE (the centrifugal load's centre
    on the axis of CD 2, which is not supported; neither carries mass) and without GRDSET's
    PS 345, so that all six rigid-body motions are seen."""
    text = (DATA / "d02011a.inp").read_text()
    text = re.sub(r"(?m)^(GRID    25|RFORCE).*\n", "", text)
    text = text.replace("2       345 ", "2           ")
    deck = tmp_path / "ring.inp"
    deck.write_text(text)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EigenupdateWarning)
        model = read_nastran(deck).model
    # CORD2C 2: origin (0, 10, 0), z = basic z, x toward C = (0, 9, 0), i.e. basic -y
    origin, ex, ey, ez = np.array([0.0, 10, 0]), np.array([0.0, -1, 0]), np.eye(3)[0], np.eye(3)[2]
    positions, frames = {}, {}
    for g in range(1, 25):
        th = np.radians(15.0 * (g - 1))
        er, et = np.cos(th) * ex + np.sin(th) * ey, -np.sin(th) * ex + np.cos(th) * ey
        positions[g] = origin + 11.0 * er
        frames[g] = np.array([er, et, ez])
    got = _rigid_body_mass(model, positions, frames, positions[19])
    assert np.max(np.abs(got - D02011A_MO)) < 1e-6 * np.abs(D02011A_MO).max()
    # exact: 24 equal chords of the radius-10 polygon
    assert abs(got[0, 0] / (24 * 20 * np.sin(np.radians(7.5)) * 500) - 1) < 1e-13


MAT = "MAT1,1,7.e10,,0.33,2700."
PBAR = "PBAR,1,1,2.4e-4,1.8e-8,2.e-9,3.e-10,0.05"
PBEAM = "PBEAM,2,1,1.6e-4,9.e-9,1.5e-9,,2.e-10,0.03"
WBAR, WBEAM = (0.0, 0.0, -0.015), (0.0, 0.004, -0.02)


def _panel(rbe2: bool = False, skin: bool = True, pbar: str = PBAR) -> str:
    """A free 4 x 2 bay panel, 0.1 m bays: 2 mm CQUAD4 skin, CBAR stiffeners on the two
    long edges (offset WBAR) and a CBEAM on the middle line (offset WBEAM, off the skin's
    plane and sideways), lumped mass. ``rbe2``: the same stiffeners as bars between grids
    at the offset ends, each tied to its skin grid by an RBE2."""
    nx, ny = 4, 2
    gid = {(i, j): 1 + i + (nx + 1) * j for i in range(nx + 1) for j in range(ny + 1)}
    cards = ["SOL 103", "CEND", "BEGIN BULK", MAT, pbar, PBEAM, "PSHELL,3,1,0.002,1,,1"]
    for (i, j), g in gid.items():
        cards.append(f"GRID,{g},,{0.1 * i!r},{0.1 * j!r},0.")
    if skin:
        for i in range(nx):
            for j in range(ny):
                cards.append(f"CQUAD4,{100 + gid[i, j]},3,{gid[i, j]},{gid[i + 1, j]},"
                             f"{gid[i + 1, j + 1]},{gid[i, j + 1]}")
    eid = 200
    for j, (card, pid, w) in ((0, ("CBAR", 1, WBAR)), (1, ("CBEAM", 2, WBEAM)),
                              (2, ("CBAR", 1, WBAR))):
        for i in range(nx):
            a, b = gid[i, j], gid[i + 1, j]
            eid += 1
            if rbe2:
                cards.append(f"{card},{eid},{pid},{1000 + a},{1000 + b},0.,0.,1.")
            else:
                cards.append(f"{card},{eid},{pid},{a},{b},0.,0.,1.,\n,,,{w[0]},{w[1]},{w[2]},"
                             f"{w[0]},{w[1]},{w[2]}")
        if rbe2:
            for i in range(nx + 1):
                g = gid[i, j]
                cards.append(f"GRID,{1000 + g},,{0.1 * i + w[0]!r},{0.1 * j + w[1]!r},{w[2]!r}")
                cards.append(f"RBE2,{2000 + g},{g},123456,{1000 + g}")
    return "\n".join(cards + ["ENDDATA"]) + "\n"


def _read(tmp_path, name: str, text: str, parameters=()):
    path = tmp_path / name
    path.write_text(text)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EigenupdateWarning)
        return read_nastran(path, parameters)


def test_offset_lumped_mass_equals_rbe2_to_the_offset_ends(tmp_path):
    """Source: a second route through other code: the same stiffeners as bars between grids
    at the offset ends, tied to the skin grids by RBE2s (the reader eliminates the
    dependent grids and carries their lumped masses rigidly). K and M agree to round-off
    (1e-12 of the largest entry: the same products in another order)."""
    off = _read(tmp_path, "offset.bdf", _panel()).model
    tied = _read(tmp_path, "rbe2.bdf", _panel(rbe2=True)).model
    assert off.coordinates.tolist() == tied.coordinates.tolist()
    for a, b in ((off.mass(), tied.mass()), (off.stiffness(), tied.stiffness())):
        a, b = a.toarray(), b.toarray()
        assert np.max(np.abs(a - b)) <= 1e-12 * np.abs(a).max()


@pytest.mark.parametrize("dense", [True, False], ids=["dense", "sparse"])
def test_free_offset_stiffened_panel_has_six_rigid_modes(tmp_path, dense):
    """A free body has exactly six rigid-body modes, with a singular, non-diagonal lumped
    M (an offset end's mass gives its grid rank 3 in 6); both eigen-solvers find six and
    the same elastic frequencies as the RBE2 model (1e-9: solver tolerance)."""
    off = _read(tmp_path, "offset.bdf", _panel()).model
    tied = _read(tmp_path, "rbe2.bdf", _panel(rbe2=True)).model
    a = solve_elastic(off.stiffness(), off.mass(), 6, dense=dense)
    b = solve_elastic(tied.stiffness(), tied.mass(), 6, dense=True)
    assert a.n_rigid == 6 and b.n_rigid == 6
    assert np.allclose(a.frequencies_hz, b.frequencies_hz, rtol=1e-9)
    assert a.frequencies_hz[0] > 1.0


def test_rigid_body_mass_properties_of_offset_bars(tmp_path):
    """Source: closed-form rigid-body mass properties about GRID 1 of the stiffeners alone
    (no skin). Exact for any convention that moves the bar's mass rigidly: total mass
    (rho A + NSM) L and first moments, those of the bar's own mass on its offset axis.
    Second moments: the bar's continuous ones, (m L^2 / 12)(1 - e e^T) about its centre
    (+ the CBEAM's polar rho (I1 + I2) L e e^T, exact), plus what lumping at the two offset
    ends adds, (m L^2 / 6)(1 - e e^T). Round-off only: 1e-12."""
    model = _read(tmp_path, "bars.bdf", _panel(skin=False)).model
    nx, ny = 4, 2
    positions = {1 + i + (nx + 1) * j: np.array([0.1 * i, 0.1 * j, 0.0])
                 for i in range(nx + 1) for j in range(ny + 1)}
    got = _rigid_body_mass(model, {g: x for g, x in positions.items()
                                   if 10 * g + 1 in set(model.coordinates.tolist())},
                           {}, positions[1])
    want = np.zeros((6, 6))
    rho = 2700.0
    for j, (area, nsm, polar, w) in ((0, (2.4e-4, 0.05, 0.0, WBAR)),
                                     (1, (1.6e-4, 0.03, 9.e-9 + 1.5e-9, WBEAM)),
                                     (2, (2.4e-4, 0.05, 0.0, WBAR))):
        for i in range(nx):
            length, e = 0.1, np.array([1.0, 0, 0])
            m = (rho * area + nsm) * length
            c = np.array([0.1 * i + 0.05, 0.1 * j, 0.0]) + np.array(w)
            inertia = (m * length**2 * (1 / 12 + 1 / 6) * (np.eye(3) - np.outer(e, e))
                       + rho * polar * length * np.outer(e, e)
                       + m * (c @ c * np.eye(3) - np.outer(c, c)))
            want += np.block([[m * np.eye(3), -m * _skew(c)], [m * _skew(c), inertia]])
    assert np.max(np.abs(got - want)) <= 1e-12 * np.abs(want).max()


def test_save_bdf_round_trip_keeps_offsets(tmp_path):
    """--save-bdf's writer on an offset, lumped deck with PBAR A a parameter: unchanged
    values write the deck back unchanged; A x 1.2 gives the matrices of the hand-edited
    deck (round-off, 1e-12), offsets kept."""
    from eigenupdate.io.nastran import CardField
    from eigenupdate.model.parameters import Parameter

    par = [(Parameter("A", 0.0), CardField("PBAR", 1, "A"))]
    nm = _read(tmp_path, "panel.bdf", _panel(), par)
    same = tmp_path / "same.bdf"
    write_updated_bdf(nm, same, {"A": 2.4e-4})
    body = [ln for ln in same.read_text().splitlines() if not ln.startswith("$")]
    assert body == _panel().splitlines()
    out = tmp_path / "out.bdf"
    write_updated_bdf(nm, out, {"A": 2.88e-4})
    got = _read(tmp_path, "out2.bdf", out.read_text()).model
    want = _read(tmp_path, "hand.bdf", _panel(pbar=PBAR.replace("2.4e-4", "2.88e-4"))).model
    for a, b in ((got.mass(), want.mass()), (got.stiffness(), want.stiffness())):
        a, b = a.toarray(), b.toarray()
        assert np.max(np.abs(a - b)) <= 1e-12 * np.abs(a).max()
    mj = nm.model.m_terms[0].toarray()  # dM/dA = rho of the offset point masses
    fd = want.mass().toarray() - _read(tmp_path, "base.bdf", _panel()).model.mass().toarray()
    assert np.max(np.abs(fd / 0.48e-4 - mj)) <= 1e-9 * np.abs(mj).max()
