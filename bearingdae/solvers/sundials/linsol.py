"""The block-arrow linear solver as a SUNDIALS ``SUNLinearSolver`` with compiled operations.

Stage: solvers (compiled IDA core). IDA's linear-solver interface calls, per set-up, our
Jacobian callback (callbacks.py: it fills the dense iteration matrix ``jd[0]`` and the CSC
SUNMatrix) and then ``SUNLinSolSetup(LS, A)``; per Newton iteration ``SUNLinSolSolve(LS, A, x,
b, tol)``. This module gives IDA a solver of type DIRECT whose ``setup`` factorises ``jd[0]``
by solvers/blockarrow.py and whose ``solve`` applies the factors: numba ``cfunc``s, no Python.

The solver object is SUNDIALS' own empty one (``SUNLinSolNewEmpty``): we write the addresses of
our operations into its ``ops`` table and the address of an int64 slot array (``L_*`` below:
sizes and the addresses of the work arrays) into ``content``, the struct's first member. Where
the ops pointer sits in the struct (7.9: third, after ``content`` and a slot for SUNDIALS' own
Python bindings; older headers: second) and the slot index of each operation in the table are
found at start-up from SUNDIALS' dense solver (its struct, read back, must hold its exported
``SUNLinSol*_Dense`` functions at the same indices), so a SUNDIALS with another layout gives a clear :class:`~.library.SundialsUnavailable` instead of a crash. ``content`` is set back to
NULL before ``SUNLinSolFree`` (which would otherwise ``free()`` our numpy memory).

IDA scales the solution for a changed c_j itself (``scalesol`` for DIRECT solvers).
"""

from __future__ import annotations

import ctypes as C
from functools import lru_cache

import numpy as np
from numba import cfunc, njit, types

from .. import blockarrow
from .callbacks import _nvector
from .library import SundialsUnavailable
from .memory import address, f64_at, i64_at

# ---- content slots (int64) ----
L_N, L_Z, L_NL, L_NG, L_OFF, L_J, L_AINV, L_W, L_C, L_S, L_PIV, L_M = range(12)
L_LAST, L_SETUPS, L_FAILS = 12, 13, 14
N_LSLOTS = 15

SUNLINEARSOLVER_DIRECT = 0
SUNLS_LUFACT_FAIL = 808  # recoverable: IDA retries with a smaller step
#: the ops-table slots we fill (SUNDIALS 7.x sundials_linearsolver.h), checked at start-up
OPS = {"gettype": 0, "getid": 1, "initialize": 7, "setup": 8, "solve": 9, "lastflag": 12,
       "free": 15}
N_OPS = 16
_DENSE_NAMES = {"gettype": "SUNLinSolGetType_Dense", "getid": "SUNLinSolGetID_Dense",
                "initialize": "SUNLinSolInitialize_Dense", "setup": "SUNLinSolSetup_Dense",
                "solve": "SUNLinSolSolve_Dense", "lastflag": "SUNLinSolLastFlag_Dense",
                "free": "SUNLinSolFree_Dense"}


# (no Python wrapper: compiled code calls it, never Python; sundials/callbacks.py)
@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True, no_cpython_wrapper=True)
def _content(S):
    """The slot array behind ``S->content`` (first member of the generic struct)."""
    addr = i64_at(address(S), (1,))[0]
    return i64_at(addr, (N_LSLOTS,))


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True, no_cpython_wrapper=True)
def _arrays(U):
    Z, nl, ng, n = U[L_Z], U[L_NL], U[L_NG], U[L_N]
    return (f64_at(U[L_J], (n, n)), f64_at(U[L_AINV], (Z, nl, nl)),
            f64_at(U[L_W], (Z, nl, ng)), f64_at(U[L_C], (Z, ng, nl)),
            f64_at(U[L_S], (ng, ng)), i64_at(U[L_PIV], (ng,)),
            f64_at(U[L_M], (nl, 2 * nl + ng)))


def _gettype(S):
    return SUNLINEARSOLVER_DIRECT


def _getid(S):
    return 17  # SUNLINEARSOLVER_CUSTOM (7.x enum); IDA does not branch on it


def _initialize(S):
    return 0


def _lastflag(S):
    return _content(S)[L_LAST]


def _setup(S, A):
    U = _content(S)
    J, Ainv, W, Cm, Sm, piv, M = _arrays(U)
    flag = blockarrow.factor(J, U[L_Z], U[L_NL], U[L_NG], Ainv, W, Cm, Sm, piv, M)
    U[L_LAST] = flag
    U[L_SETUPS] += 1
    if flag != 0:
        U[L_FAILS] += 1
        return SUNLS_LUFACT_FAIL
    return 0


def _solve(S, A, x, b, tol):
    U = _content(S)
    J, Ainv, W, Cm, Sm, piv, M = _arrays(U)
    n, off = U[L_N], U[L_OFF]
    blockarrow.solve(U[L_Z], U[L_NL], U[L_NG], Ainv, W, Cm, Sm, piv, _nvector(b, off, n),
                     _nvector(x, off, n))
    return 0


_SIGS = {
    "gettype": (_gettype, types.int32(types.voidptr)),
    "getid": (_getid, types.int32(types.voidptr)),
    "initialize": (_initialize, types.int32(types.voidptr)),
    "lastflag": (_lastflag, types.int64(types.voidptr)),
    "setup": (_setup, types.int32(types.voidptr, types.voidptr)),
    "solve": (_solve, types.int32(types.voidptr, types.voidptr, types.voidptr, types.voidptr,
                                  types.float64)),
}


#: the operations we compile (``free`` is SUNDIALS' own)
COMPILED_OPS = ("gettype", "getid", "initialize", "setup", "solve", "lastflag")


