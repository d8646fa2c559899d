"""Round-5 hostile NASTRAN input (tools/hostile_round5.py): THRU ranges pyNastran would
list id by id (or cut to their first id when reversed), an INCLUDEd file too large to
read, and a missing subcase's message. Runs in .venv-nastran."""

from __future__ import annotations

import shutil

import pytest
from conftest import ROOT
from nastran_frames import need
from refusals import one_line

pytestmark = pytest.mark.nastran
need("pyNastran")

FRAME = ROOT / "examples" / "nastran_frame"
PANEL = ROOT / "examples" / "stiffened_panel"
SPC = "SPC1           1   12456    1006"


def _copy(src, tmp_path, file=None, old=None, new=None):
    d = tmp_path / "ex"
    shutil.copytree(src, d)
    if file:
        text = (d / file).read_text()
        assert old in text
        (d / file).write_text(text.replace(old, new, 1))
    return d


def test_a_thru_range_beyond_the_budget_is_refused_before_pynastran_lists_it(
        tmp_path, run_cli, monkeypatch):
    """SPC1 1 THRU 100000000 ran out of memory inside pyNastran ('SPC1 1: MemoryError:');
    the range's size is its ids' difference + 1 (here 1..100: 100 ids, limit 10)."""
    d = _copy(FRAME, tmp_path, "frame.bdf", SPC, SPC + "\nSPC1,1,3,1,THRU,100")
    monkeypatch.setenv("EIGENUPDATE_MAX_THRU_IDS", "10")
    code, _, err = run_cli("check", d / "study.toml")
    one_line(code, err, "frame.bdf: line", "SPC1 1: 1 THRU 100 is 100 ids (pyNastran lists "
                        "them); the limit is 10 (set EIGENUPDATE_MAX_THRU_IDS to raise it)")


def test_a_reversed_thru_range_is_refused(tmp_path, run_cli):
    """pyNastran reads 3001 THRU 1001 as grid 3001 alone (its expand_thru counts up from
    the first id): the other grids' SPC was dropped without a word."""
    d = _copy(FRAME, tmp_path, "frame.bdf", SPC, SPC + "\nSPC1,1,3,3001,THRU,1001")
    code, _, err = run_cli("check", d / "study.toml")
    # the line of the range, not the set's first SPC1 card (another line)
    lines = (d / "frame.bdf").read_text().splitlines()
    at = lines.index("SPC1,1,3,3001,THRU,1001") + 1
    assert at != next(i for i, x in enumerate(lines) if x.startswith("SPC1")) + 1
    one_line(code, err, f"frame.bdf: line {at}: SPC1 1: 3001 THRU 1001: the range must "
                        "increase")


def test_an_included_file_beyond_the_size_budget_is_refused_unread(tmp_path, run_cli,
                                                                    monkeypatch):
    """A sparse 10 GB deck ran out of memory and the message named the study, not the
    deck; an INCLUDEd file is named itself (3 MB of zeros, budget 1 MB)."""
    d = _copy(PANEL, tmp_path)
    with open(d / "mesh.bdf", "r+b") as f:
        f.truncate(3 * 2**20)
    monkeypatch.setenv("EIGENUPDATE_MAX_INPUT_MB", "1")
    code, _, err = run_cli("check", d / "study.toml")
    one_line(code, err, "mesh.bdf: the NASTRAN file is 3 MB, read whole into memory; the "
                        "limit is 1 (set EIGENUPDATE_MAX_INPUT_MB to raise it)")


def test_a_missing_subcase_names_its_field_once(tmp_path, run_cli):
    """The deck's reader re-raised the message with its field prefix and the field again:
    'model.subcase: model.subcase: subcase 7 ...'."""
    d = _copy(FRAME, tmp_path, "study.toml", 'bdf = "frame.bdf"',
              'bdf = "frame.bdf"\nsubcase = 7')
    code, _, err = run_cli("check", d / "study.toml")
    one_line(code, err, "frame.bdf: model.subcase: subcase 7 is not in the case control")
    assert err.count("model.subcase") == 1, err
