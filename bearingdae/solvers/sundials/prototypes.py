"""ctypes prototypes of the SUNDIALS 7.x functions the compiled IDA core calls, and IDA's flags.

Stage: solvers (compiled IDA core). Signatures follow the SUNDIALS 7 headers (``ida/ida.h``,
``ida/ida_ls.h``, ``nvector/nvector_serial.h``, ``sunmatrix/sunmatrix_{sparse,dense}.h``,
``sunlinsol/sunlinsol_{superlumt,dense}.h``, ``sundials/sundials_context.h``); the index type
(``sunindextype``) is 32 or 64 bit as the build says (library.py). Every call that can fail
returns a flag that ``session.py`` checks.

:func:`load` also measures where a serial N_Vector keeps its data pointer: the compiled
callbacks read it directly (``*(double**)((char*)v->content + offset)``, no call per vector)
and the offset is verified against ``N_VGetArrayPointer`` on two vectors, so a changed struct
layout is an error at start-up, never a wrong read.
"""

from __future__ import annotations

import ctypes as C
from functools import lru_cache
from types import SimpleNamespace

from .library import SundialsUnavailable, check_build, find_libraries

IDA_NORMAL = 1
IDA_ROOT_RETURN = 2  #: IDASolve stopped at a root of the root function (IDARootInit)
#: our flag (no IDA flag has it): the restart after a located defect edge failed
EDGE_RESTART_FAILED = -1000
IDA_ONE_STEP = 2
IDA_YA_YDP_INIT = 1
CSC_MAT = 0

#: IDA return flags (ida/ida.h and ida_ls.h) -> cause, as reported to the user
IDA_FLAGS = {
    1: "stop time reached", 2: "root found", 99: "warning",
    -1: "too much work: IDA's maximum number of internal steps per output interval "
        "(max_num_steps = numerics.max_steps) was taken before the next output time",
    -2: "too much accuracy requested for the machine precision",
    -3: "repeated error-test failures (or the step reached the minimum step size)",
    -4: "repeated Newton convergence failures (or the step reached the minimum step size)",
    -5: "the linear solver's initialisation failed",
    -6: "the linear solver's setup (Jacobian or factorisation) failed",
    -7: "the linear solver's solve failed",
    -8: "the residual failed unrecoverably",
    -9: "the residual kept failing (non-finite values) after step reductions",
    -10: "the root function failed",
    -11: "the inequality constraints could not be met",
    -12: "the residual failed at the first call",
    -13: "the line search of the consistent initialisation failed",
    -14: "the residual, linear solver or Jacobian failed recoverably but could not recover",
    -15: "the nonlinear solver's initialisation failed",
    -16: "the nonlinear solver's setup failed",
    -17: "the nonlinear solver failed",
    -20: "no IDA memory", -21: "out of memory", -22: "illegal input",
    -23: "IDA memory not initialised", -24: "an error weight became zero or negative",
    -25: "bad derivative order", -26: "bad output time", -27: "bad dky argument",
    -28: "a vector operation failed", -29: "SUNContext error", -99: "unrecognised error",
    # ours, not IDA's: solvers/ida_edges.py
    EDGE_RESTART_FAILED: "IDA could not be restarted after crossing a sharp defect edge "
                         "(numerics.defect_edges = 'locate'; 'smooth' ramps the edge instead)",
}
#: linear-solver interface flags (ida_ls.h) met by IDASetLinearSolver / IDASetJacFn
IDALS_FLAGS = {-1: "IDALS_MEM_NULL", -2: "IDALS_LMEM_NULL", -3: "IDALS_ILL_INPUT",
               -4: "IDALS_MEM_FAIL", -5: "IDALS_PMEM_NULL", -6: "IDALS_JACFUNC_UNRECVR",
               -7: "IDALS_JACFUNC_RECVR", -8: "IDALS_SUNMAT_FAIL", -9: "IDALS_SUNLS_FAIL"}


def flag_message(flag: int) -> str:
    return f"{IDA_FLAGS.get(flag, 'unknown IDA flag')} (IDA flag {flag})"


def _proto(lib, name, restype, *argtypes):
    f = getattr(lib, name)
    f.restype, f.argtypes = restype, list(argtypes)
    return f


