"""Where a command may write (io/outputs.py, io/atomic.py, cli.main): regular files only,
never an input, checked before the work, all outputs of a run or none, and a closed or
broken stdout that loses nothing silently (issue 23)."""

import io
import os
import re
import shutil
import socket
import stat
import sys

import pytest
from conftest import EXAMPLES

from eigenupdate.cli import main
from eigenupdate.io import atomic


@pytest.fixture
def fig2(tmp_path):
    for name in ("study.toml", "truth.toml", "measured.csv"):
        shutil.copy(EXAMPLES / "paper_fig2" / name, tmp_path / name)
    return tmp_path


def snapshot(d):
    return {p.name: (p.read_bytes() if p.is_file() and not p.is_symlink() else None)
            for p in d.iterdir()}


def bad(run_cli, args, *fragments):
    code, out, err = run_cli(*args)
    assert code == 2, (out, err)
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    for f in fragments:
        assert f in lines[0], lines[0]
    assert ".tmp" not in lines[0]  # named as given, never by the temporary file
    return lines[0]


def test_fifo_device_directory_refused(fig2, run_cli):
    os.mkfifo(fig2 / "fifo")
    before = snapshot(fig2)
    bad(run_cli, ["simulate", fig2 / "truth.toml", "-o", fig2 / "fifo"], "fifo", "-o",
        "not a regular file")
    assert (fig2 / "fifo").is_fifo()
    # a socket stands for a device: a regression must not replace this machine's /dev/null
    sock = socket.socket(socket.AF_UNIX)
    sock.bind(str(fig2 / "sock"))
    try:
        bad(run_cli, ["simulate", fig2 / "truth.toml", "-o", fig2 / "sock"], "sock",
            "not a regular file")
        assert stat.S_ISSOCK(os.lstat(fig2 / "sock").st_mode)
        os.symlink(fig2 / "sock", fig2 / "to_sock")
        bad(run_cli, ["simulate", fig2 / "truth.toml", "-o", fig2 / "to_sock"], "to_sock",
            "not a regular file")
    finally:
        sock.close()
    (fig2 / "d").mkdir()
    bad(run_cli, ["update", fig2 / "study.toml", "--save", fig2 / "d"], "--save", "directory")
    bad(run_cli, ["montecarlo", fig2 / "study.toml", "--trials", "1", "--in-process", "-o",
                  fig2 / "measured.csv"], "-o", "not a directory")
    for k in ("d", "sock", "to_sock"):
        before.pop(k, None)
    after = snapshot(fig2)
    for k in ("d", "sock", "to_sock"):
        after.pop(k, None)
    assert after == before


def test_links_loops_and_dangling(fig2, run_cli):
    os.symlink(fig2 / "loop_a", fig2 / "loop_b")
    os.symlink(fig2 / "loop_b", fig2 / "loop_a")
    bad(run_cli, ["simulate", fig2 / "truth.toml", "-o", fig2 / "loop_a"], "loop_a",
        "symbolic link loop")
    os.symlink(fig2 / "nowhere" / "x.csv", fig2 / "dangling")
    line = bad(run_cli, ["simulate", fig2 / "truth.toml", "-o", fig2 / "dangling"],
               "dangling", "dangling symbolic link")
    assert "does not exist" not in line
    # a link to an input is that input, and so is a hard link
    os.symlink(fig2 / "study.toml", fig2 / "link.toml")
    bad(run_cli, ["update", fig2 / "study.toml", "--save", fig2 / "link.toml"], "--save",
        "input of this run")
    os.link(fig2 / "measured.csv", fig2 / "hard.csv")
    bad(run_cli, ["update", fig2 / "study.toml", "--save", fig2 / "hard.csv"],
        "input of this run")
    assert (fig2 / "study.toml").read_bytes() == (EXAMPLES / "paper_fig2" /
                                                  "study.toml").read_bytes()


@pytest.mark.parametrize("command", [
    ["report", "{d}/study.toml", "-o", "{d}/measured.csv"],
    ["design", "{d}/study.toml", "-o", "{d}/measured.csv"],
    ["simulate", "{d}/truth.toml", "-o", "{d}/truth.toml"],
    ["frf", "{d}/study.toml", "--input", "1", "--output", "1", "-o", "{d}/measured.csv"],
    ["sweep", "{d}/study.toml", "--coordinate", "1", "--max-mass", "1", "-o",
     "{d}/truth.toml"],
    ["report", "{d}/study.toml", "--result", "{d}/r.json", "-o", "{d}/r.json"],
])
def test_no_command_writes_an_input(fig2, run_cli, command):
    (fig2 / "r.json").write_text("{}")
    if "truth.toml" in command[-1]:  # the truth model as the study's model file
        command = [c.replace("{d}/study.toml", "{d}/truth.toml") for c in command]
    before = snapshot(fig2)
    bad(run_cli, [c.replace("{d}", str(fig2)) for c in command], "input of this run")
    assert snapshot(fig2) == before


