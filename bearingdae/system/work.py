"""The residual's work arrays as two flat buffers: what the compiled callbacks receive.

Stage: system (DAE model). ``d``, the work tuple of system/residual.py (parameters, layout
maps, per-roller and global arrays, the slice quantities, the load table, the roller pass's
scratch; their names and order: ``WORK_SLOTS`` of system/model.py), is handed to IDA's
callbacks as one float64 buffer W and one int64 buffer I (:func:`flat_work`); compiled code
rebuilds the views (:func:`work_views`; solvers/sundials/callbacks.py does the same from the
buffers' addresses).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .arrayview import borrowed_view

# Why: a compiled function unboxes every array argument on each call from Python, ~0.1 µs per
# array; IDA calls the residual ~300 000 times per baseline run, and ``d`` holds 23 arrays
# (2.3 µs per call against 1.2 µs for two). ``flat_work`` packs them into one float buffer W and
# one integer buffer I; ``d`` then consists of views of W and I (same memory), and
# ``work_views`` rebuilds the same 23 views inside compiled code, where that is free.
WORK_NDIM = (1, 1, 1, 1, 1, 1, 1, 1, 1, 2, 2, 1, 1, 2, 1, 2, 3, 3, 3, 3, 2, 2, 2)  # per entry of d
WORK_INT = (5, 6)  # entries of d that are int64 (the layout maps); the others are float64
#: dimensions of the entries after those of WORK_NDIM: a scene's own tables (the defect table
#: of system/defects.py), which the work tuple's marker holds (system/optional.py)
EXTRA_NDIM = 2
_HEADER = 4  # per entry: offset, then up to three dimensions


def flat_work(arrays) -> tuple[tuple, tuple]:
    """(d, (W, I)): the work arrays ``arrays`` (in the order of ``d``) copied into one float64
    buffer W and one int64 buffer I, and ``d`` rebuilt as views into them."""
    n_head = _HEADER * len(arrays)
    f_size = sum(a.size for i, a in enumerate(arrays) if i not in WORK_INT)
    i_size = sum(a.size for i, a in enumerate(arrays) if i in WORK_INT)
    W = np.zeros(max(f_size, 1))
    I = np.zeros(n_head + i_size, np.int64)
    fo, io = 0, n_head
    views = []
    for i, a in enumerate(arrays):
        ndim = WORK_NDIM[i] if i < len(WORK_NDIM) else EXTRA_NDIM
        if a.ndim != ndim:
            raise ValueError(f"work array {i}: {a.ndim} dimensions, expected {ndim}")
        buf, off = (I, io) if i in WORK_INT else (W, fo)
        buf[off:off + a.size] = a.ravel()
        views.append(buf[off:off + a.size].reshape(a.shape))
        I[_HEADER * i] = off
        I[_HEADER * i + 1:_HEADER * i + 1 + a.ndim] = a.shape
        if i in WORK_INT:
            io += a.size
        else:
            fo += a.size
    return tuple(views), (W, I)


# The accessors are inlined into work_views (numba IR): as compiled functions each literal
# index i made its own specialisation (21 compilations at a cold start). The views
# are made by system/arrayview.borrowed_view: ``reshape`` called a C helper each time (9 per
# call), and a slice or ``c_view`` raised and lowered the buffer's reference count (two
# atomic operations per view and call).
@njit(inline="always", error_model="numpy")
def _f1(W, I, i):
    return borrowed_view(W, I[4 * i], (I[4 * i + 1],))


@njit(inline="always", error_model="numpy")
def _f2(W, I, i):
    return borrowed_view(W, I[4 * i], (I[4 * i + 1], I[4 * i + 2]))


@njit(inline="always", error_model="numpy")
def _f3(W, I, i):
    return borrowed_view(W, I[4 * i], (I[4 * i + 1], I[4 * i + 2], I[4 * i + 3]))


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def work_views(W, I):
    """The work tuple ``d`` of ``flat_work`` rebuilt from (W, I) (views, nothing copied)."""
    return (_f1(W, I, 0), _f1(W, I, 1), _f1(W, I, 2), _f1(W, I, 3), _f1(W, I, 4),
            _f1(I, I, 5), _f1(I, I, 6), _f1(W, I, 7), _f1(W, I, 8), _f2(W, I, 9),
            _f2(W, I, 10), _f1(W, I, 11), _f1(W, I, 12), _f2(W, I, 13), _f1(W, I, 14),
            _f2(W, I, 15), _f3(W, I, 16), _f3(W, I, 17), _f3(W, I, 18), _f3(W, I, 19),
            _f2(W, I, 20), _f2(W, I, 21), _f2(W, I, 22))
