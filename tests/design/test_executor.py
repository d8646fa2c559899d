"""The batches the Dask executor sends (design/executor.py)."""

import math

from hypothesis import given
from hypothesis import strategies as st

from eigenupdate.design.executor import SHARE, batches


@given(n=st.integers(0, 100_000), workers=st.integers(1, 64))
def test_batches_cover_the_items_once_in_order_and_shrink(n, workers):
    parts = batches(n, workers)
    sizes = [s.stop - s.start for s in parts]
    # consecutive, covering range(n) exactly once, in order
    assert [s.start for s in parts] == [sum(sizes[:i]) for i in range(len(sizes))]
    assert sum(sizes) == n and all(k >= 1 for k in sizes)
    # never growing, and the last one a single item: the tail is short
    assert sizes == sorted(sizes, reverse=True)
    assert not sizes or sizes[-1] == 1
    # each takes at most 1 / (SHARE x workers) of what is left (rounded up), so no batch
    # holds more than that share of the study
    left = n
    for k in sizes:
        assert k == max(1, math.ceil(left / (SHARE * workers)))
        left -= k
    # few transfers: while batches exceed one item, what is left shrinks by the factor
    # 1 - 1/(SHARE workers) per batch; then at most SHARE x workers single items
    if n:
        q = 1 - 1 / (SHARE * workers)
        assert len(sizes) <= math.ceil(math.log(n) / -math.log(q)) + SHARE * workers + 1
