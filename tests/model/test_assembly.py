"""Sparse assembly of element blocks: node-block summation against entry-wise scatter."""

from __future__ import annotations

import numpy as np
import pytest
from bounds import EPS

from eigenupdate.model.assembly import assemble, node_dofs, scatter


@pytest.mark.parametrize("per_node", [1, 3, 6])
@pytest.mark.parametrize("chunk", [1, 7, 1000])
def test_node_block_assembly_equals_entrywise_scatter(per_node, chunk):
    """Source: the plain COO sum (scatter) of the same blocks. Summation orders differ,
    so entries agree within (number of terms) eps (sum of |terms|)."""
    rng = np.random.default_rng(per_node * 100 + chunk)
    n_nodes, m, k = 30, 40, 4
    nodes = np.array([rng.choice(n_nodes, k, replace=False) for _ in range(m)])
    blocks = rng.normal(size=(m, k * per_node, k * per_node))
    got = assemble(nodes, lambda s: blocks[s], n_nodes, per_node, chunk=chunk).toarray()
    d = node_dofs(nodes, per_node)
    ref = scatter(d, blocks, n_nodes * per_node).toarray()
    scale = scatter(d, np.abs(blocks), n_nodes * per_node).toarray()
    assert np.all(np.abs(got - ref) <= m * EPS * scale)
    assert got.shape == (n_nodes * per_node,) * 2
