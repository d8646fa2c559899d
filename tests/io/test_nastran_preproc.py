"""Decks as engineers' pre-processors write them (issue 20): Femap, Patran, HyperMesh,
Simcenter, ANSA, SimXpert, often on Windows. Each case is the shipped frame
(examples/nastran_frame) rewritten as such a tool writes it, read through the CLI. The
independent source of every number is the clean deck: the same cards give the same K and
M, so the frequencies must agree to 1e-12 relative (the arithmetic is the same; only the
text around the cards differs). A refusal is exit 2 and one line naming the file, the line
and the problem. The conventions: MSC and Autodesk QRG INCLUDE (remarks: anywhere, quotes
optional, a long name split over lines), MSC's Installation and Operations Guide
(logical symbols ``SYMBOL:file``, quoted in pyNastran issues 401/405), MSC QRG case control
ECHOON/ECHOOFF and bulk ENDDATA. Runs in .venv-nastran."""

from __future__ import annotations

import json
import shutil

import pytest
from conftest import ROOT
from nastran_frames import need
from refusals import one_line

from eigenupdate.io.nastran_include import read_lines

pytestmark = pytest.mark.nastran
need("pyNastran")

FRAME = ROOT / "examples" / "nastran_frame"
TEXT = (FRAME / "frame.bdf").read_text()
GRIDS = "\n".join(x for x in TEXT.splitlines() if x.startswith("GRID")) + "\n"
# the frame without its GRIDs, an INCLUDE of them right after BEGIN BULK (line 14)
NOGRID = "\n".join(x for x in TEXT.splitlines() if not x.startswith("GRID")).replace(
    "BEGIN BULK", "BEGIN BULK\n{include}") + "\n"
_CLEAN: list = []


def _frequencies(out: str) -> list[float]:
    return [f for c in json.loads(out)["configurations"] for f in c["frequencies_hz"]]


def _clean(run_cli) -> list[float]:
    if not _CLEAN:
        code, out, err = run_cli("frequencies", "--json", FRAME / "study.toml")
        assert code == 0, err
        _CLEAN.extend(_frequencies(out))
    return _CLEAN


def _frame(tmp_path, files: dict):
    """The frame's study in tmp_path/job, its files replaced by ``files`` (name: text
    or bytes; a name may lead into a subfolder or ``../``)."""
    d = tmp_path / "job"
    shutil.copytree(FRAME, d)
    for name, body in files.items():
        p = d / name
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_bytes(body if isinstance(body, bytes) else body.encode())
    return d / "study.toml"


def _same_as_clean(run_cli, study):
    code, out, err = run_cli("frequencies", "--json", study)
    assert code == 0, err
    got, want = _frequencies(out), _clean(run_cli)
    assert len(got) == len(want)
    assert all(abs(a - b) <= 1e-12 * b for a, b in zip(got, want, strict=True))
    return err


def _included(include: str, where: str = "grids.bdf", grids: str | bytes = GRIDS) -> dict:
    return {"frame.bdf": NOGRID.format(include=include), where: grids}


# --- INCLUDE names written on Windows: found by turning the separators ----------------

@pytest.mark.parametrize("include, where", [
    # NASTRAN_CoFE's superelement decks: INCLUDE '..\se0.dat'
    ("INCLUDE 'mesh\\grids.bdf'", "mesh/grids.bdf"),
    ("INCLUDE '..\\mesh\\grids.bdf'", "../mesh/grids.bdf"),
    ("INCLUDE 'mesh\\sub/grids.bdf'", "mesh/sub/grids.bdf"),
    ("INCLUDE mesh\\grids.bdf", "mesh/grids.bdf"),  # QRG remark: quotes optional
    # the QRG's long name split over lines, continuation lines indented, backslashes
    ("INCLUDE 'mesh\n           \\sub\n           \\grids.bdf'", "mesh/sub/grids.bdf"),
], ids=["relative", "parent", "mixed", "unquoted", "split"])
def test_windows_separators_are_read(tmp_path, run_cli, include, where):
    """Was: "INCLUDE file mesh\\grids.bdf not found" (a backslash is no separator here)."""
    _same_as_clean(run_cli, _frame(tmp_path, _included(include, where)))


@pytest.mark.parametrize("name, why", [
    ("C:\\proj\\mesh.bdf", "a Windows absolute path (drive C:)"),
    ("D:/proj/mesh.bdf", "a Windows absolute path (drive D:)"),
    ("\\\\server\\share\\mesh.bdf", "a Windows network path"),
    ("\\proj\\mesh.bdf", "a Windows path from the root of the current drive"),
])
def test_windows_absolute_names_are_refused_by_name(tmp_path, run_cli, name, why):
    """A file on a Windows drive cannot exist here: one line naming the INCLUDE, its
    line and why (was "not found (looked in ...)", as if it were a relative name)."""
    study = _frame(tmp_path, _included(f"INCLUDE '{name}'"))
    code, _, err = run_cli("frequencies", study)
    one_line(code, err, f"frame.bdf: line 14: INCLUDE {name}: {why}", "copy the file beside")


