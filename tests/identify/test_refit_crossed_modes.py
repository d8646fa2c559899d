"""A fit the data reject because two modes crossed between the start model and the
structure is fitted again from its own estimate, with the modes paired by order there
(identify/checked.py, ``_crossed``). Found by the acceptance decks (tools/accept_decks.py,
helper accept8): a 0.6 x 0.4 m aluminium plate of 24 x 16 CQUAD4 (ZOFFS) with a CBAR
stiffener on offsets, simply supported; PSHELL T, MAT1 E and PBAR I1 updated from four
0.05 kg additions. Its bare modes 1-2 are clustered, but the near-edge configuration's
are not, and they change order between the start (T 3 mm, E 70 GPa, I1 1.35e-8) and the
truth (3.1 mm, 72 GPa, 1.25e-8): tracked from the start's order pairing, error-free data
with std 0.005 Hz were rejected (exit 1). Runs in .venv-nastran (pyNastran)."""

from __future__ import annotations

import json

import pytest
from nastran_frames import need

pytestmark = pytest.mark.nastran
need("pyNastran")

NX, NY, A, B = 24, 16, 0.6, 0.4
TRUTH = {"t_plate": 0.0031, "E": 7.2e10, "I1_stiff": 1.25e-8}


def _nid(i: int, j: int) -> int:
    return i * (NY + 1) + j + 1


def _deck(t: float, e: float, i1: float) -> str:
    cards = ["SOL 103", "CEND", "SPC = 1", "BEGIN BULK"]
    cards += [f"GRID,{_nid(i, j)},,{A * i / NX!r},{B * j / NY!r},0."
              for i in range(NX + 1) for j in range(NY + 1)]
    eid = 0
    for i in range(NX):
        for j in range(NY):
            eid += 1
            q = (_nid(i, j), _nid(i + 1, j), _nid(i + 1, j + 1), _nid(i, j + 1))
            cards.append(f"CQUAD4,{eid},1,{q[0]},{q[1]},{q[2]},{q[3]},,0.0015")
    j = NY // 2  # the stiffener along x, 20 mm below the grids (WA, WB)
    cards += [f"CBAR,{5000 + i},2,{_nid(i, j)},{_nid(i + 1, j)},0.,0.,1.\n"
              f",,,0.,0.,-0.02,0.,0.,-0.02" for i in range(NX)]
    cards += [f"PBAR,2,1,1.8e-4,{i1!r},5.4e-10,1.89e-9", f"PSHELL,1,1,{t!r},1,,1",
              f"MAT1,1,{e!r},,0.33,2700."]
    edge = [_nid(i, j) for i in range(NX + 1) for j in range(NY + 1)
            if i in (0, NX) or j in (0, NY)]
    cards += [f"SPC1,1,123,{g}" for g in edge]
    return "\n".join(cards) + "\nENDDATA\n"


def _study(bdf: str, csv: str) -> str:
    text = f'[model]\ntype = "nastran"\nbdf = "{bdf}"\n'
    for name, card, pid, fld, std in (("t_plate", "PSHELL", 1, "T", 3e-4),
                                      ("E", "MAT1", 1, "E", 5e9),
                                      ("I1_stiff", "PBAR", 2, "I1", 2e-9)):
        text += (f'[[model.parameter]]\nname = "{name}"\ncard = "{card}"\nid = {pid}\n'
                 f'field = "{fld}"\nstd = {std}\n')
    for name, grid in (("centre", _nid(12, 8)), ("quarter", _nid(6, 4)),
                       ("off-stiffener", _nid(18, 12)), ("near edge", _nid(3, 13))):
        text += f'[[perturbation]]\nname = "{name}"\ngrid = {grid}\ncomponent = 3\nmass = 0.05\n'
    return text + (f'[measurement]\nfrequencies = "{csv}"\nmodes = [1, 2, 3, 4, 5, 6]\n'
                   '[updating]\nmethod = "weighted-least-squares"\n')


def test_crossed_modes_rejected_fit_is_refitted_to_the_truth(tmp_path, run_cli):
    """Source: the truth deck's own frequencies (error-free, std 0.005 Hz): the update
    must give the truth within a small fraction of its posterior std (it stops once the
    next step is below PRECISION of every std; 0.05 std allowed, measured 0.006), where
    it was rejected (exit 1) before."""
    (tmp_path / "plate.bdf").write_text(_deck(0.003, 7.0e10, 1.35e-8))
    (tmp_path / "truth.bdf").write_text(_deck(*TRUTH.values()))
    (tmp_path / "plate.toml").write_text(_study("plate.bdf", "measured.csv"))
    (tmp_path / "truth.toml").write_text(_study("truth.bdf", "measured.csv"))
    code, _, err = run_cli("simulate", tmp_path / "truth.toml", "-o",
                           tmp_path / "measured.csv", "--std-hz", "0.005")
    assert code == 0, err
    code, out, err = run_cli("update", tmp_path / "plate.toml", "--json")
    assert code == 0, err
    res = json.loads(out)
    assert "refitted from a first fit the data rejected" in res["message"]
    assert "near edge modes 1, 2" in res["message"]
    got, std = res["parameters"], res["std"]
    for name, want in TRUTH.items():
        assert abs(got[name] - want) <= 0.05 * std[name], (name, got[name], std[name])
