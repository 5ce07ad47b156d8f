"""C-contiguous views of another shape in compiled code, without numba's reshape helper.

Stage: system (DAE) plumbing of the compiled kernels (system/residual.py, jacobian_analytic.py).

Why: numba's ``ndarray.reshape`` calls an external C helper (``numba_attempt_nocopy_reshape``)
on every call, even for a C-contiguous array, and the call is opaque to LLVM. The residual made
13 of them per call (the 9 two- and three-dimensional work views of ``work_views``, the flat
views of the contact pass): ~0.6 µs of a ~9 µs kernel (CHANGELOG.md, 2026-11-23).
``c_view(a, shape)`` builds the view directly (same data pointer, C strides); it is only
defined for C-contiguous arrays, where the result is what ``reshape`` returns.

The caller guarantees ``prod(shape) == a.size`` (the work buffers are laid out by
``residual.flat_work``, which checks every shape); nothing is checked here.
"""

from __future__ import annotations

from numba import types
from numba.core import cgutils
from numba.core.imputils import impl_ret_borrowed
from numba.extending import intrinsic
from numba.np.arrayobj import make_array, populate_array


@intrinsic
def c_view(typingctx, ary, shape):
    """View of the C-contiguous array ``ary`` with the integer tuple ``shape`` (C order)."""
    if not (isinstance(ary, types.Array) and ary.layout == "C"
            and isinstance(shape, types.UniTuple) and isinstance(shape.dtype, types.Integer)):
        return None
    retty = ary.copy(ndim=shape.count, layout="C")

    def codegen(context, builder, sig, args):
        src = make_array(sig.args[0])(context, builder, args[0])
        intp = context.get_value_type(types.intp)
        dims = [context.cast(builder, d, sig.args[1].dtype, types.intp)
                for d in cgutils.unpack_tuple(builder, args[1])]
        strides = []
        step = builder.sext(src.itemsize, intp) if src.itemsize.type != intp else src.itemsize
        for d in reversed(dims):
            strides.append(step)
            step = builder.mul(step, d)
        out = make_array(retty)(context, builder)
        populate_array(out, data=src.data, shape=dims, strides=strides[::-1],
                       itemsize=src.itemsize, meminfo=src.meminfo, parent=src.parent)
        return impl_ret_borrowed(context, builder, retty, out._getvalue())

    return retty(ary, shape), codegen
