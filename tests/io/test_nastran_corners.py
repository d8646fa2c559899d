"""Corner thicknesses T1-T4 with TFLAG of CQUAD4, CTRIA3, CQUADR, CTRIAR, CQUAD8 and
CTRIA6 (io/nastran_corners.py; the thickness interpolated to each integration point,
model/shells.py and model/shells_quadratic.py ``profile``; the quadratic elements' own
checks: test_nastran_corners_quadratic.py). Independent references: the deck without T1-T4 (equal
corners are the property's T), a second method (a Timoshenko beam of the strip's section
solved by Ritz to 1e-9), a second code (CalculiX 2.20's S8R with *NODAL THICKNESS),
central differences of K, M, and the deck edited and read again. Runs in .venv-nastran
(pyNastran)."""

from __future__ import annotations

import re
import shutil
import subprocess

import numpy as np
import pytest
from bounds import assert_matrix_derivatives
from nastran_frames import need, read_quiet
from numpy.polynomial import legendre
from scipy.linalg import eigh, solve

from eigenupdate.errors import EigenupdateWarning, InputError
from eigenupdate.model.parameters import Parameter
from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")
from eigenupdate.io.nastran import CardField, read_nastran  # noqa: E402

E, NU, RHO = 2.1e11, 0.3, 7850.0
L, B, T0, T1 = 1.0, 0.1, 0.02, 0.01  # strip length, width, root and tip thickness
T = 0.02  # PSHELL T


def strip(path, nx, ny=1, card="CQUAD4", tflag=0, thick=None, held="", zoffs="",
          own=None, pshell=f"PSHELL,1,1,{T!r},1,,1"):
    """A cantilever strip L x B (clamped at x = 0) of nx x ny CQUAD4 (CQUADR, CQUAD8), or
    each split in two CTRIA3 (CTRIAR, CTRIA6), whose corner thickness is ``thick(x)``
    (default linear from T0 to T1; None: blank), written as TFLAG ``tflag`` (TFLAG 1:
    over T); the corners of elements whose centre x fails ``own`` are left blank;
    ``held``: components held at every grid besides the clamp; ``zoffs``: every
    element's ZOFFS."""
    thick = thick or (lambda x: T0 + (T1 - T0) * x / L)
    if card in ("CQUAD8", "CTRIA6"):
        return _quadratic_strip(path, nx, ny, card, tflag, thick, held, zoffs, own, pshell)
    nid = np.arange((nx + 1) * (ny + 1)).reshape(ny + 1, nx + 1) + 1
    x = np.tile(np.linspace(0.0, L, nx + 1), ny + 1)
    y = np.repeat(np.linspace(0.0, B, ny + 1), nx + 1)
    lines = ["BEGIN BULK", "PARAM,COUPMASS,1", pshell, f"MAT1,1,{E!r},,{NU!r},{RHO!r}"]
    lines += [f"GRID,{i + 1},,{a!r},{b!r},0." for i, (a, b) in enumerate(zip(x, y, strict=True))]
    quads = [[nid[j, i], nid[j, i + 1], nid[j + 1, i + 1], nid[j + 1, i]]
             for j in range(ny) for i in range(nx)]
    tri = card in ("CTRIA3", "CTRIAR")
    elems = [q[:3] for q in quads] + [[q[0], q[2], q[3]] for q in quads] if tri else quads
    for k, g in enumerate(elems):
        mine = own is None or own(np.mean([x[n - 1] for n in g]))
        ts = [t / T if tflag == 1 and t is not None else t for t in (thick(x[n - 1])
                                                                    for n in g)]
        first = [card, k + 1, 1, *g, "", zoffs]
        first += [""] * (9 - len(first))  # free field: nine a line
        tail = ",".join("" if t is None else repr(t) for t in ts) if mine else ""
        lines.append(",".join(map(str, first)) + f"\n,,{tflag},{tail}")
    lines += [f"SPC1,1,123456,{n}" for n in nid[:, 0]]
    lines += [f"SPC1,1,{held},{n}" for n in nid[:, 1:].ravel() if held]
    path.write_text("\n".join(lines) + "\nENDDATA\n")
    return path


