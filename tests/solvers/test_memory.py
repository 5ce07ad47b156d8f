"""solvers/sundials/memory.py: raw addresses as arrays inside compiled code, checked against
numpy's own view of the same memory (shape, C strides, every element, writes through)."""

from __future__ import annotations

import numpy as np
import pytest
from numba import njit

from bearingdae.solvers.sundials.memory import f64_at, i32_at, i64_at


@njit
def _views(a2, a3, b1, c1):
    x = f64_at(a2.ctypes.data, (a2.shape[0], a2.shape[1]))
    y = f64_at(a3.ctypes.data, (a3.shape[0], a3.shape[1], a3.shape[2]))
    z = i64_at(b1.ctypes.data, (b1.shape[0],))
    w = i32_at(c1.ctypes.data, (c1.shape[0],))
    x[1, 2] = -1.0  # writes reach the memory
    return x.copy(), y.copy(), z.copy(), w.copy(), x.strides, y.strides


def test_arrays_at_an_address_are_c_contiguous_views_of_that_memory():
    a2 = np.arange(12.0).reshape(3, 4)
    a3 = np.arange(24.0).reshape(2, 3, 4) * 0.5
    b1 = np.arange(5, dtype=np.int64) - 2
    c1 = np.arange(7, dtype=np.int32) * 3
    x, y, z, w, sx, sy = _views(a2, a3, b1, c1)
    assert a2[1, 2] == -1.0
    np.testing.assert_array_equal(x, a2)
    np.testing.assert_array_equal(y, a3)
    np.testing.assert_array_equal(z, b1)
    np.testing.assert_array_equal(w, c1)
    assert sx == a2.strides and sy == a3.strides


def test_a_shape_that_is_not_an_integer_tuple_does_not_type():
    @njit
    def bad(a):
        return f64_at(a.ctypes.data, (1.5,))

    with pytest.raises(Exception, match="f64_at|array_at|No implementation"):
        bad(np.zeros(2))
