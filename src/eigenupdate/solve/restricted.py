"""Fox-Kapoor sensitivities of many modes at once, each parameter matrix restricted to
the rows it touches.

d lambda_i / d s_j = phi_i^T (K_j - lambda_i M_j) phi_i (see
:mod:`eigenupdate.solve.sensitivity`). A parameter of a large model usually acts on one
region (an element group), so K_j phi only needs the rows of K_j that hold entries and
phi only those rows: with the modes of every configuration side by side, one sparse
product per parameter serves them all.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import scipy.sparse as sp


class RestrictedTerms:
    """The parameter matrices K_j, M_j (None when zero), each kept on its own rows.

    Examples
    --------
    One mass m on one spring k: lambda = k/m, d lambda/dk = 1/m, d lambda/dm = -k/m^2.

    >>> import numpy as np
    >>> t = RestrictedTerms([np.ones((1, 1)), None], [None, np.ones((1, 1))])
    >>> t.derivatives(np.array([[1 / np.sqrt(2.0)]]), np.array([400.0]))
    array([[   0.5, -200. ]])
    """

    def __init__(self, k_terms: Sequence, m_terms: Sequence):
        self._k = [_restrict(t) for t in k_terms]
        self._m = [_restrict(t) for t in m_terms]

    def derivatives(self, phi: np.ndarray | Sequence[np.ndarray], lam: np.ndarray) -> np.ndarray:
        """(modes, parameters) matrix of d lambda / d s_j for the columns of ``phi``
        (mass-normalised; or a list of such blocks, taken side by side) with eigenvalues
        ``lam``."""
        blocks = [phi] if isinstance(phi, np.ndarray) else list(phi)
        out = np.zeros((sum(b.shape[1] for b in blocks), len(self._k)))
        for j, (kj, mj) in enumerate(zip(self._k, self._m, strict=True)):
            if kj is not None:
                out[:, j] += np.concatenate([_quadratic(kj, b) for b in blocks])
            if mj is not None:
                out[:, j] -= lam * np.concatenate([_quadratic(mj, b) for b in blocks])
        return out


def _restrict(term):
    if term is None:
        return None
    t = sp.csr_array(term)
    t.eliminate_zeros()
    rows = np.flatnonzero(np.diff(t.indptr))
    cols = np.unique(t.indices)
    return rows, cols, sp.csr_array(t[rows][:, cols])


def _quadratic(term, phi: np.ndarray) -> np.ndarray:
    rows, cols, sub = term
    return np.einsum("ij,ij->j", phi[rows], sub @ phi[cols])
