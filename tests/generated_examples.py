"""Checks shared by the deck examples built by a generator (examples/stiffened_panel,
tests/data/composite_panel): the decks are what the generator writes, and the shipped
measurements are the truth deck's frequencies."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from eigenupdate.io.measurements import read_measurements


def assert_generator_writes(folder: Path, tmp_path: Path,
                            names=("mesh.bdf", "panel.bdf", "truth.bdf")) -> None:
    subprocess.run([sys.executable, str(folder / "make_panel.py")], cwd=tmp_path, check=True)
    for name in names:
        assert (tmp_path / name).read_text() == (folder / name).read_text(), name


def assert_truth_frequencies(folder: Path, tmp_path: Path, run_cli, count: int) -> None:
    """measured.csv against ``simulate truth.toml``: both are converged eigenvalues
    (residual ~ eps cond, 1e-12 relative at most) of the same model; another CPU or BLAS
    changes only the last digits."""
    out = tmp_path / "sim.csv"
    code, _, err = run_cli("simulate", folder / "truth.toml", "-o", out)
    assert code == 0, err
    shipped, again = read_measurements(folder / "measured.csv"), read_measurements(out)
    assert shipped.keys() == again.keys() and len(shipped) == count
    for key, m in shipped.items():
        assert again[key].frequency_hz == pytest.approx(m.frequency_hz, rel=1e-9)
