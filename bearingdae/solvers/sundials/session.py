"""One IDA integration on the bundled SUNDIALS: create, configure, step, report, free.

Stage: solvers (compiled IDA core; the contract lives in solvers/ida.py). The call sequence is
the one of the IDA user guide (SUNDIALS 7, "A skeleton of the user's main program"):
SUNContext_Create -> N_VNew_Serial (y, y', atol, id) -> SUNSparseMatrix + SUNLinSol_SuperLUMT
(or SUNDenseMatrix + SUNLinSol_Dense) -> IDACreate -> IDAInit(residual cfunc) ->
IDASVtolerances -> IDASetLinearSolver -> IDASetJacFn(Jacobian cfunc) -> optional inputs ->
IDACalcIC(IDA_YA_YDP_INIT) -> IDASolve(IDA_NORMAL) per output time -> IDAFree, SUNLinSolFree,
SUNMatDestroy, N_VDestroy, SUNContext_Free. :class:`Session` is a context manager: the memory
is freed on every exit path (failure, exception, Ctrl-C).

Every buffer whose address the callbacks read (``user_data``, the model's work arrays, the
Jacobian work, the pattern) is referenced by the session, so it outlives IDA's memory.
"""

from __future__ import annotations

import ctypes as C

import numpy as np

from .. import blockarrow
from . import callbacks, linsol, prototypes
from .prototypes import IDA_NORMAL, IDA_ONE_STEP, IDA_YA_YDP_INIT, CSC_MAT, IDALS_FLAGS, flag_message


class SetupError(RuntimeError):
    """A SUNDIALS set-up call failed (a bug or an out-of-memory, never a solver failure)."""


