"""The bad-input standard in tests: exit 2 and one line, no traceback."""

from __future__ import annotations


def one_line(code, err, *fragments, warnings_allowed=False):
    """Assert exit 2 with one line on stderr (besides ``eigenupdate: warning`` lines where
    ``warnings_allowed``), no traceback, that contains every fragment."""
    assert code == 2, err
    assert "Traceback" not in err
    lines = [x for x in err.strip().splitlines()
             if not (warnings_allowed and x.startswith("eigenupdate: warning"))]
    assert len(lines) == 1, err
    for f in fragments:
        assert f in lines[0], lines[0]
