"""How the physics laws are compiled: one decorator, :data:`law`, for every law the DAE kernels
call (physics/contact.py, traction.py, kinematics.py, cage.py, lubricant.py).

Stage: physics, shared by the laws; no physics here.

A law is plain Python/numpy when called from Python (static solve, tests, plots) and, inside an
``@njit`` kernel (system/*), a numba function that LLVM always inlines (``forceinline``: the contact
loops stay free of calls and vectorise). Why not numba's own IR inlining (``inline="always"``),
which the laws used before: numba then re-types the law's body at every call site, and a law that
calls laws again at each of theirs; the contact kernels spent most of their compile time there (cold
start: -3.5 s of compile CPU for the same machine code). Compiled once per argument types instead
and inlined by LLVM, the kernels run at the same speed with the same results, bit for bit. A law is
never called from Python as compiled code, so numba builds neither of its wrappers (Python and C),
~15 ms each per law.
"""

from __future__ import annotations

from numba.extending import register_jitable

from ..util import numba_flags

# numba's flags hashed and compared without rebuilding their dicts (util/numba_flags.py): the
# same answers, ~4 % less compile CPU; applied as the laws load, before any kernel compiles
numba_flags.apply()

#: decorator of a physics law (see the module docstring)
law = register_jitable(forceinline=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
#: the same for a small helper that the kernels (system/*, solvers/*) call at several sites, e.g.
#: an accessor of the work buffers: compiled once per argument types (a literal argument, such as
#: an index, is typed as its type: one specialisation) and inlined by LLVM. Numba's IR inlining
#: (``inline="always"``) read the helper's bytecode and ran numba's passes on it again at every
#: call site: the ~60 accessor calls of the IDA callbacks cost ~1 s of a cold start.
helper = law


# Array copies as loops: an array assignment in a kernel (``dst[:] = src``, ``dq[s] = q``)
# compiles numba's shape-mismatch error path (string formatting), ~3 s of CPU the first time a
# process types it (the finite-difference Jacobian's three copies: 3.2 of its 7 s).
@helper
def copy1(dst, src):
    for i in range(src.shape[0]):
        dst[i] = src[i]


@helper
def copy2(dst, src):
    for i in range(src.shape[0]):
        for j in range(src.shape[1]):
            dst[i, j] = src[i, j]
