"""NASTRAN card fields that enter K and M nonlinearly: PBARL dimensions (A, I1, I2, J
through the section's formulas) and products of fields on one element (MAT1 E with PBAR A).

Independent reference: the same deck with the fields changed by hand (pyNastran edits
the cards and writes the deck; the reader then assembles it with no parameters), central
finite differences of K, M and the eigenvalues, and the updated BDF read back.

Run for real in .venv-nastran; skipped in the core environment."""

from __future__ import annotations

import re
import warnings

import numpy as np
import pytest
import scipy.linalg
from bounds import assert_matrix_derivatives
from nastran_frames import need, random_frame

from eigenupdate.errors import EigenupdateWarning, InputError
from eigenupdate.identify.updating import update
from eigenupdate.io.measurements import Measurement
from eigenupdate.model.configurations import Configuration, mass_at
from eigenupdate.model.parameters import Parameter
from eigenupdate.solve.jacobian import linearise, solve_configurations

pytestmark = [pytest.mark.nastran,
              pytest.mark.filterwarnings("ignore::eigenupdate.errors.EigenupdateWarning")]
need("pyNastran")
from test_nastran_pbarl import SECTIONS, _pbarl, closed_form  # noqa: E402

from eigenupdate.io.nastran import CardField, dof_number, read_nastran  # noqa: E402
from eigenupdate.io.nastran_write import write_updated_bdf  # noqa: E402

# the PBARL frame's members: pids 2 TUBE, 4 BOX, 5 I, 6 T, 7 CHAN (shear-rigid here)
DIMS = [("box_h", "PBARL", 4, "DIM2"), ("i_h", "PBARL", 5, "DIM1"),
        ("t_web", "PBARL", 6, "DIM4"), ("E", "MAT1", 1, "E"), ("rho", "MAT1", 1, "RHO")]
# NASTRAN's shear-flexible PBARL ROD (1) and BAR (3): Timoshenko, phi = 12 EI/(K A G L^2)
SHEAR = [("rod_r", "PBARL", 1, "DIM1"), ("bar_h", "PBARL", 3, "DIM2"), ("E", "MAT1", 1, "E"),
         ("rho", "MAT1", 1, "RHO")]
# the PBAR frame: E with the A of one section and I1 of another (products E A, E I1)
PRODUCTS = [("E", "MAT1", 1, "E"), ("A4", "PBAR", 4, "A"), ("I5", "PBAR", 5, "I1")]
# the same on shear-flexible PBARs (K1, K2) with MAT1 G given apart from E: E, A and I1 are
# all in phi = 12 E I / (K A G L^2)
# MSC library shapes (model/sections_library.py): T2's web and H's plate spacing
LIBRARY = [("t2_web", "PBARL", 8, "DIM4"), ("h_gap", "PBARL", 9, "DIM1"), ("E", "MAT1", 1, "E")]
FIELDS = {"dims": DIMS, "shear": SHEAR, "products": PRODUCTS, "pbar_shear": PRODUCTS,
          "library": LIBRARY}


def _spec(fields):
    return [(Parameter(n, 0.0), CardField(c, i, f)) for n, c, i, f in fields]


def _frame(path, which: str, values=None):
    """test_nastran_pbarl's random frame (seed 6): members on the PBARL sections TUBE,
    BOX, I, T, CHAN (``which`` "dims") or on PBAR cards with their closed-form A, I1, I2,
    J ("products"), written with the ``values`` of DIMS or PRODUCTS in their fields (by
    hand, every digit: repr)."""
    frame = random_frame(np.random.default_rng(6), True)
    used = [p for p in sorted(SECTIONS) if (SECTIONS[p][0] in ("ROD", "BAR"))
            == (which == "shear")]
    frame.bars = [(eid, a, b, v, used[eid % len(used)]) for eid, a, b, v, _ in frame.bars]
    dims = {pid: list(d) for pid, (_, d) in SECTIONS.items()}
    frame.sections = {pid: list(closed_form(*SECTIONS[pid])) for pid in SECTIONS}
    if which == "pbar_shear":  # stubby enough that phi matters: 0.85 x the section's factor
        frame.shear_factors = {pid: (0.85, 0.7) for pid in SECTIONS}
        frame.G = 7.9e10  # not E / (2 (1 + nu)): G stays when E moves
    fields = FIELDS[which]
    for (_, card, cid, f), v in zip(fields, [] if values is None else values, strict=False):
        if card == "MAT1":
            setattr(frame, {"E": "E", "RHO": "rho"}[f], float(v))
        elif card == "PBARL":
            dims[cid][int(f[3:]) - 1] = float(v)
        else:
            frame.sections[cid][{"A": 0, "I1": 1}[f]] = float(v)
    text = frame.bdf()
    if which in ("dims", "shear", "library"):
        lines = text.splitlines()
        kept = [x for i, x in enumerate(lines) if not x.startswith("PBAR*")
                and not (i and lines[i - 1].startswith("PBAR*"))]
        text = "\n".join(kept[:-1] + [_pbarl(p, SECTIONS[p][0], dims[p]) for p in SECTIONS]
                         + ["ENDDATA\n"])
    path.write_text(text)
    return path


