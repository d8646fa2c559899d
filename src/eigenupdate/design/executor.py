"""Where independent tasks run: in this process, or on a Dask cluster.

All map ``fn(item, shared)`` over ``items`` and return the results in the order of
``items``; ``shared`` (the model and plan) is sent to every Dask worker once (scatter with
broadcast), not once per task, and the items go in batches that shrink as the study
proceeds (:func:`batches`): few transfers, and a short tail. Each task carries its own
seed, so results do not depend on the executor or on the order in which tasks finish.
:class:`Automatic` runs the first task here, and starts a local cluster for the rest only
if the study would take long enough in this process to gain from one.
"""

from __future__ import annotations

import math
import os
import time
from collections.abc import Callable, Sequence
from typing import Any

from eigenupdate.choices import SCHEDULER_ENV
from eigenupdate.errors import InputError, shorten

Progress = Callable[[int, int], None]

SHARE = 2
"""Each batch takes 1 / (SHARE x workers) of the items not yet batched (guided
self-scheduling, Polychronopoulos & Kuck 1987)."""

PARALLEL_MIN_S = 30.0
"""The automatic choice starts a local cluster only for studies estimated to take at least
this long in this process (a local cluster takes a few seconds to start, its workers to
import NumPy and SciPy and receive the model)."""


def _batch(items: list, shared: Any, fn: Callable) -> list:
    return [fn(x, shared) for x in items]


def batches(n: int, workers: int) -> list[slice]:
    """Consecutive slices of ``range(n)`` for ``workers``, large first and down to one item.

    Equal batches, four per worker, left one worker idle for up to a batch at the end
    (an eighth of a 2-worker study); batches that shrink as the study proceeds keep the
    tail to one small batch with O(workers log n) transfers.

    >>> [s.stop - s.start for s in batches(20, 2)]
    [5, 4, 3, 2, 2, 1, 1, 1, 1]
    """
    out, start = [], 0
    while start < n:
        size = max(1, math.ceil((n - start) / (SHARE * max(1, workers))))
        out.append(slice(start, start + size))
        start += size
    return out


class InProcess:
    """Run every task here, one after the other (no Dask)."""

    def map(self, fn: Callable, shared: Any, items: Sequence, progress: Progress | None = None
            ) -> list:
        out = []
        for i, x in enumerate(items, 1):
            out.append(fn(x, shared))
            if progress:
                progress(i, len(items))
        return out

    def close(self) -> None:
        pass

    def __enter__(self) -> InProcess:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def __repr__(self) -> str:
        return "in-process"


def _reachable(address: str, field: str) -> None:
    """Refuse at once a scheduler whose host is not known or whose port refuses the
    connection (Dask retries both until its 10 s timeout, then says it timed out)."""
    import socket
    from urllib.parse import urlsplit

    url = urlsplit(address)
    host, port = url.hostname, url.port
    if not host or not port:
        return  # Dask names what is wrong
    try:
        socket.getaddrinfo(host, port)
    except (OSError, UnicodeError) as exc:
        raise InputError(f"cannot connect to the Dask scheduler: host {host!r} is not known "
                         f"({getattr(exc, 'strerror', None) or exc})",
                         field=field) from None
    try:
        socket.create_connection((host, port), timeout=10).close()
    except TimeoutError:
        raise InputError(f"cannot connect to the Dask scheduler: no answer from {address} "
                         f"within 10 s", field=field) from None
    except OSError as exc:
        raise InputError(f"cannot connect to the Dask scheduler at {address}: "
                         f"{exc.strerror or exc}", field=field) from None