def _quadratic_strip(path, nx, ny, card, tflag, thick, held, zoffs, own, pshell):
    """:func:`strip` of nx x ny CQUAD8, or each split in two CTRIA6 along its G1-G3
    diagonal, on a grid of corners and mid-sides (2 nx + 1 by 2 ny + 1 grids, a
    CQUAD8's centre unused)."""
    ids = (np.arange((2 * nx + 1) * (2 * ny + 1)) + 1).reshape(2 * ny + 1, 2 * nx + 1)
    x = np.linspace(0.0, L, 2 * nx + 1)
    y = np.linspace(0.0, B, 2 * ny + 1)
    used = set()
    elems = []
    for j in range(0, 2 * ny, 2):
        for i in range(0, 2 * nx, 2):
            c = ids[j:j + 3, i:i + 3]  # c[row (y), column (x)]
            if card == "CQUAD8":
                elems.append([c[0, 0], c[0, 2], c[2, 2], c[2, 0], c[0, 1], c[1, 2], c[2, 1],
                              c[1, 0]])
            else:
                elems.append([c[0, 0], c[0, 2], c[2, 2], c[0, 1], c[1, 2], c[1, 1]])
                elems.append([c[0, 0], c[2, 2], c[2, 0], c[1, 1], c[2, 1], c[1, 0]])
    lines = ["BEGIN BULK", "PARAM,COUPMASS,1", pshell, f"MAT1,1,{E!r},,{NU!r},{RHO!r}"]
    xg = {int(ids[j, i]): x[i] for j in range(2 * ny + 1) for i in range(2 * nx + 1)}
    for k, g in enumerate(elems):
        used.update(g)
        corners = g[:4] if card == "CQUAD8" else g[:3]
        mine = own is None or own(np.mean([xg[n] for n in corners]))
        ts = [thick(xg[n]) for n in corners]
        ts = ["" if not mine or t is None else repr(t / T if tflag else t) for t in ts]
        g = [str(n) for n in g]
        if card == "CQUAD8":
            lines.append(f"CQUAD8,{k + 1},1,{','.join(g[:6])}\n,{','.join(g[6:])},"
                         f"{','.join(ts)},,{zoffs}\n,{tflag}")
        else:
            lines.append(f"CTRIA6,{k + 1},1,{','.join(g)}\n,,{zoffs},{','.join(ts)},{tflag}")
    for n in sorted(used):
        j, i = np.argwhere(ids == n)[0]
        lines.append(f"GRID,{n},,{x[i]!r},{y[j]!r},0.")
        if i == 0:
            lines.append(f"SPC1,1,123456,{n}")
        elif held:
            lines.append(f"SPC1,1,{held},{n}")
    path.write_text("\n".join(lines) + "\nENDDATA\n")
    return path


def _hz(path, count):
    m = read_quiet(path).model
    return solve_elastic(m.stiffness(), m.mass(), count).frequencies_hz


@pytest.mark.parametrize("card", ["CQUAD4", "CTRIA3", "CQUADR", "CTRIAR", "CQUAD8",
                                  "CTRIA6"])
def test_corners_equal_to_t_read_as_without_them(tmp_path, card):
    """Source: NASTRAN's convention (QRG CQUAD4: blank Ti are the PSHELL's T; TFLAG 1:
    fractions of it): T1-T4 all equal to T (TFLAG 0), all 1.0 (TFLAG 1) or blank give
    the matrices of the deck without them, bit for bit (uniform elements keep their path),
    and a linear taper written as thicknesses (TFLAG 0) or fractions (TFLAG 1) the same
    K and M (the fractions' product with T: round-off, 1e-12)."""
    ref = read_quiet(strip(tmp_path / "r.bdf", 4, 2, card, own=lambda x: False)).model
    for tflag, name in ((0, "t"), (1, "f")):
        m = read_quiet(strip(tmp_path / f"{name}.bdf", 4, 2, card, tflag,
                             thick=lambda x: T)).model
        for a, b in ((m.stiffness(), ref.stiffness()), (m.mass(), ref.mass())):
            assert (a != b).nnz == 0
    a, b = (read_quiet(strip(tmp_path / f"l{f}.bdf", 4, 2, card, f)).model for f in (0, 1))
    assert abs(a.stiffness() - ref.stiffness()).max() > 0.1 * abs(ref.stiffness()).max()
    for x, y in ((a.stiffness(), b.stiffness()), (a.mass(), b.mass())):
        assert abs(x - y).max() <= 1e-12 * abs(y).max()


