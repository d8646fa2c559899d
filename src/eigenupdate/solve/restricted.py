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

from eigenupdate.solve import parallel


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
        rows = sum(b.shape[1] for b in blocks)

        def columns(share):
            out = []
            for kj, mj in share:
                d = np.zeros(rows)
                if kj is not None:
                    d += np.concatenate([_quadratic(kj, b) for b in blocks])
                if mj is not None:
                    d -= lam * np.concatenate([_quadratic(mj, b) for b in blocks])
                out.append(d)
            return out

        n_rows = blocks[0].shape[0] if blocks else 0
        cols = parallel.map_shares(columns, list(zip(self._k, self._m, strict=True)), n_rows)
        return np.column_stack(cols) if cols else np.zeros((rows, 0))


def _restrict(term):
    if term is None:
        return None
    # a copy: eliminate_zeros works in place, and the model's own matrices (shared by
    # csr_array(term)) may be read meanwhile by another thread assembling K(s)
    t = sp.csr_array(term, copy=True)
    t.eliminate_zeros()
    rows = np.flatnonzero(np.diff(t.indptr))
    cols = np.unique(t.indices)
    return rows, cols, sp.csr_array(t[rows][:, cols])


def projected(term, V: np.ndarray) -> np.ndarray:
    """V^T T V for a sparse parameter matrix T, through the rows it touches only.

    >>> import numpy as np, scipy.sparse as sp
    >>> T = sp.csr_array(([2.0], ([1], [1])), shape=(3, 3))
    >>> projected(T, np.arange(6.0).reshape(3, 2))   # 2 [2 3]^T [2 3]
    array([[ 8., 12.],
           [12., 18.]])
    """
    rows, cols, sub = _restrict(term)
    P = V[rows].T @ (sub @ V[cols])
    return (P + P.T) / 2


def _quadratic(term, phi: np.ndarray) -> np.ndarray:
    rows, cols, sub = term
    return np.einsum("ij,ij->j", phi[rows], sub @ phi[cols])


class ProjectedTerms:
    """Sensitivities of modes given by their coordinates in a basis V = [phi | Q].

    With P_j = V^T K_j V and R_j = V^T M_j V, a mode x = V y has
    d lambda / d s_j = y^T (P_j - lambda R_j) y. The blocks of ``phi`` (shared by every
    basis) are computed once; :meth:`derivatives` adds those of Q. For many
    configurations sharing a small basis (screening) this replaces one product with the
    full modes per configuration by one per basis.
    """

    def __init__(self, terms: RestrictedTerms, phi: np.ndarray):
        self.phi = phi
        self._terms = []
        for kind in (terms._k, terms._m):
            cache = []
            for t in kind:
                if t is None:
                    cache.append(None)
                    continue
                rows, cols, sub = t
                b_phi = sub @ phi[cols]  # rows of K_j phi that are not zero
                cache.append((rows, cols, sub, b_phi, phi[rows].T @ b_phi))
            self._terms.append(cache)

    def derivatives(self, Q: np.ndarray, coef: np.ndarray, lam: np.ndarray) -> np.ndarray:
        """(modes, parameters) d lambda / d s_j of the modes [phi | Q] @ coef, eigenvalues
        ``lam`` (``coef`` may hold several configurations' modes side by side)."""
        kb = self.phi.shape[1]
        a, b = coef[:kb], coef[kb:]
        out = np.zeros((coef.shape[1], len(self._terms[0])))
        for sign, cache in zip((1.0, -1.0), self._terms, strict=True):
            for j, t in enumerate(cache):
                if t is None:
                    continue
                rows, cols, sub, b_phi, pp = t
                q_rows = Q[rows]
                pq = b_phi.T @ q_rows  # phi^T B Q
                qq = q_rows.T @ (sub @ Q[cols])
                quad = (np.einsum("ai,ab,bi->i", a, pp, a) + 2 * np.einsum("ai,ab,bi->i", a, pq, b)
                        + np.einsum("ai,ab,bi->i", b, qq, b))
                out[:, j] += quad if sign > 0 else -lam * quad
        return out