def compile_operations(ops=COMPILED_OPS) -> None:
    """Compile (or load from numba's cache) the operations ``ops`` of the block-arrow solver
    (all by default; a cold start splits them between two processes: precompile.py)."""
    for op in ops:
        _compiled(op)


@lru_cache(maxsize=None)
def _compiled(op: str):
    fn, sig = _SIGS[op]
    return cfunc(sig, cache=True, error_model="numpy")(fn)


_OPS_INDEX: list = []  #: index of the ops pointer in the generic struct (found once, at start-up)
_STRUCT_FIELDS_MAX = 4


def check_ops_layout(api) -> None:
    """Raise :class:`SundialsUnavailable` unless SUNDIALS' dense solver holds its operations at the slots
    of :data:`OPS` (the layout this module writes into)."""
    if _OPS_INDEX:  # checked in this process already
        return
    dense = api.libraries.get("sunlinsoldense")
    if dense is None:
        raise SundialsUnavailable("the SUNDIALS dense linear solver library was not found; it is needed "
                         "to check the SUNLinearSolver layout")
    ctx = C.c_void_p()
    if api.SUNContext_Create(None, C.byref(ctx)) != 0:
        raise SundialsUnavailable("SUNContext_Create failed")
    v = A = LS = None
    try:
        v = api.N_VNew_Serial(2, ctx.value)
        A = api.SUNDenseMatrix(2, 2, ctx.value)
        LS = api.SUNLinSol_Dense(v, A, ctx.value)
        if not (v and A and LS):
            raise SundialsUnavailable("could not create SUNDIALS' dense solver to check the layout")
        # the generic struct: content first, then (7.9: a NULL slot for SUNDIALS' own Python
        # bindings) the ops table and the context; find the ops table and the context
        struct = C.cast(LS, C.POINTER(C.c_void_p))
        fields = [struct[i] for i in range(_STRUCT_FIELDS_MAX)]
        want = {op: C.cast(getattr(dense, _DENSE_NAMES[op]), C.c_void_p).value for op in OPS}
        ops_index = None
        for i, f in enumerate(fields[: fields.index(ctx.value) if ctx.value in fields else 0]):
            if i > 0 and f:
                table = C.cast(f, C.POINTER(C.c_void_p))
                if table[OPS["setup"]] == want["setup"]:
                    ops_index = i
                    break
        if ops_index is None or not fields[0]:
            raise SundialsUnavailable(
                "SUNLinearSolver struct: no ops table after the content and before the context; "
                "this SUNDIALS build is not the layout bearingdae's block-arrow solver was "
                "written for (use IDA(linsolver='sparse'))")
        table = C.cast(fields[ops_index], C.POINTER(C.c_void_p))
        table = [table[i] or 0 for i in range(N_OPS)]
        for op, slot in OPS.items():
            if table[slot] != want[op]:
                found = table.index(want[op]) if want[op] in table else None
                raise SundialsUnavailable(
                    f"SUNLinearSolver ops table: '{op}' expected at slot {slot}, SUNDIALS has it "
                    f"at {found}; this SUNDIALS build is not the layout bearingdae's block-arrow "
                    "solver was written for (use IDA(linsolver='sparse'))")
        _OPS_INDEX.append(ops_index)
    finally:
        if LS:
            api.SUNLinSolFree(LS)
        if A:
            api.SUNMatDestroy(A)
        if v:
            api.N_VDestroy(v)
        api.SUNContext_Free(C.byref(ctx))


def content_slots(n: int, rollers: int, n_local: int, n_global: int, nvec_offset: int,
                  jacobian_dense: np.ndarray, work: tuple) -> np.ndarray:
    """The int64 ``content`` array; ``work``: blockarrow.work_arrays(...), kept alive by the
    caller as long as the solver lives, like ``jacobian_dense`` (the Jacobian callback's
    dense iteration matrix, jd[0])."""
    if n != rollers * n_local + n_global or jacobian_dense.shape != (n, n):
        raise SundialsUnavailable(f"block-arrow solver: n = {n} is not Z·nl + ng = {rollers}·{n_local} "
                         f"+ {n_global}, or the dense Jacobian is {jacobian_dense.shape}")
    Ainv, W, Cm, S, piv, M = work
    U = np.zeros(N_LSLOTS, np.int64)
    U[L_N], U[L_Z], U[L_NL], U[L_NG], U[L_OFF] = n, rollers, n_local, n_global, nvec_offset
    for slot, a in ((L_J, jacobian_dense), (L_AINV, Ainv), (L_W, W), (L_C, Cm), (L_S, S),
                    (L_PIV, piv), (L_M, M)):
        if not a.flags.c_contiguous:
            raise SundialsUnavailable("block-arrow solver: work arrays must be C-contiguous")
        U[slot] = a.ctypes.data
    return U


def block_arrow_solver(api, ctx: int, content: np.ndarray) -> int:
    """A new SUNLinearSolver (address) whose operations are the compiled block-arrow ones;
    free it with :func:`free`."""
    check_ops_layout(api)
    LS = api.SUNLinSolNewEmpty(ctx)
    if not LS:
        raise SundialsUnavailable("SUNLinSolNewEmpty returned NULL")
    struct = C.cast(LS, C.POINTER(C.c_void_p))
    ops = C.cast(struct[_OPS_INDEX[0]], C.POINTER(C.c_void_p))
    for op in COMPILED_OPS:
        ops[OPS[op]] = _compiled(op).address
    struct[0] = content.ctypes.data
    return LS


def free(api, LS: int) -> None:
    """Free the solver object, not our content (SUNLinSolFree would free() a non-NULL one)."""
    if LS:
        C.cast(LS, C.POINTER(C.c_void_p))[0] = None
        api.SUNLinSolFree(LS)
