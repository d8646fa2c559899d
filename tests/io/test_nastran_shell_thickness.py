"""PSHELL T as a parameter: membrane and drilling E T, bending E T^3, transverse shear
G s(T) (T on CQUAD4; T^3 / (T^2 + alpha h^2) per size on CTRIA3), mass RHO T + NSM.

Independent references: the deck with T (and MAT1 E, RHO) changed in its text and read
again; central finite differences of K, M; Navier's simply supported plate (frequency
proportional to T in bending); an update from the frequencies of a hand-edited deck,
and the updated BDF read back. Runs in .venv-nastran (pyNastran)."""

from __future__ import annotations

import numpy as np
import pytest
from bounds import assert_matrix_derivatives
from nastran_frames import need
from plates import square_mesh

from eigenupdate.errors import EigenupdateWarning
from eigenupdate.identify.updating import update
from eigenupdate.io.measurements import Measurement
from eigenupdate.model.configurations import Configuration, mass_at
from eigenupdate.solve.eigen import solve_elastic
from eigenupdate.solve.jacobian import solve_configurations

pytestmark = pytest.mark.nastran
need("pyNastran")
from plates import (  # noqa: E402
    FIELDS,
    INIT,
    NU,
    RHO,
    E,
    two_region_deck,  # noqa: E402
)
from plates import card_specs as _spec  # noqa: E402
from plates import read_deck as _read  # noqa: E402

from eigenupdate.io.nastran import dof_number, read_nastran  # noqa: E402
from eigenupdate.io.nastran_write import write_updated_bdf  # noqa: E402


def plate(path, v=INIT, nx=8, a=1.0, triangles=False, nsm=0.5):
    """The two-region plate (tests/plates.py), simply supported, in-plane and drilling
    held."""
    return two_region_deck(path, v, nx, a, "CTRIA3" if triangles else "CQUAD4", nsm, "126")


@pytest.mark.parametrize("triangles", [False, True], ids=["CQUAD4", "CTRIA3"])
def test_model_at_new_values_is_the_hand_edited_deck(tmp_path, triangles):
    nm = _read(plate(tmp_path / "a.bdf", triangles=triangles), _spec())
    assert nm.model.nonlinear and nm.model.values.tolist() == list(INIT.values())
    new = dict(zip(INIT, np.array(list(INIT.values())) * [1.1, 0.93, 1.05, 0.97], strict=True))
    ref = _read(plate(tmp_path / "b.bdf", new, triangles=triangles)).model
    s = np.array(list(new.values()))
    # the same element matrices times products of the same values, summed in another
    # order: a few ulps of the largest entry
    for a, b in ((nm.model.stiffness(s), ref.stiffness()), (nm.model.mass(s), ref.mass())):
        assert abs(a - b).max() <= 1e-12 * abs(b).max()


@pytest.mark.parametrize("triangles", [False, True], ids=["CQUAD4", "CTRIA3"])
def test_derivatives_match_central_differences(tmp_path, triangles):
    model = _read(plate(tmp_path / "a.bdf", triangles=triangles), _spec()).model
    assert_matrix_derivatives(model)  # central differences (tests/bounds.py)


def test_bending_frequency_scales_with_thickness_as_navier(tmp_path):
    """Source: Navier, omega_11 = 2 pi^2 / a^2 sqrt(D / (rho h)) with D ~ E h^3: for a
    thin plate (a/h = 1000, Mindlin's correction ~1e-5) omega ~ h, so evaluating the
    model at a thickness 1.3 times the deck's (both regions) scales the lowest frequency
    by 1.3, as re-reading the deck with that T does; and the mesh converges toward
    Navier's value."""
    t = 1e-3
    v = {"t1": t, "t2": t, "E": E, "rho": RHO}
    out = []
    for nx in (8, 16):
        nm = _read(plate(tmp_path / f"p{nx}.bdf", v, nx=nx, nsm=0.0), _spec(FIELDS[:2]))
        f0 = solve_elastic(nm.model.stiffness(), nm.model.mass(), 1).frequencies_hz[0]
        f1 = solve_elastic(nm.model.stiffness([1.3 * t] * 2), nm.model.mass([1.3 * t] * 2),
                           1).frequencies_hz[0]
        out.append((f0, f1))
        # Mindlin's shear correction (pi h / a)^2 ~ 1e-5 changes between the thicknesses
        assert f1 / f0 == pytest.approx(1.3, rel=5e-5)
    for k, h in ((0, t), (1, 1.3 * t)):
        D = E * h**3 / (12 * (1 - NU**2))
        exact = 2 * np.pi**2 * np.sqrt(D / (RHO * h)) / (2 * np.pi)
        f8, f16 = out[0][k], out[1][k]
        # the support holds w only: with CQUAD4's residual bending flexibility the
        # Mindlin boundary layer there is an element wide and the error falls about as
        # h (measured -1.0, -0.64 %); order 1/2 allowed: 1 / (sqrt(2) - 1) of the change
        assert abs(f16 - exact) <= abs(f16 - f8) / (np.sqrt(2) - 1) + 1e-4 * exact


