"""Mode shapes from the FRFs' modal constants, and pairing of measured modes by MAC.

With one reference coordinate q, the modal constant of mode r in the FRF of response j is
A_r(j) = phi_j phi_q (mass-normalised shapes, receptance; Ewins, Modal Testing, 2nd ed.,
Sec. 2.6), so the Dobson fits of a configuration's FRFs give mode r's shape at the response
coordinates up to the factor phi_q: enough for the modal assurance criterion

    MAC(a, b) = |a^T b|^2 / ((a^T a) (b^T b)),

which is blind to scale and sign (Allemang, Sound and Vibration 37(8), 2003). Lightly
damped modes have modal constants of one phase; each shape is rotated by the phase of its
largest constant and its real part kept.

:func:`shape_pairing` compares the shape of every numbered resonance of a configuration
with the initial model's modes of that configuration at the measured coordinates: a
resonance numbered k (by frequency, as updating pairs them) whose shape is the model's
mode j != k means the test and the model order modes k and j differly, e.g. an added mass
moves them across each other in the structure but not in the model (or the other way
round). The update, pairing by order, would then fit mode k's frequency with the
sensitivities of the wrong shape: this is a mode exchange, caught before any fit and
without refits. Each perturbed configuration's shapes are also set against the bare
structure's, naming which bare mode each measured mode is (the crossing itself).
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from eigenupdate.errors import InputError
from eigenupdate.measure.frf import FRF
from eigenupdate.model.configurations import Configuration
from eigenupdate.model.parametric import ParametricModel

MAC_SAME = 0.8
"""A measured shape is taken as a model mode when their MAC reaches this. Well-separated
modes of a good model give MAC > 0.9 (Allemang 2003); near a crossing the initial
model's two modes mix (0.86 in the test of two weakly coupled oscillators), hence 0.8."""
MAC_MARGIN = 0.2
"""... and exceeds the MAC with the mode of its own number by this much: close to a
crossing, two modes mix and both MACs are middling, which says nothing."""
MIN_POINTS = 3
"""Fewest response coordinates a MAC is computed over (with two, any two shapes
give MAC 1 up to the choice of sign in a plane)."""


@dataclass(frozen=True)
class MeasuredShape:
    """Shape of one numbered resonance at the response points of one reference."""

    configuration: str
    mode: int
    frequency_hz: float
    points: tuple[tuple[int, int], ...]
    shape: np.ndarray


def measured_shape(configuration: str, mode: int, frequency_hz: float,
                   fits: Sequence, frfs: Sequence[FRF]) -> MeasuredShape | None:
    """The shape of a resonance from its per-FRF fits (``fits[i]`` of ``frfs[i]``, None
    where that FRF showed no accepted peak), at the responses of the most common
    reference among the fits; None with fewer than :data:`MIN_POINTS` responses or fewer
    than 2 fits. A response whose FRF shows no accepted peak of this mode counts as 0:
    the mode is too weak there to be seen above the others (near a node).

    >>> from eigenupdate.measure.modal_fit import ModalFit
    >>> f = np.array([1.0, 2.0])
    >>> frfs = [FRF(f, f + 0j, (p, 3), (1, 3)) for p in (1, 2, 3, 4)]
    >>> fits = [ModalFit(10.0, 0.01, a * (1 + 1j), 0.1, 0.0, (9, 11), "dobson")
    ...         for a in (2.0, -1.0, 0.5)] + [None]
    >>> s = measured_shape("base", 1, 10.0, fits, frfs)
    >>> s.points, np.round(s.shape / s.shape[0], 6).tolist()
    (((1, 3), (2, 3), (3, 3), (4, 3)), [1.0, -0.5, 0.25, 0.0])
    """
    have = [x.reference for x, fit in zip(frfs, fits, strict=True) if fit is not None]
    if len(have) < 2:
        return None
    ref = Counter(have).most_common(1)[0][0]
    pts, a = [], []
    for x, fit in zip(frfs, fits, strict=True):
        if x.reference == ref and x.response not in pts:
            pts.append(x.response)  # a response in a negative direction has its sign turned
            a.append(0.0 if fit is None else
                     np.sign(x.response[1]) * complex(fit.modal_constant))
    if len(pts) < MIN_POINTS:
        return None
    a = np.array(a, dtype=complex)
    phase = np.angle(a[np.argmax(np.abs(a))])
    return MeasuredShape(configuration, mode, frequency_hz, tuple(pts),
                         np.real(a * np.exp(-1j * phase)))