class Session:
    """IDA memory for one model and one run (see module docstring).

    ``y``, ``yp``: numpy views of IDA's solution vectors, valid while the session is open.
    """

    def __init__(self, n: int, y0, yp0, t0: float, residual_work, jacobian_work, jacobian,
                 pattern_rows, pattern_cols, linsolver: str, rtol: float, atol, algebraic,
                 max_steps: int, min_step: float, max_step: float, suppress_alg: bool = False,
                 blocks: tuple | None = None):
        self.api = api = prototypes.load()
        self._ptrs: dict = {}
        self.errors: list[str] = []
        self._keep = [residual_work, jacobian_work]
        self.n, self.linsolver = n, linsolver
        self.user_data = np.zeros(callbacks.N_SLOTS, np.int64)
        self.blocks = blocks  # (Z, n_local, n_global) of linsolver "blockarrow"
        try:
            self._create(n, y0, yp0, t0, residual_work, jacobian_work, jacobian, pattern_rows,
                         pattern_cols, linsolver, rtol, atol, algebraic, max_steps, min_step,
                         max_step, suppress_alg)
        except BaseException:
            self.close()
            raise

    # ---- set-up ---------------------------------------------------------------------------
    def _check(self, flag, what, table=None):
        if flag < 0:
            cause = (table or {}).get(flag) or flag_message(flag)
            last = f"; SUNDIALS said: {self.errors[-1]}" if self.errors else ""
            raise SetupError(f"{what} failed: {cause}{last}")

    def _vector(self, key, values):
        v = self.api.N_VNew_Serial(self.n, self._ptrs["ctx"])
        if not v:
            raise SetupError(f"N_VNew_Serial({self.n}) returned NULL (out of memory)")
        self._ptrs[key] = v
        arr = np.ctypeslib.as_array(C.cast(self.api.N_VGetArrayPointer(v),
                                           C.POINTER(C.c_double)), shape=(self.n,))
        arr[:] = values
        return v, arr

    def _create(self, n, y0, yp0, t0, residual_work, jacobian_work, jacobian, rows, cols,
                linsolver, rtol, atol, algebraic, max_steps, min_step, max_step, suppress_alg):
        api = self.api
        ctx = C.c_void_p()
        self._check(api.SUNContext_Create(None, C.byref(ctx)), "SUNContext_Create")
        self._ptrs["ctx"] = ctx.value
        # Replace the default handler (prints to stderr) by one that keeps the message: it is
        # quoted in the failure message. Called only on errors, so a Python callback is fine.
        self._handler = api.ErrHandler(self._on_error)
        api.SUNContext_ClearErrHandlers(ctx.value)
        api.SUNContext_PushErrHandler(ctx.value, self._handler, None)

        yv, self.y = self._vector("y", y0)
        ypv, self.yp = self._vector("yp", yp0)
        atv, _ = self._vector("atol", atol)
        idv, self._id = self._vector("id", np.where(algebraic, 0.0, 1.0))

        # CSC pattern (column-major, rows sorted); the dense matrix is the full pattern.
        if linsolver == "dense":
            rows = np.tile(np.arange(n, dtype=np.int64), n)
            cols = np.repeat(np.arange(n, dtype=np.int64), n)
        order = np.lexsort((rows, cols))
        rows, cols = np.ascontiguousarray(rows[order], np.int64), np.ascontiguousarray(
            cols[order], np.int64)
        indptr = np.zeros(n + 1, np.int64)
        np.cumsum(np.bincount(cols, minlength=n), out=indptr[1:])
        jd = jacobian_work(rows, cols)
        if linsolver in ("sparse", "blockarrow"):
            A = api.SUNSparseMatrix(n, n, rows.size, CSC_MAT, ctx.value)
            if not A:
                raise SetupError("SUNSparseMatrix returned NULL")
            self._ptrs["A"] = A
            matrix = (api.SUNSparseMatrix_Data(A), api.SUNSparseMatrix_IndexValues(A),
                      api.SUNSparseMatrix_IndexPointers(A))
            if linsolver == "sparse":
                LS = api.SUNLinSol_SuperLUMT(yv, A, 1, ctx.value)
            else:  # ours (solvers/blockarrow.py): factorises the dense jd[0] the Jacobian fills
                Z, nl, ng = self.blocks
                work = blockarrow.work_arrays(Z, nl, ng)
                content = linsol.content_slots(n, Z, nl, ng, api.nvec_data_offset, jd[0], work)
                self._keep += [work, content]
                LS = linsol.block_arrow_solver(api, ctx.value, content)
        else:
            A = api.SUNDenseMatrix(n, n, ctx.value)
            if not A:
                raise SetupError("SUNDenseMatrix returned NULL")
            self._ptrs["A"] = A
            matrix = (api.SUNDenseMatrix_Data(A), 0, 0)
            LS = api.SUNLinSol_Dense(yv, A, ctx.value)
        if not LS:
            raise SetupError(f"the {linsolver} linear solver constructor returned NULL")
        self._ptrs["LS"] = LS
        # (W, I, marker): the marker says which passes compile apart (system/optional.py)
        optional = residual_work[2]
        jac_cfunc = callbacks.compiled(jacobian, optional)
        layout = callbacks.JD_LAYOUT[jacobian]
        self.user_data = callbacks.user_data(n, api.nvec_data_offset, residual_work,
                                             api.build.index_bytes, matrix, (rows, indptr), jd,
                                             layout)
        self._keep += [rows, cols, indptr, jd]

        mem = api.IDACreate(ctx.value)
        if not mem:
            raise SetupError("IDACreate returned NULL")
        self._ptrs["mem"] = mem
        self._check(api.IDASetUserData(mem, self.user_data.ctypes.data), "IDASetUserData")
        self._check(api.IDAInit(mem, callbacks.compiled("residual", optional).address, t0, yv, ypv), "IDAInit")
        self._check(api.IDASVtolerances(mem, rtol, atv), "IDASVtolerances")
        self._check(api.IDASetLinearSolver(mem, LS, A), "IDASetLinearSolver", IDALS_FLAGS)
        self._check(api.IDASetJacFn(mem, jac_cfunc.address), "IDASetJacFn", IDALS_FLAGS)
        self._check(api.IDASetId(mem, idv), "IDASetId")
        self._check(api.IDASetMinStep(mem, min_step), "IDASetMinStep")
        self._check(api.IDASetMaxStep(mem, max_step), "IDASetMaxStep")
        self._check(api.IDASetMaxNumSteps(mem, int(max_steps)), "IDASetMaxNumSteps")
        if suppress_alg:
            self._check(api.IDASetSuppressAlg(mem, 1), "IDASetSuppressAlg")
        self.mem = mem
        self._yv, self._ypv, self._idv = yv, ypv, idv
        self._tret = C.c_double()

    def track_extremes(self, buffer: np.ndarray, rtol: float) -> None:
        """Fold every accepted step into the running-extremes ``buffer`` (system/extremes.py):
        IDA's error weights are computed by the compiled hook instead of IDA's own function
        (``IDAWFtolerances``; the same weights for ``rtol`` and the absolute tolerances given
        at creation), which IDA calls at the start of each step with the last accepted state.
        Call before :meth:`calc_ic`, then :meth:`arm_extremes` after it (the weights of the
        initialisation's iterates are not states). The buffer must outlive the session."""
        if buffer.dtype != np.float64 or not buffer.flags.c_contiguous:
            raise RuntimeError("track_extremes: expected a contiguous float64 buffer")
        from ...system.extremes import H_ARMED, H_RTOL
        from .callbacks import S_ATOL, S_EXT, S_EXTN, S_MEM, S_TNOW

        self._keep.append(buffer)
        self._extremes = buffer
        buffer[H_RTOL], buffer[H_ARMED] = rtol, 0.0
        U = self.user_data
        U[S_EXT], U[S_EXTN] = buffer.ctypes.data, buffer.size
        U[S_ATOL] = self.api.N_VGetArrayPointer(self._ptrs["atol"])
        U[S_MEM] = self.mem
        U[S_TNOW] = C.cast(self.api.IDAGetCurrentTime, C.c_void_p).value
        self._check(self.api.IDAWFtolerances(self.mem, callbacks.compiled("extremes").address),
                    "IDAWFtolerances")

    def arm_extremes(self) -> None:
        """From now on the hook of :meth:`track_extremes` folds the states it sees."""
        from ...system.extremes import H_ARMED

        self._extremes[H_ARMED] = 1.0

    def set_delta_cj_lsetup(self, dcj: float) -> None:
        """``IDASetDeltaCjLSetup``: IDA refreshes the Jacobian and its factorisation when
        c_j = α/h has changed by more than this fraction since the last one (SUNDIALS' default
        0.25)."""
        self._check(self.api.IDASetDeltaCjLSetup(self.mem, float(dcj)), "IDASetDeltaCjLSetup")

    def set_step_controls(self, max_order: int | None = None,
                          nonlin_conv_coef: float | None = None,
                          max_nonlin_iters: int | None = None,
                          eta_max_fx: float | None = None, eta_max: float | None = None,
                          eta_conv_fail: float | None = None) -> None:
        """``IDASetMaxOrd`` (SUNDIALS' default 5), ``IDASetNonlinConvCoef`` (0.33),
        ``IDASetMaxNonlinIters`` (4), the upper bound of the step ratio IDA keeps the step
        fixed below (``IDASetEtaFixedStepBounds``, 2; its lower bound stays SUNDIALS'), the
        largest growth of a step (``IDASetEtaMax``, 2) and the step's cut after a Newton
        failure (``IDASetEtaConvFail``, 0.25), each only when given: SUNDIALS' defaults
        otherwise."""
        if max_order is not None:
            self._check(self.api.IDASetMaxOrd(self.mem, int(max_order)), "IDASetMaxOrd")
        if nonlin_conv_coef is not None:
            self._check(self.api.IDASetNonlinConvCoef(self.mem, float(nonlin_conv_coef)),
                        "IDASetNonlinConvCoef")
        if max_nonlin_iters is not None:
            self._check(self.api.IDASetMaxNonlinIters(self.mem, int(max_nonlin_iters)),
                        "IDASetMaxNonlinIters")
        if eta_max_fx is not None:  # a lower bound < 0 is SUNDIALS' default
            self._check(self.api.IDASetEtaFixedStepBounds(self.mem, -1.0, float(eta_max_fx)),
                        "IDASetEtaFixedStepBounds")
        if eta_max is not None:
            self._check(self.api.IDASetEtaMax(self.mem, float(eta_max)), "IDASetEtaMax")
        if eta_conv_fail is not None:
            self._check(self.api.IDASetEtaConvFail(self.mem, float(eta_conv_fail)),
                        "IDASetEtaConvFail")

    def _on_error(self, line, func, file, msg, code, user_data, ctx):
        self.errors.append(f"{(func or b'').decode(errors='replace')}: "
                           f"{(msg or b'').decode(errors='replace').strip()}")

    # ---- integration ----------------------------------------------------------------------
    def calc_ic(self, t1: float) -> int:
        """IDACalcIC(IDA_YA_YDP_INIT, t1), then the corrected (y, y') into ``y``, ``yp``."""
        flag = self.api.IDACalcIC(self.mem, IDA_YA_YDP_INIT, t1)
        if flag >= 0:
            flag = self.api.IDAGetConsistentIC(self.mem, self._yv, self._ypv)
        return flag

    def suppress_algebraic(self) -> None:
        """Leave the algebraic unknowns out of IDA's local error test from now on
        (``IDASetSuppressAlg``, as ``suppress_alg`` at creation; between ``IDASolve`` calls)."""
        self._check(self.api.IDASetSuppressAlg(self.mem, 1), "IDASetSuppressAlg")

    def set_error_test_mask(self, in_error_test: np.ndarray) -> None:
        """Which unknowns IDA's local error test sees from now on (with ``suppress_alg``).

        IDA keeps its own copy of the id vector (``IDASetId`` clones it and copies the data,
        SUNDIALS 7 src/ida/ida_io.c) and reads that copy at every error test through
        ``N_VWrmsNormMask(x, ewt, id)`` (components with id > 0 count); ``IDACalcIC`` reads it
        too, as the algebraic/differential flag. So: call this only after :meth:`calc_ic`,
        between ``IDASolve`` calls; a differential unknown must stay in (True).
        """
        self._id[:] = np.where(in_error_test, 1.0, 0.0)
        self._check(self.api.IDASetId(self.mem, self._idv), "IDASetId")

    def restart(self, t: float, y: np.ndarray, yp: np.ndarray) -> None:
        """IDAReInit at (t, y, y'): a fresh BDF history (order 1), same options and solvers.

        IDAReInit zeroes IDA's counters (steps, residual calls, failures...), and the linear
        solver's at the next set-up: read them before (solvers/ida_statistics.StatsTracker.bank).
        """
        self.y[:] = y
        self.yp[:] = yp
        self._check(self.api.IDAReInit(self.mem, t, self._yv, self._ypv), "IDAReInit")

    def init_roots(self, count: int, function_address: int) -> None:
        """``IDARootInit``: IDA watches ``count`` root functions (the compiled callback at
        ``function_address``, solvers/sundials/roots.py); :meth:`solve` then returns
        ``IDA_ROOT_RETURN`` at a root, and :meth:`roots_found` says which."""
        self._check(self.api.IDARootInit(self.mem, int(count), function_address), "IDARootInit")
        self._roots = (C.c_int * int(count))()

    def roots_found(self) -> np.ndarray:
        """``IDAGetRootInfo``: per root function 0, or +1 / -1 where it crossed zero rising /
        falling at the root IDASolve last returned."""
        self._check(self.api.IDAGetRootInfo(self.mem, self._roots), "IDAGetRootInfo")
        return np.array(self._roots[:], dtype=np.int64)

    def solve(self, t_out: float) -> tuple[int, float]:
        """One IDASolve(IDA_NORMAL) to ``t_out``: (flag, time reached)."""
        flag = self.api.IDASolve(self.mem, t_out, C.byref(self._tret), self._yv, self._ypv,
                                 IDA_NORMAL)
        return flag, self._tret.value

    def solve_recording(self, t_out: float, steps_s: list, times_s: list,
                        limiters: list | None = None) -> tuple[int, float]:
        """As :meth:`solve`, but one internal step per IDASolve(IDA_ONE_STEP) call, appending
        each step size and the time it reached (and, to ``limiters``, the step's limiter:
        :meth:`limiter`); the final IDA_NORMAL call then only interpolates, so the trajectory
        is the one of :meth:`solve`. For benchmarks: a Python round trip per step, and
        ``max_steps`` then counts per step, not per output."""
        # A ONE_STEP call right after a NORMAL one that interpolated first returns the last
        # step's own result without stepping: only calls that took a step are recorded.
        steps = self.get_long("IDAGetNumSteps")
        while self.get_double("IDAGetCurrentTime") < t_out:
            flag = self.api.IDASolve(self.mem, t_out, C.byref(self._tret), self._yv,
                                     self._ypv, IDA_ONE_STEP)
            if flag < 0:
                return flag, self._tret.value
            now = self.get_long("IDAGetNumSteps")
            if now > steps:
                steps = now
                steps_s.append(self.get_double("IDAGetLastStep"))
                times_s.append(self._tret.value)
                if limiters is not None:
                    limiters.append(self.limiter())
        return self.solve(t_out)

    def limiter(self) -> int:
        """The unknown (its index in y) with the largest weighted local error |e_i w_i| of the
        step IDA last accepted (IDAGetEstLocalErrors, IDAGetErrWeights): the one whose error
        test sets the step size and order (IDA's test is on the weighted RMS norm of e)."""
        if "ele" not in self._ptrs:
            self._ele = self._vector("ele", 0.0)
            self._ewt = self._vector("ewt", 0.0)
        self.api.IDAGetEstLocalErrors(self.mem, self._ele[0])
        self.api.IDAGetErrWeights(self.mem, self._ewt[0])
        return int(np.argmax(np.abs(self._ele[1] * self._ewt[1])))

    def get_long(self, name: str) -> int:
        v = C.c_long()
        getattr(self.api, name)(self.mem, C.byref(v))
        return v.value

    def get_double(self, name: str) -> float:
        v = C.c_double()
        getattr(self.api, name)(self.mem, C.byref(v))
        return v.value

    def get_int(self, name: str) -> int:
        v = C.c_int()
        getattr(self.api, name)(self.mem, C.byref(v))
        return v.value

    def last_error(self) -> str:
        return self.errors[-1] if self.errors else ""

    # ---- freeing --------------------------------------------------------------------------
    def close(self) -> None:
        """Free every SUNDIALS object (idempotent)."""
        api, p = self.api, self._ptrs
        if p.get("mem"):
            m = C.c_void_p(p.pop("mem"))
            api.IDAFree(C.byref(m))
        if p.get("LS"):
            ls = p.pop("LS")
            # SUNDIALS 7.9's SUNLinSolFree_SuperLUMT finalises the factorisation it assumes was
            # made (pxgstrf_finalize on uninitialised memory): freeing a SuperLU_MT solver that
            # was never set up segfaults. It was set up iff a Jacobian succeeded (IDALs calls
            # SUNLinSolSetup right after); otherwise its few kB are left to the process.
            if self.linsolver == "blockarrow":
                linsol.free(api, ls)  # our content is numpy memory: not SUNDIALS' to free
            elif self.linsolver != "sparse" or self.user_data[callbacks.S_JOK] > 0:
                api.SUNLinSolFree(ls)
        if p.get("A"):
            api.SUNMatDestroy(p.pop("A"))
        for key in ("y", "yp", "atol", "id", "ele", "ewt"):
            if p.get(key):
                api.N_VDestroy(p.pop(key))
        if p.get("ctx"):
            c = C.c_void_p(p.pop("ctx"))
            api.SUNContext_Free(C.byref(c))
        self.mem = None
        # the handler holds a bound method of self: drop the cycle so the run's arrays (the
        # dense Jacobian work alone is n² doubles) go at once, not at the next cyclic GC
        self._handler = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False
