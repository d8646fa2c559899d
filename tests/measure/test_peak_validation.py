"""Issue 9: measured FRFs never give a spurious or mis-numbered mode.

Synthetic FRFs of the paper's free beam (the 'truth' of examples/paper_beam_frf, Table 6's
updated values) by modal superposition of its exact modes, with the artefacts of real tests
added: one-line noise spikes (20-100 x the noise), mains harmonics (50 or 60 Hz and
multiples, on a line or leaking over neighbouring lines), leakage ripple (alternating sign,
decaying as 1/k) beside a resonance, coarse lines (0.1-2 half-power bandwidths per line)
and a mode missing from the FRFs. The study's initial model (2-4 % off the truth) numbers
the modes. Nothing is accepted that is not a true mode, every number is the true one,
every mode standing 30 noise std out of the noise is found, and every mode not found
(the missing one, or one buried in the noise at these response points) is reported as
expected but not found.
"""

import numpy as np
import pytest
from conftest import EXAMPLES

from eigenupdate.io.study import load_study
from eigenupdate.measure.frf import FRF
from eigenupdate.measure.survey import extract_test
from eigenupdate.solve.jacobian import solve_configurations

FRF_EXAMPLE = EXAMPLES / "paper_beam_frf"
N_CASES = 50
F_MAX = 1150.0  # three elastic modes of the beam below it
CLEAR_SNR = 30.0  # a mode whose peak alone is this many noise std high must be found


@pytest.fixture(scope="module")
def beam():
    study = load_study(FRF_EXAMPLE / "study.toml")
    truth = load_study(FRF_EXAMPLE / "truth.toml")
    configs = study.configurations[:3]  # base and two perturbations: enough per case
    sols = solve_configurations(truth.model, configs, 4)
    return study, configs, sols


def _modal_frf(sol, f, rows, etas, skip):
    """Receptance rows[0] / rows[1] from the exact modes, without mode ``skip``."""
    x = (2 * np.pi * f) ** 2
    h = np.zeros(f.size, complex)
    for r, lam in enumerate(sol.eigenvalues):
        if r + 1 == skip:
            continue
        phi = sol.modes[:, r]
        h += phi[rows[0]] * phi[rows[1]] / (lam * (1 + 1j * etas[r]) - x)
    return h