def mac(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """MAC of every column of ``a`` with every column of ``b`` (vectors: one value).

    >>> float(mac(np.array([1.0, 2.0]), np.array([-2.0, -4.0])))
    1.0
    """
    a2, b2 = np.atleast_2d(a.T).T, np.atleast_2d(b.T).T
    num = np.abs(a2.T @ b2) ** 2
    den = np.outer(np.sum(a2 * a2, axis=0), np.sum(b2 * b2, axis=0))
    out = np.divide(num, den, out=np.zeros_like(num), where=den > 0)
    return out if a.ndim > 1 or b.ndim > 1 else out[0, 0]


@dataclass(frozen=True)
class ShapePairing:
    """Outcome of :func:`shape_pairing`.

    ``problems``: one line per resonance whose shape is another model mode's (a mode
    exchange); ``notes``: which bare mode each perturbed mode is where that differs from
    its number (a crossing the model also has is no problem); ``mac``: by configuration,
    (numbered modes, model modes) MAC matrix over the measured points."""

    problems: list[str]
    notes: list[str]
    mac: dict[str, np.ndarray]


def _model_rows(model: ParametricModel, points: Sequence[tuple[int, int]]
                ) -> tuple[list[int] | None, list[tuple[int, int]]]:
    """Model rows of the measured points; None and the points the model does not have
    (no comparison then)."""
    table = model.coordinate_table
    rows, absent = [], []
    for node, direction in points:
        try:
            c = table.from_uff((node, abs(direction)))
        except InputError:
            absent.append((node, direction))
            continue
        rows.append(model.index(c.number))
    return (None if absent else rows), absent


def shape_pairing(shapes: dict[str, list[MeasuredShape]], model: ParametricModel,
                  configurations: Sequence[Configuration]) -> ShapePairing:
    """Compare measured shapes with the initial model's modes and with the bare
    structure's measured shapes (see the module)."""
    from eigenupdate.solve.jacobian import solve_configurations

    configs = [c for c in configurations if shapes.get(c.name)]
    problems: list[str] = []
    notes: list[str] = []
    macs: dict[str, np.ndarray] = {}
    if not configs:
        return ShapePairing(problems, notes, macs)
    top = max(s.mode for c in configs for s in shapes[c.name])
    n = min(top + 2, model.n)
    sols = solve_configurations(model, configs, n)
    bare = next((shapes[c.name] for c in configs if not c.additions), None)
    for c, sol in zip(configs, sols, strict=True):
        these = sorted(shapes[c.name], key=lambda s: s.mode)
        table = np.full((len(these), sol.modes.shape[1]), np.nan)
        unseen: set = set()
        for i, s in enumerate(these):
            rows, absent = _model_rows(model, s.points)
            if rows is None:
                unseen.update(absent)
                continue
            table[i] = mac(s.shape, sol.modes[rows])
            k = s.mode - 1
            j = int(np.nanargmax(table[i]))
            if (j != k and table[i, j] >= MAC_SAME and k < table.shape[1]
                    and table[i, j] - table[i, k] >= MAC_MARGIN):
                problems.append(
                    f"configuration {c.name!r}: the resonance numbered mode {s.mode} "
                    f"({s.frequency_hz:.5g} Hz) has the shape of the model's mode {j + 1} "
                    f"(MAC {table[i, j]:.2f}, against {table[i, k]:.2f} with mode "
                    f"{s.mode}): the test and the initial model order modes {s.mode} and "
                    f"{j + 1} differently (a mode exchange; an added mass moves them across "
                    f"each other in one but not the other); the update would pair them "
                    f"wrongly")
        if unseen:  # the exchange check is off there: say so, not nothing
            notes.append(f"configuration {c.name!r}: shapes not compared with the model's "
                         f"modes: it has no coordinate at measured point(s) "
                         f"{sorted(unseen)} (node, direction)")
        macs[c.name] = table
        if c.additions and bare:
            for s in these:
                best = max(((mac(s.shape, b.shape), b) for b in bare
                            if b.points == s.points), key=lambda t: t[0], default=None)
                if best is not None and best[0] >= MAC_SAME and best[1].mode != s.mode:
                    notes.append(f"configuration {c.name!r}: mode {s.mode} has the shape of "
                                 f"the bare structure's mode {best[1].mode} (MAC "
                                 f"{best[0]:.2f}): the addition moves modes across each "
                                 f"other")
    return ShapePairing(problems, notes, macs)
