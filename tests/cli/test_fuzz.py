"""The fuzz invariant over seeded mutations of the shipped examples, every command, output
path attacks, resource attacks and a broken stdout (see tools/fuzz.py; ``python
tools/fuzz.py --cases 10000`` runs a long campaign)."""

import importlib.util

import pytest
from conftest import ROOT

spec = importlib.util.spec_from_file_location("fuzz", ROOT / "tools" / "fuzz.py")
fuzz = importlib.util.module_from_spec(spec)
spec.loader.exec_module(fuzz)


def test_fuzz_short_seeded():
    """The CI form: 120 cases, about 30 s; every class of outcome but violations."""
    counts, violations, by_command = fuzz.run(120, seed=20261125)
    assert not violations, "\n".join(d for ds in violations.values() for d in ds[:3])
    assert sum(counts.values()) == 120
    # the campaign must reach both outcomes and most commands, or it has gone blunt
    assert counts["exit 0"] > 15 and counts["exit 2 (input error)"] > 15, counts
    assert len(by_command) >= 9, sorted(by_command)


@pytest.mark.parametrize("case", [1449, 4764, 5454])
def test_fuzz_cases_that_printed_nan(case):
    """Seed 23: corrupted UFF lines made a rejected candidate's fit NaN, printed in the
    table of an exit-0 run; it is now named by its band with the reason."""
    counts, violations, _ = fuzz.run(1, seed=23, first=case)
    assert not violations, violations
