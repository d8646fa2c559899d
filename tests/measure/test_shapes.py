"""Pairing of measured modes by their shapes (measure/shapes.py, issue 23 item 3): shapes
from the Dobson fits' modal constants, MAC against the initial model's modes and the bare
structure's measured shapes.

The crossing case: two 2-mass oscillators (A on coordinates 1-2, B on 3-4) joined by a
weak spring. A mass of 0.25 kg on coordinate 4 lowers B's first mode below A's in the
structure (kb = 1.12e4 N/m: 9.60 Hz against 9.99 Hz) but not in the initial model
(kb = 1.25e4: B stays above A), so the resonance numbered 1 by frequency is the model's
mode 2 by shape: a mode exchange, caught before any fit."""

import warnings

import numpy as np
import pytest

from eigenupdate.measure.shapes import MAC_SAME, mac, measured_shape, shape_pairing
from eigenupdate.measure.survey import extract_test
from eigenupdate.measure.synthetic import synthetic_frfs
from eigenupdate.model.configurations import Configuration, mass_at
from eigenupdate.model.parameters import Parameter
from eigenupdate.model.spring_mass import Mass, Spring, spring_mass_model
from eigenupdate.solve.jacobian import solve_configurations

CONFIGS = [Configuration("base"), mass_at(4, 0.25)]
AXIS = np.linspace(1.0, 40.0, 4000)


def _oscillators(kb: float, kc: float = 150.0):
    return spring_mass_model(
        [Mass(Parameter(f"m{i}", 1.0), i) for i in range(1, 5)],
        [Spring(Parameter("ka1", 1e4), (0, 1)), Spring(Parameter("ka2", 1e4), (1, 2)),
         Spring(Parameter("kb1", kb), (0, 3)), Spring(Parameter("kb2", kb), (3, 4)),
         Spring(Parameter("kc", kc), (2, 3))])


def _frfs(truth, seed=1):
    return {c.name: synthetic_frfs(truth, c, AXIS, 2, [1, 2, 3, 4], 0.01, noise=1e-3,
                                   seed=seed) for c in CONFIGS}


def _extract(truth, model):
    frfs = _frfs(truth)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return frfs, extract_test(frfs, model=model, configurations=CONFIGS,
                                  used_modes=[1, 2, 3])


def test_mac_against_closed_forms():
    # MAC is 1 for parallel vectors of any scale and sign, 0 for orthogonal ones, and
    # (a.b)^2 / (|a|^2 |b|^2) = cos^2 of the angle otherwise: 45 degrees gives 1/2
    a = np.array([1.0, 0.0, 0.0])
    assert mac(a, -3.0 * a) == pytest.approx(1.0, abs=1e-15)
    assert mac(a, np.array([0.0, 2.0, 0.0])) == 0.0
    assert mac(a, np.array([1.0, 1.0, 0.0])) == pytest.approx(0.5, abs=1e-15)
    m = mac(np.eye(3), np.eye(3))
    assert np.array_equal(m, np.eye(3))


def test_shapes_from_synthetic_frfs_are_the_true_modes():
    """Reference: the true model's eigenvectors at the four responses. A response where
    a mode shows no accepted peak counts as 0, so the MAC can reach at most the share
    of |phi|^2 at the other responses; the FRF noise (1e-3 relative) costs ~1e-3 more,
    allowed as 1e-2. Where every response has a fit the bound is 1."""
    truth = _oscillators(1.12e4)
    frfs, res = _extract(truth, truth)
    sols = solve_configurations(truth, CONFIGS, 4)
    for ex, sol in zip(res.configurations, sols, strict=True):
        assert [m.mode for m in ex.modes][:3] == [1, 2, 3]
        for m in ex.modes[:3]:
            s = measured_shape(ex.configuration, m.mode, m.frequency_hz, m.fits,
                               frfs[ex.configuration])
            phi = sol.modes[:, m.mode - 1]
            kept = s.shape != 0
            bound = np.sum(phi[kept] ** 2) / np.sum(phi ** 2)
            assert bound > 0.95  # the leak through the weak coupling spring is small
            assert mac(s.shape, phi) >= bound - 1e-2, (ex.configuration, m.mode)


def test_a_mass_that_makes_modes_cross_is_caught_before_the_fit():
    truth, model = _oscillators(1.12e4), _oscillators(1.25e4)
    # the premise, from the two models' eigenvectors: B (coordinates 3-4) is the truth's
    # perturbed mode 1 and the initial model's perturbed mode 2
    t, m = (solve_configurations(x, CONFIGS[1:], 2)[0].modes for x in (truth, model))
    assert np.abs(t[2:, 0]).sum() > np.abs(t[:2, 0]).sum()
    assert np.abs(m[2:, 1]).sum() > np.abs(m[:2, 1]).sum()
    _, res = _extract(truth, model)
    found = [p for p in res.problems if "has the shape of the model's mode" in p]
    assert len(found) >= 1
    assert "'0.25 kg at 4'" in found[0] and "numbered mode 1" in found[0]
    assert "mode 2" in found[0] and "mode exchange" in found[0]
    crossed = [n for ex in res.configurations for n in ex.notes
               if "bare structure's mode 2" in n]
    assert crossed and "mode 1 has the shape" in crossed[0]


def test_no_exchange_when_the_model_orders_the_modes_as_the_test():
    # the initial model is the truth: the crossing is real but shared, so it is a note,
    # not a problem
    truth = _oscillators(1.12e4)
    _, res = _extract(truth, truth)
    assert not [p for p in res.problems if "shape" in p], res.problems
    assert any("moves modes across each other" in n for ex in res.configurations
               for n in ex.notes)


def test_shape_pairing_needs_the_margin():
    """Two equally good matches (MAC 0.9 both) say nothing: no problem is raised."""
    model = _oscillators(1.12e4)
    sol = solve_configurations(model, CONFIGS[:1], 2)[0]
    mixed = (sol.modes[:, 0] + sol.modes[:, 1]) / np.sqrt(2)  # MAC ~0.5 with each
    s = measured_shape("base", 1, 10.0, [_Fit(v) for v in mixed],
                       _frfs(model)["base"])
    p = shape_pairing({"base": [s]}, model, CONFIGS[:1])
    assert p.problems == []
    assert p.mac["base"][0, :2].max() < MAC_SAME


class _Fit:
    """A modal fit with only the modal constant, for shapes built by hand."""

    def __init__(self, a):
        self.modal_constant = complex(a)


def test_a_measured_point_the_model_lacks_is_named_not_skipped_silently():
    """One FRF's response relabelled to node 9, which the 4-mass model does not have:
    the shapes of that configuration were not compared with the model's (the exchange
    check off) and nothing said so."""
    import dataclasses

    truth = _oscillators(1.12e4)
    frfs = _frfs(truth)
    frfs["base"] = [dataclasses.replace(frfs["base"][0], response=(9, frfs["base"][0].response[1])),
                    *frfs["base"][1:]]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = extract_test(frfs, model=truth, configurations=CONFIGS, used_modes=[1, 2, 3])
    base = next(ex for ex in res.configurations if ex.configuration == "base")
    assert any("shapes not compared with the model's modes" in n and "(9, " in n
               for n in base.notes), base.notes
