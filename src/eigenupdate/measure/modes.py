"""A real normal mode known at some nodes: what modal analysis of measured FRFs gives and
what a universal file's dataset 55 stores."""

from __future__ import annotations

import math
import operator
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from eigenupdate.errors import InputError


@dataclass(frozen=True, eq=False, repr=False)
class Mode:
    """A real normal mode as stored in dataset 55 (analysis type 2, normal mode).

    Parameters
    ----------
    frequency_hz : float
        Natural frequency in Hz (``freq``, record 8 field 1), finite and ``>= 0``.
    loss_factor : float
        Hysteretic (structural) damping loss factor eta, written to ``modal_damp_his``
        ("modal hysteretic damping ratio", record 8 field 4).
    damping_ratio : float
        Viscous damping ratio zeta (``modal_damp_vis``, record 8 field 3); 0 if unused.
        For light damping eta ~ 2 zeta; the two are stored independently.
    modal_mass : float
        Modal mass (``modal_m``, record 8 field 2); 0 means unknown / not mass-normalised.
    node_nums : array_like of int, shape (m,)
        Node numbers of the shape (record 9).
    shape : array_like of float, shape (m, 3) or (m, 6), optional
        Shape values per node: translations X, Y, Z (``r1``-``r3``) and optionally
        rotations (``r4``-``r6``).  Default: zeros with 3 columns.
    mode_number : int
        Mode number (``mode_n``, record 7 field 4); 0 means "use the position in the list"
        when writing.
    source : str
        File the mode came from, used in error messages.
    label : str
        Free text kept in the dataset's third ID line, e.g. the test configuration.

    Notes
    -----
    Dataset 55 stores every number with 6 significant digits (``%13.5e``).

    Examples
    --------
    >>> m = Mode.point(12.5, 0.8, (7, -3), loss_factor=0.02)
    >>> m
    Mode(12.5 Hz, loss_factor=0.02, 1 node(s))
    >>> m.shape.tolist()
    [[0.0, 0.0, -0.8]]
    """

    frequency_hz: float
    loss_factor: float = 0.0
    damping_ratio: float = 0.0
    modal_mass: float = 0.0
    node_nums: ArrayLike = (1,)
    shape: ArrayLike | None = None
    mode_number: int = 0
    source: str = ""
    label: str = ""

    def __post_init__(self) -> None:
        src = self.source or None
        for name in ("frequency_hz", "loss_factor", "damping_ratio", "modal_mass"):
            try:
                value = float(getattr(self, name))
            except (TypeError, ValueError):
                raise InputError(
                    f"not a number: {getattr(self, name)!r}", source=src, field=name
                ) from None
            if not math.isfinite(value):
                raise InputError(f"non-finite value {value!r}", source=src, field=name)
            object.__setattr__(self, name, value)
        if self.frequency_hz < 0:
            raise InputError(
                f"negative frequency {self.frequency_hz:g} Hz", source=src, field="frequency_hz"
            )
        nodes = np.array(self.node_nums).ravel()
        if nodes.size == 0 or not np.issubdtype(nodes.dtype, np.integer):
            raise InputError(
                f"must be a non-empty sequence of integers, got {self.node_nums!r}",
                source=src,
                field="node_nums",
            )
        nodes = nodes.astype(np.int64)
        if self.shape is None:
            shape = np.zeros((nodes.size, 3))
        else:
            try:
                shape = np.array(self.shape, dtype=np.float64)
            except (TypeError, ValueError):
                raise InputError(
                    "must be real numbers (complex shapes are not supported)",
                    source=src,
                    field="shape",
                ) from None
            if shape.ndim == 1:
                shape = shape.reshape(1, -1)
        if shape.ndim != 2 or shape.shape[0] != nodes.size or shape.shape[1] not in (3, 6):
            raise InputError(
                f"must have shape ({nodes.size}, 3) or ({nodes.size}, 6), got {shape.shape}",
                source=src,
                field="shape",
            )
        if not np.isfinite(shape).all():
            raise InputError("non-finite value", source=src, field="shape")
        try:
            number = operator.index(self.mode_number)
        except TypeError:
            raise InputError(
                f"must be an integer, got {self.mode_number!r}", source=src, field="mode_number"
            ) from None
        nodes.flags.writeable = False
        shape.flags.writeable = False
        object.__setattr__(self, "node_nums", nodes)
        object.__setattr__(self, "shape", shape)
        object.__setattr__(self, "mode_number", int(number))
        object.__setattr__(self, "source", str(self.source))

    @classmethod
    def point(
        cls,
        frequency_hz: float,
        value: float,
        dof: tuple[int, int],
        *,
        loss_factor: float = 0.0,
        damping_ratio: float = 0.0,
        modal_mass: float = 0.0,
        mode_number: int = 0,
    ) -> Mode:
        """A mode known at one DOF only, e.g. a (real) modal constant from a point FRF.

        ``value`` is placed in the column of ``dof``'s direction (``r1``..``r6``) of a
        one-node shape, negated for a negative direction code.
        """
        node, direction = int(dof[0]), int(dof[1])
        if not 1 <= abs(direction) <= 6:
            raise ValueError(f"dof direction must be +-1..6, got {direction}")
        shape = np.zeros((1, 6 if abs(direction) > 3 else 3))
        shape[0, abs(direction) - 1] = value if direction > 0 else -value
        return cls(
            frequency_hz,
            loss_factor=loss_factor,
            damping_ratio=damping_ratio,
            modal_mass=modal_mass,
            node_nums=(node,),
            shape=shape,
            mode_number=mode_number,
        )

    def __repr__(self) -> str:
        return (
            f"Mode({self.frequency_hz:g} Hz, loss_factor={self.loss_factor:g}, "
            f"{np.asarray(self.node_nums).size} node(s))"
        )
