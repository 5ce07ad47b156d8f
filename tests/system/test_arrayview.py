"""system/arrayview.c_view: the compiled C-contiguous view that replaces ``reshape`` in the
kernels. Reference: numpy's reshape of the same array (same shape, same strides, same memory,
so that writes through the view land in the original)."""

from __future__ import annotations

import numba
import numpy as np

from bearingdae.system.arrayview import c_view


@numba.njit
def _views(flat, cube):
    a = c_view(flat[2:14], (3, 4))  # a C-contiguous slice of a flat buffer, as in work_views
    b = c_view(cube, (cube.size,))  # a 3-D array flattened, as in the contact passes
    c = c_view(flat, (2, 3, 4))
    a[1, 2] = -1.0
    b[5] = -2.0
    return a.copy(), a.strides, b.copy(), c.copy(), c.strides


def test_c_view_matches_reshape_and_shares_memory():
    flat = np.arange(24.0)
    cube = np.arange(24.0).reshape(2, 3, 4) * 10.0
    a, a_strides, b, c, c_strides = _views(flat, cube)
    np.testing.assert_array_equal(c, flat.reshape(2, 3, 4))  # copied after the write to ``a``
    assert a_strides == (32, 8) and c_strides == (96, 32, 8)
    assert flat[2 + 1 * 4 + 2] == -1.0 and a[1, 2] == -1.0  # the write landed in ``flat``
    assert cube.reshape(-1)[5] == -2.0 and b[5] == -2.0
    expected_a = np.arange(2.0, 14.0).reshape(3, 4)
    expected_a[1, 2] = -1.0
    np.testing.assert_array_equal(a, expected_a)
