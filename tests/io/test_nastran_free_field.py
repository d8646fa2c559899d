"""Lines that hold data NASTRAN does not read as data. A free-field line has 10 fields (6
in large-field ``*`` format), a fixed-field line 80 columns, the last field (columns 73-80)
being the continuation field; pyNastran drops anything after it without a word.
Source: the tester's acceptance run (issue 21),
where a hand-written cantilever plate's ``SPC1,1,123456,1,10,19,28,37,46,55,64,73`` clamped
6 of its 9 edge grids (pyNastran's SPC1 nodes, checked below) and the plate's first
frequency came out 7 % low, 28 % low on the 16 x 16 mesh, with exit status 0.
Runs in .venv-nastran (pyNastran)."""

from __future__ import annotations

import pytest
from nastran_frames import need

pytestmark = pytest.mark.nastran
need("pyNastran")

# a CBAR cantilever along x with a free-field SPC1 at the root
BARS = """GRID,1,,0.,0.,0.
GRID,2,,1.,0.,0.
GRID,3,,2.,0.,0.
CBAR,1,1,1,2,0.,1.,0.
CBAR,2,1,2,3,0.,1.,0.
PBAR,1,1,1.e-3,1.e-7,2.e-7,3.e-7
MAT1,1,2.e11,,.3,7850.
"""


def _run(tmp_path, run_cli, bulk):
    (tmp_path / "deck.bdf").write_text("BEGIN BULK\n" + bulk + "ENDDATA\n")
    study = tmp_path / "s.toml"
    study.write_text('[model]\ntype = "nastran"\nbdf = "deck.bdf"\n[measurement]\nmodes = [1]\n')
    return run_cli("frequencies", study)


def test_pynastran_drops_the_fields_after_the_continuation_field(tmp_path):
    """The reference for the refusal: what pyNastran makes of such a line."""
    from pyNastran.bdf.bdf import BDF
    (tmp_path / "d.bdf").write_text("SPC1,1,123456,1,10,19,28,37,46,55,64,73\n"
                                    "GRID*,2,,1.0,2.0,3.0\n"
                                    "SPC1    2       123456  1       2       3       4"
                                    "       5       6       7       8\n")
    bdf = BDF(debug=None)
    bdf.read_bdf(str(tmp_path / "d.bdf"), xref=False, punch=True)
    assert bdf.spcs[1][0].nodes == [1, 10, 19, 28, 37, 46]
    assert list(bdf.nodes[2].xyz) == [1.0, 2.0, 0.0]
    assert bdf.spcs[2][0].nodes == [1, 2, 3, 4, 5, 6]


@pytest.mark.parametrize("line,words", [
    ("SPC1,1,123456,1,1,1,1,1,1,1,2,3\n", ["line 9: SPC1", "field 10 of a free-field",
                                          "'2', '3'"]),
    ("SPC1,1,123456,1 $ a,b,c,d,e,f,g,h,i,j\nGRID*,4,,3.0,0.0,+C,9.0\n*C,0.0\n",
     ["line 10: GRID", "field 6 of a free-field", "read '9.0'"]),
])
def test_data_beyond_the_continuation_field_is_refused(tmp_path, run_cli, line, words):
    code, out, err = _run(tmp_path, run_cli, BARS + line)
    errors = [x for x in err.splitlines() if "error" in x]
    assert code == 2 and len(errors) == 1 and "Traceback" not in err, err
    assert str(tmp_path / "deck.bdf") in errors[0]
    for w in words:
        assert w in errors[0], errors[0]


def test_text_beyond_column_80_of_a_fixed_field_line_is_named_not_refused(tmp_path, run_cli):
    """NASTRAN reads a fixed-field line to column 80, and pyNastran too (its SPC1 above
    kept grids 1-6 of the fixed-field line, as NASTRAN would): nothing is misread, so the
    deck runs and the ignored text is named (a ZAERO deck keeps its continuation markers
    in columns 81-88)."""
    line = "SPC1    1       123456  1       1       1       1       1       1       1       2\n"
    code, out, err = _run(tmp_path, run_cli, BARS + line)
    assert code == 0 and "line 9: columns 81-81 are not read ('2')" in err, err


def test_a_number_in_an_unused_continuation_field_is_named(tmp_path, run_cli):
    code, out, err = _run(tmp_path, run_cli, BARS + "SPC1,1,12345,1,,,,,,6\n")
    assert code == 0 and "line 9: SPC1: '6' is in the continuation field" in err, err
    code, out, err = _run(tmp_path, run_cli, BARS + "SPC1    1       12345   1" + " " * 47 + "6\n")
    assert code == 0 and "line 9: SPC1: '6' is in the continuation field" in err, err


def test_continued_free_field_cards_are_read_silently(tmp_path, run_cli):
    text = BARS + ("SPC1,1,123456,1,,,,,,+A\n+A,1\nGRID*,4,,3.0,0.0,+B\n*B,0.0\n"
                   "PBAR,9,1,1.e-3\n,,,,,,,,,\n,1.\n")  # a continuation of blank fields
    code, out, err = _run(tmp_path, run_cli, text)
    assert code == 0 and "continuation" not in err and "error" not in err, err


# free-field replication (MSC QRG, Bulk Data free field: '=' repeats a field, '*(x)' adds x,
# '==' repeats the rest, '=n' makes n more cards), expanded by hand: the cards written out


def test_a_third_replication_in_a_row_is_refused_naming_its_line(tmp_path, run_cli):
    """Issue 20 acceptance (accept8): three '=' cards in a row, valid for MSC, failed with
    pyNastran's 'ReplicationError: dig=False...old_card=' and no line; two in a row and
    '=n' are expanded (grids 2-5 at x = 1..4, by hand)."""
    rep = "=,*(1),=,*(1.),==\n"
    beam = BARS.replace("CBAR,2,1,2,3,0.,1.,0.\n", "CBAR,2,1,2,3,0.,1.,0.\nCBAR,3,1,3,4,0.,1.,0.\n"
                        "CBAR,4,1,4,5,0.,1.,0.\n") + "SPC1,1,123456,1\n"
    written = beam.replace("GRID,3,,2.,0.,0.\n", "GRID,3,,2.,0.,0.\nGRID,4,,3.,0.,0.\n"
                           "GRID,5,,4.,0.,0.\n")
    two = beam.replace("GRID,2,,1.,0.,0.\nGRID,3,,2.,0.,0.\n", rep * 2 + "GRID,4,,3.,0.,0.\n"
                       "GRID,5,,4.,0.,0.\n")
    repeat = beam.replace("GRID,2,,1.,0.,0.\nGRID,3,,2.,0.,0.\n", rep + "=3\n")
    outs = [_run(tmp_path, run_cli, t) for t in (written, two, repeat)]
    assert all(c == 0 for c, _, _ in outs) and outs[0][1] == outs[1][1] == outs[2][1], outs
    code, out, err = _run(tmp_path, run_cli, beam.replace("GRID,2,,1.,0.,0.\nGRID,3,,2.,0.,0.\n",
                                                          rep * 4))
    errors = [x for x in err.splitlines() if "error" in x]
    assert code == 2 and len(errors) == 1 and "Traceback" not in err, err
    assert "deck.bdf: line 5: free-field replication" in errors[0], errors[0]
    assert "dig=False" not in errors[0]