def test_long_names(fig2, run_cli):
    name = "a" * 245 + ".csv"  # 249 characters: the temporary name must not exceed 255
    code, _, err = run_cli("simulate", fig2 / "truth.toml", "-o", fig2 / name)
    assert code == 0, err
    assert (fig2 / name).is_file()
    assert not [p for p in fig2.iterdir() if ".tmp" in p.name]
    bad(run_cli, ["simulate", fig2 / "truth.toml", "-o", fig2 / ("b" * 256)], "-o",
        "too long")


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into a read-only directory")
def test_read_only_directory_before_the_work(fig2, run_cli):
    ro = fig2 / "ro"
    ro.mkdir()
    ro.chmod(0o555)
    try:
        line = bad(run_cli, ["update", fig2 / "study.toml", "--save", ro / "r.json"],
                   "r.json", "cannot create a file in directory")
        assert "ro" in line
    finally:
        ro.chmod(0o755)


def test_transaction_all_or_none(tmp_path, monkeypatch):
    """The second rename fails: the first target gets its old content back."""
    (tmp_path / "a.txt").write_text("old a")
    real = os.replace
    calls = []

    def failing(src, dst):
        calls.append(dst)
        if str(dst).endswith("b.txt"):
            raise OSError(28, "No space left on device", str(dst))
        return real(src, dst)

    monkeypatch.setattr(atomic.os, "replace", failing)
    with pytest.raises(OSError), atomic.transaction():
        atomic.write_text(tmp_path / "a.txt", "new a")
        atomic.write_text(tmp_path / "b.txt", "new b")
        atomic.write_text(tmp_path / "c.txt", "new c")
    monkeypatch.setattr(atomic.os, "replace", real)
    assert (tmp_path / "a.txt").read_text() == "old a"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt"]
    assert any(str(c).endswith("a.txt") for c in calls)  # a was renamed, then put back


def test_write_through_a_link_keeps_the_link(tmp_path):
    (tmp_path / "real.txt").write_text("old")
    os.symlink(tmp_path / "real.txt", tmp_path / "link.txt")
    atomic.write_text(tmp_path / "link.txt", "new")
    assert (tmp_path / "link.txt").is_symlink()
    assert (tmp_path / "real.txt").read_text() == "new"


class _Broken(io.StringIO):
    def write(self, s):
        raise BrokenPipeError(32, "Broken pipe")


@pytest.mark.parametrize("stdout", [None, _Broken()])
def test_closed_or_broken_stdout(fig2, monkeypatch, capsys, stdout):
    monkeypatch.setattr(sys, "stdout", stdout)
    monkeypatch.setattr(os, "dup2", lambda *a: None)  # not this test process's own fd 1
    code = main(["update", str(fig2 / "study.toml"), "--save", str(fig2 / "r.json")])
    err = capsys.readouterr().err
    assert code == 2
    # one error line; the others are the update's progress lines ("[i/N] ...")
    lines = err.strip().splitlines()
    assert "standard output" in lines[-1]
    assert all(re.match(r"\[\d+/\d+\] ", line) for line in lines[:-1]), lines
    assert '"success": true' in (fig2 / "r.json").read_text()


@pytest.mark.parametrize("args,flag", [
    (["design", "{s}", "-o", "{d}/p.toml", "--scheduler", "tls://10.0.0.1:8786"],
     "--scheduler"),
    (["simulate-frf", "{s}", "-o", "{d}/f", "--input", "1", "--outputs", "1", "--fmax",
      "100", "--noise", "-1"], "--noise"),
    (["simulate", "{s}", "-o", "{d}/x.csv", "--noise-hz", "-1"], "--noise-hz"),
])
def test_options_blame_themselves(fig2, run_cli, args, flag):
    line = bad(run_cli, [a.replace("{s}", str(fig2 / "study.toml")).replace("{d}", str(fig2))
                         for a in args], flag)
    assert "study.toml" not in line


def test_unwritable_directory_named_before_the_work(fig2, run_cli, monkeypatch):
    """As root a chmod 555 directory is writable, so the refusal of the file system
    (EACCES, or EROFS of a read-only mount) is simulated; the update must not run."""
    from eigenupdate import workflow
    from eigenupdate.io import outputs

    real_open = os.open

    def refuse(path, *a, **k):
        if os.path.dirname(path) == str(fig2 / "ro"):
            raise PermissionError(13, "Permission denied", path)
        return real_open(path, *a, **k)

    def no_work(*a, **k):
        raise AssertionError("the update ran before the output was checked")

    (fig2 / "ro").mkdir()
    monkeypatch.setattr(outputs.os, "open", refuse)
    monkeypatch.setattr(workflow, "update_study", no_work)
    bad(run_cli, ["update", fig2 / "study.toml", "--save", fig2 / "ro" / "r.json"],
        "ro/r.json", "--save", f"cannot create a file in directory '{fig2 / 'ro'}'",
        "Permission denied")
