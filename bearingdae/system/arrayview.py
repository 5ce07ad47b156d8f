"""C-contiguous views of another shape in compiled code, without numba's reshape helper.

Stage: system (DAE) plumbing of the compiled kernels (system/residual.py, jacobian_analytic.py).

Why: numba's ``ndarray.reshape`` calls an external C helper (``numba_attempt_nocopy_reshape``)
on every call, even for a C-contiguous array, and the call is opaque to LLVM. The residual made
13 of them per call (the 9 two- and three-dimensional work views of ``work_views``, the flat
views of the contact pass): ~0.6 µs of a ~9 µs kernel.
``c_view(a, shape)`` builds the view directly (same data pointer, C strides); it is only
defined for C-contiguous arrays, where the result is what ``reshape`` returns.

The caller guarantees ``prod(shape) == a.size`` (the work buffers are laid out by
``work.flat_work``, which checks every shape); nothing is checked here.
``borrowed_view`` is the same view without a reference to the buffer's owner (the work views
rebuilt on every call), and ``compact_positions`` the inverse of the layout's index maps, which
the kernels' Jacobian passes use to place their slopes.
"""

from __future__ import annotations

import numpy as np
from numba import njit, types
from numba.core import cgutils
from numba.core.imputils import impl_ret_borrowed
from numba.extending import intrinsic
from numba.np.arrayobj import make_array, populate_array


def _c_layout(context, builder, src, shape_type, shape):
    """(dims, strides) as LLVM values of a C-contiguous array of ``src``'s items with the
    integer tuple ``shape`` (the last axis contiguous)."""
    intp = context.get_value_type(types.intp)
    dims = [context.cast(builder, d, shape_type.dtype, types.intp)
            for d in cgutils.unpack_tuple(builder, shape)]
    strides = []
    step = builder.sext(src.itemsize, intp) if src.itemsize.type != intp else src.itemsize
    for d in reversed(dims):
        strides.append(step)
        step = builder.mul(step, d)
    return dims, strides[::-1]


@intrinsic
def c_view(typingctx, ary, shape):
    """View of the C-contiguous array ``ary`` with the integer tuple ``shape`` (C order)."""
    if not (isinstance(ary, types.Array) and ary.layout == "C"
            and isinstance(shape, types.UniTuple) and isinstance(shape.dtype, types.Integer)):
        return None
    retty = ary.copy(ndim=shape.count, layout="C")

    def codegen(context, builder, sig, args):
        src = make_array(sig.args[0])(context, builder, args[0])
        dims, strides = _c_layout(context, builder, src, sig.args[1], args[1])
        out = make_array(retty)(context, builder)
        populate_array(out, data=src.data, shape=dims, strides=strides,
                       itemsize=src.itemsize, meminfo=src.meminfo, parent=src.parent)
        return impl_ret_borrowed(context, builder, retty, out._getvalue())

    return retty(ary, shape), codegen


@intrinsic
def borrowed_view(typingctx, buf, offset, shape):
    """C-contiguous view of ``buf[offset : offset + prod(shape)]`` (``buf`` 1-D C-contiguous)
    with the integer tuple ``shape``, which does not own a reference to ``buf``'s memory: no
    reference count is raised or lowered when it is made, passed or dropped (numba's reference
    counting skips an array without a memory owner). Why: the residual's IDA callback rebuilds
    its ~20 work views from two flat buffers on every call (system/residual.py), and a slice or
    ``c_view`` raises and lowers the buffer's count atomically each time, ~0.3 µs of a ~5 µs
    call. Only for views that live within a call while the caller holds ``buf``."""
    if not (isinstance(buf, types.Array) and buf.ndim == 1 and buf.layout == "C"
            and isinstance(offset, types.Integer)
            and isinstance(shape, types.UniTuple) and isinstance(shape.dtype, types.Integer)):
        return None
    retty = buf.copy(ndim=shape.count, layout="C")

    def codegen(context, builder, sig, args):
        src = make_array(sig.args[0])(context, builder, args[0])
        off = context.cast(builder, args[1], sig.args[1], types.intp)
        dims, strides = _c_layout(context, builder, src, sig.args[2], args[2])
        out = make_array(retty)(context, builder)
        populate_array(out, data=builder.gep(src.data, [off]), shape=dims, strides=strides,
                       itemsize=src.itemsize, meminfo=None, parent=None)
        return out._getvalue()

    return retty(buf, offset, shape), codegen


@njit(inline="always", error_model="numpy")
def compact_positions(lmap, gmap, n_local_full, n_global_full):
    """(lpos, gpos): the compact position of each kernel index of the full local and global
    unknowns (system/layout.py ``local_map``, ``global_map``), -1 where switched off."""
    lpos = np.full(n_local_full, -1)
    gpos = np.full(n_global_full, -1)
    for a in range(lmap.shape[0]):
        lpos[lmap[a]] = a
    for b in range(gmap.shape[0]):
        gpos[gmap[b]] = b
    return lpos, gpos