def test_update_recovers_two_thicknesses_and_E_and_writes_them_back(tmp_path):
    fields = FIELDS[:3]
    nm = _read(plate(tmp_path / "a.bdf"), _spec(fields))
    truth = dict(INIT, t1=0.0043, t2=0.0057, E=2.06e11)
    true_model = _read(plate(tmp_path / "truth.bdf", truth)).model
    grids = [dof_number(g, 3) for g in (21, 41, 50)]  # interior grids (9 x 9 of them)
    configs = [Configuration("base")] + [mass_at(c, 2.0, f"m{c}") for c in grids]
    modes = [1, 2, 3, 4]
    sols = solve_configurations(true_model, configs, max(modes))
    data = {(c.name, k): Measurement(c.name, k, float(sol.frequencies_hz[k - 1]))
            for c, sol in zip(configs, sols, strict=True) for k in modes}
    res = update(nm.model, configs, modes, data, max_iterations=30)
    assert res.success, res.message
    want = np.array([truth[n] for n, *_ in fields])
    # error-free data: limited by the eigenvalues' round-off over cond(J)
    assert np.max(np.abs(res.x / want - 1)) < 1e-6
    out = tmp_path / "updated.bdf"
    write_updated_bdf(nm, out, res.parameters)
    back = _read(out, _spec(fields)).model.values
    assert back == pytest.approx(res.x, rel=1e-11)  # 12 significant digits written


@pytest.mark.slow
def test_study_update_writes_the_thicknesses_into_the_bdf(tmp_path, run_cli):
    """The command line from a study to the updated BDF: PSHELL T named by card, id and
    field; the data the hand-edited truth deck's frequencies (written with 17 digits).
    Slow: the workflow refits with modes exchanged between configurations."""
    plate(tmp_path / "plate.bdf", nx=6)
    truth = dict(INIT, t1=0.0042, t2=0.0061)
    true_model = _read(plate(tmp_path / "truth.bdf", truth, nx=6)).model
    grids = (16, 25, 32)  # interior grids of the 7 x 7
    configs = [Configuration("base")] + [mass_at(dof_number(g, 3), 2.0, f"g{g}")
                                         for g in grids]
    sols = solve_configurations(true_model, configs, 3)
    rows = ["configuration,mode,frequency_hz,std_hz"]
    rows += [f"{c.name},{k},{float(s.frequencies_hz[k - 1])!r},"
             for c, s in zip(configs, sols, strict=True) for k in (1, 2, 3)]
    (tmp_path / "measured.csv").write_text("\n".join(rows) + "\n")
    study = tmp_path / "study.toml"
    study.write_text(
        '[model]\ntype = "nastran"\nbdf = "plate.bdf"\n'
        + "".join(f'[[model.parameter]]\nname = "{n}"\ncard = "PSHELL"\nid = {i}\n'
                  f'field = "T"\n' for n, i in (("t1", 1), ("t2", 2)))
        + "".join(f'[[perturbation]]\nname = "g{g}"\ngrid = {g}\ncomponent = 3\nmass = 2.0\n'
                  for g in grids)
        + '[measurement]\nfrequencies = "measured.csv"\nmodes = [1, 2, 3]\n')
    out = tmp_path / "updated.bdf"
    code, text, err = run_cli("update", study, "--save-bdf", out)
    assert code == 0, err
    back = _read(out, _spec(FIELDS[:2])).model.values
    assert back == pytest.approx([truth["t1"], truth["t2"]], rel=1e-6)
    assert "PSHELL" in out.read_text() and "eigenupdate: updated" in out.read_text()


