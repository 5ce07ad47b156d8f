"""util/numba_flags.py: numba's compiler flags hashed and compared faster, with numba's answers.

Reference: numba's own ``TargetConfig.__hash__`` and ``__eq__`` (kept by the module), on flags
with options set at random, to their defaults or to other values, in either order."""

from __future__ import annotations

import random

from numba.core import cpu
from numba.core.compiler import Flags
from numba.core.targetconfig import TargetConfig

import bearingdae.physics.compiled  # noqa: F401 - installs the comparison
from bearingdae.util import numba_flags

#: values an option is set to besides its default (the option's type converts them)
OTHERS = {bool: (True, False), str: ("numpy", "python"), int: (0, 1)}


def _random_flags(rng: random.Random) -> Flags:
    flags = Flags()
    for name in rng.sample(sorted(Flags.options), 5):
        default = Flags.options[name].default
        values = [default] + list(OTHERS.get(type(default), ()))
        if name == "fastmath":
            values = [cpu.FastMathOptions(set()), cpu.FastMathOptions({"nnan"})]
        try:
            setattr(flags, name, rng.choice(values))
        except Exception:  # noqa: BLE001 - an option that takes no such value stays unset
            pass
    return flags


def test_installed():
    assert TargetConfig.__hash__ is numba_flags._hash
    assert TargetConfig.__eq__ is numba_flags._eq


def test_the_same_answers_as_numba():
    rng = random.Random(7)
    flags = [_random_flags(rng) for _ in range(200)] + [Flags(), Flags()]
    equal = 0
    for a in flags:
        assert numba_flags._hash(a) == numba_flags._numba_hash(a)
        for b in flags[:80]:
            same = numba_flags._numba_eq(a, b)
            assert numba_flags._eq(a, b) == same
            equal += bool(same)
    assert 80 < equal < 200 * 80  # equal and unequal pairs were both compared
    assert (Flags() == 3) is False  # another type: numba's NotImplemented


def test_set_to_its_default_equals_unset():
    a, b = Flags(), Flags()
    a.error_model = "python"  # numba's default
    assert a == b and hash(a) == hash(b)
    a.error_model = "numpy"
    assert a != b
