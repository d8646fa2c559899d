"""The fuzz invariant over a few hundred seeded mutations of the shipped examples (see
tools/fuzz.py; ``python tools/fuzz.py --cases 10000`` runs a long campaign)."""

import importlib.util

import pytest
from conftest import ROOT

spec = importlib.util.spec_from_file_location("fuzz", ROOT / "tools" / "fuzz.py")
fuzz = importlib.util.module_from_spec(spec)
spec.loader.exec_module(fuzz)


@pytest.mark.slow
def test_fuzz_invariant():
    counts, violations = fuzz.run(300, seed=20261123)
    assert not violations, "\n".join(d for ds in violations.values() for d in ds[:3])
    assert sum(counts.values()) == 300
    # the campaign must exercise both outcomes, or the mutations have gone blunt
    assert counts["exit 0"] > 30 and counts["exit 2 (input error)"] > 30, counts


@pytest.mark.parametrize("case", [1449, 4764, 5454])
def test_fuzz_cases_that_printed_nan(case):
    """Seed 23: corrupted UFF lines made a rejected candidate's fit NaN, printed in the
    table of an exit-0 run; it is now named by its band with the reason."""
    counts, violations = fuzz.run(1, seed=23, first=case)
    assert not violations, violations
