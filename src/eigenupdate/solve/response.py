"""Receptance FRFs predicted by a model, with hysteretic (structural) damping.

Conventions (the same as :mod:`eigenupdate.measure.frf`): harmonic time dependence
``exp(+i w t)``, ``w = 2 pi f``, receptance = displacement / force in m/N (rad/N,
m/(N m), rad/(N m) for rotational coordinates).

Two ways to compute the receptance matrix ``H(w)`` of a configuration with stiffness
``K`` and mass ``M`` (the model's matrices plus the configuration's additions):

* **direct**: ``H(w) = (K (1 + i eta) - w**2 M)**-1`` with one loss factor ``eta`` for
  the whole structure (hysteretic damping proportional to stiffness, so it applies to
  added grounded springs too);
* **modal superposition**::

      H_jk(w) = sum_r phi_jr phi_kr / (lambda_r (1 + i eta_r) - w**2)

  over mass-normalised modes, which allows one loss factor per mode. Rigid-body modes
  (``lambda_r = 0``, undamped) are always included: their term is
  ``-phi_jr phi_kr / w**2``. With all modes both methods give the same result; a
  truncated modal sum leaves out the (residual) flexibility of the higher modes.

At ``w = 0`` a structure with rigid-body modes has no static receptance: the result is
NaN there (not inf, so it can still be stored in an :class:`~eigenupdate.measure.frf.FRF`).
Start the frequency axis above 0 Hz to avoid it.

Coordinates are the user's 1-based numbers (:meth:`ParametricModel.index`); their node
and direction are in the model's :class:`~eigenupdate.model.coordinates.CoordinateTable`.
"""

from __future__ import annotations

import numbers
from collections.abc import Mapping, Sequence

import numpy as np
import scipy.linalg
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numpy.typing import ArrayLike

from eigenupdate.errors import InputError, SingularMatrixError
from eigenupdate.model.configurations import Configuration
from eigenupdate.model.parametric import ParametricModel
from eigenupdate.solve.eigen import DENSE_LIMIT, ShiftInvert, all_modes, base_operator, lowest_modes

__all__ = [
    "METHODS",
    "configuration_matrices",
    "receptance",
]

#: Accepted values of ``method`` in :func:`receptance`.
METHODS: tuple[str, str, str] = ("auto", "direct", "modal")

# Dense complex systems solved at once by the direct method: a bound on memory (bytes).
_BATCH_BYTES = 64 * 2**20
# The direct method uses dense LAPACK up to this size, or when more than this fraction
# of K and M is non-zero; sparse LU otherwise.
_DENSE_DIRECT = 64
_DENSE_FILL = 0.2


# -------------------------------------------------------------------------- matrices


def configuration_matrices(
    model: ParametricModel,
    configuration: Configuration | None = None,
    values: Sequence[float] | Mapping[str, float] | None = None,
) -> tuple[sp.csr_array, sp.csr_array]:
    """K and M of a configuration: the model at ``values`` plus the configuration's additions.

    ``values`` is a sequence in parameter order, a dict by parameter name (others keep
    their current value), or None for the model's current values.

    Examples
    --------
    >>> from eigenupdate.model.beam import beam_model
    >>> from eigenupdate.model.configurations import mass_at
    >>> model = beam_model([0.0, 0.4, 0.8], 4557.0, 3.4)
    >>> K, M = configuration_matrices(model, mass_at(1, 0.2))
    >>> print(f"{M[0, 0]:.4f} kg = {model.mass()[0, 0]:.4f} kg + 0.2 kg")
    0.7051 kg = 0.5051 kg + 0.2 kg
    """
    if isinstance(values, Mapping):
        model, values = model.with_values(dict(values)), None
    K, M = model.stiffness(values), model.mass(values)
    if configuration is not None and configuration.additions:
        dk, dm = configuration.delta(model)
        K, M = sp.csr_array(K + dk), sp.csr_array(M + dm)
    return K, M


