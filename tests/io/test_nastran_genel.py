"""NASTRAN's general element GENEL (stiffness K or flexibility Z, UD and S).

Independent sources: NASTRAN-95's printed eigenvalues of its demonstration problems
D11-03-1A (a jet transport wing: a 10 x 10 flexibility GENEL with UD and S, CMASS2s with
negative coupling terms, CONM1, an MPC) and D11-01-1A (a ten-cell beam: CBARs and a 6 x 6
flexibility GENEL on large-field continuations); the element a GENEL replaces (a CELAS4
spring, a CBAR with the closed-form stiffness and flexibility of a cantilever); the
closed-form cantilever of NASTRAN-95's static GENEL beam D01-14-1A; the one-line refusal
standard (exit 2). Runs in .venv-nastran.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse.linalg as sla
from conftest import ROOT
from nastran_frames import need, read_quiet
from refusals import one_line

from eigenupdate.errors import InputError
from eigenupdate.solve.eigen import solve_elastic

pytestmark = pytest.mark.nastran
need("pyNastran")

DATA = ROOT / "tests" / "data" / "nastran_published"
SINGLE = 2.0 ** -24  # NASTRAN-95 keeps a card's real values in single precision


def _deck(tmp_path, body: str, name: str = "deck.bdf"):
    path = tmp_path / name
    path.write_text("BEGIN BULK\n" + body + "ENDDATA\n")
    return path


def _eigenvalues(path, n: int) -> tuple[np.ndarray, np.ndarray, object]:
    nm = read_quiet(path)
    sol = solve_elastic(nm.model.stiffness(), nm.model.mass(), n)
    return sol.eigenvalues, sol.modes, nm


def _genel_bound(nm, lam: np.ndarray, modes: np.ndarray) -> np.ndarray:
    """Relative change of each eigenvalue that single-precision Z and S of the deck's
    GENEL can make (first order): with f = K (u_i - S u_d) the element's forces in the
    mass-normalised mode, d lambda = -f^T dZ f - 2 f^T dS u_d, and ||dZ||_2 <=
    2^-24 ||Z||_F, ||dS||_2 <= 2^-24 ||S||_F for entries each rounded to 2^-24."""
    model = nm.model
    (e,) = [x for x in nm.bdf.elements.values() if x.type == "GENEL"]
    m = len(e.ul)
    z = np.zeros((m, m))
    i, j = np.triu_indices(m)  # the lower triangle by columns
    z[i, j] = z[j, i] = e.z
    s = np.reshape(e.s, (m, -1))

    def at(pairs, phi):  # a restrained coordinate does not move
        rows = [np.flatnonzero(model.coordinates == 10 * g + c) for g, c in pairs]
        return np.array([phi[r[0]] if r.size else 0.0 for r in rows])

    out = []
    mass = model.mass()
    for k, value in enumerate(lam):
        phi = modes[:, k] / np.sqrt(modes[:, k] @ (mass @ modes[:, k]))
        ud = at(e.ud, phi)
        f = np.linalg.solve(z, at(e.ul, phi) - s @ ud)
        out.append(SINGLE * (np.linalg.norm(z) * f @ f
                             + 2 * np.linalg.norm(s) * np.linalg.norm(f) * np.linalg.norm(ud))
                   / value)
    return np.array(out)


# NASTRAN-95's INV stops when its vector estimate has converged to A EPS = 0.1 x 1e-4
# (mis/invp3.f, mis/reig.f with EIGR's E blank); its eigenvalue, a ratio of that vector's
# norms, errs to first order in it. GIV is a direct method.
SOLVER = {"GIV": 0.0, "INV": 1e-5}


@pytest.mark.parametrize("stem,rigid,method", [("d11031a", 1, "GIV"), ("d11011a", 0, "INV")])
def test_nastran95_genel_decks_reproduce_nastran95(stem, rigid, method):
    """Source: NASTRAN-95's printed eigenvalues (d11031a.csv, d11011a.csv; decks
    inp/d11031a.inp and inp/d11011a.inp of nasa/NASTRAN-95 commit 65e29e9, NASA Open
    Source Agreement 1.3). d11031a's wing: a GENEL by flexibility Z (10 x 10) with UD at
    the fuselage and S, CMASS2s with negative coupling terms, CONM1, an MPC aileron, one
    rigid-body plunge (SUPORT), EIGR GIV; d11011a's beam: CBARs, CONM2s and a GENEL by Z
    with UD and S on large-field continuations (its small-field line ends with the marker
    ``*30``), EIGR INV. Tolerance per mode: the 7 printed digits (5e-7), NASTRAN-95's
    single-precision card values entering K and M linearly (4 x 2^-24), those of Z and S
    through K = Z^-1 (_genel_bound, up to 1.6e-4 for mode 11 of d11031a, the GENEL's own),
    and the INV iteration's convergence (SOLVER). Measured worst: 1.7e-6 (d11031a mode 10)
    and 1.1e-6 (d11011a mode 1)."""
    table = np.loadtxt(DATA / f"{stem}.csv", delimiter=",", comments="#", skiprows=4)
    want = table[rigid:, 1]
    lam, modes, nm = _eigenvalues(DATA / f"{stem}.inp", want.size)
    assert lam.size == want.size
    tol = 5e-7 + 4 * SINGLE + SOLVER[method] + _genel_bound(nm, lam, modes)
    assert np.all(np.abs(lam / want - 1) <= tol), (np.abs(lam / want - 1), tol)


# two scalar points: k1 from point 1 to ground, k2 between them, m1 and m2 on them
K1, K2, M1, M2 = 3.0e4, 1.0e4, 2.0, 5.0
CHAIN = f"SPOINT,1,2\nCELAS4,1,{K1},1\nCMASS4,3,{M1},1\nCMASS4,4,{M2},2\n"


@pytest.mark.parametrize("element", [
    "GENEL,2,,1,0,2,0\n,K,1.e4,-1.e4,1.e4\n",  # K on both points, no UD
    "GENEL,2,,2,0\n,UD,,1,0\n,K,1.e4\n,S,1.\n",  # K on point 2, point 1 by S
    "GENEL,2,,2,0\n,UD,,1,0\n,Z,1.e-4\n,S,1.\n",  # the flexibility 1/k2
], ids=["K", "K with UD and S", "Z with UD and S"])
def test_genel_replaces_a_spring(tmp_path, element):
    """Second method and closed form: a GENEL equal to the CELAS4 spring k2 between the
    two points gives the spring's eigenvalues, which solve m1 m2 l^2 - (m1 k2 + m2 (k1 +
    k2)) l + k1 k2 = 0. The same K to rounding (Z = 1e-4 is printed exactly): 1e-12."""
    spring, _, _ = _eigenvalues(_deck(tmp_path, CHAIN + f"CELAS4,2,{K2},1,2\n", "s.bdf"), 2)
    got, _, _ = _eigenvalues(_deck(tmp_path, CHAIN + element), 2)
    b = M1 * K2 + M2 * (K1 + K2)
    closed = np.array([b - np.sqrt(b * b - 4 * M1 * M2 * K1 * K2),
                       b + np.sqrt(b * b - 4 * M1 * M2 * K1 * K2)]) / (2 * M1 * M2)
    assert np.allclose(spring, closed, rtol=1e-12)
    assert np.allclose(got, spring, rtol=1e-12)


# a CBAR from grid 1 to grid 2 (L = 2 along x; E 1000, G 400, A 0.5, I1 = I2 0.25, J 0.5),
# free, with CONM2 masses and inertias at both ends: six rigid-body and six elastic modes
ENDS = ("GRID,1,,0.,0.,0.\nGRID,2,,2.,0.,0.\n"
        "CONM2,11,1,,2.\n,1.,,1.,,,1.\nCONM2,12,2,,3.\n,1.5,,2.,,,2.5\n")
BAR = "CBAR,1,1,1,2,0.,1.,0.\nPBAR,1,1,.5,.25,.25,.5\nMAT1,1,1000.,400.\n"
# grid 2's stiffness with grid 1 clamped (components 1-6): EA/L = 250, 12EI/L^3 = 375,
# 6EI/L^2 = 375, 4EI/L = 500, GJ/L = 100, with v-rz -375 and w-ry +375 (Euler-Bernoulli)
K22 = [250., 0., 0., 0., 0., 0., 375., 0., 0., 0., -375., 375., 0., 375., 0., 100., 0., 0.,
       500., 0., 500.]
# its flexibility: L/EA = .004, L^3/3EI = 8/750, L^2/2EI = .008 (v-rz +, w-ry -), L/EI = .008,
# L/GJ = .01
A = 8 / 750
Z22 = [.004, 0., 0., 0., 0., 0., A, 0., 0., 0., .008, A, 0., -.008, 0., .01, 0., 0., .008, 0.,
       .008]
# grid 2 rigidly moved by grid 1 at 2 m along x: v2 = v1 + 2 rz1, w2 = w1 - 2 ry1
S21 = np.eye(6)
S21[1, 5], S21[2, 4] = 2.0, -2.0


def _genel(kind: str, values, s=None) -> str:
    """GENEL 1 on grid 2 (UI) and grid 1 (UD) in free field: 7 values after the K, Z or S
    word, then 8 a line (pyNastran's list ends at a blank field)."""
    def rows(word, vals):
        vals = [repr(float(v)) for v in vals]
        lines = [[word, *vals[:7]]] + [vals[i:i + 8] for i in range(7, len(vals), 8)]
        return "".join("," + ",".join(x) + "\n" for x in lines)

    text = "GENEL,1,,2,1,2,2,2,3\n,2,4,2,5,2,6\n,UD,,1,1,1,2,1,3\n,1,4,1,5,1,6\n"
    return text + rows(kind, values) + ("" if s is None else rows("S", np.ravel(s)))


@pytest.mark.parametrize("element", [_genel("K", K22), _genel("Z", Z22),
                                     _genel("K", K22, S21)],
                         ids=["K, S computed", "Z, S computed", "K, S given"])
def test_genel_replaces_a_cbar(tmp_path, element):
    """Second method and closed form: a GENEL whose UI are grid 2's six components with the
    closed-form cantilever stiffness (or flexibility) of the CBAR clamped at grid 1, and
    whose UD are grid 1's, is the CBAR itself: K S is the bar's off-diagonal block and
    S^T K S grid 1's (rigid-body motions strain neither). S computed from the grids'
    positions (NASTRAN's six UD) or given by hand. Its K is the CBAR's and its elastic
    eigenvalues theirs, to rounding: Z's and K's entries are printed to 17 digits and
    cond(K22) = 14 (1e-12)."""
    bar = read_quiet(_deck(tmp_path, ENDS + BAR, "bar.bdf")).model
    genel = read_quiet(_deck(tmp_path, ENDS + element)).model
    assert np.array_equal(bar.coordinates, genel.coordinates)
    kb, kg = bar.stiffness().toarray(), genel.stiffness().toarray()
    assert np.allclose(kg, kb, rtol=0, atol=1e-12 * np.abs(kb).max())
    want = solve_elastic(bar.stiffness(), bar.mass(), 6)
    got = solve_elastic(genel.stiffness(), genel.mass(), 6)
    assert want.n_rigid == got.n_rigid == 6
    assert np.allclose(got.eigenvalues, want.eigenvalues, rtol=1e-12)


def _refused(tmp_path, run_cli, body: str, *words: str) -> None:
    (tmp_path / "deck.bdf").write_text("BEGIN BULK\n" + body + "ENDDATA\n")
    (tmp_path / "study.toml").write_text('[model]\ntype = "nastran"\nbdf = "deck.bdf"\n')
    code, out, err = run_cli("frequencies", tmp_path / "study.toml", "--modes", "1")
    one_line(code, err, "deck.bdf", *words)
    assert out == ""


POINTS = "SPOINT,1,2,3\nCMASS4,1,1.,1\nCMASS4,2,1.,2\nCMASS4,3,1.,3\nCELAS4,4,1.,3\n"
GRIDS = "GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nGRID,3,,0.,1.,0.\nCONM2,9,3,,1.\n"
# (case, deck, words of the one line): NASTRAN-95 User's Manual GENEL
REFUSED = [
    ("Z singular", POINTS + "GENEL,7,,1,0,2,0\n,Z,1.,1.,1.\n",
     ("line 7: GENEL 7: Z is singular",)),
    ("Z indefinite", POINTS + "GENEL,7,,1,0,2,0\n,Z,1.,3.,1.\n",
     ("GENEL 7: Z is not positive definite",)),
    ("K indefinite", POINTS + "GENEL,7,,1,0,2,0\n,K,1.,3.,1.\n",
     ("GENEL 7: K is not positive semi-definite",)),
    ("UI pair twice", POINTS + "GENEL,7,,1,0,1,0\n,K,1.,-1.,1.\n",
     ("GENEL 7: coordinate 1-0 is listed twice",)),
    ("UI pair again in UD", POINTS + "GENEL,7,,1,0\n,UD,,1,0\n,K,1.\n,S,1.\n",
     ("GENEL 7: coordinate 1-0 is listed twice",)),
    ("K one value short", POINTS + "GENEL,7,,1,0,2,0\n,K,1.,-1.\n",
     ("GENEL 7: K lists 2 values; 2 UI coordinates need 3",)),
    ("S one value short", POINTS + "GENEL,7,,1,0,2,0\n,UD,,3,0\n,K,1.,0.,1.\n,S,1.\n",
     ("GENEL 7: S lists 1 values; 2 UI by 1 UD coordinates need 2",)),
    ("S without UD", POINTS + "GENEL,7,,1,0,2,0\n,K,1.,-1.,1.\n,S,1.,1.\n",
     ("GENEL 7: S is given without a UD list",)),
    ("S omitted, one UD", POINTS + "GENEL,7,,2,0\n,UD,,1,0\n,K,1.\n",
     ("GENEL 7: S is omitted and UD lists 1 coordinates", "give S")),
    ("S omitted, a scalar point", GRIDS + "SPOINT,5\nCMASS4,8,1.,5\nGENEL,7,,5,0\n"
     ",UD,,1,1,1,2,1,3\n,1,4,1,5,1,6\n,K,1.\n", ("GENEL 7: S is omitted and 5 is a scalar",)),
    # translations of two grids leave the rotation about the line through them free
    ("S omitted, six UD not fixing the body", GRIDS + "GENEL,7,,3,1\n"
     ",UD,,1,1,1,2,1,3\n,2,1,2,2,2,3\n,K,1.\n", ("do not fix the element's rigid-body",)),
    # pyNastran's own failures on the card, said in NASTRAN's terms
    ("neither K nor Z", POINTS + "GENEL,7,,1,0,2,0\n", ("GENEL 7: neither K nor Z",)),
    ("K and Z", POINTS + "GENEL,7,,1,0,2,0\n,K,1.,0.,1.\n,Z,1.,0.,1.\n",
     ("GENEL 7: both K and Z are given",)),
    ("K twice", POINTS + "GENEL,7,,1,0,2,0\n,K,1.,0.,1.\n,K,1.,0.,1.\n",
     ("GENEL 7: one of the words UD, K, Z, S appears twice",)),
    ("z in lower case", POINTS + "GENEL,7,,1,0,2,0\n,z,1.,0.,1.\n",
     ("GENEL 7: write the words UD, K, Z, S in capitals",)),
    ("scalar point's component blank", POINTS + "GENEL,7,,1,,2,0\n,K,1.,0.,1.\n",
     ("GENEL 7: a UI or UD grid without its component",)),
    ("no UI", POINTS + "GENEL,7\n,K,1.\n", ("GENEL 7: no UI coordinates",)),
]


@pytest.mark.parametrize("case,body,words", REFUSED, ids=[r[0] for r in REFUSED])
def test_bad_genel_is_refused_in_one_line(tmp_path, run_cli, case, body, words):
    """Source: the GENEL card's rules (NASTRAN-95 User's Manual: K or Z's lower triangle,
    S m x n, S computed only for six UD; Z inverted; a coordinate once) and the bad-input
    standard: exit 2 and one line naming the file, the line and the card."""
    _refused(tmp_path, run_cli, body, *words)


def test_huge_genel_is_refused_before_its_matrices_are_built(tmp_path, run_cli, monkeypatch):
    """Source: the resource standard (eigenupdate.budget): a GENEL of m UI coordinates
    is checked as three dense m x m matrices (24 m^2 bytes) before they are allocated;
    m = 300 is 2.16 MB, beyond a 1 MB memory limit."""
    m = 300
    monkeypatch.setenv("EIGENUPDATE_MAX_MEMORY_MB", "1")
    pairs = [x for g in range(1, m + 1) for x in (str(g), "0")]
    i, j = np.triu_indices(m)
    k = ["1." if a == b else "0." for a, b in zip(i, j, strict=True)]

    def lines(head: list[str], vals: list[str], first: int) -> str:  # 8 fields a line
        rows = [head + vals[:first]] + [[""] + vals[a:a + 8]
                                        for a in range(first, len(vals), 8)]
        return "".join(",".join(r) + "\n" for r in rows)

    body = (f"SPOINT,1,THRU,{m}\n" + "".join(f"CMASS4,{g},1.,{g}\n" for g in range(1, m + 1))
            + lines(["GENEL", str(m + 1), ""], pairs, 6) + lines(["", "K"], k, 7))
    _refused(tmp_path, run_cli, body, f"GENEL {m + 1}: K of 300 UI coordinates would take 2 MB",
             "EIGENUPDATE_MAX_MEMORY_MB")


def test_rounded_singular_k_is_read_as_printed(tmp_path):
    """Source: the card's K by hand and Weyl's bound. Springs 1234.5678 and 2345.678 in a
    chain of three points, printed to four digits: K11 1235, K22 3580 (their sum rounded),
    K33 2346, K21 -1235, K32 -2346. The printed K is indefinite (ones' quadratic form -1:
    a smallest eigenvalue below -1/3) but within half a unit of each printed entry (0.5 on
    seven entries: ||.||_F = 0.5 sqrt 7 = 1.32) of the springs' singular K: read, as
    printed (1e-12: exact small integers)."""
    printed = np.array([[1235., -1235., 0.], [-1235., 3580., -2346.], [0., -2346., 2346.]])
    lam = np.linalg.eigvalsh(printed)
    assert -0.5 * np.sqrt(7) < lam[0] < -1 / 3  # the case this test is about
    path = _deck(tmp_path, POINTS.replace("CELAS4,4,1.,3\n", "")
                 + "GENEL,7,,1,0,2,0,3,0\n,K,1235.,-1235.,0.,3580.,-2346.,2346.\n")
    k = read_quiet(path).model.stiffness().toarray()
    assert np.allclose(np.linalg.eigvalsh(k), lam, rtol=0, atol=1e-12 * 3580)


def test_nastran95_static_genel_beam_with_s_written_out(tmp_path):
    """Source: NASTRAN-95's D01-14-1A (inp/d01141a.inp of nasa/NASTRAN-95 commit 65e29e9,
    NASA Open Source Agreement 1.3), a cantilever of five GENELs (Z without UD; K 6 x 6; K
    with UD and S; K with three UD and S omitted; Z with UD and S) and a CBAR, L = 6, E 6,
    A 1, I 1/12, tip loads 1. GENEL 4's S computed from three UD is NASTRAN-95's code
    (TA1CA), not its manual (six UD): refused in one line. With that S written out (a unit
    offset along x, GENEL 3's), the displacements are the closed-form cantilever's:
    u = F x / EA, v = P x^2 (3L - x) / 6EI, rz = P x (2L - x) / 2EI (NASTRAN-95 printed the
    same, 1.440000E+02 and 3.600000E+01 at the tip, with its own S). Tolerance 1e-5: the
    deck's six-digit .166666 (Z of GENEL 5) and .083333 (I of the CBAR) are 4e-6 off."""
    text = (DATA / "d01141a.inp").read_text()
    with pytest.raises(InputError, match="line 32: GENEL 4: S is omitted and UD lists 3"):
        read_quiet(DATA / "d01141a.inp")
    old = "+G42    K       6.      .0      .0      6.      3.      2.                      "
    new = ("+G42    K       6.      .0      .0      6.      3.      2.              +G43\n"
           "+G43    S       1.      .0      .0      .0      1.      -1.     .0      +G44\n"
           "+G44    .0      1.")
    assert old in text
    path = tmp_path / "d01141a.inp"
    path.write_text(text.replace(old, new))
    model = read_quiet(path).model
    coords = model.coordinates.tolist()
    x = np.arange(1.0, 7.0)  # grids 2..7
    for comp, want in ((1, {1: x / 6}), (2, {2: x * x * (18 - x) / 3, 6: x * (12 - x)})):
        f = np.zeros(len(coords))
        f[coords.index(70 + comp)] = 1.0
        u = sla.spsolve(model.stiffness().tocsc(), f)
        for c, closed in want.items():
            got = np.array([u[coords.index(10 * g + c)] for g in range(2, 8)])
            assert np.allclose(got, closed, rtol=1e-5, atol=0), (comp, c, got)