@pytest.mark.parametrize("include, fragment", [
    # MSC's logical symbols (pyNastran's Satellite_V02: 'Satellite_V02_BULK:TOP/...'),
    # defined in the nastran command or rc file, never in the deck
    ("INCLUDE 'MESHDIR:grids.bdf'", "INCLUDE MESHDIR:grids.bdf: MESHDIR is a logical symbol"),
    ("INCLUDE \"grids.bdf\"", "a file name in double quotes"),
    ("INCLUDE '/mydir' /level1 'grids.bdf'", "a name pieced from several quoted"),
    ("INCLUDE 'grids.bdf", "the file name's quote is never closed"),
    ("INCLUDE my grids.bdf", "an unquoted file name holding a blank or comma"),
    ("INCLUDE 'GRIDS.BDF'", "grids.bdf differs from it in letter case only"),
])
def test_include_names_not_read_are_refused_in_one_line(tmp_path, run_cli, include,
                                                        fragment):
    """Conventions this reader does not take (logical symbols, MSC's names pieced from
    quoted and unquoted parts, double quotes) or a deck error (a quote never closed
    swallowed the rest of the file into the name: a line of 8,000 characters), each
    named with its file and line."""
    code, _, err = run_cli("frequencies", _frame(tmp_path, _included(include)))
    one_line(code, err, "frame.bdf: line 14: INCLUDE", fragment)
    assert len(err) < 400


# --- the bytes of the files ----------------------------------------------------------

def test_byte_order_mark_of_an_included_file_is_dropped(tmp_path, run_cli):
    """Notepad's UTF-8 mark before an INCLUDEd file's first GRID: was refused as an
    unknown card '\\ufeffGRID'."""
    grids = b"\xef\xbb\xbf" + GRIDS.encode()
    _same_as_clean(run_cli, _frame(tmp_path, _included("INCLUDE 'grids.bdf'", grids=grids)))


def test_utf16_deck_is_refused_in_one_line(tmp_path, run_cli):
    """Windows' "Unicode" (UTF-16) deck: was pyNastran's "No spaces allowed in card name"
    after a warning for each of 180 lines; NASTRAN reads one byte per character."""
    code, _, err = run_cli("frequencies", _frame(tmp_path, {"frame.bdf": TEXT.encode("utf-16")}))
    one_line(code, err, "frame.bdf: the file is UTF-16 text")


def test_read_lines_keeps_windows_text_and_line_numbers(tmp_path):
    """A Femap title in cp1252 (é, and '…' = byte 0x85, Latin-1's NEL) and a form feed:
    str.splitlines cut lines at 0x85 and form feeds, shifting every later line number;
    the accents were U+FFFD (lost in a --save-bdf deck)."""
    p = tmp_path / "d.bdf"
    p.write_bytes("$ Femap: poutre \xe9\x85\r\n$ page\x0c\r\nGRID,1\r\n".encode("latin-1"))
    assert read_lines(p) == ["$ Femap: poutre \xe9\x85", "$ page\x0c", "GRID,1"]
    p.write_bytes(b"\xef\xbb\xbfGRID,1\nGRID,2")  # UTF-8 with its mark, no final newline
    assert read_lines(p) == ["GRID,1", "GRID,2"]
    p.write_bytes(b"GRID,1\r\nGRID,2\r\n\x1a")  # DOS's end-of-file mark: was a card
    assert read_lines(p) == ["GRID,1", "GRID,2"]


# --- sections and delimiters ---------------------------------------------------------

def test_case_control_echooff_is_read(tmp_path, run_cli):
    """ECHOOFF/ECHOON in the case control (MSC QRG: they only stop and resume the
    input's echo; Femap and SimXpert write them): was pyNastran's IndexError, which it
    takes for ECHO = ... without its '='."""
    text = TEXT.replace("TITLE =", "ECHOOFF\nTITLE =").replace("METHOD = 10",
                                                               "METHOD = 10\nECHOON")
    _same_as_clean(run_cli, _frame(tmp_path, {"frame.bdf": text}))


def test_data_after_enddata_is_not_read_and_named(tmp_path, run_cli):
    """QRG ENDDATA ends the bulk data: a free-field SPC1 with too many fields after it was
    refused ("data beyond the continuation field"), which NASTRAN never reads; now a
    warning names the ENDDATA and the first line not read."""
    text = TEXT + "SPC1,1,123456,1,2,3,4,5,6,7,8,9\n"
    err = _same_as_clean(run_cli, _frame(tmp_path, {"frame.bdf": text}))
    assert "line 190: ENDDATA ends the bulk data: 1 line(s) after it are not read, from " \
           "line 191" in err