ELL = {"box_h": 0.2, "i_h": 0.3, "t_web": 0.005, "rho": 7850.0}


def _ell(path, values=ELL):
    """A small L frame (54 coordinates: dense eigen-solves stay cheap): a BOX column
    clamped at its base, an I beam, a T brace from the base to the tip, a CONM2 at the
    corner; 4 elements a member. ``values``: ELL's fields as written (repr)."""
    v = dict(values)
    grids, cbars, chain = [], [], []
    pts = [np.zeros(3), np.array([0.0, 0.0, 3.0]), np.array([2.5, 0.0, 3.0])]
    for (a, b), pid in (((0, 1), 4), ((1, 2), 5)):
        for k in range(0 if not chain else 1, 5):
            x = pts[a] + (pts[b] - pts[a]) * k / 4
            chain.append(len(chain) + 1)
            grids.append(f"GRID,{chain[-1]},,{x[0]!r},{x[1]!r},{x[2]!r}")
        for k in range(4):
            g = chain[-5 + k], chain[-4 + k]
            cbars.append(f"CBAR,{len(cbars) + 1},{pid},{g[0]},{g[1]},0.3,1.,0.2")
    cbars.append(f"CBAR,{len(cbars) + 1},6,1,{chain[-1]},0.,1.,0.")
    text = "\n".join([
        "SOL 103", "CEND", "SUBCASE 1", "  SPC = 1", "BEGIN BULK", "PARAM,COUPMASS,1",
        *grids, *cbars,
        "PBARL,4,1,,BOX", f",0.12,{v['box_h']!r},0.008,0.01",
        "PBARL,5,1,,I", f",{v['i_h']!r},0.15,0.15,0.0071,0.0107,0.0107",
        "PBARL,6,1,,T", f",0.05,0.05,0.006,{v['t_web']!r}",
        f"MAT1,1,2.1e11,,0.3,{v['rho']!r}", f"CONM2,900,{chain[4]},,150.",
        "SPC1,1,123456,1", "ENDDATA", ""])
    path.write_text(text)
    return path


@pytest.fixture
def ell(tmp_path):
    return _ell(tmp_path / "ell.bdf")


@pytest.mark.parametrize("which", ["dims", "shear", "products", "pbar_shear", "library"])
def test_model_at_new_values_is_the_hand_edited_deck(tmp_path, which):
    fields = FIELDS[which]
    nm = read_nastran(_frame(tmp_path / "a.bdf", which), _spec(fields))
    assert nm.model.nonlinear
    new = nm.model.values * np.array([1.05, 0.97, 1.1, 1.03, 0.98][:len(fields)])
    ref = read_nastran(_frame(tmp_path / "b.bdf", which, new)).model
    assert np.array_equal(ref.coordinates, nm.model.coordinates)
    # the same element matrices summed in another order: a few ulps of the largest entry
    for a, b in ((nm.model.stiffness(new), ref.stiffness()), (nm.model.mass(new), ref.mass())):
        assert abs(a - b).max() <= 1e-12 * abs(b).max()


@pytest.mark.parametrize("which", ["dims", "shear", "products", "pbar_shear", "library"])
def test_derivatives_match_central_differences(tmp_path, which):
    fields = FIELDS[which]
    model = read_nastran(_frame(tmp_path / "a.bdf", which), _spec(fields)).model
    assert_matrix_derivatives(model)  # central differences (tests/bounds.py)


def _plan(nm, tops):
    return [Configuration("base")] + [mass_at(dof_number(g, c), 200.0, f"{g}-{c}")
                                      for g in tops for c in (1, 2)]