def timoshenko(order=14, modes=3):
    """Frequencies (Hz) of the clamped-free strip in cylindrical bending (rx held: plate
    modulus D = E / (1 - NU^2), shear 5/6 G t, no rotary inertia, as the shell), a
    Timoshenko beam with b t(x)^3 D / 12, b t 5/6 G, rho b t: Ritz on x P_j(2x/L - 1)
    (w and the rotation), the rotation condensed; Gauss-Legendre with 64 points
    integrates the polynomial integrands exactly. Orders 14 and 18 agree to 1e-9."""
    x, w = legendre.leggauss(64)
    x, w = (x + 1) * L / 2, w * L / 2
    t = T0 + (T1 - T0) * x / L
    s, eye = 2 * x / L - 1, np.eye(order)
    p = np.array([legendre.legval(s, eye[j]) for j in range(order)])
    dp = np.array([legendre.legval(s, legendre.legder(eye[j])) * 2 / L for j in range(order)])
    f, df = x * p, p + x * dp
    bend = E / (1 - NU**2) * B * t**3 / 12 * w
    shear = 5 / 6 * E / (2 * (1 + NU)) * B * t * w
    kww, kwp = (df * shear) @ df.T, -(df * shear) @ f.T
    kpp = (df * bend) @ df.T + (f * shear) @ f.T
    K = kww - kwp @ solve(kpp, kwp.T)
    M = (f * RHO * B * t * w) @ f.T
    return np.sqrt(eigh(K, M, eigvals_only=True)[:modes]) / (2 * np.pi)


