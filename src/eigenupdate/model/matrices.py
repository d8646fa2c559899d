"""Models assembled elsewhere (NASTRAN, FEMtools, ...): K = K0 + sum s_j K_j and
M = M0 + sum s_j M_j, plus monomial terms (E t^3, rho t), from given matrices
(:mod:`eigenupdate.io.matrix_market` reads them from files)."""

from __future__ import annotations

from collections.abc import Sequence

from eigenupdate.errors import InputError
from eigenupdate.model.parameters import Parameter
from eigenupdate.model.parametric import ParametricModel, Term


def matrix_model(k0, m0, terms: Sequence[tuple[Parameter, object | None, object | None]],
                 parts: Sequence[tuple[tuple[tuple[int, float], ...], float, object | None,
                                       object | None]] = ()) -> ParametricModel:
    """Model from K0, M0 and, per parameter, (parameter, dK/ds_j or None, dM/ds_j or None);
    ``parts`` adds (powers, coefficient, K or None, M or None) monomial terms
    coefficient * prod_j s_j^a_j times the matrix (``powers``: (parameter index, a_j)).

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

    A plate strip's bending stiffness 1e6 t^3 (t a parameter, 0.01):

    >>> model = matrix_model(np.zeros((1, 1)), np.eye(1), [(Parameter("t", 0.01), None, None)],
    ...                      [(((0, 3.0),), 1e6, np.eye(1), None)])
    >>> round(float(model.stiffness()[0, 0]), 12), model.nonlinear
    (1.0, True)
    """
    params = [p for p, _, _ in terms]
    k_parts, m_parts = [], []
    for j, (p, k, m) in enumerate(terms):
        used = any(any(i == j for i, _ in pw) for pw, *_ in parts)
        if k is None and m is None and not used:
            raise InputError("needs a K and/or an M matrix, or a term with a power of it",
                             field=f"parameter {p.name}")
        k_parts += [] if k is None else [Term(k, ((j, 1.0),))]
        m_parts += [] if m is None else [Term(m, ((j, 1.0),))]
    for pw, c, k, m in parts:
        k_parts += [] if k is None else [Term(k, tuple(pw), c)]
        m_parts += [] if m is None else [Term(m, tuple(pw), c)]
    return ParametricModel.from_parts(k0, m0, params, k_parts, m_parts)
