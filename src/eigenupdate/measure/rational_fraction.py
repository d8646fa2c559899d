"""Global multi-mode fit of a receptance FRF: a rational fraction in ``x = w**2``.

A cross-check for the band-by-band :mod:`eigenupdate.measure.dobson` fits.  With hysteretic
damping every mode is a simple pole in ``x = w**2``::

    alpha(x) = sum_r A_r / (P_r - x) + R0 + R1 x - A0 / x,     P_r = w_r**2 (1 + i eta_r)

so the receptance over a wide band is a rational function of ``x`` with complex
coefficients.  ``R0 + R1 x`` models the modes above the band, ``-A0 / x`` rigid-body
modes (or modes far below the band).  The fit runs in three steps, all in the scaled
variable ``u = (x - x_c) / x_h`` that maps the band onto [-1, 1]:

1. poles by vector fitting (Gustavsen & Semlyen 1999: iterated linear least squares
   with pole relocation, i.e. a Sanathanan-Koerner iteration on the partial-fraction
   form, which is far better conditioned than a power-series rational fraction);
2. modal constants and residual terms by linear least squares with the poles fixed
   (least-squares frequency domain, LSFD);
3. a nonlinear least-squares refinement of all parameters together
   (:func:`scipy.optimize.least_squares`), which is the maximum-likelihood estimate
   for white noise on ``alpha``.  Its Jacobian gives the parameter covariance, scaled
   by the residual noise level, and so the standard deviations.

Limits: the number of modes in the band must be given; if ``n_modes`` is too large the
spare pole lands outside the band or is undamped (an :class:`InputError` from
:func:`rational_fraction_fit`, a ``NoResonance`` status from
:func:`rational_fraction_status`).  A mode just above the band is only approximated
by ``R0 + R1 x``: for the beam-like test case (a mode 11 % above the band edge) the
in-band frequencies are biased by < 2e-6 relative, but the bias grows as the mode gets
closer; end the band well below such a mode.
Unlike :mod:`eigenupdate.measure.dobson` it separates modes closer than their bandwidth.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares
from scipy.signal import find_peaks

from eigenupdate.errors import InputError
from eigenupdate.measure.modal_fit import ModalFit, NoResonance, select_band
from eigenupdate.measure.peaks import estimate_noise_std

__all__ = ["rational_fraction_fit", "rational_fraction_status"]

_VF_MAX_ITERATIONS = 40
_VF_TOLERANCE = 1e-11
#: Normal equations up to this condition number (relative error ~1e-6 at worst).
_MAX_COND_NORMAL_EQUATIONS = 1e10
#: Loss factor assumed for the starting poles.
_START_LOSS_FACTOR = 0.01


@dataclass(frozen=True)
class _Model:
    """Partial-fraction model in ``u``: ``sum amps / (poles - u) + basis @ coefs``."""

    poles: np.ndarray
    amps: np.ndarray
    coefs: np.ndarray


def rational_fraction_fit(frequency_hz: np.ndarray, receptance: np.ndarray,
                          band_hz: tuple[float, float], n_modes: int,
                          **options: bool | str | None) -> list[ModalFit]:
    """Fit ``n_modes`` hysteretically damped modes at once over ``band_hz``.

    Parameters
    ----------
    frequency_hz : ndarray
        Frequency axis in Hz, strictly increasing.
    receptance : ndarray
        Complex receptance in m/N at ``frequency_hz``.
    band_hz : tuple of float
        ``(low, high)`` band in Hz; it must lie above 0 Hz.
    n_modes : int
        Number of modes in the band.
    **options
        Keywords of :func:`rational_fraction_status`:
    lower_residual : bool, optional
        Fit a ``-A0 / w**2`` term (rigid-body modes, modes far below the band).
    upper_residual : bool, optional
        Fit ``R0 + R1 w**2`` (modes above the band).
    source : str, optional
        Name of the data source, used in error messages.

    Returns
    -------
    list of ModalFit
        One fit per mode, in increasing frequency, with ``method="rfp"``.

    Raises
    ------
    InputError
        If the arrays are malformed, the band has too few points for the model, or
        the fit gives a pole that is not a damped resonance.

    Examples
    --------
    >>> import numpy as np
    >>> f = np.arange(20.0, 400.0, 0.5)
    >>> x = (2 * np.pi * f) ** 2
    >>> alpha = sum(1.0 / ((2 * np.pi * fr) ** 2 * (1 + 0.01j) - x) for fr in (100.0, 250.0))
    >>> fits = rational_fraction_fit(f, alpha - 1.0 / x, (20.0, 400.0), n_modes=2)
    >>> print([f"{fit.frequency_hz:.6f} Hz, eta = {fit.loss_factor:.6f}" for fit in fits])
    ['100.000000 Hz, eta = 0.010000', '250.000000 Hz, eta = 0.010000']
    """
    fits = rational_fraction_status(frequency_hz, receptance, band_hz, n_modes, **options)
    if isinstance(fits, NoResonance):
        raise InputError(fits.message, source=options.get("source"), field="band_hz")
    return fits


def rational_fraction_status(
    frequency_hz: np.ndarray,
    receptance: np.ndarray,
    band_hz: tuple[float, float],
    n_modes: int,
    *,
    lower_residual: bool = True,
    upper_residual: bool = True,
    source: str | None = None,
) -> list[ModalFit] | NoResonance:
    """:func:`rational_fraction_fit`, with a :class:`NoResonance` status instead of an
    error when the data do not hold ``n_modes`` damped resonances (or too few points).

    >>> import numpy as np
    >>> f = np.arange(20.0, 400.0, 0.5)
    >>> alpha = 1.0 / ((2 * np.pi * 100.0) ** 2 * (1 + 0.01j) - (2 * np.pi * f) ** 2)
    >>> rational_fraction_status(f, alpha, (90.0, 95.0), n_modes=2).message
    'band (90, 95) Hz has 11 points, too few for 2 modes and the residual terms'
    """
    if int(n_modes) != n_modes or n_modes < 1:
        raise InputError(f"n_modes must be a positive integer, got {n_modes}",
                         source=source, field="n_modes")
    n_modes = int(n_modes)
    f_band, a_band = select_band(frequency_hz, receptance, band_hz, source)
    band = (float(band_hz[0]), float(band_hz[1]))
    x = (2.0 * np.pi * f_band) ** 2
    x_c, x_h = 0.5 * (x[0] + x[-1]), 0.5 * (x[-1] - x[0])
    u = (x - x_c) / x_h
    basis = _residual_basis(u, -x_c / x_h, lower_residual, upper_residual)
    n_par = 4 * n_modes + 2 * basis.shape[1]
    if u.size < n_par:  # 2 * u.size real data: at least twice the parameter count
        return NoResonance(band, f"band ({band[0]:g}, {band[1]:g}) Hz has {u.size} points, "
                                 f"too few for {n_modes} modes and the residual terms")

    poles = _vector_fit(u, a_band, basis, _start_poles(u, a_band, x_c, x_h, n_modes))
    model = _lsfd(u, a_band, basis, poles)
    model, cov = _refine(u, a_band, basis, model)
    fits = [_to_modal_fit(model, cov, i, x_c, x_h, band) for i in range(n_modes)]
    failed = next((fit for fit in fits if isinstance(fit, NoResonance)), None)
    return failed or sorted(fits, key=lambda fit: fit.frequency_hz)


def _residual_basis(u: np.ndarray, u_zero: float, lower: bool, upper: bool) -> np.ndarray:
    """Columns of the residual terms: ``1/(u - u(x=0))``, ``1``, ``u``."""
    cols = []
    if lower:
        cols.append(1.0 / (u - u_zero))
    if upper:
        cols += [np.ones_like(u), u]
    return np.array(cols, dtype=complex).T.reshape(u.size, len(cols))


def _start_poles(u: np.ndarray, alpha: np.ndarray, x_c: float, x_h: float,
                 n_modes: int) -> np.ndarray:
    """Starting poles at the most prominent peaks of ``|alpha|``, else spread evenly."""
    # Log scale over a noise floor, so that noise in anti-resonances is not prominent.
    floor = 3.0 * estimate_noise_std(alpha)
    level = np.log(np.abs(alpha) ** 2 + floor**2 + np.finfo(float).tiny)
    peaks, props = find_peaks(level, prominence=0.0)
    best = peaks[np.argsort(props["prominences"])[::-1][:n_modes]]
    re = list(u[np.sort(best)])
    spread = np.linspace(-1.0, 1.0, n_modes + 2)[1:-1]
    re += list(spread[len(re):])
    re = np.array(re[:n_modes])
    # Im of a pole in u for loss factor eta: eta * x / x_h (kept clear of zero).
    im = np.maximum(_START_LOSS_FACTOR * (x_c + x_h * re) / x_h, 1e-6)
    return re + 1j * im


def _vector_fit(u: np.ndarray, alpha: np.ndarray, basis: np.ndarray,
                poles: np.ndarray) -> np.ndarray:
    """Relocate the poles by vector fitting until they settle."""
    n = poles.size
    for _ in range(_VF_MAX_ITERATIONS):
        phi = 1.0 / (u[:, None] - poles[None, :])
        # alpha * (1 + sum ct/(u - a)) ~ sum c/(u - a) + residual terms
        mat = np.hstack([phi, basis, -alpha[:, None] * phi])
        sol = _lstsq_scaled(mat, alpha)
        sigma_res = sol[-n:]
        new = np.linalg.eigvals(np.diag(poles) - np.outer(np.ones(n), sigma_res))
        new = np.where(new.imag < 0, new.conj(), new)  # keep damping positive
        new = np.sort_complex(new)
        shift = np.max(np.abs(new - poles))
        poles = new
        if shift < _VF_TOLERANCE:
            break
    return poles


def _lstsq_scaled(mat: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """Least squares with unit-norm columns (the columns differ by many decades).

    The partial-fraction matrices are tall, skinny and well conditioned (condition
    numbers of 3..300 in the tests), and these solutions only start the nonlinear
    refinement, so the normal equations are accurate enough.  Formed with ``einsum``
    they avoid multithreaded BLAS, which is many times slower on such matrices when
    other processes load the cores.  LAPACK's ``lstsq`` takes over when the matrix is
    ill-conditioned.
    """
    norms = np.linalg.norm(mat, axis=0)
    norms[norms == 0] = 1.0
    a = mat / norms
    gram = np.einsum("ki,kj->ij", a.conj(), a)
    if np.linalg.cond(gram) < _MAX_COND_NORMAL_EQUATIONS:
        sol = np.linalg.solve(gram, np.einsum("ki,k->i", a.conj(), rhs))
    else:
        sol, *_ = np.linalg.lstsq(a, rhs, rcond=None)
    return sol / norms


def _lsfd(u: np.ndarray, alpha: np.ndarray, basis: np.ndarray,
          poles: np.ndarray) -> _Model:
    """Modal constants and residual coefficients for fixed poles (linear LS)."""
    mat = np.hstack([1.0 / (poles[None, :] - u[:, None]), basis])
    sol = _lstsq_scaled(mat, alpha)
    return _Model(poles=poles, amps=sol[:poles.size], coefs=sol[poles.size:])


def _pack(model: _Model) -> np.ndarray:
    z = np.concatenate([model.poles, model.amps, model.coefs])
    return np.concatenate([z.real, z.imag])


def _unpack(params: np.ndarray, n_modes: int) -> _Model:
    half = params.size // 2
    z = params[:half] + 1j * params[half:]
    return _Model(poles=z[:n_modes], amps=z[n_modes:2 * n_modes], coefs=z[2 * n_modes:])


def _refine(u: np.ndarray, alpha: np.ndarray, basis: np.ndarray,
            start: _Model) -> tuple[_Model, np.ndarray]:
    """Nonlinear LS on all parameters; returns the model and its covariance."""
    n = start.poles.size

    def complex_jac(params: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        m = _unpack(params, n)
        phi = 1.0 / (m.poles[None, :] - u[:, None])
        # Element-wise sums: skinny BLAS products are slow when BLAS threads compete.
        resid = (phi * m.amps).sum(axis=1) + (basis * m.coefs).sum(axis=1) - alpha
        # d/d pole = -amp * phi**2, d/d amp = phi, d/d coef = basis (holomorphic)
        return resid, np.hstack([-m.amps * phi**2, phi, basis])

    def fun(params: np.ndarray) -> np.ndarray:
        resid, _ = complex_jac(params)
        return np.concatenate([resid.real, resid.imag])

    def jac(params: np.ndarray) -> np.ndarray:
        _, jz = complex_jac(params)
        # Real parameters (Re z, Im z); d/d Im z = 1j * d/d z.
        return np.block([[jz.real, -jz.imag], [jz.imag, jz.real]])

    sol = least_squares(fun, _pack(start), jac=jac, method="lm", x_scale="jac",
                        xtol=1e-12, ftol=1e-12, gtol=1e-12, max_nfev=200)
    dof = max(sol.fun.size - sol.x.size, 1)
    noise_var = float(sol.fun @ sol.fun) / dof
    scale = np.linalg.norm(sol.jac, axis=0)
    scale[scale == 0] = 1.0
    jmat = sol.jac / scale  # unit columns: the normal matrix is well conditioned
    cov = np.linalg.pinv(np.einsum("ki,kj->ij", jmat, jmat)) / np.outer(scale, scale)
    return _unpack(sol.x, n), cov * noise_var


def _to_modal_fit(model: _Model, cov: np.ndarray, i: int, x_c: float, x_h: float,
                  band: tuple[float, float]) -> ModalFit | NoResonance:
    """Mode ``i`` in physical units, with standard deviations from ``cov``."""
    pole = x_c + x_h * model.poles[i]
    wr2 = pole.real
    if wr2 <= 0.0 or pole.imag <= 0.0:
        return NoResonance(band, f"band ({band[0]:g}, {band[1]:g}) Hz: fitted pole {i + 1} "
                                 "is not a damped resonance; try fewer modes or another band")
    half = cov.shape[0] // 2
    idx = [i, half + i]  # Re and Im of pole i in the parameter vector
    cov_pole = cov[np.ix_(idx, idx)] * x_h**2  # covariance of (Re P, Im P)
    wr = np.sqrt(wr2)
    eta = pole.imag / wr2
    grad_eta = np.array([-pole.imag / wr2**2, 1.0 / wr2])
    return ModalFit(
        frequency_hz=float(wr / (2.0 * np.pi)),
        loss_factor=float(eta),
        modal_constant=complex(model.amps[i] * x_h),
        frequency_std_hz=float(np.sqrt(cov_pole[0, 0]) / (2.0 * wr) / (2.0 * np.pi)),
        loss_factor_std=float(np.sqrt(grad_eta @ cov_pole @ grad_eta)),
        band_hz=band,
        method="rfp",
    )
