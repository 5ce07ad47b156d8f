"""exp, log, the 1/9 power and the floored modulo in plain arithmetic, so that loops vectorise.

Stage: helpers of physics/* (contact loads, traction), used inside the compiled DAE kernels
(system/*) and, bit for bit the same, from Python/numpy (static solve, tests).

Why: the residual's contact pass is 400 slice contacts per call, and about half of its time went
into libm's scalar ``pow`` (the Palmgren load δ^(10/9)) and ``exp`` (the traction law, three per
loaded contact). numba can vectorise calls to libm only through Intel's SVML, which needs an
SVML-patched llvmlite that the PyPI wheels are not (measured: ``numba -s`` reports "llvmlite Using
SVML Patched LLVM: False" with ``intel-cmplr-lib-rt`` installed; glibc's libmvec through
``--vector-library`` is not picked up either). Written here as range reduction + polynomial + an
exponent bit-cast, they are plain floating-point arithmetic that LLVM's loop vectoriser packs 4-8
wide.

Accuracy (tests/physics/test_elementary.py against numpy): ``exp_`` within 2 ulp on [-708, 709] and
exactly 0.0 below -708 (true values < 3.3e-308, where the kernels' exponentials multiply
loads); ``log_`` within 4 ulp for positive normal numbers (2 ulp of 1 absolute near x = 1);
``root9`` = exp_(log_(s)/9) within 2e-15 relative on the smoothed approaches 1e-25..1e-3 m
(log's absolute error / 9). ``mod_`` (the pocket lead's angle wrap) is numpy's floored
``np.mod`` for a positive divisor, bit for bit, without the C call to fmod (``mod_`` below says
why it is exact).

Fused multiply-adds: the compiled polynomials (Horner steps of exp_ and log_) are explicit
``llvm.fma`` calls, one rounding per step (-1 µs of the residual's contact pass, whose time is
mostly these polynomials). Deterministic: the same operations in the same order in the vector and
scalar compiled paths (a fused multiply-add is correctly rounded in both), no fastmath
reassociation. (numba compiles for the host CPU; on one without FMA instructions LLVM calls libm's
fma instead: the same bits, slower.) The numpy twins below run the same steps as a product and a sum
(numpy has no fma): they agree with the compiled functions to 1 ulp (exp_), 2 ulp (log_), 2e-15
(root9; tests/physics/test_elementary.py), i.e. the static solve and the kernels share each law to
round-off, not to the bit.
"""

from __future__ import annotations

import numpy as np
from llvmlite import ir
from numba import types
from numba.extending import intrinsic, overload

LOG2E = 1.4426950408889634
# ln 2 split so that n * LN2_HI is exact for |n| < 2^11 (Cody-Waite reduction)
LN2_HI = 6.93147180369123816490e-01
LN2_LO = 1.90821492927058770002e-10
LN2 = 0.6931471805599453
SQRT2 = 1.4142135623730951
EXP_ZERO_BELOW = -708.0  # exp_ returns exactly 0.0 for x below this (a subnormal result)
EXP_MAX = 709.0  # arguments are clipped here (the kernels' exponents are <= 0)
_EXP_ONE_BITS = 1023 << 52
_MANTISSA_MASK = (1 << 52) - 1
# Taylor coefficients 1/n! of e^r on |r| <= ln2/2: the n = 14 term is < 0.05 ulp.
_E = tuple(1.0 / float(np.prod(np.arange(1, n + 1))) for n in range(14))
# 2 atanh(f) = log((1 + f)/(1 - f)) = 2 (f + f³/3 + ...): f² <= 0.0295 on [√½, √2), terms to f^23.
_L = tuple(1.0 / (2 * n + 1) for n in range(12))


def pow2(n):
    """2^n (exact) for integer-valued float n in [-1022, 1023]."""
    with np.errstate(invalid="ignore"):  # NaN arguments: the caller's result is NaN anyway
        return np.ldexp(1.0, np.asarray(n).astype(np.int64))


def exp_(x):
    """e^x [-] for x <= 709 (exactly 0.0 for x < -708; NaN stays NaN)."""
    xc = np.minimum(np.maximum(x, EXP_ZERO_BELOW), EXP_MAX)
    n = np.floor(xc * LOG2E + 0.5)
    r = (xc - n * LN2_HI) - n * LN2_LO
    p = _E[13]
    for c in _E[12::-1]:
        p = p * r + c
    return p * pow2(n) * (x >= EXP_ZERO_BELOW)


def log_(x):
    """Natural logarithm of a positive normal float x."""
    m, e = np.frexp(x)
    m, e = 2.0 * m, e - 1.0  # x = m 2^e, m in [1, 2)
    big = m > SQRT2
    m = m * (1.0 - 0.5 * big)  # exact: m or m/2
    e = e + big
    f = (m - 1.0) / (m + 1.0)
    s = f * f
    p = _L[11]
    for c in _L[10::-1]:
        p = p * s + c
    return (e * LN2_HI + 2.0 * f * p) + e * LN2_LO


def root9(x):
    """x^(1/9) for positive normal x: exp(log(x)/9)."""
    return exp_(log_(x) * (1.0 / 9.0))


def mod_(x, y):
    """Floored remainder x - y floor(x / y) of ``np.mod`` for y > 0, bit for bit.

    Compiled as n = floor(x / y), r = fma(-n, y, x), r + y if r < 0: fma rounds the exact
    x - n y once. n is the true floor or one more (x / y can round up onto an integer, never
    down past one); for x >= 0 the exact x - n y is then fmod(x, y) (exactly representable)
    or fmod - y (exact by Sterbenz), which + y restores; for x < 0 both paths round the same
    exact value fmod + y once, as np.mod does. NaN and inf give NaN as in np.mod.
    """
    return np.mod(x, y)


