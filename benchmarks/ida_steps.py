"""IDA step statistics that scikit-sundae 1.2 does not expose (benchmark helper, not package code).

scikit-sundae returns only ``nfev``/``njev``. SUNDIALS itself keeps the step count, the
error-test and nonlinear-convergence failures and the last step size in its IDA memory; this
module reads them with ``ctypes`` from the same ``libsundials_ida`` the extension links.

How the IDA memory is found: ``sksundae.ida.IDA`` wraps a Cython ``_IDA`` object whose first
C field after the object header and the Cython vtable pointer is ``void* mem``
(``sksundae/_cy_ida.pyx``: ``cdef class IDA: cdef void* mem ...``). That layout is an
implementation detail, so every reading is **verified**: the residual-call count read through
the pointer must equal the ``nfev`` scikit-sundae reports, else :class:`StepStatsUnavailable`
is noted and the benchmark prints "n/a" instead of guessing.

:func:`recording_make_solver` wraps ``bearingdae.solvers.ida.make_solver`` so that
``simulate`` runs unchanged while every internal step size is recorded: a ``step(t)`` call
(IDA_NORMAL) is replayed as IDA_ONE_STEP calls up to ``t`` followed by the same IDA_NORMAL call,
which then only interpolates. IDA takes the same internal steps either way (NORMAL mode steps
past ``t`` and interpolates), so the trajectory is unchanged; the benchmark checks this by
comparing residual-call counts with an unwrapped run. If the IDA memory cannot be verified, the
proxy passes every call through unchanged and sets ``StepRecord.unavailable`` to the reason. One difference: IDA's ``max_num_steps``
counts per IDASolve call, i.e. per ONE_STEP call here, so a run that fails by exceeding it
in the plain run would not fail in the recording run.
"""

from __future__ import annotations

import ctypes
import glob
import os
from dataclasses import dataclass, field

# Offset of `void* mem` in the Cython object: PyObject header (refcount, type) + vtable pointer.
_MEM_OFFSET = 3 * ctypes.sizeof(ctypes.c_void_p)


class StepStatsUnavailable(RuntimeError):
    """The IDA memory could not be located or verified."""


def _library():
    import sksundae

    libdir = os.path.join(os.path.dirname(os.path.dirname(sksundae.__file__)),
                          "scikit_sundae.libs")
    found = glob.glob(os.path.join(libdir, "libsundials_ida*"))
    if not found:
        raise StepStatsUnavailable(f"libsundials_ida not found in {libdir}")
    # dlopen of an already loaded file returns the same handle: these are the functions the
    # extension itself calls.
    lib = ctypes.CDLL(found[0])
    for name in ("IDAGetNumSteps", "IDAGetNumResEvals", "IDAGetNumErrTestFails",
                 "IDAGetNumNonlinSolvConvFails", "IDAGetNumNonlinSolvIters",
                 "IDAGetNumLinSolvSetups"):
        getattr(lib, name).argtypes = [ctypes.c_void_p, ctypes.POINTER(ctypes.c_long)]
    for name in ("IDAGetLastStep", "IDAGetCurrentTime"):
        getattr(lib, name).argtypes = [ctypes.c_void_p, ctypes.POINTER(ctypes.c_double)]
    return lib


@dataclass
class StepRecord:
    """Step statistics of one integration (filled by :class:`RecordingIDA`)."""

    steps_s: list = field(default_factory=list)  #: size of every accepted internal step [s]
    times_s: list = field(default_factory=list)  #: time reached by each of those steps [s]
    steps: int = 0
    error_test_failures: int = 0
    nonlinear_convergence_failures: int = 0
    nonlinear_iterations: int = 0
    linear_solver_setups: int = 0
    max_steps_per_output: int = 0  #: most internal steps between two output times
    unavailable: str | None = None  #: why nothing was recorded (None: recorded)


class RecordingIDA:
    """Proxy of an ``sksundae.ida.IDA`` that records every internal step (see module doc)."""

    def __init__(self, solver, record: StepRecord):
        self._solver = solver
        self._record = record
        self._lib = _library()
        self._mem = None

    def __getattr__(self, name):
        return getattr(self._solver, name)

    def _long(self, fn: str) -> int:
        v = ctypes.c_long()
        flag = getattr(self._lib, fn)(self._mem, ctypes.byref(v))
        if flag != 0:
            raise StepStatsUnavailable(f"{fn} returned {flag}")
        return int(v.value)

    def _double(self, fn: str) -> float:
        v = ctypes.c_double()
        flag = getattr(self._lib, fn)(self._mem, ctypes.byref(v))
        if flag != 0:
            raise StepStatsUnavailable(f"{fn} returned {flag}")
        return float(v.value)

    def init_step(self, t0, y0, yp0):
        r = self._solver.init_step(t0, y0, yp0)
        try:
            self._locate(r)
        except StepStatsUnavailable as exc:
            self._mem = None
            self._record.unavailable = str(exc)
        return r

    def _locate(self, r) -> None:
        inner = getattr(self._solver, "_IDA__IDA", None)
        if inner is None:
            raise StepStatsUnavailable("sksundae.ida.IDA has no _IDA__IDA attribute")
        self._mem = ctypes.c_void_p(ctypes.c_void_p.from_address(id(inner) + _MEM_OFFSET).value)
        if not self._mem.value:
            raise StepStatsUnavailable("IDA memory pointer is NULL")
        if self._long("IDAGetNumResEvals") != int(r.nfev):
            raise StepStatsUnavailable("residual count read through the IDA memory does not "
                                       "match scikit-sundae's nfev: layout differs")

    def step(self, t, method="normal", tstop=None):
        if method != "normal" or self._mem is None:
            return self._solver.step(t, method, tstop)
        rec = self._record
        n_before = self._long("IDAGetNumSteps")
        stalls = 0
        while self._double("IDAGetCurrentTime") < t and stalls < 2:
            nst = self._long("IDAGetNumSteps")
            r = self._solver.step(t, "onestep", tstop)
            if r.status < 0:
                self._update(n_before)
                return r
            if self._long("IDAGetNumSteps") > nst:
                rec.steps_s.append(self._double("IDAGetLastStep"))
                rec.times_s.append(self._double("IDAGetCurrentTime"))
                stalls = 0
            else:  # first ONE_STEP call after an interpolated return gives t_n back unchanged
                stalls += 1
            if r.status == 1:  # reached tstop
                break
        r = self._solver.step(t, "normal", tstop)
        if r.status >= 0 and self._long("IDAGetNumResEvals") != int(r.nfev):
            self._record.unavailable = "residual count mismatch during the run"
        self._update(n_before)
        return r

    def _update(self, n_before: int) -> None:
        rec = self._record
        rec.steps = self._long("IDAGetNumSteps")
        rec.max_steps_per_output = max(rec.max_steps_per_output, rec.steps - n_before)
        rec.error_test_failures = self._long("IDAGetNumErrTestFails")
        rec.nonlinear_convergence_failures = self._long("IDAGetNumNonlinSolvConvFails")
        rec.nonlinear_iterations = self._long("IDAGetNumNonlinSolvIters")
        rec.linear_solver_setups = self._long("IDAGetNumLinSolvSetups")


def recording_make_solver(original, record: StepRecord):
    """A drop-in for ``bearingdae.solvers.ida.make_solver`` returning a :class:`RecordingIDA`."""

    def make_solver(*args, **kwargs):
        solver, counts = original(*args, **kwargs)
        return RecordingIDA(solver, record), counts

    return make_solver