class DaskExecutor:
    """Tasks on a Dask cluster: an existing one at ``address``, else a local cluster of
    ``n_workers`` single-threaded worker processes (default: one per core)."""

    def __init__(self, address: str | None = None, n_workers: int | None = None,
                 field: str = "--scheduler"):
        from distributed import Client, LocalCluster

        self.cluster = None
        if address:
            _reachable(address, field)  # field: where the address came from
            try:
                self.client = Client(address, timeout="10s")
            except (OSError, TimeoutError) as exc:
                raise InputError(f"cannot connect to the Dask scheduler: {exc}",
                                 field=field) from None
            except Exception as exc:  # another server's reply read as Dask's handshake: a
                # frame length of exabytes (MemoryError: 'out of memory'), too many dimensions
                raise InputError(f"{address} answered, but not as a Dask scheduler "
                                 f"({type(exc).__name__}: {shorten(str(exc), 80)}); is "
                                 f"that the scheduler's port?", field=field) from None
        else:
            # one core per worker: its sparse solves must not start threads of their own
            self.cluster = LocalCluster(n_workers=n_workers or os.cpu_count() or 1,
                                        threads_per_worker=1, processes=True,
                                        host="127.0.0.1", dashboard_address=None,
                                        env={"EIGENUPDATE_THREADS": "1"})
            self.client = Client(self.cluster)

    def map(self, fn: Callable, shared: Any, items: Sequence, progress: Progress | None = None
            ) -> list:
        from distributed import as_completed

        items = list(items)
        if not items:
            return []
        [remote] = self.client.scatter([shared], broadcast=True)
        workers = max(1, len(self.client.scheduler_info()["workers"]))
        chunks = [items[s] for s in batches(len(items), workers)]
        futures = self.client.map(_batch, chunks, [remote] * len(chunks),
                                  [fn] * len(chunks), pure=False)
        done = 0
        for f in as_completed(futures):
            done += len(chunks[futures.index(f)])
            if progress:
                progress(done, len(items))
        return [r for chunk in self.client.gather(futures) for r in chunk]

    def close(self) -> None:
        self.client.close()
        if self.cluster is not None:
            self.cluster.close()

    def __enter__(self) -> DaskExecutor:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def __repr__(self) -> str:
        return f"Dask at {self.client.scheduler.address}"


class Automatic:
    """In this process or on a local cluster, whichever the study's size calls for: the
    first task runs here and is timed; the rest go to a local cluster of ``n_workers``
    processes only if they would take at least PARALLEL_MIN_S here and there is more than
    one core. Once started, that cluster runs every later map (a design's screening, then
    its validation trials). ``str(self)`` says which it chose and why."""

    def __init__(self, n_workers: int | None = None):
        self.n_workers = n_workers or os.cpu_count() or 1
        self.choice = "automatic: nothing run yet"
        self._dask: DaskExecutor | None = None

    def map(self, fn: Callable, shared: Any, items: Sequence, progress: Progress | None = None
            ) -> list:
        items = list(items)
        if not items:
            return []
        if self._dask is not None:  # an earlier map started a cluster: one is enough
            return self._dask.map(fn, shared, items, progress)
        t = time.perf_counter()
        first = [fn(items[0], shared)]
        per_task = time.perf_counter() - t
        if progress:
            progress(1, len(items))
        rest = items[1:]
        estimate = per_task * len(rest)
        why = (f"{len(rest)} more tasks x {per_task:.2g} s = {estimate:.2g} s in this process"
               f"{'' if self.n_workers > 1 else ', one core'}")
        if self.n_workers < 2 or estimate < PARALLEL_MIN_S:
            self.choice = f"in-process (automatic: {why}, below {PARALLEL_MIN_S:g} s)"
            return first + InProcess().map(fn, shared, rest, progress and (
                lambda i, n: progress(i + 1, n + 1)))
        self._dask = DaskExecutor(n_workers=self.n_workers)
        self.choice = (f"local Dask cluster of {self.n_workers} workers at "
                       f"{self._dask.client.scheduler.address} (automatic: {why})")
        return first + self._dask.map(fn, shared, rest, progress and (
            lambda i, n: progress(i + 1, n + 1)))

    def close(self) -> None:
        if self._dask is not None:
            self._dask.close()

    def __enter__(self) -> Automatic:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def __repr__(self) -> str:
        return self.choice


def executor_for(scheduler: str | None = None, in_process: bool = False,
                 n_workers: int | None = None) -> InProcess | DaskExecutor | Automatic:
    """The executor the command line asked for: ``in_process``, else the scheduler at
    ``scheduler`` or ``$EIGENUPDATE_SCHEDULER``, else a local cluster of ``n_workers``
    if given, else the :class:`Automatic` choice."""
    if in_process:
        return InProcess()
    address = scheduler or os.environ.get(SCHEDULER_ENV) or None
    if address is None and n_workers is None:
        return Automatic()
    return DaskExecutor(address, n_workers, "--scheduler" if scheduler else SCHEDULER_ENV)
