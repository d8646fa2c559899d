"""Threads for the independent parts of a sparse solve.

SciPy's SuperLU releases the GIL while it factorises and while it solves, and NumPy
while it multiplies, so the Krylov subspaces of different perturbed configurations and
the Sturm-sequence factorisation of the missed-mode check are built in parallel in
threads, sharing the factors in memory. The Lanczos run of the bare structure cannot
be split: it is one sequence of single solves.

``EIGENUPDATE_THREADS`` sets the number of threads (default: the cores this process
may use, at most MAX_THREADS; 1 turns the threads off).
"""

from __future__ import annotations

import contextvars
import os
from collections.abc import Callable, Sequence
from concurrent.futures import Future, ThreadPoolExecutor, wait

import numpy as np

from eigenupdate.errors import InputError, shorten

MAX_THREADS = 4
"""More threads than this gain little: the triangular solves are memory-bound."""

MIN_ROWS = 20_000
"""Below this many coordinates the work of one solve is not shared out (each share would
take about a millisecond); single background tasks (the Sturm count) still run beside."""

_pool: ThreadPoolExecutor | None = None


def threads() -> int:
    """Number of threads to use (``EIGENUPDATE_THREADS``, else the usable cores, at most
    MAX_THREADS)."""
    env = os.environ.get("EIGENUPDATE_THREADS", "").strip()
    if env:
        if not (env.isascii() and env.isdigit() and len(env) <= 3) or not 1 <= int(env) <= 256:
            raise InputError(f"must be a whole number from 1 to 256, not {shorten(env, 40)!r}",
                             source="environment", field="EIGENUPDATE_THREADS")
        return int(env)
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        cores = os.cpu_count() or 1
    return max(1, min(cores, MAX_THREADS))


def _forget_pool() -> None:  # a forked child has none of the parent's threads
    global _pool
    _pool = None
    for reset in _AFTER_FORK:
        reset()


_AFTER_FORK: list[Callable[[], None]] = []
"""Resets other modules need in a forked child (a lock held by a thread that is gone)."""


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_forget_pool)


def _executor() -> ThreadPoolExecutor:
    global _pool
    if _pool is None:
        # one more than the work shares: the missed-mode check runs beside them
        _pool = ThreadPoolExecutor(threads() + 1, thread_name_prefix="eigenupdate")
    return _pool


def in_background(f: Callable, *args) -> Future:
    """Run ``f(*args)`` in a thread (at once in this one if threads are off). A task must
    not wait on another task: the pool is small.

    >>> in_background(sum, [1, 2, 3]).result()
    6
    """
    if threads() < 2:
        done: Future = Future()
        try:
            done.set_result(f(*args))
        except Exception as exc:  # re-raised by result(), as a thread's would be
            done.set_exception(exc)
        return done
    # NumPy's floating-point error handling and context variables (an output
    # transaction) are per thread: the task runs with the caller's
    settings, context = np.geterr(), contextvars.copy_context()

    def task():
        with np.errstate(**settings):
            return f(*args)

    return _executor().submit(context.run, task)


def shares(rows: int) -> int:
    """Threads to share work on vectors of ``rows`` coordinates among (1 below MIN_ROWS)."""
    return threads() if rows >= MIN_ROWS else 1


def map_shares(f: Callable[[list], list], items: Sequence, rows: int) -> list:
    """``f`` applied to one contiguous share of ``items`` per thread (``shares(rows)``),
    the results joined in order (``f`` maps a list to a list of the same length).

    >>> map_shares(lambda share: [x * x for x in share], range(5), rows=10**6)
    [0, 1, 4, 9, 16]
    """
    items = list(items)
    n = min(shares(rows), len(items))
    if n < 2:
        return list(f(items))
    bounds = [len(items) * i // n for i in range(n + 1)]
    parts = [items[a:b] for a, b in zip(bounds[:-1], bounds[1:], strict=True)]
    pending = [in_background(f, p) for p in parts[1:]]
    try:
        out = list(f(parts[0]))
    finally:  # no share left running on shared data once this returns or raises
        wait(pending)
    for p in pending:
        out.extend(p.result())
    return out
