"""Calling a compiled kernel through its address: the caller does not link the callee's code.

Stage: solvers (compiled IDA core, projection), start-up cost only. When a numba function calls
another, numba links the callee's whole module (and everything it links) into the caller's and
LLVM optimises and emits it all again: the projection of the samples re-optimised the residual,
the algebraic Jacobian block and the block-arrow solve (16 600 LLVM instructions, ~4 s of a cold
start), each IDA callback the kernel it wraps (docs/performance.md, "Cold start"). An entry
point that calls a large kernel with :func:`native_call` instead emits one indirect call to the
kernel's own machine code, whose address the caller hands in at run time (:func:`entry`: the
kernel compiles once, or loads from numba's cache). A call costs a few ns against the µs of the
kernels called so; the numbers are the same, bit for bit (the same machine code of the callee;
numba compiles without fast-math, so inlining never changed a result).

Used by the projection (projection_kernel.project_batch), Newmark's step loop and the scipy
peers' reduced system (:func:`residual_entry`). The per-step IDA callbacks call their
kernels directly: through addresses the default run took 9-18 % more CPU at the same steps
(measured, not explained: CHANGELOG.md).

The entry is (address, key): ``key`` is a checksum of the callee and its argument types, baked
into the caller when it compiles; a caller handed another specialisation's address raises
instead of calling it.
"""

from __future__ import annotations

import zlib

import numpy as np

from llvmlite import ir
from numba import typeof, types
from numba.core import cgutils
from numba.extending import intrinsic


def _key(dispatcher, args: tuple) -> int:
    """Checksum of a kernel and the numba types of its arguments (what its address calls)."""
    text = f"{dispatcher.py_func.__module__}.{dispatcher.py_func.__qualname__}{tuple(args)}"
    return zlib.crc32(text.encode())


def entry(dispatcher, *args) -> tuple[int, int]:
    """(address, key) of ``dispatcher``'s machine code for these arguments (compiled here, or
    loaded from numba's cache): what :func:`native_call` in a compiled caller needs."""
    sig = tuple(typeof(a) for a in args)
    dispatcher.compile(sig)
    cres = dispatcher.overloads[sig]
    return cres.library.get_pointer_to_function(cres.fndesc.llvm_func_name), _key(dispatcher, sig)


@intrinsic
def native_call(typingctx, kernel, entry, args):
    """``kernel(*args)`` in compiled code (only), through ``entry`` = (address, key) of
    :func:`entry` for the same argument types; ``args``: a tuple."""
    if not isinstance(kernel, types.Dispatcher) or not isinstance(args, types.BaseTuple):
        return None
    callee = typingctx.resolve_function_type(kernel, tuple(args.types), {})  # compiles it
    if callee is None:
        return None
    argtypes, restype = tuple(callee.args), callee.return_type
    key = _key(kernel.dispatcher, argtypes)

    def codegen(context, builder, signature, llargs):
        _, entry_val, tup = llargs
        address = builder.extract_value(entry_val, 0)
        given = builder.extract_value(entry_val, 1)
        with cgutils.if_unlikely(builder, builder.icmp_unsigned(
                "!=", given, ir.Constant(given.type, key))):
            context.call_conv.return_user_exc(
                builder, RuntimeError, ("native_call: the entry is another kernel's or "
                                        "another specialisation's",))
        fnty = context.call_conv.get_function_type(restype, argtypes)
        fn = builder.inttoptr(address, fnty.as_pointer())
        vals = [context.cast(builder, v, frm, to) for v, frm, to in
                zip(cgutils.unpack_tuple(builder, tup), args.types, argtypes)]
        status, res = context.call_conv.call_function(builder, fn, restype, argtypes, vals)
        with cgutils.if_unlikely(builder, status.is_error):
            context.call_conv.return_status_propagate(builder, status)
        return res

    return restype(kernel, entry, args), codegen


def residual_entry(d) -> tuple[int, int]:
    """:func:`entry` of the DAE residual (system/residual.py) for the work tuple ``d``, as its
    callers pass it: ``(t, y, y', res, d)`` with float64 vectors."""
    from ..system.residual import residual

    v = np.empty(1)
    return entry(residual, 0.0, v, v, v, d)
