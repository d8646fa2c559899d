"""Issue 9: honest standard deviations also when a half-power band holds few lines.

One hysteretically damped mode (100 Hz, eta = 0.01: a 1 Hz half-power bandwidth) plus a
mode above the band and a rigid-body term, complex white noise 1 % of the peak, a random
offset of the frequency lines; line spacings from 0.1 to 5 half-power bandwidths. The
true error must lie within 3 reported std in (nearly) every case, for the frequency and
the loss factor (the 3-std criterion of the issue that built the extraction); modes
narrower than 3 lines are flagged as under-resolved.
"""

import numpy as np
import pytest

from eigenupdate.measure.frf import FRF
from eigenupdate.measure.survey import extract_test

FR, ETA = 100.0, 0.01
CASES = 40


def _frf(df, rng):
    f = np.arange(20.0 + rng.uniform(0, df), 300.0, df)
    x = (2 * np.pi * f) ** 2
    wr2 = (2 * np.pi * FR) ** 2
    h = ((1 + 0.3j) / (wr2 * (1 + 1j * ETA) - x)
         + 1 / ((2 * np.pi * 250) ** 2 * (1 + 0.01j) - x) - 0.3 / x)
    sigma = 0.01 / (ETA * wr2)
    h += sigma / np.sqrt(2) * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size))
    return FRF(f, h)


def coverage(lines_per_bandwidth: float, cases: int = CASES, seed: int = 0):
    rng = np.random.default_rng(seed)
    zf, ze, under = [], [], []
    for _ in range(cases):
        res = extract_test({"c": [_frf(lines_per_bandwidth * ETA * FR, rng)]})
        (m,) = [m for m in res.modes if abs(m.frequency_hz - FR) < 5]
        zf.append((m.frequency_hz - FR) / m.std_hz)
        ze.append((m.loss_factor - ETA) / m.loss_factor_std)
        under.append(m.under_resolved)
    zf, ze = np.abs(zf), np.abs(ze)
    return np.mean(zf < 3), np.mean(ze < 3), np.mean(under)


@pytest.mark.slow
@pytest.mark.parametrize("spacing", [0.1, 0.3, 1.0, 2.0, 5.0])
def test_three_std_cover_the_error_at_every_line_spacing(spacing):
    f_cov, eta_cov, under = coverage(spacing)
    print(f"line spacing {spacing} bandwidths: coverage f {f_cov:.2f}, eta {eta_cov:.2f}, "
          f"under-resolved {under:.2f}")
    assert f_cov >= 0.9 and eta_cov >= 0.9
    assert under == (1.0 if spacing > 1 / 3 else 0.0)
