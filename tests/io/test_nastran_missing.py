"""Without the nastran extra, a NASTRAN study is bad input with the install hint."""

from __future__ import annotations

import importlib.util

import pytest
from conftest import EXAMPLES


@pytest.mark.skipif(importlib.util.find_spec("pyNastran") is not None,
                    reason="pyNastran is installed (the nastran environment)")
def test_nastran_study_needs_the_extra(run_cli):
    code, out, err = run_cli("check", EXAMPLES / "nastran_frame" / "study.toml")
    assert code == 2
    assert "pip install 'eigenupdate[nastran]'" in err and err.count("\n") == 1
