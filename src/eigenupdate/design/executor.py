"""Where independent tasks run: in this process, or on a Dask cluster.

Both map ``fn(item, shared)`` over ``items`` and return the results in the order of
``items``; ``shared`` (the model and plan) is sent to every Dask worker once (scatter with
broadcast), not once per task. Each task carries its own seed, so results do not depend on
the executor or on the order in which tasks finish.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from typing import Any

from eigenupdate.errors import InputError

SCHEDULER_ENV = "EIGENUPDATE_SCHEDULER"
"""Environment variable with the address of an existing Dask scheduler (tcp://host:port)."""

Progress = Callable[[int, int], None]


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


class DaskExecutor:
    """Tasks on a Dask cluster: an existing one at ``address``, else a local cluster of
    ``n_workers`` single-threaded worker processes (default: one per core)."""

    def __init__(self, address: str | None = None, n_workers: int | None = None):
        from distributed import Client, LocalCluster

        self.cluster = None
        if address:
            try:
                self.client = Client(address, timeout="10s")
            except (OSError, TimeoutError, ValueError) as exc:
                raise InputError(f"cannot connect to the Dask scheduler: {exc}",
                                 field="--scheduler") from None
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

        [remote] = self.client.scatter([shared], broadcast=True)
        futures = self.client.map(fn, list(items), [remote] * len(items), pure=False)
        for i, _ in enumerate(as_completed(futures), 1):
            if progress:
                progress(i, len(futures))
        return self.client.gather(futures)

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


def executor_for(scheduler: str | None = None, in_process: bool = False,
                 n_workers: int | None = None) -> InProcess | DaskExecutor:
    """The executor the command line asked for: ``in_process``, else the scheduler at
    ``scheduler`` or ``$EIGENUPDATE_SCHEDULER``, else a local cluster."""
    if in_process:
        return InProcess()
    return DaskExecutor(scheduler or os.environ.get(SCHEDULER_ENV) or None, n_workers)
