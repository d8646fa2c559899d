"""Models assembled elsewhere (NASTRAN, FEMtools, ...): K = K0 + sum s_j K_j and
M = M0 + sum s_j M_j from given matrices (:mod:`eigenupdate.io.matrix_market` reads them
from files)."""

from __future__ import annotations

from collections.abc import Sequence

from eigenupdate.errors import InputError
from eigenupdate.model.parameters import Parameter
from eigenupdate.model.parametric import ParametricModel


def matrix_model(k0, m0, terms: Sequence[tuple[Parameter, object | None, object | None]]
                 ) -> ParametricModel:
    """Model from K0, M0 and, per parameter, (parameter, dK/ds_j or None, dM/ds_j or None).

    Matrices are anything :class:`scipy.sparse.csr_array` accepts; coordinates are
    numbered 1..n, each an X translation of its own node.

    Examples
    --------
    A 2 kg mass on an 800 N/m spring, the stiffness a parameter:

    >>> import numpy as np
    >>> model = matrix_model(np.zeros((1, 1)), 2.0 * np.eye(1),
    ...                      [(Parameter("k", 800.0), np.eye(1), None)])
    >>> model.names, float(model.stiffness()[0, 0]), model.coordinate_table.label(1)
    (['k'], 800.0, 'coordinate 1 (node 1, X)')
    """
    params, kt, mt = [], [], []
    for p, k, m in terms:
        if k is None and m is None:
            raise InputError("needs a K and/or an M matrix", field=f"parameter {p.name}")
        params.append(p)
        kt.append(k)
        mt.append(m)
    return ParametricModel(k0, m0, tuple(params), tuple(kt), tuple(mt))
