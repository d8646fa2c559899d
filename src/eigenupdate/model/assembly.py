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


def _node_blocks(keys: np.ndarray, blocks: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Sorted unique keys and the sum of the (b, b) blocks that share each (one sparse
    product: NumPy's reduceat over blocks is several times slower)."""
    unique, inverse = np.unique(keys, return_inverse=True)
    b = blocks.shape[1]
    pick = sp.csr_array((np.ones(keys.size), (inverse.ravel(), np.arange(keys.size))),
                        shape=(unique.size, keys.size))
    return unique, (pick @ blocks.reshape(keys.size, b * b)).reshape(-1, b, b)


def assemble(nodes: np.ndarray, blocks: Callable[[slice], np.ndarray], n_nodes: int,
             per_node: int, chunk: int = 8192) -> sp.csr_array:
    """Sum of element blocks (m, k b, k b) over elements with node indices ``nodes``
    (m, k), b = ``per_node`` coordinates per node, ``blocks(s)`` giving the blocks of
    the elements of slice ``s``: an (n_nodes b)-square CSR.

    The blocks are summed node block by node block (b x b at a time, b^2 fewer indices
    to sort than entry by entry), a chunk of elements at a time so that the blocks of
    all elements never exist at once (a 500k-coordinate shell mesh has 48 M entries).

    Examples
    --------
    >>> k = np.array([[1.0, -1.0], [-1.0, 1.0]])
    >>> nodes = np.array([[0, 1], [1, 2], [2, 3]])
    >>> a = assemble(nodes, lambda s: np.broadcast_to(k, (s.stop - s.start, 2, 2)), 4, 1,
    ...              chunk=2)
    >>> d = node_dofs(nodes, 1)
    >>> bool(np.array_equal(a.toarray(), scatter(d, np.stack([k, k, k]), 4).toarray()))
    True
    """
    return assemble_many(nodes, lambda s: [blocks(s)], 1, n_nodes, per_node, chunk)[0]


def assemble_many(nodes: np.ndarray, blocks: Callable[[slice], list], count: int,
                  n_nodes: int, per_node: int, chunk: int = 8192) -> list[sp.csr_array]:
    """:func:`assemble` of ``count`` matrices at once: ``blocks(s)`` gives a list of
    ``count`` block arrays (or None for an empty one) for the elements of slice ``s``,
    so that what they share (element axes, Jacobians) is computed once."""
    nodes = np.asarray(nodes, dtype=np.int64)
    m, k = nodes.shape
    b = per_node
    keys: list[list] = [[] for _ in range(count)]
    sums: list[list] = [[] for _ in range(count)]
    for start in range(0, m, chunk):
        s = slice(start, min(start + chunk, m))
        e = nodes[s]
        key = (e[:, :, None] * n_nodes + e[:, None, :]).ravel()
        for i, blk in enumerate(blocks(s)):
            if blk is None:
                continue
            data = np.asarray(blk, float).reshape(-1, k, b, k, b).transpose(0, 1, 3, 2, 4)
            u, summed = _node_blocks(key, data.reshape(-1, b, b))
            keys[i].append(u)
            sums[i].append(summed)
    out = []
    for kk, ss in zip(keys, sums, strict=True):
        if not kk:
            out.append(sp.csr_array((n_nodes * b, n_nodes * b)))
            continue
        key, summed = _node_blocks(np.concatenate(kk), np.concatenate(ss))
        indptr = np.searchsorted(key // n_nodes, np.arange(n_nodes + 1))
        out.append(sp.bsr_array((summed, key % n_nodes, indptr),
                                shape=(n_nodes * b, n_nodes * b)).tocsr())
    return out
