"""SUNDIALS' memory and our work buffers as numpy arrays inside compiled callbacks.

Stage: solvers (compiled IDA core), used by callbacks.py and linsol.py.

``f64_at(address, shape)`` (``i64_at``, ``i32_at``) is the C-contiguous array of that shape whose
data start at the integer ``address``: what ``numba.carray(pointer, shape)`` gives, built
in place by an intrinsic. Why not ``carray``: numba compiles ``carray`` as an overload, one
function per pointer type and number of dimensions (five at a cold start, ~0.4 s of compile
CPU), where an intrinsic is a few instructions emitted into the caller.
The arrays own nothing (no meminfo): the caller keeps the memory alive (user_data, session.py).
``address(p)`` is a ``void*`` as an int64.
"""

from __future__ import annotations

from numba import types
from numba.core import cgutils
from numba.core.imputils import impl_ret_untracked
from numba.extending import intrinsic
from numba.np.arrayobj import make_array, populate_array


def _array_at(dtype):
    @intrinsic
    def array_at(typingctx, addr, shape):
        if not (isinstance(addr, types.Integer) and isinstance(shape, types.UniTuple)
                and isinstance(shape.dtype, types.Integer)):
            return None
        retty = types.Array(dtype, shape.count, "C")

        def codegen(context, builder, sig, args):
            intp = types.intp
            data = builder.inttoptr(args[0], context.get_value_type(types.CPointer(dtype)))
            dims = [context.cast(builder, d, sig.args[1].dtype, intp)
                    for d in cgutils.unpack_tuple(builder, args[1])]
            itemsize = context.get_constant(intp, context.get_abi_sizeof(
                context.get_data_type(dtype)))
            strides, step = [], itemsize
            for d in reversed(dims):  # C order: the last axis is contiguous
                strides.append(step)
                step = builder.mul(step, d)
            out = make_array(retty)(context, builder)
            populate_array(out, data=data, shape=dims, strides=strides[::-1],
                           itemsize=itemsize, meminfo=None)
            return impl_ret_untracked(context, builder, retty, out._getvalue())

        return retty(addr, shape), codegen
    return array_at


f64_at = _array_at(types.float64)
i64_at = _array_at(types.int64)
i32_at = _array_at(types.int32)


@intrinsic
def address(typingctx, ptr):
    """A ``void*`` as an int64."""
    if ptr != types.voidptr:
        return None

    def codegen(context, builder, signature, args):
        return builder.ptrtoint(args[0], context.get_value_type(types.int64))
    return types.int64(types.voidptr), codegen


@intrinsic
def call_int_ptr_ptr(typingctx, fn, a, b):
    """``((int (*)(void*, void*)) fn)(a, b)`` with the three as int64 addresses: a C function
    called through an address that comes in ``user_data`` at run time (an address baked into
    the compiled code would defeat numba's cache)."""
    if not all(isinstance(x, types.Integer) for x in (fn, a, b)):
        return None

    def codegen(context, builder, signature, args):
        from llvmlite import ir

        i8p = ir.IntType(8).as_pointer()
        fnty = ir.FunctionType(ir.IntType(32), [i8p, i8p])
        f = builder.inttoptr(args[0], fnty.as_pointer())
        return builder.call(f, [builder.inttoptr(args[1], i8p), builder.inttoptr(args[2], i8p)])
    return types.int32(fn, a, b), codegen