def test_enddata_of_an_included_file_is_named(tmp_path, run_cli):
    """A bulk file exported with its own ENDDATA, INCLUDEd first: NASTRAN stops there,
    so every card of the main deck after the INCLUDE is lost; the warning says where."""
    files = _included("INCLUDE 'grids.bdf'", grids=GRIDS + "ENDDATA\n")
    code, _, err = run_cli("frequencies", _frame(tmp_path, files))
    assert code == 2
    assert "grids.bdf:71: ENDDATA ends the bulk data" in err


def test_begin_bulk_repeated_in_an_included_file_is_refused(tmp_path, run_cli):
    """A bulk file with its own BEGIN BULK INCLUDEd after the main deck's: was
    pyNastran's 'expected "BEGIN SUPER=1"...', no file or line."""
    files = _included("INCLUDE 'grids.bdf'", grids="BEGIN BULK\n" + GRIDS)
    code, _, err = run_cli("frequencies", _frame(tmp_path, files))
    one_line(code, err, "grids.bdf:1: BEGIN BULK a second time (first at line 13)")


# --- already read as NASTRAN reads them (kept so) ------------------------------------

FEMAP_HEAD = ("$ Femap with NX Nastran\nINIT MASTER(S)\nNASTRAN SYSTEM(442)=-1,SYSTEM(319)=1\n"
              "ASSIGN OUTPUT2 = 'C:\\Users\\me\\frame.op2', UNIT = 12, FORM = UNFORMATTED\n"
              "ID frame,Femap\n")


@pytest.mark.parametrize("files", [
    {"frame.bdf": TEXT.replace("\n", "\r\n").encode()},  # Windows line ends
    {"frame.bdf": b"\xef\xbb\xbf" + TEXT.encode()},  # UTF-8 mark
    {"frame.bdf": TEXT.replace("$column steel", "$ Femap Material 1 : acier \xe9\xb0"
                               ).replace("two-storey", "ch\xe2ssis").encode("cp1252")},
    {"frame.bdf": FEMAP_HEAD + TEXT.replace("$columns", "$ Femap Property 1 : HEB200")},
    {"frame.bdf": TEXT.replace("GRID        1002              0.      3.      0.",
                               "GRID\t1002\t\t0.\t3.\t0.")},  # tabs between fields
    {"frame.bdf": TEXT.replace("MAT1           1  2.1+11              .3   7850.",
                               "MAT1,1,2.1+11,,.3,7850. $ S355")},  # trailing comment
    {"frame.bdf": TEXT.replace("ENDDATA\n", "").replace("BEGIN BULK",
                                                        "begin bulk $ Femap")},
    _included("include grids.bdf $ mesh"),
    _included("INCLUDE 'mesh/\n$ the mesh\n     grids.bdf'", "mesh/grids.bdf"),
    # bulk data only (no executive or case control): the only SPC set
    {"frame.bdf": TEXT.split("BEGIN BULK\n")[1]},
    # the bulk file INCLUDEd by a main deck holding the case control (the README's way
    # for a bulk-only file whose SPC or MPC set must be chosen)
    {"model.bdf": TEXT.split("BEGIN BULK\n")[1].replace("ENDDATA\n", ""),
     "frame.bdf": "SOL 103\nCEND\nSPC = 1\nMETHOD = 10\nBEGIN BULK\nINCLUDE 'model.bdf'\n"
                  "ENDDATA\n"},
    # Patran: system-cell and direct-text comments, ENDDATA followed by a checksum
    {"frame.bdf": "$ NASTRAN input file created by the Patran 2019 input file translator\n"
                  + TEXT.replace("PARAM   COUPMASS       1", "PARAM   PATVER   3.\n"
                                 "PARAM   COUPMASS       1").replace("ENDDATA",
                                                                     "ENDDATA 2b4b6a8c")},
    # Simcenter: $* comments, a Windows path in one, SOL by name, MDLPRM
    {"frame.bdf": "$*  Simcenter 2306\n$*  FEM FILE: C:\\Users\\me\\frame_fem1.fem\n"
                  + TEXT.replace("SOL 103", "SOL SEMODES").replace(
                      "BEGIN BULK", "BEGIN BULK\n$*  PARAM CARDS\nPARAM,POST,-1\nMDLPRM,HDF5,0")},
], ids=["crlf", "bom", "cp1252", "femap-exec", "tabs", "trailing-comment",
        "begin-bulk-comment-no-enddata", "unquoted-lowercase", "split-comment",
        "bulk-only", "bulk-included", "patran", "simcenter"])
def test_pre_processor_conventions_read_as_the_clean_deck(tmp_path, run_cli, files):
    _same_as_clean(run_cli, _frame(tmp_path, files))