@lru_cache(maxsize=1)
def load() -> SimpleNamespace:
    """The bound functions (``api.IDASolve`` ...), the build facts (``api.build``) and the
    serial N_Vector data offset (``api.nvec_data_offset``); cached for the process."""
    paths = find_libraries()
    libs = {k: C.CDLL(v) for k, v in paths.items()}
    build = check_build(libs["core"], paths)
    idx = C.c_int32 if build.index_bytes == 4 else C.c_int64
    P, D, I, L = C.c_void_p, C.c_double, C.c_int, C.c_long
    core, ida, nv = libs["core"], libs["ida"], libs["nvecserial"]
    sps, dns = libs["sunmatrixsparse"], libs["sunmatrixdense"]
    slu, lsd = libs["sunlinsolsuperlumt"], libs["sunlinsoldense"]
    a = SimpleNamespace(build=build, index_type=idx)
    # context, vectors, matrices, linear solvers
    a.SUNContext_Create = _proto(core, "SUNContext_Create", I, P, C.POINTER(P))
    a.SUNContext_Free = _proto(core, "SUNContext_Free", I, C.POINTER(P))
    a.SUNContext_ClearErrHandlers = _proto(core, "SUNContext_ClearErrHandlers", I, P)
    a.ErrHandler = C.CFUNCTYPE(None, I, C.c_char_p, C.c_char_p, C.c_char_p, I, P, P)
    a.SUNContext_PushErrHandler = _proto(core, "SUNContext_PushErrHandler", I, P,
                                         a.ErrHandler, P)
    a.N_VNew_Serial = _proto(nv, "N_VNew_Serial", P, idx, P)
    a.N_VGetArrayPointer = _proto(core, "N_VGetArrayPointer", P, P)
    a.N_VDestroy = _proto(core, "N_VDestroy", None, P)
    a.SUNSparseMatrix = _proto(sps, "SUNSparseMatrix", P, idx, idx, idx, I, P)
    a.SUNSparseMatrix_Data = _proto(sps, "SUNSparseMatrix_Data", P, P)
    a.SUNSparseMatrix_IndexValues = _proto(sps, "SUNSparseMatrix_IndexValues", P, P)
    a.SUNSparseMatrix_IndexPointers = _proto(sps, "SUNSparseMatrix_IndexPointers", P, P)
    a.SUNDenseMatrix = _proto(dns, "SUNDenseMatrix", P, idx, idx, P)
    a.SUNDenseMatrix_Data = _proto(dns, "SUNDenseMatrix_Data", P, P)
    a.SUNMatDestroy = _proto(core, "SUNMatDestroy", None, P)
    a.SUNLinSol_SuperLUMT = _proto(slu, "SUNLinSol_SuperLUMT", P, P, P, I, P)
    a.SUNLinSol_Dense = _proto(lsd, "SUNLinSol_Dense", P, P, P, P)
    a.SUNLinSolFree = _proto(core, "SUNLinSolFree", I, P)
    a.SUNLinSolNewEmpty = _proto(core, "SUNLinSolNewEmpty", P, P)
    a.SUNLinSolInitialize = _proto(core, "SUNLinSolInitialize", I, P)
    a.SUNLinSolSetup = _proto(core, "SUNLinSolSetup", I, P, P)
    a.SUNLinSolSolve = _proto(core, "SUNLinSolSolve", I, P, P, P, P, D)
    a.libraries = libs  # every mapped libsundials_*, by component (benchmarks use the others)
    # IDA
    a.IDACreate = _proto(ida, "IDACreate", P, P)
    a.IDAFree = _proto(ida, "IDAFree", None, C.POINTER(P))
    a.IDAInit = _proto(ida, "IDAInit", I, P, P, D, P, P)
    a.IDASVtolerances = _proto(ida, "IDASVtolerances", I, P, D, P)
    a.IDASetUserData = _proto(ida, "IDASetUserData", I, P, P)
    a.IDASetLinearSolver = _proto(ida, "IDASetLinearSolver", I, P, P, P)
    a.IDASetJacFn = _proto(ida, "IDASetJacFn", I, P, P)
    a.IDASetId = _proto(ida, "IDASetId", I, P, P)
    a.IDASetSuppressAlg = _proto(ida, "IDASetSuppressAlg", I, P, I)
    a.IDASetMaxNumSteps = _proto(ida, "IDASetMaxNumSteps", I, P, L)
    a.IDASetMinStep = _proto(ida, "IDASetMinStep", I, P, D)
    a.IDASetMaxStep = _proto(ida, "IDASetMaxStep", I, P, D)
    a.IDASetMaxOrd = _proto(ida, "IDASetMaxOrd", I, P, I)
    a.IDASetDeltaCjLSetup = _proto(ida, "IDASetDeltaCjLSetup", I, P, D)
    a.IDASetMaxNonlinIters = _proto(ida, "IDASetMaxNonlinIters", I, P, I)
    a.IDASetNonlinConvCoef = _proto(ida, "IDASetNonlinConvCoef", I, P, D)
    a.IDASetEtaFixedStepBounds = _proto(ida, "IDASetEtaFixedStepBounds", I, P, D, D)
    a.IDASetEtaMax = _proto(ida, "IDASetEtaMax", I, P, D)
    a.IDASetEtaConvFail = _proto(ida, "IDASetEtaConvFail", I, P, D)
    a.IDASetMaxConvFails = _proto(ida, "IDASetMaxConvFails", I, P, I)
    a.IDAReInit = _proto(ida, "IDAReInit", I, P, D, P, P)
    a.IDAWFtolerances = _proto(ida, "IDAWFtolerances", I, P, P)
    a.IDACalcIC = _proto(ida, "IDACalcIC", I, P, I, D)
    a.IDAGetConsistentIC = _proto(ida, "IDAGetConsistentIC", I, P, P, P)
    a.IDASolve = _proto(ida, "IDASolve", I, P, D, C.POINTER(D), P, P, I)
    a.IDARootInit = _proto(ida, "IDARootInit", I, P, I, P)  # (mem, nrtfn, IDARootFn)
    a.IDAGetRootInfo = _proto(ida, "IDAGetRootInfo", I, P, C.POINTER(I))
    for name in ("IDAGetNumSteps", "IDAGetNumResEvals", "IDAGetNumErrTestFails",
                 "IDAGetNumNonlinSolvConvFails", "IDAGetNumNonlinSolvIters",
                 "IDAGetNumLinSolvSetups", "IDAGetNumJacEvals", "IDAGetNumLinResEvals",
                 "IDAGetNumLinIters", "IDAGetNumGEvals"):
        setattr(a, name, _proto(ida, name, I, P, C.POINTER(L)))
    for name in ("IDAGetLastStep", "IDAGetCurrentStep", "IDAGetCurrentTime"):
        setattr(a, name, _proto(ida, name, I, P, C.POINTER(D)))
    for name in ("IDAGetLastOrder", "IDAGetCurrentOrder"):
        setattr(a, name, _proto(ida, name, I, P, C.POINTER(I)))
    for name in ("IDAGetEstLocalErrors", "IDAGetErrWeights"):  # (mem, N_Vector out)
        setattr(a, name, _proto(ida, name, I, P, P))
    a.nvec_data_offset = _nvector_data_offset(a)
    return a


def _nvector_data_offset(a) -> int:
    """Byte offset of ``data`` in ``struct _N_VectorContent_Serial`` (verified, see module)."""
    ctx = C.c_void_p()
    if a.SUNContext_Create(None, C.byref(ctx)) != 0:
        raise SundialsUnavailable("SUNContext_Create failed")
    vecs = [a.N_VNew_Serial(n, ctx) for n in (3, 5)]
    try:
        found = None
        for off in (8, 16, 24):
            ok = True
            for v in vecs:
                content = C.cast(v, C.POINTER(C.c_void_p))[0]  # v->content (first member)
                ptr = C.cast(content + off, C.POINTER(C.c_void_p))[0]
                ok &= ptr == a.N_VGetArrayPointer(v)
            if ok:
                found = off
                break
    finally:
        for v in vecs:
            a.N_VDestroy(v)
        a.SUNContext_Free(C.byref(ctx))
    if found is None:
        raise SundialsUnavailable(
            f"SUNDIALS {a.build.version}: the serial N_Vector layout differs from the 7.x one "
            "the compiled callbacks read; use solver IDAScikitSundae() with this build")
    return found
