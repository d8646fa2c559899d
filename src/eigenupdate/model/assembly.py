"""Scatter of element matrices (n, k, k) into one SciPy sparse matrix.

The element libraries (:mod:`~eigenupdate.model.shells`, :mod:`~eigenupdate.model.solids`,
:mod:`~eigenupdate.model.frame3d`) return dense element blocks in global axes; a deck
reader maps each element's nodes to global coordinate numbers and calls :func:`scatter`.
Large meshes are assembled in chunks (:func:`assemble`) so that the dense blocks of all
elements never exist at once (a 500k-coordinate shell mesh has 48 M block entries).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import scipy.sparse as sp


def node_dofs(nodes: np.ndarray, per_node: int) -> np.ndarray:
    """Global coordinate indices (n, nodes * per_node) of elements whose node indices
    (0-based, (n, nodes)) number the coordinates ``per_node`` at a time.

    Examples
    --------
    >>> node_dofs(np.array([[0, 2]]), 3).tolist()
    [[0, 1, 2, 6, 7, 8]]
    """
    nodes = np.asarray(nodes, dtype=np.int64)
    return (nodes[:, :, None] * per_node + np.arange(per_node)).reshape(nodes.shape[0], -1)


def scatter(dofs: np.ndarray, blocks: np.ndarray, n: int) -> sp.csr_array:
    """Sum of element blocks (m, k, k) at rows and columns ``dofs`` (m, k): an (n, n) CSR.

    Examples
    --------
    Two springs of unit stiffness in series:

    >>> k = np.array([[1.0, -1.0], [-1.0, 1.0]])
    >>> scatter(np.array([[0, 1], [1, 2]]), np.stack([k, k]), 3).toarray().tolist()
    [[1.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]]
    """
    index = np.int32 if n < 2**31 - 1 else np.int64  # halves the index arrays' memory
    dofs = np.asarray(dofs, dtype=index)
    k = dofs.shape[1]
    rows = np.repeat(dofs, k, axis=1).ravel()
    cols = np.tile(dofs, (1, k)).ravel()
    return sp.coo_array((np.asarray(blocks, float).ravel(), (rows, cols)), shape=(n, n)).tocsr()


def assemble(dofs: np.ndarray, blocks: Callable[[slice], np.ndarray], n: int,
             chunk: int = 8192) -> sp.csr_array:
    """:func:`scatter` of ``blocks(s)`` for the elements of each slice ``s`` of ``chunk``
    elements, summed once at the end (adding CSR matrices chunk by chunk would cost the
    whole matrix's size per chunk).

    Examples
    --------
    >>> k = np.array([[1.0, -1.0], [-1.0, 1.0]])
    >>> d = np.array([[0, 1], [1, 2], [2, 3]])
    >>> a = assemble(d, lambda s: np.broadcast_to(k, (s.stop - s.start, 2, 2)), 4, chunk=2)
    >>> bool(np.array_equal(a.toarray(), scatter(d, np.stack([k, k, k]), 4).toarray()))
    True
    """
    parts = []
    for start in range(0, dofs.shape[0], chunk):
        s = slice(start, min(start + chunk, dofs.shape[0]))
        parts.append(scatter(dofs[s], blocks(s), n).tocoo())
    if not parts:
        return sp.csr_array((n, n))
    return sp.coo_array((np.concatenate([p.data for p in parts]),
                         (np.concatenate([p.row for p in parts]),
                          np.concatenate([p.col for p in parts]))), shape=(n, n)).tocsr()
