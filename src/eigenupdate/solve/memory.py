"""Keep freed memory in the process, for processes that solve large models repeatedly.

Every update iteration allocates and frees the same large blocks: the LU factors of
K - sigma M (SuperLU's own allocations), the Lanczos workspace, the Krylov blocks. By
default glibc returns large freed blocks to the operating system, and each new one is
page-faulted in again: on the 2-core virtual test machine about 30,000 page faults per
eigen-solve of the 103k benchmark frame and 40,000-58,000 per update iteration; with
the memory kept, none after the first. Both get faster; their ratio stays within the
run-to-run spread (benchmarks/README.md).

:func:`keep_freed_memory` tells glibc to serve large blocks from its heap and keep them
(``mallopt``: no mmap, no trimming, one arena). The process then keeps at least its
peak memory until it exits (heap fragmentation can add to it). The command line does
this; a notebook user can call it too. Other C libraries (macOS, musl): nothing is done.
"""

from __future__ import annotations

import ctypes

# glibc malloc.h parameter numbers
_M_TRIM_THRESHOLD = -1
_M_MMAP_MAX = -4
_M_ARENA_MAX = -8


def keep_freed_memory() -> bool:
    """Ask glibc to keep freed memory for reuse; True if it accepted (for the whole
    process, for good: not undone)."""
    try:  # the C library the interpreter is linked against (no ldconfig lookup)
        mallopt = ctypes.CDLL(None).mallopt
    except (OSError, AttributeError, TypeError):  # not glibc / not POSIX
        return False
    mallopt.argtypes = [ctypes.c_int, ctypes.c_int]
    return all(mallopt(p, v) == 1 for p, v in ((_M_MMAP_MAX, 0),
                                               (_M_TRIM_THRESHOLD, 2**31 - 1),
                                               (_M_ARENA_MAX, 1)))