def test_jacobian_matches_central_differences(ell):
    nm = read_nastran(ell, _spec(DIMS))
    model = nm.model
    tops = sorted(nm.bdf.nodes)[-1:]
    configs = _plan(nm, tops)
    modes = [1, 2, 3]
    s = model.values * 1.02
    lin = linearise(model, configs, modes, s, dense=True)
    f = 1e-4
    fd = np.empty_like(lin.J)
    for j in range(s.size):
        up, dn = s.copy(), s.copy()
        up[j] *= 1 + f
        dn[j] *= 1 - f
        fd[:, j] = (linearise(model, configs, modes, up, dense=True).eigenvalues
                    - linearise(model, configs, modes, dn, dense=True).eigenvalues) / (2 * f * s[j])
    # bound: truncation f^2 plus the eigenvalues' round-off eps kappa over f
    # (CBAR has no torsional inertia: M is singular, its infinite eigenvalues left out)
    lam = scipy.linalg.eigvals(model.stiffness(s).toarray(), model.mass(s).toarray())
    lam = np.sort(np.abs(lam[np.isfinite(lam)]))
    bound = f**2 + np.finfo(float).eps * lam[-1] / lam[0] / f
    scale = np.abs(lin.eigenvalues)[:, None] / s[None, :]
    assert np.max(np.abs(lin.J - fd) / scale) < 2 * bound


def test_update_recovers_section_dimensions_and_writes_them_back(ell, tmp_path):
    pbarl = ell
    fields = DIMS[:3] + DIMS[4:]  # box and I heights, T web, RHO (E fixed): ELL's order
    nm = read_nastran(pbarl, _spec(fields))
    truth = nm.model.values * np.array([1.04, 0.96, 1.08, 1.02])
    true_deck = read_nastran(_ell(tmp_path / "truth.bdf", dict(zip(ELL, truth, strict=True))))
    tops = sorted(nm.bdf.nodes)[-3:]
    configs = _plan(nm, tops)
    modes = [1, 2, 3, 4, 5]
    # the data: the hand-edited deck's own frequencies
    sols = solve_configurations(true_deck.model, configs, max(modes), dense=True)
    data = {(c.name, k): Measurement(c.name, k, float(sol.frequencies_hz[k - 1]))
            for c, sol in zip(configs, sols, strict=True) for k in modes}
    res = update(nm.model, configs, modes, data, max_iterations=30)
    assert res.success, (res.message, res.nit, res.x / truth - 1)
    # error-free data: limited by the eigenvalues' round-off over cond(J)
    assert np.max(np.abs(res.x / truth - 1)) < 1e-6
    out = tmp_path / "updated.bdf"
    write_updated_bdf(nm, out, res.parameters)
    back = read_nastran(out, _spec(fields)).model.values
    assert back == pytest.approx(res.x, rel=1e-11)  # 12 significant digits written


def test_refusals(tmp_path):
    pbarl = _frame(tmp_path / "a.bdf", "dims")
    with pytest.raises(InputError, match="PBARL 4: section BOX has DIM1-DIM4, not DIM5"):
        read_nastran(pbarl, [(Parameter("d", 0.0), CardField("PBARL", 4, "DIM5"))])
    # pin flags on a shear-flexible BAR with a dimension parameter: refused
    text = _frame(tmp_path / "b.bdf", "shear").read_text().replace("PARAM,COUPMASS,1\n", "")
    text = re.sub(r"(?m)^(CBAR\*,1,\d+,\d+,\d+)\n\*,(.*)$", r"\1\n*,\2,GGG\n*,6,", text)
    bar = tmp_path / "bar.bdf"
    bar.write_text(text)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EigenupdateWarning)
        with pytest.raises(InputError, match="not supported with pin flags"):
            read_nastran(bar, _spec(SHEAR[:2]))
    # a step that leaves the shape's domain is named, not assembled
    nm = read_nastran(pbarl, [(Parameter("t", 0.0), CardField("PBARL", 4, "DIM3"))])
    with pytest.raises(InputError, match="section BOX needs DIM2 > 2 DIM3"):
        nm.model.stiffness([0.15])


def test_mat1_with_nu_blank_keeps_g_when_e_moves(tmp_path):
    """NASTRAN's MAT1 rule: G given and NU blank, NU = E / (2 G) - 1 follows E and G
    stays, so a bar's torsion GJ does not move with E. Source: the hand-edited deck (as
    above); pyNastran fills NU in, so only the card's blank field tells the two apart."""
    def deck(path, e):
        text = _frame(path, "pbar_shear").read_text()
        line = next(x for x in text.splitlines() if x.startswith("MAT1*"))
        path.write_text(text.replace(line, f"MAT1*,1,{e!r},{7.9e10!r},"))
        return path

    e0 = 2.1e11
    nm = read_nastran(deck(tmp_path / "a.bdf", e0), _spec(PRODUCTS[:1]))
    ref = read_nastran(deck(tmp_path / "b.bdf", 1.1 * e0)).model
    a, b = nm.model.stiffness([1.1 * e0]), ref.stiffness()
    assert abs(a - b).max() <= 1e-12 * abs(b).max()
