"""The batches the Dask executor sends (design/executor.py)."""

import math
from types import SimpleNamespace

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


def test_automatic_starts_one_cluster_for_every_map(monkeypatch):
    # a design screens its candidates and then runs its validation trials on the same
    # executor: the second map must reuse the cluster the first one started
    from eigenupdate.design import executor

    started, closed = [], []

    class Cluster(executor.InProcess):  # a local cluster without the processes
        def __init__(self, address=None, n_workers=None):
            started.append(n_workers)
            self.client = SimpleNamespace(scheduler=SimpleNamespace(address="tcp://here:1"))

        def close(self):
            closed.append(1)

    monkeypatch.setattr(executor, "DaskExecutor", Cluster)
    monkeypatch.setattr(executor, "PARALLEL_MIN_S", 0.0)
    seen = []
    with executor.Automatic(n_workers=2) as ex:
        assert ex.map(lambda x, s: x + s, 10, [1, 2, 3]) == [11, 12, 13]
        assert ex.map(lambda x, s: x * s, 10, [1, 2],
                      lambda i, n: seen.append((i, n))) == [10, 20]
        assert ex.map(lambda x, s: x, 0, []) == []
    assert started == [2] and closed == [1] and seen == [(1, 2), (2, 2)]
