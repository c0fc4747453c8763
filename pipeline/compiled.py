"""Compilation of the simulator's kernels: numba's ``njit`` when installed, plain Python otherwise.

One source, two paths: a function decorated with :func:`jit` is compiled (cached, releasing the GIL) when numba
is installed, and runs as plain Python without it or under ``NUMBA_DISABLE_JIT=1`` (the tests run both).

**The cache.** numba's, beside each module; at import the kernels whose module, or a module it imports, changed
since they were cached are dropped (:func:`pipeline.kernel_cache.drop_stale_kernels`).

**One version per solver.** numba compiles a function once per set of argument types, and in compiled code a constant
argument (``True``, ``0``, a module constant) is a literal type of its own, as is a counter before its loop's types
are unified (the literal 0 it starts at): each such call compiled the callee again. A compiled call of a solver passes
``bool(...)`` or ``int(...)`` of such a value, which numba types as Python's calls are typed, and gives every argument
(an empty array for no history, not ``None`` or the default), so that every caller shares one version
(docs/validation.md, "One compiled version per solver": 281 compiled functions against 311).
"""

from __future__ import annotations

import types
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import TypeVar

import numpy as np

from .kernel_cache import drop_stale_kernels

_T = TypeVar("_T")

try:  # numba is a core dependency; the same source still runs as Python without it
    from numba import literal_unroll as unroll
    from numba import njit as _njit
    from numba.core.errors import NumbaExperimentalFeatureWarning

    # The scene-model registry's compiled dispatch (rocking.models.judge) loops over the registered models'
    # certificates and twins with literal_unroll, which numba types as first-class functions and marks
    # experimental. The dispatch is tested against the Python entries (tests/rocking/test_models.py) and measured at par
    # (docs/validation.md); the notice would only reach users at the one-time compilation, so it is not shown.
    warnings.filterwarnings("ignore", message="First-class function type feature is experimental",
                            category=NumbaExperimentalFeatureWarning)

    drop_stale_kernels(Path(__file__).resolve().parent)

    def jit(f):
        return _njit(cache=True, nogil=True)(f)

    def jit_inline(f):
        """:func:`jit`, and inlined into its compiled callers: for the step functions of a kernel's loop, which
        are split out to be read one at a time but should cost what one loop body costs (measured: the rocking
        kernel split into calls ran 6 % slower, inlined at par)."""
        return _njit(cache=True, nogil=True, inline="always")(f)

    def jit_lean(f):
        """:func:`jit` without numba's reference counting of arrays (``_nrt=False``): for a kernel's hot loop and
        the solvers it calls per step, whose arrays are all made by the caller in Python and outlive the call. Such
        a function cannot make an array. Measured on the 3D contact model: the atomic increments and decrements of
        the arrays passed to its per-step solver and unpacked from its tuples took 38 % of its time."""
        options: dict = {"_nrt": False}                 # numba's flag, not in its type stubs
        return _njit(cache=True, nogil=True, **options)(f)

    HAVE_NUMBA = True
except ImportError:  # pragma: no cover - exercised by the no-numba install
    def jit(f):
        return f

    jit_inline = jit
    jit_lean = jit

    def unroll(container: _T) -> _T:
        """numba's ``literal_unroll``: a tuple of functions of different types looped over in compiled code (plain
        Python: the tuple itself)."""
        return container

    HAVE_NUMBA = False


def rebound(f: Callable, **names) -> Callable:
    """A copy of the kernel ``f`` (decorated with :func:`jit`, or plain) in which the module globals ``names`` are
    replaced: how a compiled dispatch is built again from a registry changed at run time. The copy is compiled on
    its first call and not cached on disk (its globals are not its module's)."""
    py = getattr(f, "py_func", f)
    copy = types.FunctionType(py.__code__, {**py.__globals__, **names}, py.__name__, py.__defaults__,
                              py.__closure__)
    return _njit(nogil=True)(copy) if HAVE_NUMBA else copy


def tuple_with(values: tuple, index: int, value) -> tuple:
    """``values`` with its element ``index`` replaced by ``value``: a new tuple (compiled: numba's
    ``tuple_setitem``, no array made)."""
    return values[:index] + (value,) + values[index + 1:]


def filled_like(value, like: tuple) -> tuple:
    """A tuple of ``len(like)`` copies of ``value`` (compiled: its size is ``like``'s type's, known when compiling)."""
    return (value,) * len(like)


def array_as_tuple(values: np.ndarray, size: int) -> tuple:
    """The first ``size`` elements of the array ``values`` as a tuple (compiled: ``size`` a constant, such as a
    module's state size)."""
    return tuple(values[:size])


@jit_inline
def copy_into(out: np.ndarray, values: np.ndarray) -> None:
    """``out[:] = values`` for arrays of one dimension, element by element (a slice assignment needs numba's
    reference counting, which :func:`jit_lean` code goes without)."""
    for q in range(out.shape[0]):
        out[q] = values[q]


@jit_inline
def fill_with(out: np.ndarray, value: float) -> None:
    """``out[:] = value`` for an array of one dimension, element by element (see :func:`copy_into`)."""
    for q in range(out.shape[0]):
        out[q] = value


@jit_inline
def store(out: np.ndarray, values: tuple) -> None:
    """Write the tuple ``values`` into the first elements of the array ``out``."""
    for q in range(len(values)):
        out[q] = values[q]


if HAVE_NUMBA:
    from numba.core import types as _types
    from numba.core.errors import TypingError as _TypingError
    from numba.cpython.unsafe.tuple import tuple_setitem as _tuple_setitem
    from numba.extending import intrinsic as _intrinsic
    from numba.extending import overload as _overload

    @_intrinsic
    def _filled(typingctx, value, like):
        if not isinstance(like, _types.BaseTuple):
            return None
        count = len(like)
        result = _types.UniTuple(value, count)

        def codegen(context, builder, signature, args):
            if context.enable_nrt:                      # every element holds a reference to the borrowed value
                for _ in range(count):
                    context.nrt.incref(builder, value, args[0])
            return context.make_tuple(builder, result, [args[0]] * count)
        return result(value, like), codegen

    @_overload(tuple_with)
    def _compiled_tuple_with(values, index, value):
        return lambda values, index, value: _tuple_setitem(values, index, value)  # type: ignore[call-arg]

    @_overload(array_as_tuple)
    def _compiled_array_as_tuple(values, size):
        from numba.np.unsafe.ndarray import to_fixed_tuple
        if not isinstance(size, _types.IntegerLiteral):
            raise _TypingError(f"array_as_tuple: the size must be a constant, found {size}")
        count = size.literal_value
        return lambda values, size: to_fixed_tuple(values, count)  # type: ignore[call-arg]

    @_overload(filled_like)
    def _compiled_filled_like(value, like):
        return lambda value, like: _filled(value, like)  # type: ignore[call-arg]


def state_factory(dtype: np.dtype) -> Callable[[], np.ndarray]:
    """A function that returns a new zeroed one-element array of the record ``dtype``, whose element's fields
    are set by attribute (``state[0].t = ...``).

    It holds the mutable state of a compiled loop, as a solver object's attributes do in plain Python:
    helpers that take the array change its element in place, in compiled code (a numba ``Record``) and in
    plain Python (a ``numpy.recarray``) alike. The caller keeps the array, not the element, so that the
    memory outlives every reference to it.
    """
    def new_state():
        return np.rec.array(np.zeros(1, dtype))

    if HAVE_NUMBA:
        from numba.extending import overload

        @overload(new_state)
        def _compiled_new_state():
            def impl():
                return np.zeros(1, dtype)
            return impl
    return new_state