# ------------------------------------------------------------------------ receptance


def receptance(
    model: ParametricModel,
    frequency_hz: ArrayLike,
    inputs: int | Sequence[int],
    outputs: int | Sequence[int],
    *,
    configuration: Configuration | None = None,
    values: Sequence[float] | Mapping[str, float] | None = None,
    loss_factor: float | Sequence[float] = 0.0,
    method: str = "auto",
    n_modes: int | None = None,
    static_correction: bool = True,
) -> np.ndarray:
    """Receptance (m/N) between input and output coordinates of a configuration.

    Parameters
    ----------
    model : ParametricModel
        The model; ``values`` (sequence in parameter order or dict by name) override its
        parameter values.
    frequency_hz : array_like
        Frequencies in Hz, finite and ``>= 0`` (any order). At 0 Hz the result is NaN
        if the structure has rigid-body modes (see the module notes).
    inputs, outputs : int or sequence of int
        User coordinate numbers of the force(s) and response(s).
    configuration : Configuration, optional
        Added masses/springs (the bare structure if None).
    loss_factor : float or sequence of float
        Hysteretic loss factor ``eta >= 0``: one for the whole structure, or one per
        elastic mode in ascending order (modes beyond the list take the last value;
        rigid-body modes are undamped). A list needs modal superposition; on a dense
        model, more values than elastic modes is an error.
    method : {"auto", "direct", "modal"}
        ``"direct"`` solves ``(K (1 + i eta) - w**2 M) x = f`` at every frequency
        (scalar loss factor only); ``"modal"`` sums modes. ``"auto"`` is direct for
        models with at most ``eigen.DENSE_LIMIT`` (400) coordinates, a scalar loss
        factor and no ``n_modes``, and modal otherwise.
    n_modes : int, optional
        Number of elastic modes in the modal sum (rigid-body modes are always added).
        Default: all modes for small models (dense eigen-solution, exact); for large
        models every mode up to at least twice the highest frequency asked for.
    static_correction : bool
        Add the static (residual) flexibility of the elastic modes left out of a
        truncated modal sum, ``sum phi phi^T / (lambda (1 + i eta))``. It makes a
        truncated sum exact at low frequency and removes most of the truncation error
        near anti-resonances. False gives the plain truncated sum.

    Returns
    -------
    ndarray, complex
        ``H[i, j, k] = x(outputs[j]) / f(inputs[k])`` at ``frequency_hz[i]``, shape
        ``(n_freq, n_outputs, n_inputs)``; the output axis is left out when ``outputs``
        is one integer, the input axis when ``inputs`` is: ``(n_freq, n_outputs)``
        for one input and several outputs, ``(n_freq,)`` for one of each.

    Notes
    -----
    Accuracy of the direct method: for a free structure the dynamic stiffness has a
    condition number of about ``lambda_max / w**2``, so far below the first elastic
    mode a direct solve loses digits (about 6e-10 relative for the paper's 18-coordinate
    beam at 2 Hz, but 1e-5 for a 400-coordinate beam at 5 Hz). The modal sum treats the
    rigid-body modes exactly and stays accurate there; prefer ``method="modal"`` for
    fine meshes of free structures at low frequency.

    Raises
    ------
    InputError
        Unknown coordinate, negative or non-finite frequency or loss factor, a
        per-mode loss factor with ``method="direct"``, or an undamped resonance hit
        exactly by the direct method.

    Examples
    --------
    A 2 kg mass on an 800 N/m spring (20 rad/s), loss factor 0.02, driven at 10 rad/s:
    ``H = 1 / (k (1 + i eta) - w**2 m) = 1 / (600 + 16 i)``.

    >>> import numpy as np
    >>> from eigenupdate.model.spring_mass import Mass, Spring, spring_mass_model
    >>> from eigenupdate.model.parameters import Parameter
    >>> sdof = spring_mass_model([Mass(Parameter("m", 2.0), 1)],
    ...                          [Spring(Parameter("k", 800.0), (0, 1))])
    >>> H = receptance(sdof, [10 / (2 * np.pi)], 1, 1, loss_factor=0.02)
    >>> print(f"{H[0]:.6e}, exact {1 / (600 + 16j):.6e}")
    1.665482e-03-4.441286e-05j, exact 1.665482e-03-4.441286e-05j

    The paper's beam, force at coordinate 11, responses at 1 and 15 (m/N), at 100 Hz and
    at the first elastic natural frequency (203.707 Hz), where the responses are in
    quadrature with the force:

    >>> from eigenupdate.model.beam import beam_model
    >>> from eigenupdate.model.parameters import Parameter
    >>> beam = beam_model([0, 0.09, 0.19, 0.29, 0.39, 0.49, 0.59, 0.69, 0.80], 4557.0, 3.4,
    ...                   point_masses=[(Parameter("m_L", 0.0), 11)])
    >>> H = receptance(beam, [100.0, 203.707], 11, [1, 15], loss_factor=0.01)
    >>> H.shape
    (2, 2)
    >>> print(np.array2string(abs(H), precision=3))
    [[8.254e-07 1.608e-06]
     [4.466e-05 1.642e-05]]
    >>> print(np.array2string(np.angle(H[1], deg=True), precision=1))
    [90.  91.2]
    """
    freq = np.atleast_1d(np.asarray(frequency_hz, dtype=float))
    if freq.ndim != 1:
        raise InputError(f"must be 1-D, got shape {freq.shape}", field="frequency_hz")
    if not np.all(np.isfinite(freq)) or np.any(freq < 0):
        raise InputError("frequencies must be finite and >= 0 Hz", field="frequency_hz")
    in_rows, in_scalar = _rows(model, inputs, "inputs")
    out_rows, out_scalar = _rows(model, outputs, "outputs")
    eta = _loss_factors(loss_factor)
    if method not in METHODS:
        raise InputError(f"unknown method {method!r} (expected one of {', '.join(METHODS)})",
                         field="method")
    if n_modes is not None and (not isinstance(n_modes, numbers.Integral) or n_modes < 1):
        raise InputError(f"n_modes must be an integer >= 1, got {n_modes!r}", field="n_modes")
    K, M = configuration_matrices(model, configuration, values)
    if method == "auto":
        small = K.shape[0] <= DENSE_LIMIT
        method = "direct" if small and eta.size == 1 and n_modes is None else "modal"
    if method == "direct":
        if eta.size > 1:
            raise InputError("a loss factor per mode needs method='modal'", field="loss_factor")
        if n_modes is not None:
            raise InputError("n_modes applies to method='modal' only", field="n_modes")
        H = _direct(K, M, freq, float(eta[0]), in_rows, out_rows)
    else:
        H = _modal(K, M, freq, eta, in_rows, out_rows, n_modes, static_correction)
    if in_scalar:
        H = H[:, :, 0]
    if out_scalar:
        H = H[:, 0]
    return H


