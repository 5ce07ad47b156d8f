"""IDA's residual and Jacobian as compiled C callbacks (numba ``cfunc``): no Python per call.

Stage: solvers (compiled IDA core). SUNDIALS calls

    IDAResFn:   int res(sunrealtype t, N_Vector yy, N_Vector yp, N_Vector rr, void* user_data)
    IDALsJacFn: int jac(sunrealtype t, sunrealtype cj, N_Vector yy, N_Vector yp, N_Vector rr,
                        SUNMatrix J, void* user_data, N_Vector tmp1, tmp2, tmp3)
    IDAEwtFn:   int efun(N_Vector y, N_Vector ewt, void* user_data)
                (IDA's error weights, and the per-step extremes hook: system/extremes.py)

and these functions call the model's own kernels — ``residual`` (system/residual.py),
``fill_jacobian_analytic`` + ``gather_csc`` (the body of ``jacobian_analytic_sparse``,
system/jacobian_analytic.py) or ``jacobian_sparse`` (system/jacobian.py) — on views of
SUNDIALS' memory and of the model's work buffers. Everything a callback needs comes through
``user_data``: an int64 array of addresses and sizes (slots ``S_*`` below, filled by :func:`user_data`). Nothing is
baked into the compiled code (no ctypes function, no address), so ``cache=True`` holds across
processes. Serial N_Vector data is read as ``((double**)((char*)v->content + offset))[0]``
with the offset measured and verified at start-up (prototypes.py).

Return flags: 0 success; 1 (recoverable: IDA cuts the step) when the residual or the matrix
holds a NaN or inf — a cfunc cannot raise, and a NaN must not reach the Newton iteration.

IDA's linear-solver setup zeroes the matrix before calling the Jacobian (``SUNMatZero``, which
for a sparse matrix also clears its index arrays), so the sparse pattern is rewritten on every
call. A dense matrix is handled as a sparse one whose pattern is every entry in column-major
order: the same kernels fill it.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from numba import cfunc, njit, types
from numba.extending import overload

from ...physics.compiled import helper
from ...system import work as _work_module
from ...system.jacobian import gather_csc, jacobian_sparse
from ...system.extremes import H_ARMED, H_RTOL, H_TNOW, update_extremes
from ...system.jacobian_analytic import fill_jacobian_analytic
from ...system.optional import DEFECTS, EXTENSION, apart_marker, pattern_tag, variant
from ...system.residual import residual
from . import precompile
from .memory import address, call_int_ptr_ptr, f64_at, i32_at, i64_at

#: the layout of the work tuple ``d`` that the callbacks rebuild (system/residual.py)
MODEL_WORK_NDIM = (1, 1, 1, 1, 1, 1, 1, 1, 1, 2, 2, 1, 1, 2, 1, 2, 3, 3, 3, 3, 2, 2, 2)
MODEL_WORK_INT = (5, 6)

# ---- user_data slots (int64) ----
S_N, S_OFF, S_W, S_WN, S_I, S_IN, S_IDXB, S_WRITE_IDX = 0, 1, 2, 3, 4, 5, 6, 7
S_MDATA, S_MIDX, S_MPTR, S_NNZ, S_PROWS, S_PPTR = 8, 9, 10, 11, 12, 13
S_JD = 14  #: then (address, dim0, dim1) per array of the Jacobian work tuple
MAX_JD = 9
#: successful Jacobian evaluations: each is followed by a linear-solver setup (session.py frees
#: SuperLU_MT only once it has been set up: freeing it before crashes, see there)
S_JOK = S_JD + 3 * MAX_JD
#: residual / Jacobian evaluations refused as non-finite (returned 1: IDA retries smaller)
S_RFAIL, S_JFAIL = S_JOK + 1, S_JOK + 2
#: the per-step extremes hook: the running-extremes buffer (system/extremes.py) and its size,
#: the data of IDA's absolute-tolerance vector, IDA's memory and ``IDAGetCurrentTime``
S_EXT, S_EXTN, S_ATOL, S_MEM, S_TNOW = S_JOK + 3, S_JOK + 4, S_JOK + 5, S_JOK + 6, S_JOK + 7
N_SLOTS = S_JOK + 8

#: (kind, ndim) of each array of the Jacobian work tuples, as the cfuncs rebuild them:
#: analytic (system/jacobian_analytic.analytic_work) and finite differences (ida._jacobian_work)
JD_ANALYTIC = (("f", 2), ("i", 1), ("i", 1), ("f", 1), ("f", 2), ("f", 2), ("f", 2), ("f", 2))
JD_FD = (("f", 2), ("i", 1), ("i", 1), ("f", 1), ("f", 1), ("f", 1), ("f", 2), ("f", 2),
         ("f", 1))


# Every kernel compiles without numba's C wrapper (no kernel is a first-class function
# value), and these private helpers, which only compiled callbacks call, without its Python
# wrapper as well (called from Python they would crash): at a cold start each wrapper was
# typing, lowering and machine code for nothing (docs/performance.md, "Cold start").
@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True, no_cpython_wrapper=True)
def _slots(ud):
    return i64_at(address(ud), (N_SLOTS,))


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True, no_cpython_wrapper=True)
def _nvector(v, offset, n):
    """The data of a serial N_Vector ``v`` as a float64 array of length n (no copy)."""
    content = i64_at(address(v), (1,))[0]
    data = i64_at(content + offset, (1,))[0]
    return f64_at(data, (n,))


# The model's work tuple ``d`` (system/work.py ``flat_work``: the float buffer W, the int
# buffer I, whose header holds per entry its offset and shape) is rebuilt in each callback from
# the two buffer addresses (memory.py): the same array types as ``model.data`` from Python
# (C-contiguous, writable), so the callbacks call the very specialisation of ``residual`` that
# the initial state compiles. Why, for the cold start: this replaces
# ``residual_flat`` and ``work_views`` in the callbacks, two compiled layers (each compiled
# function re-optimises and re-emits all it links, here the whole residual: ~0.5 s each) and a
# compiled function returning the 23-array tuple (~0.9 s to compile, with or without
# ``reshape``); written out in each callback body, the tuple costs ~0.3 s in all.
@helper
def _w1(U, I, i):
    return f64_at(U[S_W] + 8 * I[4 * i], (I[4 * i + 1],))


@helper
def _w2(U, I, i):
    return f64_at(U[S_W] + 8 * I[4 * i], (I[4 * i + 1], I[4 * i + 2]))


@helper
def _w3(U, I, i):
    return f64_at(U[S_W] + 8 * I[4 * i], (I[4 * i + 1], I[4 * i + 2], I[4 * i + 3]))


@helper
def _wi(U, I, i):
    return i64_at(U[S_I] + 8 * I[4 * i], (I[4 * i + 1],))


@njit(inline="always", error_model="numpy")
def _work(U, I, marker):
    """The work tuple ``d`` (its 23 arrays and the optional passes' marker, None or a tuple:
    system/optional.py), as ``model.data`` holds it."""
    return (_w1(U, I, 0), _w1(U, I, 1), _w1(U, I, 2), _w1(U, I, 3), _w1(U, I, 4),
            _wi(U, I, 5), _wi(U, I, 6), _w1(U, I, 7), _w1(U, I, 8), _w2(U, I, 9),
            _w2(U, I, 10), _w1(U, I, 11), _w1(U, I, 12), _w2(U, I, 13), _w1(U, I, 14),
            _w2(U, I, 15), _w3(U, I, 16), _w3(U, I, 17), _w3(U, I, 18), _w3(U, I, 19),
            _w2(U, I, 20), _w2(U, I, 21), _w2(U, I, 22), marker)


# The accessors of the Jacobian work tuple are inlined (numba IR), not compiled: as compiled
# functions each literal index k made its own specialisation (8 compilations at a cold start,
# as residual.py's work-view accessors before them).
@helper
def _f1(U, k):
    s = S_JD + 3 * k
    return f64_at(U[s], (U[s + 1],))


@helper
def _f2(U, k):
    s = S_JD + 3 * k
    return f64_at(U[s], (U[s + 1], U[s + 2]))


@helper
def _i1(U, k):
    s = S_JD + 3 * k
    return i64_at(U[s], (U[s + 1],))


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True, no_cpython_wrapper=True)
def _all_finite(a):
    for i in range(a.shape[0]):
        if not np.isfinite(a[i]):
            return False
    return True


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True, no_cpython_wrapper=True)
def _write_pattern(U):
    """The CSC index arrays of the sparse SUNMatrix, from our copy of the pattern."""
    if U[S_WRITE_IDX] == 0:
        return
    n, nnz = U[S_N], U[S_NNZ]
    rows = i64_at(U[S_PROWS], (nnz,))
    ptr = i64_at(U[S_PPTR], (n + 1,))
    if U[S_IDXB] == 4:
        iv32 = i32_at(U[S_MIDX], (nnz,))
        ip32 = i32_at(U[S_MPTR], (n + 1,))
        for k in range(nnz):
            iv32[k] = rows[k]
        for k in range(n + 1):
            ip32[k] = ptr[k]
    else:
        iv64 = i64_at(U[S_MIDX], (nnz,))
        ip64 = i64_at(U[S_MPTR], (n + 1,))
        for k in range(nnz):
            iv64[k] = rows[k]
        for k in range(n + 1):
            ip64[k] = ptr[k]


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True, no_cpython_wrapper=True)
def _jacobian_done(U, JJ):
    """What every Jacobian callback ends with: the sparse pattern rewritten (IDA's setup
    zeroes the whole SUNMatrix), a non-finite entry counted and reported to IDA (flag 1: a
    recoverable failure), a good one counted."""
    _write_pattern(U)
    if not _all_finite(JJ):
        U[S_JFAIL] += 1
        return 1
    U[S_JOK] += 1
    return 0


RES_SIG = types.int32(types.float64, types.voidptr, types.voidptr, types.voidptr, types.voidptr)
JAC_SIG = types.int32(types.float64, types.float64, types.voidptr, types.voidptr, types.voidptr,
                      types.voidptr, types.voidptr, types.voidptr, types.voidptr, types.voidptr)


@njit(inline="always", error_model="numpy")
def _residual_body(t, yy, yp, rr, ud, marker):
    U = _slots(ud)
    n, off = U[S_N], U[S_OFF]
    r = _nvector(rr, off, n)
    I = i64_at(U[S_I], (U[S_IN],))
    d = _work(U, I, marker)
    residual(t, _nvector(yy, off, n), _nvector(yp, off, n), r, d)
    if _all_finite(r):
        return 0
    U[S_RFAIL] += 1
    return 1


@njit(inline="always", error_model="numpy")
def _jacobian_analytic_body(t, cj, yy, yp, ud, marker):
    U = _slots(ud)
    n, off = U[S_N], U[S_OFF]
    I = i64_at(U[S_I], (U[S_IN],))
    d = _work(U, I, marker)
    jd = (_f2(U, 0), _i1(U, 1), _i1(U, 2), _f1(U, 3), _f2(U, 4), _f2(U, 5), _f2(U, 6),
          _f2(U, 7))
    JJ = f64_at(U[S_MDATA], (U[S_NNZ],))
    # what jacobian_analytic_sparse does, without its compiled layer (cold start: -0.7 s)
    fill_jacobian_analytic(t, _nvector(yy, off, n), _nvector(yp, off, n), cj, d, jd)
    gather_csc(jd[0], jd[1], jd[2], JJ)
    return _jacobian_done(U, JJ)


@njit(inline="always", error_model="numpy")
def _jacobian_fd_body(t, cj, yy, yp, rr, ud, marker):
    U = _slots(ud)
    n, off = U[S_N], U[S_OFF]
    I = i64_at(U[S_I], (U[S_IN],))
    d = _work(U, I, marker)
    jd = (_f2(U, 0), _i1(U, 1), _i1(U, 2), _f1(U, 3), _f1(U, 4), _f1(U, 5), _f2(U, 6),
          _f2(U, 7), _f1(U, 8))
    JJ = f64_at(U[S_MDATA], (U[S_NNZ],))
    jacobian_sparse(t, _nvector(yy, off, n), _nvector(yp, off, n), _nvector(rr, off, n), cj,
                    JJ, d, jd)
    return _jacobian_done(U, JJ)


# The C callbacks, each in variants: for a scene without the optional passes (marker None,
# system/optional.py), for one with some of them (:func:`_apart_callbacks`: the marker's tuple,
# built here as ``model.data`` holds it, so that both call the same specialisations)
def _residual(t, yy, yp, rr, ud):
    return _residual_body(t, yy, yp, rr, ud, None)


def _jacobian_analytic(t, cj, yy, yp, rr, J, ud, tmp1, tmp2, tmp3):
    return _jacobian_analytic_body(t, cj, yy, yp, ud, None)


def _jacobian_fd(t, cj, yy, yp, rr, J, ud, tmp1, tmp2, tmp3):
    return _jacobian_fd_body(t, cj, yy, yp, rr, ud, None)


@njit(inline="always", error_model="numpy")
def _table(ud):
    """A defect scene's table: the work tuple's entry after the 23 (system/defects.py)."""
    U = _slots(ud)
    return _w2(U, i64_at(U[S_I], (U[S_IN],)), 23)


def _defect_table(ud, on):
    """:func:`_table` where ``on`` (a literal bool), else None: compiled code only."""
    raise NotImplementedError("compiled code only")


@overload(_defect_table, inline="always", prefer_literal=True)
def _defect_table_choice(ud, on):
    if not isinstance(on, types.BooleanLiteral):
        return None  # a compile-time constant only
    if not on.literal_value:
        return lambda ud, on: None
    return lambda ud, on: _table(ud)


@lru_cache(maxsize=None)
def _apart_callbacks(optional: tuple) -> dict:
    """{kind: (Python function of the C callback, its C signature)} of a scene whose effects
    compiled apart are on as the variant ``optional`` says (system/optional.variant): one
    function per variant, named after it (its own entry in numba's cache, e.g.
    ``_residual_apart_0010``, ``_residual_defects``, ``_residual_defects_0001``); with
    extensions (system/extensions.py), their passes."""
    PATTERN, EXT, TABLE = optional[:EXTENSION], optional[EXTENSION], optional[DEFECTS]

    def residual_cb(t, yy, yp, rr, ud):
        return _residual_body(t, yy, yp, rr, ud, apart_marker(
            PATTERN, _slots(ud)[S_N] >= 0, EXT, _defect_table(ud, TABLE)))

    def analytic_cb(t, cj, yy, yp, rr, J, ud, tmp1, tmp2, tmp3):
        return _jacobian_analytic_body(t, cj, yy, yp, ud, apart_marker(
            PATTERN, _slots(ud)[S_N] >= 0, EXT, _defect_table(ud, TABLE)))

    def fd_cb(t, cj, yy, yp, rr, J, ud, tmp1, tmp2, tmp3):
        return _jacobian_fd_body(t, cj, yy, yp, rr, ud, apart_marker(
            PATTERN, _slots(ud)[S_N] >= 0, EXT, _defect_table(ud, TABLE)))

    tag = ("defects" + (f"_{pattern_tag(PATTERN)}" if any(PATTERN) else "") if TABLE
           else f"apart_{pattern_tag(PATTERN)}") + ("_extension" if EXT is not None else "")
    out = {}
    for kind, fn, sig, name in (("residual", residual_cb, RES_SIG, "_residual"),
                                ("analytic", analytic_cb, JAC_SIG, "_jacobian_analytic"),
                                ("fd", fd_cb, JAC_SIG, "_jacobian_fd")):
        fn.__name__ = fn.__qualname__ = f"{name}_{tag}"
        out[kind] = (fn, sig)
    return out


def python_callback(kind: str, optional):
    """(Python function, C signature) of the C callback ``kind`` for the variant ``optional``
    (:func:`variant`)."""
    optional = variant(optional)
    if isinstance(optional, tuple) and kind != "extremes":
        return _apart_callbacks(optional)[kind]
    return _PY[kind]


#: IDAEwtFn: int efun(N_Vector y, N_Vector ewt, void* user_data)
EWT_SIG = types.int32(types.voidptr, types.voidptr, types.voidptr)


def _ewt_extremes(yy, ewt, ud):
    """IDA's error-weight function, used as a per-step hook. IDA calls it once at the start of
    every step with its last accepted state y_n (``phi[0]``; and during the consistent
    initialisation, before the hook is armed). It computes the weights exactly as IDA's own
    ``IDAEwtSetSV`` does for the scene's tolerances (``N_VAbs``, ``N_VLinearSum`` =
    rtol |y_i| + atol_i, ``N_VInv``: the same two roundings, so IDA's steps are those of a run
    without it), then asks IDA for t_n (``IDAGetCurrentTime``, by the address in
    ``user_data``) and folds the step into the running extremes (system/extremes.py). No
    interpolation, no extra residual."""
    U = _slots(ud)
    n, off = U[S_N], U[S_OFF]
    y = _nvector(yy, off, n)
    w = _nvector(ewt, off, n)
    atol = f64_at(U[S_ATOL], (n,))
    E = f64_at(U[S_EXT], (U[S_EXTN],))
    rtol = E[H_RTOL]
    for i in range(n):
        w[i] = 1.0 / (rtol * abs(y[i]) + atol[i])
    if E[H_ARMED] > 0.5:
        if call_int_ptr_ptr(U[S_TNOW], U[S_MEM], U[S_EXT] + 8 * H_TNOW) != 0:
            return 0  # no time: leave this step out rather than fail the run
        I = i64_at(U[S_I], (U[S_IN],))
        # of the work tuple: unknown scales, local map, slice loads, slips, pocket forces
        update_extremes(E[H_TNOW], y, _w1(U, I, 3), _wi(U, I, 5), _w3(U, I, 16),
                        _w3(U, I, 18), _w2(U, I, 20), E)
    return 0


#: kind -> (Python function of the C callback, its C signature) of a scene without the
#: optional passes; the variants with some: :func:`_apart_callbacks`
_PY = {"residual": (_residual, RES_SIG), "analytic": (_jacobian_analytic, JAC_SIG),
       "fd": (_jacobian_fd, JAC_SIG), "extremes": (_ewt_extremes, EWT_SIG)}
#: the Jacobian work-tuple layout each Jacobian callback rebuilds
JD_LAYOUT = {"analytic": JD_ANALYTIC, "fd": JD_FD}


_OPTIONS = {"error_model": "numpy"}


def compiled(kind: str, optional=False):
    """The C callback ``kind`` ("residual", "analytic", "fd", "extremes") for a scene without
    (``optional`` False) or with passes compiled apart (its marker or what else
    system/optional.variant takes: effects, extensions, defects), compiled on first use (or
    loaded from numba's cache): a run compiles only the callbacks it uses (cold start), and
    importing this module compiles nothing. If a child process is compiling it
    (precompile.py), waits for the child and loads its result from the cache."""
    if kind == "extremes":
        optional = False  # no work tuple: one variant
    return _compiled(kind, variant(optional))


@lru_cache(maxsize=None)
def _compiled(kind: str, optional):
    if precompile.running(kind):
        compiled("residual", optional)  # this process's share while the child compiles
        compiled("extremes")
        precompile.wait(kind)
    fn, sig = python_callback(kind, optional)
    # a variant with extensions holds their jitted passes: not cached (their functions live
    # in the user's module, compiled in this process)
    cache = not (isinstance(optional, tuple) and optional[EXTENSION] is not None)
    return cfunc(sig, cache=cache, **_OPTIONS)(fn)


def compile_aside(kind: str, busy_ok: bool = False, optional=False, scene=None) -> bool:
    """Cold start: have a child process compile the Jacobian callback ``kind`` (and the other
    kernels of aside.child) while this one compiles the residual (precompile.py), if it is
    not cached and a CPU is idle. True when a child was started. ``busy_ok``: start the child
    whatever the machine's load (precompile._spare_cpu); ``optional``: the variant for a
    scene with passes compiled apart (:func:`variant`); ``scene``: the run's scene, whose
    projection of the samples the child compiles after the Jacobian (None: this process
    compiles it)."""
    optional = variant(optional)
    if (kind not in JD_LAYOUT or not is_cold(kind, optional) or isinstance(optional, tuple)
            and optional[EXTENSION] is not None):
        return False  # (the extensions' passes live in the user's module: compiled here)
    tag = ""
    if isinstance(optional, tuple):
        tag = pattern_tag(optional) + ("d" if optional[DEFECTS] else "")
    return precompile.start(kind, busy_ok, tag, scene)


def is_cold(kind: str, optional=False) -> bool:
    """True when the C callback ``kind`` has no valid entry in numba's cache (compiling it is
    then the cold start's work). Reads the cache index only; a surprise counts as cold."""
    from numba.core.caching import FunctionCache

    try:
        # the cache a cfunc(cache=True) of this function uses; {} when missing or stale
        return not FunctionCache(python_callback(kind, optional)[0])._cache_file._load_index()
    except Exception:  # noqa: BLE001 - numba internals: assume cold
        return True


def user_data(n: int, nvec_offset: int, work, index_bytes: int, matrix, pattern, jd,
              layout) -> np.ndarray:
    """The int64 ``user_data`` array of the callbacks. ``matrix``: (data, indexvals,
    indexptrs) addresses of the SUNMatrix (indexvals 0: dense, no pattern to write);
    ``pattern``: (rows, indptr) int64 arrays of its CSC pattern; ``jd``: the Jacobian work
    tuple, checked against ``layout`` (JD_ANALYTIC / JD_FD). The caller keeps every array
    alive while IDA lives."""
    if (tuple(_work_module.WORK_NDIM) != MODEL_WORK_NDIM
            or tuple(_work_module.WORK_INT) != MODEL_WORK_INT):
        raise RuntimeError("the work tuple of system/work.py (WORK_NDIM, WORK_INT) changed: "
                           "the callbacks of solvers/sundials/callbacks.py are out of date")
    if len(jd) != len(layout):
        raise RuntimeError(f"Jacobian work tuple has {len(jd)} arrays, the compiled callback "
                           f"expects {len(layout)}: solvers/sundials/callbacks.py is out of date "
                           "with system/jacobian*.py")
    U = np.zeros(N_SLOTS, np.int64)
    W, I = work[0], work[1]
    rows, indptr = pattern
    U[S_N], U[S_OFF], U[S_IDXB] = n, nvec_offset, index_bytes
    U[S_W], U[S_WN], U[S_I], U[S_IN] = W.ctypes.data, W.size, I.ctypes.data, I.size
    U[S_MDATA], U[S_MIDX], U[S_MPTR] = matrix
    U[S_WRITE_IDX] = 1 if matrix[1] else 0
    U[S_NNZ], U[S_PROWS], U[S_PPTR] = rows.size, rows.ctypes.data, indptr.ctypes.data
    for k, (a, (kind, ndim)) in enumerate(zip(jd, layout)):
        want = np.float64 if kind == "f" else np.int64
        if a.dtype != want or a.ndim != ndim or not a.flags.c_contiguous:
            raise RuntimeError(f"Jacobian work array {k}: {a.dtype}, {a.ndim}-D, expected "
                               f"{np.dtype(want)} {ndim}-D contiguous (callbacks.py is out of "
                               "date with system/jacobian*.py)")
        s = S_JD + 3 * k
        U[s], U[s + 1] = a.ctypes.data, a.shape[0]
        U[s + 2] = a.shape[1] if ndim == 2 else 0
    for arr, want in ((W, np.float64), (I, np.int64), (rows, np.int64), (indptr, np.int64)):
        if arr.dtype != want or not arr.flags.c_contiguous:
            raise RuntimeError(f"user_data: expected contiguous {np.dtype(want)} arrays")
    return U