def graded_plate(path, t, nx=12, triangles=False):
    """A trapezoid of graded elements, every one of its own size (more than
    MAX_SIZES), simply supported as :func:`plate`, one PSHELL of thickness ``t``."""
    xyz, el = square_mesh(nx, 1.0, triangles)
    x, y = xyz[:, 0], xyz[:, 1]
    edge = [i + 1 for i in range(len(xyz)) if min(x[i], y[i]) < 1e-12 or max(x[i], y[i])
            > 1 - 1e-12]
    gx, gy = x**1.4, y**1.25 * (1.0 + 0.3 * x)
    lines = [f"GRID,{i + 1},,{a!r},{b!r},0." for i, (a, b) in enumerate(zip(gx, gy,
                                                                             strict=True))]
    card = "CTRIA3" if triangles else "CQUAD4"
    lines += [f"{card},{k + 1},1," + ",".join(str(n + 1) for n in e) for k, e in enumerate(el)]
    lines += [f"SPC1,1,126,1,THRU,{len(xyz)}"] + [f"SPC1,1,3,{n}" for n in edge]
    path.write_text("BEGIN BULK\nPARAM,COUPMASS,1\n" f"PSHELL,1,1,{t!r},1,,1\n"
                    f"MAT1,1,{E!r},,{NU!r},{RHO!r}\n" + "\n".join(lines) + "\nENDDATA\n")
    return path


@pytest.mark.parametrize("triangles", [False, True], ids=["CQUAD4", "CTRIA3"])
def test_a_graded_mesh_linearises_its_shear_about_the_decks_T(tmp_path, triangles):
    """Past MAX_SIZES element sizes the shear part is s(T0) + s'(T0) (T - T0) per
    element. Sources: the deck read without parameters (equal at T0); central
    differences (tests/bounds.py); and the deck rewritten with T = 1.05 T0: the model
    there differs from the exact elements only in the shear part, by at most
    eps = max_e |s_lin / s - 1| of it, so (Courant-Fischer, K_shear <= K) every
    eigenvalue within a factor 1 +- eps (measured: eps 6.6e-3, eigenvalues 4.7e-4 off
    with CQUAD4, 5.4e-4 with CTRIA3)."""
    from eigenupdate.io.nastran_plies import MAX_SIZES
    from eigenupdate.model import shells

    t0 = 0.002
    deck = graded_plate(tmp_path / "a.bdf", t0, triangles=triangles)
    with pytest.warns(EigenupdateWarning, match=r"PSHELL 1 field T: the transverse shear "
                      r"of its \d+ element sizes is linearised about the deck's T"):
        nm = read_nastran(deck, _spec([("t", "PSHELL", 1, "T")]))
    plain = _read(deck).model
    for a, b in ((nm.model.stiffness(), plain.stiffness()), (nm.model.mass(), plain.mass())):
        assert abs(a - b).max() <= 1e-12 * abs(b).max()
    assert_matrix_derivatives(nm.model)
    # the elements' sizes, as the reader takes them
    xyz, el = square_mesh(12, 1.0, triangles)
    g = np.column_stack([xyz[:, 0]**1.4, xyz[:, 1]**1.25 * (1 + 0.3 * xyz[:, 0]), xyz[:, 2]])
    h = shells.stabilisation_size(g[el])
    assert np.unique(h).size > MAX_SIZES
    t1 = 1.05 * t0
    s0, ds = shells.shear_thickness(t0, h), shells.shear_thickness_derivative(t0, h)
    eps = np.max(np.abs((s0 + ds * (t1 - t0)) / shells.shear_thickness(t1, h) - 1))
    exact = _read(graded_plate(tmp_path / "b.bdf", t1, triangles=triangles)).model
    f_exact = solve_elastic(exact.stiffness(), exact.mass(), 6).eigenvalues
    f_lin = solve_elastic(nm.model.stiffness([t1]), nm.model.mass([t1]), 6).eigenvalues
    assert 0 < eps < 0.01
    assert np.all(np.abs(f_lin / f_exact - 1) <= eps + 1e-9)
