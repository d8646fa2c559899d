"""The ordering and interlacing checks of measured frequencies, and their allowance."""

import math

import pytest

from eigenupdate.errors import InputError
from eigenupdate.identify.plausibility import check_measured_frequencies, n_std_for
from eigenupdate.measure.measurement import Measurement
from eigenupdate.model.configurations import Configuration, mass_at


def _data(offset_std: float):
    """A bare structure and 20 added masses, 10 modes each, std 0.01 Hz; the masses
    lower every mode by 0.5 % except mode 3 of the first, which lies ``offset_std``
    combined std above the bare structure's mode 3 (noise, or a swap)."""
    std = 0.01
    bare = [10.0 * k for k in range(1, 11)]
    configs = [Configuration("base")] + [mass_at(c, 0.1, f"m{c}") for c in range(1, 21)]
    data = {("base", k): Measurement("base", k, f, std) for k, f in enumerate(bare, 1)}
    for c in configs[1:]:
        for k, f in enumerate(bare, 1):
            g = 0.995 * f
            if c.name == "m1" and k == 3:
                g = f + offset_std * math.hypot(std, std)
            data[(c.name, k)] = Measurement(c.name, k, g, std)
    return configs, data


def test_allowance_is_the_family_wise_normal_quantile():
    """Source: the normal distribution; 9 ordering pairs x 21 configurations and two
    bounds for each of the 200 perturbed frequencies: 589 comparisons."""
    assert n_std_for(589) == pytest.approx(5.100, abs=1e-3)
    assert n_std_for(1) == pytest.approx(3.719, abs=1e-3)


def test_noise_of_four_std_in_a_large_test_passes_and_a_swap_does_not():
    """4 std above is a 3e-5 event for one comparison, but one of 589 reaches it with
    probability 2 %: correct data (the fixed 3 std refused it). 8 std is a labelling
    error."""
    check_measured_frequencies(*_data(4.0))
    with pytest.raises(InputError, match="added mass cannot raise an eigenvalue"):
        check_measured_frequencies(*_data(8.0))
