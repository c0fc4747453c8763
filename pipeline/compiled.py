"""Compilation of the simulator's kernels: numba's ``njit`` when installed, plain Python otherwise.

One source, two paths: a function decorated with :func:`jit` is compiled (cached, releasing the GIL) when numba
is installed, and runs as plain Python without it or under ``NUMBA_DISABLE_JIT=1`` (the tests run both).
"""

from __future__ import annotations

try:  # numba is a core dependency; the same source still runs as Python without it
    from numba import njit as _njit

    def jit(f):
        return _njit(cache=True, nogil=True)(f)

    HAVE_NUMBA = True
except ImportError:  # pragma: no cover - exercised by the no-numba install
    def jit(f):
        return f

    HAVE_NUMBA = False
