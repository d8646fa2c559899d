"""Synthetic "measured" FRFs: model receptances with complex Gaussian noise.

Used to exercise the modal-extraction and updating chain without a test rig: predict
the receptance of a configuration with :func:`eigenupdate.solve.response.receptance`, add noise,
and label every FRF with the universal-file points of the model's coordinate table.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
from numpy.typing import ArrayLike

from eigenupdate.errors import InputError
from eigenupdate.measure.frf import FRF
from eigenupdate.measure.measurement import Measurement
from eigenupdate.model.configurations import Configuration
from eigenupdate.model.parametric import ParametricModel
from eigenupdate.solve.jacobian import solve_configurations
from eigenupdate.solve.response import receptance

__all__ = ["PEAK_BAND_FRACTION", "noise_reference", "simulate_measurements", "synthetic_frfs"]

#: The noise reference peak is taken above this fraction of the highest frequency.
PEAK_BAND_FRACTION = 0.05


def noise_reference(frequency_hz: ArrayLike, values: ArrayLike) -> float:
    """Largest ``|H|`` above ``PEAK_BAND_FRACTION`` (5 %) of the highest frequency.

    For a free structure ``|H|`` grows like ``1 / w**2`` towards 0 Hz (rigid-body
    modes); the lowest 5 % of the band is left out so the reference is the largest
    resonance peak, not that singularity. Non-finite values (the NaN at 0 Hz) are
    ignored.

    Examples
    --------
    >>> import numpy as np
    >>> f = np.array([0.0, 1.0, 50.0, 100.0])
    >>> print(noise_reference(f, [np.nan, 1e3, 2e-6, 5e-7]))   # 1 Hz is below 5 Hz
    2e-06
    """
    freq = np.asarray(frequency_hz, dtype=float)
    mag = np.abs(np.asarray(values, dtype=complex))
    keep = (freq >= PEAK_BAND_FRACTION * freq.max()) & np.isfinite(mag)
    if not keep.any():
        keep = np.isfinite(mag)
    return float(mag[keep].max()) if keep.any() else 0.0


def synthetic_frfs(
    model: ParametricModel,
    configuration: Configuration | None,
    frequency_hz: ArrayLike,
    excitation: int,
    outputs: int | Sequence[int],
    loss_factor: float | Sequence[float],
    noise: float = 0.01,
    seed: int | np.random.Generator | None = None,
    *,
    values: Sequence[float] | Mapping[str, float] | None = None,
) -> list[FRF]:
    """Receptance FRFs of a configuration with added complex Gaussian noise.

    Parameters
    ----------
    model : ParametricModel
        The "true" structure (``values`` override its parameter values).
    configuration : Configuration or None
        Added masses/springs; None for the bare structure.
    frequency_hz : array_like
        Strictly increasing frequency axis in Hz, ``>= 0``. At 0 Hz a free structure
        has no receptance: that line is NaN (the FRF type allows it).
    excitation : int
        Coordinate of the force.
    outputs : int or sequence of int
        Response coordinates, one FRF each.
    loss_factor : float or sequence of float
        Hysteretic loss factor, one for all modes or one per elastic mode
        (see :func:`eigenupdate.solve.response.receptance`).
    noise : float
        Standard deviation of the noise, ``sqrt(E |n|**2)``, as a fraction of each
        FRF's own largest peak ``max |H|`` above 5 % of the band
        (:func:`noise_reference`). Real and imaginary parts are independent, each with
        standard deviation ``noise * peak / sqrt(2)``, the same at every frequency.
    seed : int, Generator or None
        Random seed (reproducible noise) or a NumPy Generator.

    Returns
    -------
    list of FRF
        One per output, in order; ``response`` and ``reference`` are the UFF points
        of the output and excitation coordinates (``model.coordinate_table``),
        ``source`` says where it came from.

    Examples
    --------
    The paper's beam driven at coordinate 11 (node 6, +Z), responses at the two ends:

    >>> import numpy as np
    >>> from eigenupdate.model.beam import beam_model
    >>> beam = beam_model([0, 0.09, 0.19, 0.29, 0.39, 0.49, 0.59, 0.69, 0.80], 4557.0, 3.4)
    >>> f = np.arange(2.0, 1600.0 + 1.0, 2.0)
    >>> frfs = synthetic_frfs(beam, None, f, 11, [1, 17], 0.01, noise=0.0)
    >>> frfs[0]
    FRF(n=800, 2..1600 Hz, response=1+Z, reference=6+Z, source='synthetic base: 1/11')
    >>> h, above = frfs[1].receptance, f >= 80.0
    >>> peak_hz = f[above][np.argmax(abs(h[above]))]
    >>> print(f"noise reference {noise_reference(f, h):.3e} m/N, the peak at {peak_hz:g} Hz")
    noise reference 4.281e-05 m/N, the peak at 204 Hz
    """
    freq = np.asarray(frequency_hz, dtype=float)
    if not (np.isfinite(noise) and noise >= 0):
        raise InputError(f"noise must be a finite fraction >= 0, got {noise!r}", field="noise")
    outs = [outputs] if np.ndim(outputs) == 0 else list(outputs)
    table = model.coordinate_table
    reference = table[excitation].uff_point
    points = [table[c].uff_point for c in outs]
    H = receptance(model, freq, excitation, outs, configuration=configuration, values=values,
                   loss_factor=loss_factor)
    H = H.reshape(freq.size, len(outs))
    rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
    name = configuration.name if configuration is not None else "base"
    out = []
    for j, (c, point) in enumerate(zip(outs, points, strict=True)):
        h = H[:, j]
        if noise > 0:
            scale = noise * noise_reference(freq, h) / np.sqrt(2.0)
            h = h + scale * (rng.standard_normal(freq.size) + 1j * rng.standard_normal(freq.size))
        out.append(FRF(freq, h, point, reference, source=f"synthetic {name}: {c}/{excitation}"))
    return out


def simulate_measurements(
    model: ParametricModel,
    configurations: Sequence[Configuration],
    modes: Sequence[int],
    *,
    noise_hz: float = 0.0,
    std_hz: float | None = None,
    seed: int | np.random.Generator | None = None,
    noise_relative: float = 0.0,
) -> list[Measurement]:
    """The natural frequencies the model (taken as the truth) gives, with Gaussian noise.

    Parameters
    ----------
    noise_hz : standard deviation (Hz) of the noise added to every frequency.
    std_hz : the std recorded with each frequency; default the noise level (None if 0).
    seed : random seed or Generator.
    noise_relative : standard deviation of a further noise as a fraction of each
        frequency (0.001: 0.1 %); the two add in quadrature, and the default recorded std
        is that sum, frequency by frequency.

    Examples
    --------
    >>> from eigenupdate.model.parameters import Parameter
    >>> from eigenupdate.model.spring_mass import Mass, Spring, spring_mass_model
    >>> from eigenupdate.model.configurations import Configuration, mass_at
    >>> model = spring_mass_model([Mass(Parameter("m", 2.0), 1)],
    ...                           [Spring(Parameter("k", 800.0), (0, 1))])
    >>> rows = simulate_measurements(model, [Configuration("base"), mass_at(1, 2.0)], [1])
    >>> [(m.configuration, round(m.frequency_hz, 6)) for m in rows]   # sqrt(k/m) / 2 pi
    [('base', 3.183099), ('2 kg at 1', 2.250791)]
    """
    if not (np.isfinite(noise_hz) and noise_hz >= 0):
        raise InputError(f"{noise_hz!r} must be a finite number >= 0", field="--noise-hz")
    if std_hz is not None and not (np.isfinite(std_hz) and std_hz > 0):
        raise InputError(f"{std_hz!r} must be a finite number > 0", field="--std-hz")
    if not (np.isfinite(noise_relative) and 0 <= noise_relative < 0.5):
        raise InputError(f"{noise_relative!r} must be a fraction >= 0 and < 0.5",
                         field="--noise-relative")
    sols = solve_configurations(model, configurations, max(modes))
    rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
    rows = []
    for c, s in zip(configurations, sols, strict=True):
        for k in modes:
            f = float(s.frequencies_hz[k - 1])
            sd = float(np.hypot(noise_hz, noise_relative * f))
            if sd > 0:
                f += float(rng.normal(0.0, sd))
                if f <= 0:
                    raise InputError(f"noise of {sd:g} Hz made the frequency of "
                                     f"{c.name!r} mode {k} negative; use less noise",
                                     field="--noise-hz")
            rows.append(Measurement(c.name, k, f, std_hz if std_hz is not None else
                                    (sd or None)))
    return rows