def _rows(model: ParametricModel, coords, name: str) -> tuple[np.ndarray, bool]:
    scalar = np.ndim(coords) == 0
    values = np.atleast_1d(np.asarray(coords))
    if values.ndim != 1 or values.size == 0:
        raise InputError("expected a coordinate number or a non-empty list of them", field=name)
    rows = []
    for c in values.tolist():
        if not isinstance(c, numbers.Integral):
            raise InputError(f"coordinate {c!r} is not an integer", field=name)
        try:
            rows.append(model.index(int(c)))
        except InputError as exc:
            raise InputError(str(exc), field=name) from None
    return np.array(rows, dtype=int), scalar


def _loss_factors(loss_factor) -> np.ndarray:
    eta = np.atleast_1d(np.asarray(loss_factor, dtype=float))
    if eta.ndim != 1 or eta.size == 0:
        raise InputError("expected a number or a non-empty list", field="loss_factor")
    if not np.all(np.isfinite(eta)) or np.any(eta < 0):
        raise InputError(f"loss factors must be finite and >= 0, got {eta.tolist()}",
                         field="loss_factor")
    return eta


def _direct(K, M, freq, eta, in_rows, out_rows) -> np.ndarray:
    n = K.shape[0]
    H = np.full((freq.size, out_rows.size, in_rows.size), np.nan + 0j)
    w2 = (2 * np.pi * freq) ** 2
    todo = np.arange(freq.size)
    # K (1 + i eta) is singular for a free structure: no static receptance at 0 Hz.
    if np.any(w2 == 0) and _count_rigid(K, M) > 0:
        todo = todo[w2 != 0]
    B = np.zeros((n, in_rows.size))
    B[in_rows, np.arange(in_rows.size)] = 1.0
    Kc = (1 + 1j * eta) * K
    pattern = sp.csr_array(abs(K) + abs(M))
    if n <= _DENSE_DIRECT or pattern.nnz > _DENSE_FILL * n * n:
        # Small or full matrices: batched LAPACK solves, many frequencies per call.
        Kd, Md = Kc.toarray(), M.toarray()
        batch = max(1, _BATCH_BYTES // (16 * n * n))
        for start in range(0, todo.size, batch):
            idx = todo[start:start + batch]
            A = Kd[None, :, :] - w2[idx, None, None] * Md[None, :, :]
            try:
                X = np.linalg.solve(A, np.broadcast_to(B, (idx.size, n, in_rows.size)))
            except np.linalg.LinAlgError:
                X = np.stack([_solve_one(Kd - w2[i] * Md, B, freq[i]) for i in idx])
            H[idx] = X[:, out_rows, :]
    else:
        # Sparse (banded) FE matrices: a sparse LU per frequency is far cheaper than dense.
        Kc, Mc, Bc = sp.csc_array(Kc), sp.csc_array(M, dtype=complex), B.astype(complex)
        for i in todo:
            try:
                lu = spla.splu(sp.csc_array(Kc - w2[i] * Mc))
            except RuntimeError:
                raise _resonance_error(freq[i]) from None
            X = lu.solve(Bc)
            if not np.all(np.isfinite(X)):
                raise _resonance_error(freq[i])
            H[i] = X[out_rows, :]
    return H


def _solve_one(A: np.ndarray, B: np.ndarray, f: float) -> np.ndarray:
    try:
        return scipy.linalg.solve(A, B)
    except (np.linalg.LinAlgError, scipy.linalg.LinAlgError):
        raise _resonance_error(f) from None


def _resonance_error(f: float) -> SingularMatrixError:
    return SingularMatrixError(
        f"{f:g} Hz is an undamped natural frequency (singular dynamic stiffness); "
        "use a loss factor > 0 or move the frequency",
        field="frequency_hz",
    )


def _count_rigid(K, M) -> int:
    """Number of rigid-body modes of (K, M)."""
    if K.shape[0] <= DENSE_LIMIT:
        return int(all_modes(K, M)[2].sum())
    return int(lowest_modes(K, M, 7, _operator(K, M))[2].sum())


def _operator(K, M) -> ShiftInvert:
    return base_operator(K, M, 1)[0]


def _modal(K, M, freq, eta, in_rows, out_rows, n_modes, static_correction) -> np.ndarray:
    n = K.shape[0]
    op = None
    if n <= DENSE_LIMIT:
        lam, phi, rigid = all_modes(K, M)
    else:
        op = _operator(K, M)
        lam, phi, rigid = _sparse_modes(K, M, op, n_modes, 2 * np.pi * float(freq.max()))
    el_all = np.flatnonzero(~rigid)
    if op is None and eta.size > max(el_all.size, 1):  # all modes known: a surplus is a mistake
        raise InputError(f"{eta.size} loss factors given but the model has only {el_all.size} "
                         "elastic modes", field="loss_factor")
    el = el_all
    if n_modes is not None:
        if n_modes > el_all.size:
            raise InputError(f"{n_modes} modes requested but only {el_all.size} elastic modes "
                             "are available", field="n_modes")
        el = el_all[:n_modes]
    rg = np.flatnonzero(rigid)
    use = np.concatenate([rg, el])
    lam_use = np.concatenate([np.zeros(rg.size), lam[el]])  # rigid: lambda = 0 exactly
    eta_use = np.concatenate([np.zeros(rg.size), _per_mode(eta, 0, el.size)])
    # Modal constants phi_jr phi_kr for every (output, input) pair, then the sum over r.
    consts = phi[out_rows][:, None, use] * phi[in_rows][None, :, use]  # (n_out, n_in, modes)
    w2 = (2 * np.pi * freq) ** 2
    with np.errstate(divide="ignore", invalid="ignore"):
        denom = 1.0 / (lam_use * (1 + 1j * eta_use) - w2[:, None])  # (n_freq, modes)
    H = np.einsum("fr,jkr->fjk", denom[:, rg.size:], consts[:, :, rg.size:])
    if rg.size:
        H = H + np.einsum("fr,jkr->fjk", denom[:, :rg.size].real, consts[:, :, :rg.size])
        H[w2 == 0] = np.nan  # the rigid-body term -phi phi / w^2 is infinite at 0 Hz
    if static_correction:
        H = H + _residual_flexibility(K, M, lam, phi, use, el.size, el_all, eta, op,
                                      in_rows, out_rows)
    return H


def _per_mode(eta: np.ndarray, start: int, stop: int) -> np.ndarray:
    """Loss factors of elastic modes start..stop-1; beyond the list the last value."""
    return eta[np.minimum(np.arange(start, stop), eta.size - 1)]


def _residual_flexibility(K, M, lam, phi, use, n_used, el_all, eta, op, in_rows, out_rows):
    """Static flexibility of the elastic modes left out of the modal sum (0 if none).

    Far below their natural frequencies the omitted modes respond quasi-statically,
    ``phi phi^T / (lambda (1 + i eta))``. A dense solution has all of them. On the
    sparse path they were not computed: the flexibility is ``(K - sigma M)^-1`` applied
    to the force with the used modes projected out (sigma is tiny, so
    ``1 / (lambda - sigma) = 1 / lambda``), and takes the loss factor of the first
    omitted mode.
    """
    if op is None:
        omitted = el_all[n_used:]
        if omitted.size == 0:
            return 0.0
        eta_om = _per_mode(eta, n_used, el_all.size)
        weight = 1.0 / (lam[omitted] * (1 + 1j * eta_om))
        return np.einsum("jr,kr,r->jk", phi[out_rows][:, omitted], phi[in_rows][:, omitted],
                         weight)
    n = K.shape[0]
    if use.size >= n:
        return 0.0
    B = np.zeros((n, in_rows.size))
    B[in_rows, np.arange(in_rows.size)] = 1.0
    Phi = phi[:, use]
    B = B - M @ (Phi @ (Phi.T @ B))  # M-orthogonal projection: the omitted modes' part
    X = np.column_stack([op.solve(b) for b in B.T])
    X = X - Phi @ (Phi.T @ (M @ X))  # drop round-off along the used (incl. rigid) modes
    eta_om = float(_per_mode(eta, n_used, n_used + 1)[0])
    return X[out_rows, :] / (1 + 1j * eta_om)


def _sparse_modes(K, M, op, n_modes, w_max) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    n = K.shape[0]
    k = min(n - 1, (n_modes + 7) if n_modes is not None else 20)
    while True:
        lam, phi, rigid = lowest_modes(K, M, k, op)
        n_el = int((~rigid).sum())
        if n_modes is not None:
            done = n_el >= n_modes
        else:  # every mode up to at least twice the highest frequency
            done = n_el > 0 and lam[-1] >= (2 * w_max) ** 2
        if done or k == n - 1:
            return lam, phi, rigid
        k = min(n - 1, 2 * k)
