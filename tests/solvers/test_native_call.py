"""A compiled kernel called through its address (bearingdae/solvers/native_call.py): the same
result as the direct call, the callee's code not linked into the caller (so not optimised and
emitted again there: docs/performance.md, "Cold start"), and a wrong entry refused."""

from __future__ import annotations

import numpy as np
import pytest
from numba import njit

from bearingdae.solvers.native_call import entry, native_call


@njit(error_model="numpy")
def _kernel(a, scale, pair):
    """A kernel typed afresh here: a[i] <- a[i] scale + pair[0][i], returns the sum; writes
    its argument, returns a value and takes a tuple with a None, as the real kernels do."""
    total = 0.0
    for i in range(a.shape[0]):
        a[i] = a[i] * scale + pair[0][i]
        total += a[i]
    return total


@njit(error_model="numpy")
def _through_address(at, a, scale, pair):
    return native_call(_kernel, at, (a, scale, pair))


@njit(error_model="numpy")
def _direct(a, scale, pair):
    return _kernel(a, scale, pair)


def _linked(dispatcher) -> list[str]:
    """The libraries numba linked into the compiled function (and optimised again there)."""
    library = dispatcher.overloads[dispatcher.signatures[0]].library
    return [lib.name for lib in library._linking_libraries]


def test_the_call_through_the_address_is_the_direct_call_and_links_nothing():
    pair = (np.linspace(0.0, 1.0, 7), None)
    a1, a2 = np.arange(7.0), np.arange(7.0)
    at = entry(_kernel, a1, 2.5, pair)
    s1 = _through_address(at, a1, 2.5, pair)
    s2 = _direct(a2, 2.5, pair)
    expected = np.arange(7.0) * 2.5 + pair[0]  # the formula, typed afresh
    assert np.array_equal(a1, expected) and np.array_equal(a2, expected)
    assert s1 == s2 == pytest.approx(expected.sum(), rel=1e-15)
    # the direct caller carries the kernel's code; the one through the address does not
    assert "_kernel" in _linked(_direct)
    assert "_kernel" not in _linked(_through_address)
    assert len(_kernel.overloads) == 1  # entry() and the caller use one specialisation


def test_an_entry_of_another_kernel_or_specialisation_is_refused():
    pair = (np.ones(3), None)
    a = np.zeros(3)
    address, key = entry(_kernel, a, 1.0, pair)
    with pytest.raises(RuntimeError, match="another specialisation"):
        _through_address((address, key + 1), a, 1.0, pair)
    assert np.array_equal(a, np.zeros(3))  # nothing was called
