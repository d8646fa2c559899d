"""``python -m eigenupdate`` runs the command line (the helpers' briefs and a user without
the console script call it so). Source: the tester's acceptance run, where it failed with
"No module named eigenupdate.__main__"."""

import os
import subprocess
import sys

from conftest import EXAMPLES, ROOT


def test_python_dash_m_runs_the_command_line():
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    done = subprocess.run([sys.executable, "-m", "eigenupdate", "frequencies",
                           str(EXAMPLES / "paper_fig2" / "truth.toml")],
                          capture_output=True, text=True, env=env, timeout=120)
    assert done.returncode == 0, done.stderr
    assert "elastic natural frequencies (Hz)" in done.stdout
    bad = subprocess.run([sys.executable, "-m", "eigenupdate", "frequencies", "nowhere.toml"],
                         capture_output=True, text=True, env=env, timeout=120)
    assert bad.returncode == 2 and bad.stderr.startswith("eigenupdate: error:"), bad.stderr