def _case(seed, beam):
    """FRFs of every configuration with artefacts; returns (frfs, spikes_hz, true_hz)."""
    study, configs, sols = beam
    rng = np.random.default_rng(seed)
    etas = rng.uniform(0.002, 0.02, 4)
    df = float(rng.choice([0.25, 0.5, 1.0, 2.0]))
    f = np.arange(df, F_MAX, df)
    skip = int(rng.choice([0, 0, 3]))  # a mode missing from every FRF in 1 case of 3
    mains = float(rng.choice([50.0, 60.0]))
    frfs, spikes, truth, snr = {}, {}, {}, {}
    for c, sol in zip(configs, sols, strict=True):
        idx = [study.model.index(k) for k in (11, 1, 15)]
        hs = [_modal_frf(sol, f, (idx[0], j), etas, skip) for j in idx[1:]]
        peak = max(np.abs(h).max() for h in hs)
        sigma = float(rng.uniform(0.002, 0.01)) * peak
        true_hz = [float(v) for k, v in enumerate(sol.frequencies_hz, 1) if k != skip]
        near = np.zeros(f.size, bool)  # lines within 3 half-power bandwidths of a mode
        for fr, eta in zip(sol.frequencies_hz, etas, strict=True):
            near |= np.abs(f - fr) < 3 * eta * fr + 2 * df
        # peak of each mode alone over the noise, best FRF (to check nothing clear is missed)
        snr[c.name] = {k + 1: max(abs(sol.modes[idx[0], k] * sol.modes[j, k])
                                  / (sol.eigenvalues[k] * etas[k]) for j in idx[1:]) / sigma
                       for k in range(len(sol.eigenvalues))
                       if k + 1 != skip and sol.frequencies_hz[k] < F_MAX - 20}
        out, where = [], []
        for h in hs:
            h = h + sigma / np.sqrt(2) * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size))
            free = np.flatnonzero(~near)
            for i in rng.choice(free, 4, replace=False):  # one-line spikes
                h[i] += rng.uniform(20, 100) * sigma * np.exp(2j * np.pi * rng.uniform())
                where.append(f[i])
            for k in range(1, int(F_MAX // mains)):  # mains harmonics
                fk = k * mains
                i = int(np.argmin(np.abs(f - fk)))
                if near[max(i - 2, 0):i + 3].any():
                    continue
                a = rng.uniform(20, 100) * sigma * np.exp(2j * np.pi * rng.uniform())
                if abs(f[i] - fk) < 1e-9:  # on a line
                    h[i] += a
                else:  # between lines: leaks into the neighbours (Hann main lobe)
                    for d, w in ((-1, 0.5), (0, 1.0), (1, 0.5)):
                        h[i + d] += w * a
                where.append(fk)
            # leakage ripple beside the strongest mode of this FRF
            p = int(np.argmax(np.abs(h)))
            for k in range(3, 16):
                for s in (-1, 1):
                    if 0 <= p + s * k < f.size:
                        h[p + s * k] += 8 * sigma * (-1) ** k / (k / 3) * np.exp(1j * 0.3)
            out.append(FRF(f, h, (11, 3), (1, 3)))
        frfs[c.name] = out
        spikes[c.name] = where
        truth[c.name] = true_hz
    return frfs, spikes, truth, df, skip, snr


def _check(seed, beam):
    study, configs, _ = beam
    frfs, spikes, truth, df, skip, snr = _case(seed, beam)
    res = extract_test(frfs, model=study.model, configurations=configs)
    assert res.numbered_by == "model"
    named = 0
    for ex in res.configurations:
        true_hz = truth[ex.configuration]
        for m in [*ex.modes, *ex.unexpected]:
            k = int(np.argmin([abs(m.frequency_hz - t) for t in true_hz]))
            err = abs(m.frequency_hz - true_hz[k])
            assert err < max(5 * m.std_hz, 1e-3 * true_hz[k]), (seed, ex.configuration, m)
            number = [j for j in range(1, 5) if j != skip][k]
            assert m.mode == number, (seed, ex.configuration, m.frequency_hz, m.mode, number)
        assert not ex.unexpected
        if skip:
            assert skip in [k for k, _ in ex.missing], (seed, ex.missing)
        # every mode standing clearly out of the noise is found; the others are reported
        found = {m.mode for m in ex.modes}
        clear = {k for k, v in snr[ex.configuration].items() if v > CLEAR_SNR}
        assert clear <= found, (seed, ex.configuration, snr[ex.configuration], found)
        assert set(snr[ex.configuration]) - found <= {k for k, _ in ex.missing}
        rejected = [r.frequency_hz for r in ex.rejected]
        named += sum(any(abs(r - s) <= 1.5 * df for r in rejected)
                     for s in spikes[ex.configuration])
    assert not res.problems, (seed, res.problems)
    return named, sum(len(v) for v in spikes.values())


def test_one_case_names_its_spikes(beam):
    named, total = _check(0, beam)
    assert named >= 0.5 * total  # the rejected list names the spikes (those picked as peaks)


@pytest.mark.slow
def test_no_spurious_or_misnumbered_mode_in_50_cases(beam):
    named = total = 0
    for seed in range(1, N_CASES + 1):
        n, t = _check(seed, beam)
        named, total = named + n, total + t
    print(f"{N_CASES} cases: {named} of {total} spikes/harmonics named in the rejected lists")
    assert named >= 0.5 * total



def _close_pair(seed, second):
    rng = np.random.default_rng(seed)
    f = np.arange(50.0, 160.0, 0.1)
    x = (2 * np.pi * f) ** 2
    h = sum(a / ((2 * np.pi * fr) ** 2 * (1 + 0.01j) - x) for fr, a in ((100, 1), (103, second)))
    sigma = 0.01 * np.abs(h).max()
    h += sigma / np.sqrt(2) * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size))
    spikes = rng.choice(np.flatnonzero((f < 95) | (f > 108)), 5, replace=False)
    h[spikes] += rng.uniform(20, 100, 5) * sigma
    return extract_test({"c": [FRF(f, h)]})


@pytest.mark.parametrize("seed", range(5))
def test_close_modes_both_found_spikes_not(seed):
    """Two modes 3 half-power bandwidths apart (100 and 103 Hz, eta = 0.01, an
    anti-resonance between them), 0.1 Hz lines, 1 % noise, 20-100 x noise spikes: both
    modes and nothing else, numbered by order."""
    res = _close_pair(seed, 0.8)
    (ex,) = res.configurations
    assert [m.mode for m in ex.modes] == [1, 2] and res.numbered_by == "order"
    for m, fr in zip(ex.modes, (100.0, 103.0), strict=True):
        assert abs(m.frequency_hz - fr) < 5 * m.std_hz, (m.frequency_hz, m.std_hz)
    assert len(ex.rejected) >= 4  # the spikes (two may share a band)


def test_merged_peaks_are_rejected_not_misread():
    """Opposite modal constants: no dip between the two modes, one peak. The single-mode
    fit cannot explain it, so it is rejected with that reason (and a study using these
    modes stops), rather than read as one mode with a wrong frequency."""
    (ex,) = _close_pair(0, -0.8).configurations
    assert not ex.modes
    assert any("one mode does not explain the band" in r.reason for r in ex.rejected)
