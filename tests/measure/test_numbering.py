"""Issue 9: mode numbers against the model cannot drift silently (measure/numbering.py)."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from eigenupdate.measure.numbering import interlacing_bounds, number_resonances

MODEL = [50.0, 140.0, 275.0, 455.0, 680.0, 950.0]


@settings(max_examples=200, deadline=None)
@given(offset=st.floats(-0.05, 0.05), drop=st.sets(st.integers(0, 5), max_size=2),
       extra=st.lists(st.floats(20.0, 1000.0), max_size=3))
def test_model_a_few_percent_off_numbers_every_true_mode(offset, drop, extra):
    """The model off by up to 5 %, modes missing, spurious resonances added far from
    modes: each true resonance gets its own number, each missing mode is reported."""
    true = [f * (1 + offset) for k, f in enumerate(MODEL) if k not in drop]
    spurious = [x for x in extra
                if all(abs(np.log(x / f)) > np.log(1.25) for f in MODEL)]
    measured = sorted(true + spurious)
    r = number_resonances(measured, MODEL, range_hz=(10.0, 1000.0))
    for f, k in zip(measured, r.numbers, strict=True):
        if f in spurious:
            assert k is None
        else:
            assert k is not None and abs(f / MODEL[k - 1] - 1 - offset) < 1e-9
    assert r.missing == sorted(k + 1 for k in drop)
    assert not r.ambiguous


def test_one_resonance_between_two_close_model_modes_is_ambiguous():
    r = number_resonances([101.0], [100.0, 102.0])
    assert r.ambiguous == ["the resonance at 101 Hz: model mode 1 (100 Hz) or 2 (102 Hz)"]


def test_two_resonances_for_one_model_mode_are_ambiguous():
    r = number_resonances([99.0, 101.0], [100.0])
    assert len(r.ambiguous) == 1
    assert "model mode 1 (100 Hz): the resonance at 99 Hz or at 101 Hz" in r.ambiguous[0]


def test_interlacing_decides_what_the_model_cannot():
    """Added mass lowers mode 2 below the bare mode 2 but not below bare mode 1: a
    resonance just above bare mode 2 cannot be perturbed mode 2."""
    bare = {1: 100.0, 2: 200.0}
    bounds = interlacing_bounds(bare, 2, masses=1, springs=0)
    r = number_resonances([95.0, 203.0], [97.0, 198.0], bounds_hz=bounds)
    assert r.numbers == [1, None] and r.missing == [2]
    r = number_resonances([95.0, 196.0], [97.0, 198.0], bounds_hz=bounds)
    assert r.numbers == [1, 2]
    # added springs raise: the bounds are the bare mode and the next one
    assert interlacing_bounds(bare, 2, masses=0, springs=1) == [(100.0, 200.0),
                                                                 (200.0, np.inf)]
    assert interlacing_bounds(bare, 2, masses=1, springs=1) == [None, None]