@pytest.mark.parametrize("card", ["CQUAD4", "CTRIA3", "CQUADR", "CQUAD8", "CTRIA6"])
def test_tapered_strip_in_cylindrical_bending_is_the_timoshenko_beam(tmp_path, card):
    """Source: a second method, the linearly tapered (T0 to T0/2) cantilever strip with
    rx held everywhere (no curvature across it: cylindrical bending) is a Timoshenko
    beam of plate modulus (:func:`timoshenko`, converged to 1e-9). Bending takes
    t^3 at each point, shear and mass t, so its three bending modes test all three.
    The elements converge as h^2 (measured ratios 3.9-4.1 from 10 to 80 elements), so
    the finer mesh's error is about a third of its change from the coarser, and the
    change bounds it. The mesh is refined across too (nx / 10 elements: a CTRIA3 strip
    one element wide converges to a limit 0.1-1 % soft, uniform or tapered). Measured
    at 40 elements: CQUAD4 2.3e-4, 4.9e-4, 2.2e-3 from the beam, bounds 6.8e-4, 1.5e-3,
    6.6e-3; CTRIA3 1.7e-4, 7.4e-4, 2.8e-3, bounds 5.2e-4, 2.2e-3, 8.3e-3; CQUAD8 (as h^4)
    7.7e-9, 3.2e-7, 2.6e-6, bounds 1.0e-7, 4.4e-6, 3.7e-5; CTRIA6 (as h^2) -2.8e-5,
    -1.2e-4, -2.7e-4, bounds 7.9e-5, 2.6e-4, 5.2e-4."""
    ref = timoshenko()
    nx = (20, 40)
    got = [_hz(strip(tmp_path / f"s{n}.bdf", n, n // 10, card, held="4"), 6) for n in nx]
    bending = [np.argmin(np.abs(got[1] - f)) for f in ref]  # CQUAD4's in-plane mode between
    a, b = (g[bending] for g in got)
    assert np.all(np.abs(b - ref) <= np.abs(b - a)), (a, b, ref)


def _calculix(tmp_path, nx):
    """CalculiX's S8R frequencies (Hz, six) of the strip of :func:`strip` (nx x nx / 10,
    clamped at x = 0), its thickness at every node by *NODAL THICKNESS."""
    ny, ids, lines = nx // 10, {}, ["*NODE,NSET=NALL"]
    for j in range(2 * ny + 1):
        for i in range(2 * nx + 1):
            if i % 2 == 0 or j % 2 == 0:  # corners and mid-sides of the 8-node elements
                ids[i, j] = len(ids) + 1
                lines.append(f"{ids[i, j]},{L * i / (2 * nx)!r},{B * j / (2 * ny)!r},0.")
    lines.append("*ELEMENT,TYPE=S8R,ELSET=EALL")
    for j in range(ny):
        for i in range(nx):
            a, b = 2 * i, 2 * j
            c = [(a, b), (a + 2, b), (a + 2, b + 2), (a, b + 2), (a + 1, b), (a + 2, b + 1),
                 (a + 1, b + 2), (a, b + 1)]
            lines.append(f"{j * nx + i + 1}," + ",".join(str(ids[q]) for q in c))
    lines.append("*NODAL THICKNESS")
    lines += [f"{n},{T0 + (T1 - T0) * i / (2 * nx)!r}" for (i, _), n in ids.items()]
    lines += ["*BOUNDARY"] + [f"{n},1,6" for (i, _), n in ids.items() if i == 0]
    lines += ["*MATERIAL,NAME=STEEL", "*ELASTIC", f"{E!r},{NU!r}", "*DENSITY", f"{RHO!r}",
              "*SHELL SECTION,ELSET=EALL,MATERIAL=STEEL,NODAL THICKNESS", f"{T0!r}",
              "*STEP", "*FREQUENCY", "6", "*END STEP"]
    (tmp_path / f"c{nx}.inp").write_text("\n".join(lines) + "\n")
    subprocess.run(["ccx", f"c{nx}"], cwd=tmp_path, capture_output=True, check=True,
                   env={"OMP_NUM_THREADS": "1", "PATH": "/usr/bin:/bin"})
    text = (tmp_path / f"c{nx}.dat").read_text().split("E I G E N V A L U E   O U T P U T")[1]
    return np.array([float(m.group(3)) for m in re.finditer(
        r"^\s+\d+\s+(\S+)\s+(\S+)\s+(\S+)", text, re.M)][:6])


@pytest.mark.skipif(shutil.which("ccx") is None, reason="CalculiX (ccx) absent")
@pytest.mark.parametrize("card", ["CQUAD4", "CTRIA3"])
def test_tapered_cantilever_strip_agrees_with_calculix(tmp_path, card):
    """Source: a second code, CalculiX 2.20's S8R (8-node shells expanded to 20-node
    bricks) with *NODAL THICKNESS, of the free strip (clamped at its root, T0 to T0/2 at
    its tip, L / B = 10): the three bending modes (t^3 and t at each point), and on
    CQUAD4 the in-plane bending mode (membrane t; a linear triangle two to four
    elements wide locks in it, as without taper). Each code's 40-element error is below
    its change from 20, and their plate models differ by O((T0/L)^2) = 4e-4, so they
    agree within the sum (measured, CQUAD4: 0.19, 0.13, 0.05, 0.07 % apart, bounds
    0.28, 0.41, 0.21, 0.95 %). The torsion mode is left out: a strip B / T0 = 5 twists as a solid
    section, not a plate (O(T0 / B))."""
    nx = (20, 40)
    ours = [_hz(strip(tmp_path / f"o{n}.bdf", n, n // 10, card), 6) for n in nx]
    ccx = [_calculix(tmp_path, n) for n in nx]
    modes = [0, 1, 2, 3] if card == "CQUAD4" else [0, 1, 3]
    got = [np.array([o[np.argmin(np.abs(o - c))] for c in ccx[1][modes]]) for o in ours]
    ref = [c[modes] for c in ccx]
    bound = np.abs(got[1] - got[0]) + np.abs(ref[1] - ref[0]) + (T0 / L) ** 2 * ref[1]
    assert np.all(np.abs(got[1] - ref[1]) <= bound), (got, ref)


def _specs(fields):
    return [(Parameter(f"p{i}", 0.0), CardField(*f)) for i, f in enumerate(fields)]


FIELDS = [("PSHELL", 1, "T"), ("MAT1", 1, "E"), ("MAT1", 1, "RHO")]
NSM = "PSHELL,1,1,0.02,1,,1,,0.7"  # NSM 0.7 per area, uniform


@pytest.mark.parametrize("card", ["CQUAD4", "CTRIA3", "CQUADR", "CTRIAR", "CQUAD8",
                                  "CTRIA6"])
def test_thickness_parameter_scales_a_tflag1_taper(tmp_path, card):
    """Sources: central differences of K, M (tests/bounds.py: K is a polynomial in T,
    E, RHO but the shear's stabilisation, smooth) of a strip tapered by fractions of T
    (TFLAG 1) with NSM and ZOFFS, and the deck with T, E and RHO edited in its text and
    read again (the same element integrals: round-off, 1e-12 of the largest entry):
    membrane T, bending T^3 and mass RHO T at the same profile, NSM per area fixed."""
    path = strip(tmp_path / "a.bdf", 6, 2, card, 1, zoffs="0.005", pshell=NSM)
    text = path.read_text()
    nm = read_quiet(path, _specs(FIELDS))
    assert_matrix_derivatives(nm.model)
    new = [1.1 * T, 1.05 * E, 1.2 * RHO]
    edited = tmp_path / "b.bdf"
    edited.write_text(text.replace(NSM, NSM.replace("0.02", repr(new[0]))).replace(
        f"MAT1,1,{E!r},,{NU!r},{RHO!r}", f"MAT1,1,{new[1]!r},,{NU!r},{new[2]!r}"))
    ref = read_quiet(edited).model
    for a, b in ((nm.model.stiffness(new), ref.stiffness()), (nm.model.mass(new), ref.mass())):
        assert abs(a - b).max() <= 1e-12 * abs(b).max()


def test_own_corner_thicknesses_do_not_follow_t(tmp_path):
    """Source: NASTRAN's convention (QRG CQUAD4: with TFLAG 0 the Ti are the thicknesses):
    a strip half of whose elements give T1-T4 (TFLAG 0) and half leave them blank, with
    PSHELL T a parameter: the model at a new T is the deck with T edited (the blank half
    moves, the other not: round-off, 1e-12), and its derivatives are central
    differences."""
    path = strip(tmp_path / "a.bdf", 8, 1, "CQUAD4", 0, own=lambda x: x < L / 2)
    nm = read_quiet(path, _specs(FIELDS[:1]))
    assert_matrix_derivatives(nm.model)
    edited = tmp_path / "b.bdf"
    edited.write_text(path.read_text().replace(f"PSHELL,1,1,{T!r}", "PSHELL,1,1,0.03"))
    ref = read_quiet(edited).model
    for a, b in ((nm.model.stiffness([0.03]), ref.stiffness()),
                 (nm.model.mass([0.03]), ref.mass())):
        assert abs(a - b).max() <= 1e-12 * abs(b).max()
    fixed = read_quiet(path).model  # the own half unchanged, the other moved
    assert abs(ref.stiffness() - fixed.stiffness()).max() > 0.1 * abs(fixed.stiffness()).max()
    with pytest.warns(EigenupdateWarning, match=r"PSHELL 1: T is a parameter but 4 of its 8 "
                      r"elements give their own corner thicknesses"):
        read_nastran(path, _specs(FIELDS[:1]))


def _edit(path, old, new):
    path.write_text(path.read_text().replace(old, new, 1))
    return path


PCOMP = "PCOMP,1\n,1,0.02,0."


@pytest.mark.parametrize(("edit", "fields", "message"), [
    (lambda p: strip(p, 4, thick=lambda x: T if x < 0.6 else None), FIELDS[:1],
     "PSHELL 1 field T: not a parameter of CQUAD4 3, whose corner thicknesses are partly "
     "its own"),
    (lambda p: _edit(strip(p, 4), ",,0,0.02,", ",,0,-0.02,"), (),
     "CQUAD4 1: corner thicknesses T1-T4 (TFLAG 0): [-0.02"),
    (lambda p: strip(p, 4, thick=lambda x: 0.0), (), "CQUAD4 1: corner thicknesses "
     "T1-T4 (TFLAG 0): all zero"),
    (lambda p: _edit(strip(p, 4), ",,0,0.02,", ",,2,0.02,"), (), "CQUAD4 1: TFLAG = 2 must "
     "be 0 (blank) or 1"),
    (lambda p: strip(p, 4, pshell=PCOMP), (), "CQUAD4 1: corner thicknesses T1-T4 (TFLAG "
     "0): differing from PCOMP 1's thickness 0.02 (the sum of its plies)"),
    (lambda p: strip(p, 4, card="CQUAD8", pshell=PCOMP), (), "CQUAD8 1: corner "
     "thicknesses T1-T4 (TFLAG 0): differing from PCOMP 1's thickness 0.02 (the sum of "
     "its plies)"),
    (lambda p: strip(p, 4, card="CTRIA6", pshell=PCOMP), (), "CTRIA6 1: corner "
     "thicknesses T1-T3 (TFLAG 0): differing from PCOMP 1's thickness 0.02"),
    (lambda p: strip(p, 4, card="CTRIA6", thick=lambda x: 0.0), (), "CTRIA6 1: corner "
     "thicknesses T1-T3 (TFLAG 0): all zero"),
    (lambda p: strip(p, 4, card="CQUAD8", thick=lambda x: T if x < 0.6 else None),
     FIELDS[:1], "PSHELL 1 field T: not a parameter of CQUAD8 3, whose corner "
     "thicknesses are partly its own"),
], ids=["mixed-with-T", "negative", "all-zero", "TFLAG-2", "PCOMP", "CQUAD8-PCOMP",
        "CTRIA6-PCOMP", "CTRIA6-all-zero", "CQUAD8-mixed-with-T"])
def test_corner_thicknesses_refused_in_one_line(tmp_path, run_cli, edit, fields, message):
    """Bad or unsupported corner thicknesses (a laminate's, whose coupling with a taper
    is not formed, on any element): one line naming the element (or the parameter's
    card) and the problem, exit 2, through the CLI."""
    from refusals import one_line

    deck = edit(tmp_path / "deck.bdf")
    table = "".join(f'[[model.parameter]]\nname = "p{i}"\ncard = "{c}"\nid = {j}\n'
                    f'field = "{f}"\n' for i, (c, j, f) in enumerate(fields))
    study = tmp_path / "study.toml"
    study.write_text(f'[model]\ntype = "nastran"\nbdf = "{deck}"\n{table}')
    code, _, err = run_cli("frequencies", study, "--modes", "1")
    one_line(code, err, "deck.bdf", message, warnings_allowed=True)
    with pytest.raises(InputError, match=re.escape(message.split(": ", 1)[-1][:30])):
        read_quiet(deck, _specs(fields))


@pytest.mark.parametrize("card", ["CQUAD4", "CTRIA3", "CQUAD8", "CTRIA6"])
def test_nsm_stays_uniform_per_area_under_a_taper(tmp_path, card):
    """Source: MSC QRG PSHELL (NSM is mass per unit area) and NASTRAN-95's tria3d.f (NSM
    spread by area, not by thickness; its quad4d.f scales it with the thickness instead:
    the totals agree, the distribution is the convention this pins). With RHO = 0 the
    mass is NSM's alone: a strip tapered 8:1 has the M of one without corners
    (round-off)."""
    pshell = f"PSHELL,1,1,{T!r},1,,1,,3.5"
    mat = f"MAT1,1,{E!r},,{NU!r},{RHO!r}"

    def mass(thick):
        path = strip(tmp_path / f"{card}{thick is None}.bdf", 4, 1, card, pshell=pshell,
                     thick=thick)
        path.write_text(path.read_text().replace(mat, f"MAT1,1,{E!r},,{NU!r},0."))
        return read_quiet(path).model.mass()

    uniform, tapered = mass(lambda x: None), mass(lambda x: 0.04 - 0.035 * x / L)
    assert abs(uniform).max() > 0
    assert abs(tapered - uniform).max() <= 1e-12 * abs(uniform).max()