# ---- the same operations in the same order as LLVM IR (numba) ---------------------------------
# Why intrinsics: emitted straight into the calling kernel, they need no typing or inlining
# pass of numba (which made the kernels' first compilation 2-4x slower when these were
# ``inline="always"`` jitables) and leave the contact loop free of calls, so it vectorises.

def _const(v):
    return ir.Constant(ir.DoubleType(), float(v))


def _fma(builder, a, b, c):
    f64 = ir.DoubleType()
    fn = builder.module.declare_intrinsic("llvm.fma", [f64], ir.FunctionType(f64, [f64] * 3))
    return builder.call(fn, [a, b, c])


def _exp_codegen(builder, x):
    f64, i64 = ir.DoubleType(), ir.IntType(64)
    low, high = _const(EXP_ZERO_BELOW), _const(EXP_MAX)
    xc = builder.select(builder.fcmp_ordered("<", x, low), low, x)  # NaN stays NaN
    xc = builder.select(builder.fcmp_ordered(">", xc, high), high, xc)
    floor = builder.module.declare_intrinsic("llvm.floor", [f64])
    n = builder.call(floor, [builder.fadd(builder.fmul(xc, _const(LOG2E)), _const(0.5))])
    r = builder.fsub(builder.fsub(xc, builder.fmul(n, _const(LN2_HI))),
                     builder.fmul(n, _const(LN2_LO)))
    p = _const(_E[13])
    for c in _E[12::-1]:
        p = _fma(builder, p, r, _const(c))
    n_ok = builder.select(builder.fcmp_unordered("uno", n, n), _const(0.0), n)  # no poison
    bits = builder.shl(builder.add(builder.fptosi(n_ok, i64), ir.Constant(i64, 1023)),
                       ir.Constant(i64, 52))
    scale = builder.bitcast(bits, f64)
    keep = builder.uitofp(builder.fcmp_ordered(">=", x, low), f64)
    return builder.fmul(builder.fmul(p, scale), keep)


def _log_codegen(builder, x):
    f64, i64 = ir.DoubleType(), ir.IntType(64)
    b = builder.bitcast(x, i64)
    m = builder.bitcast(builder.or_(builder.and_(b, ir.Constant(i64, _MANTISSA_MASK)),
                                    ir.Constant(i64, _EXP_ONE_BITS)), f64)
    e = builder.sitofp(builder.sub(builder.ashr(b, ir.Constant(i64, 52)),
                                   ir.Constant(i64, 1023)), f64)
    big = builder.uitofp(builder.fcmp_ordered(">", m, _const(SQRT2)), f64)
    m = builder.fmul(m, builder.fsub(_const(1.0), builder.fmul(_const(0.5), big)))
    e = builder.fadd(e, big)
    f = builder.fdiv(builder.fsub(m, _const(1.0)), builder.fadd(m, _const(1.0)))
    s = builder.fmul(f, f)
    p = _const(_L[11])
    for c in _L[10::-1]:
        p = _fma(builder, p, s, _const(c))
    return builder.fadd(builder.fadd(builder.fmul(e, _const(LN2_HI)),
                                     builder.fmul(builder.fmul(_const(2.0), f), p)),
                        builder.fmul(e, _const(LN2_LO)))


def _float_intrinsic(gen):
    @intrinsic
    def _fn(typingctx, x):
        if not isinstance(x, types.Float):
            return None

        def codegen(context, builder, signature, args):
            v = context.cast(builder, args[0], signature.args[0], types.float64)
            return gen(builder, v)

        return types.float64(x), codegen

    return _fn


_exp_ir = _float_intrinsic(_exp_codegen)
_log_ir = _float_intrinsic(_log_codegen)


def _root9_codegen(builder, x):
    return _exp_codegen(builder, builder.fmul(_log_codegen(builder, x), _const(1.0 / 9.0)))


_root9_ir = _float_intrinsic(_root9_codegen)


@intrinsic
def _mod_ir(typingctx, x, y):
    if not (isinstance(x, types.Float) and isinstance(y, types.Float)):
        return None

    def codegen(context, builder, signature, args):
        f64 = ir.DoubleType()
        a = context.cast(builder, args[0], signature.args[0], types.float64)
        b = context.cast(builder, args[1], signature.args[1], types.float64)
        floor = builder.module.declare_intrinsic("llvm.floor", [f64])
        fma = builder.module.declare_intrinsic("llvm.fma", [f64], ir.FunctionType(f64, [f64] * 3))
        n = builder.call(floor, [builder.fdiv(a, b)])
        r = builder.call(fma, [builder.fneg(n), b, a])
        return builder.select(builder.fcmp_ordered("<", r, _const(0.0)), builder.fadd(r, b), r)

    return types.float64(x, y), codegen


@overload(exp_, inline="always")
def _ol_exp(x):
    if isinstance(x, types.Float):
        return lambda x: _exp_ir(x)


@overload(log_, inline="always")
def _ol_log(x):
    if isinstance(x, types.Float):
        return lambda x: _log_ir(x)


@overload(root9, inline="always")
def _ol_root9(x):
    if isinstance(x, types.Float):
        return lambda x: _root9_ir(x)


@overload(mod_, inline="always")
def _ol_mod(x, y):
    if isinstance(x, types.Float) and isinstance(y, types.Float):
        return lambda x, y: _mod_ir(x, y)
