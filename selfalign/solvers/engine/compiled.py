"""The compilation settings of the engine (:data:`jit`, :data:`inlined`) and array arguments
without reference counting (:func:`borrowed`).
"""

from __future__ import annotations

from numba import njit, types
from numba.extending import intrinsic, overload

#: Options of every compiled function of the engine (the implementations of its overloads too):
#: numpy's error model (a division by zero gives inf or nan, as in the model's formulas, with no
#: check and no exception path in the arithmetic).
OPTIONS = {"error_model": "numpy"}
jit = njit(cache=True, nogil=True, **OPTIONS)
inlined = njit(cache=True, nogil=True, inline="always", **OPTIONS)


def borrowed(array):
    """``array`` itself, for use inside the kernel without reference counting (below)."""
    return array


@intrinsic
def _without_refcount(typingctx, array):
    def codegen(context, builder, signature, args):
        view = context.make_array(signature.args[0])(context, builder, value=args[0])
        view.meminfo = context.get_constant_null(types.MemInfoPointer(types.voidptr))
        return view._getvalue()
    return array(array), codegen


@overload(borrowed)
def _borrowed(array):
    """Compiled, a view of ``array`` with no memory-info pointer: numba increments and
    decrements the reference count of every array argument at every call (an atomic
    operation each, ~10 per period), and skips both for a NULL memory-info.  Safe because
    the entry points' callers hold the arrays for the whole kernel call."""
    return lambda array: _without_refcount(array)


@jit
def borrowed_all(table, bnd, cross, hist, arcs, events, samples, steps):
    """:func:`borrowed` of every array an entry point passes down to :func:`drive`."""
    return (borrowed(table), borrowed(bnd), borrowed(cross), borrowed(hist), borrowed(arcs), borrowed(events),
            borrowed(samples), borrowed(steps))
