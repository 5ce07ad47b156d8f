"""exp, log and the 1/9 power in plain arithmetic, so that the contact loops vectorise.

Stage: helpers of physics/* (contact loads, traction), used inside the compiled DAE kernels
(system/*) and, bit for bit the same, from Python/numpy (static solve, tests).

Why (docs/performance.md, "Kernels at their floor"): the residual's contact pass is 400 slice
contacts per call, and about half of its time went into libm's scalar ``pow`` (the Palmgren
load δ^(10/9)) and ``exp`` (the traction law, three per loaded contact). numba can vectorise
calls to libm only through Intel's SVML, which needs an SVML-patched llvmlite that the PyPI
wheels are not (measured: ``numba -s`` reports "llvmlite Using SVML Patched LLVM: False" with
``intel-cmplr-lib-rt`` installed; glibc's libmvec through ``--vector-library`` is not picked up
either). Written here as range reduction + polynomial + an exponent bit-cast, they are plain
floating-point arithmetic that LLVM's loop vectoriser packs 4-8 wide.

Accuracy (tests/test_elementary.py against numpy): ``exp_`` within 2 ulp on [-708, 709] and
exactly 0.0 below -708 (true values < 3.3e-308, where the kernels' exponentials multiply
loads); ``log_`` within 4 ulp for positive normal numbers (2 ulp of 1 absolute near x = 1);
``root9`` = exp_(log_(s)/9) within 2e-15 relative on the smoothed approaches 1e-25..1e-3 m
(log's absolute error / 9). Deterministic: the same operations in the same order in the vector and scalar
paths and in numpy (no fastmath reassociation, no FMA contraction).
"""

from __future__ import annotations

import numpy as np
from numba import types
from numba.extending import intrinsic, overload, register_jitable

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


@intrinsic
def _bitcast_i2f(typingctx, bits):
    if not isinstance(bits, types.Integer):
        return None

    def codegen(context, builder, signature, args):
        v = context.cast(builder, args[0], signature.args[0], types.int64)
        return builder.bitcast(v, context.get_value_type(types.float64))

    return types.float64(bits), codegen


@intrinsic
def _bitcast_f2i(typingctx, x):
    if not isinstance(x, types.Float):
        return None

    def codegen(context, builder, signature, args):
        v = context.cast(builder, args[0], signature.args[0], types.float64)
        return builder.bitcast(v, context.get_value_type(types.int64))

    return types.int64(x), codegen


def pow2(n):
    """2^n (exact) for integer-valued float n in [-1022, 1023]."""
    with np.errstate(invalid="ignore"):  # NaN arguments: the caller's result is NaN anyway
        return np.ldexp(1.0, np.asarray(n).astype(np.int64))


def split_exponent(x):
    """(m, e) with x = m 2^e, m in [1, 2), e an integer-valued float; x positive and normal."""
    m, e = np.frexp(x)
    return 2.0 * m, e - 1.0


@overload(pow2, inline="always")
def _ol_pow2(n):
    if isinstance(n, types.Float):
        def impl(n):
            return _bitcast_i2f((np.int64(n) + 1023) << 52)
        return impl


@overload(split_exponent, inline="always")
def _ol_split_exponent(x):
    if isinstance(x, types.Float):
        def impl(x):
            b = _bitcast_f2i(x)
            return (_bitcast_i2f((b & _MANTISSA_MASK) | _EXP_ONE_BITS),
                    np.float64((b >> 52) - 1023))
        return impl


@register_jitable(inline="always")
def exp_(x):
    """e^x [-] for x <= 709 (exactly 0.0 for x < -708; NaN stays NaN)."""
    xc = np.minimum(np.maximum(x, EXP_ZERO_BELOW), EXP_MAX)
    n = np.floor(xc * LOG2E + 0.5)
    r = (xc - n * LN2_HI) - n * LN2_LO
    p = _E[13]
    p = p * r + _E[12]
    p = p * r + _E[11]
    p = p * r + _E[10]
    p = p * r + _E[9]
    p = p * r + _E[8]
    p = p * r + _E[7]
    p = p * r + _E[6]
    p = p * r + _E[5]
    p = p * r + _E[4]
    p = p * r + _E[3]
    p = p * r + _E[2]
    p = p * r + _E[1]
    p = p * r + _E[0]
    return p * pow2(n) * (x >= EXP_ZERO_BELOW)


@register_jitable(inline="always")
def log_(x):
    """Natural logarithm of a positive normal float x."""
    m, e = split_exponent(x)
    big = m > SQRT2
    m = m * (1.0 - 0.5 * big)  # exact: m or m/2
    e = e + big
    f = (m - 1.0) / (m + 1.0)
    s = f * f
    p = _L[11]
    p = p * s + _L[10]
    p = p * s + _L[9]
    p = p * s + _L[8]
    p = p * s + _L[7]
    p = p * s + _L[6]
    p = p * s + _L[5]
    p = p * s + _L[4]
    p = p * s + _L[3]
    p = p * s + _L[2]
    p = p * s + _L[1]
    p = p * s + _L[0]
    return (e * LN2_HI + 2.0 * f * p) + e * LN2_LO


@register_jitable(inline="always")
def root9(x):
    """x^(1/9) for positive normal x: exp(log(x)/9)."""
    return exp_(log_(x) * (1.0 / 9.0))
