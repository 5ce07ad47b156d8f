"""The vector width numba compiles the kernels for: all 512 bits on a CPU with AVX-512.

LLVM compiles for AVX-512 CPUs with 256-bit vectors unless told otherwise (its tuning flag
``prefer-256-bit``: 512-bit instructions lowered the clock of the first AVX-512 cores). The
kernels' slice loops (contact loads and tractions, the film parameter and the asperities'
share, the contact slopes) are long runs of independent arithmetic that fill the wider vectors.
Scenes whose slice loops dominate (many slices, mixed lubrication) take less CPU, the others
the same (measured side by side: docs/performance.md, "Vector width"). The results are the
same to the bit: each element goes through the same operations in the same
order (the polynomials are explicit fused multiply-adds, physics/elementary.py), and numba does
not reassociate floating point without ``fastmath``, which no kernel uses.

So on a CPU with AVX-512F, before numba builds its CPU target, numba's ``CPU_FEATURES`` is set
to the host's features (numba's own reading of them) plus ``-prefer-256-bit``. Left alone:

* when ``NUMBA_CPU_FEATURES`` or ``NUMBA_CPU_NAME`` is set: the user's choice;
* when ``BEARINGDAE_VECTOR_BITS=256``: LLVM's choice (for a CPU whose clock drops under
  512-bit load; ``512``, the default, applies only where AVX-512F is);
* when numba's CPU target already exists in this process (a kernel of the user's compiled
  before bearingdae was imported): it cannot change any more, and bearingdae's kernels are
  compiled with it.

Numba keys each cached kernel on the CPU features it was compiled for (its index), so kernels
of the two widths never share machine code. Every kernel numba compiles in the process after
this, the user's included, gets the wider vectors; the same bits for code without fastmath.

Standard library only at import; :func:`apply` imports numba.
"""

from __future__ import annotations

import os
import warnings

#: the environment variable that chooses; its values
ENV = "BEARINGDAE_VECTOR_BITS"
CHOICES = ("256", "512")
#: the LLVM feature that keeps 256-bit vectors on AVX-512 CPUs, switched off
WIDE = "-prefer-256-bit"


def features(host: str, environ=os.environ) -> str | None:
    """numba's CPU features for the host's feature string ``host`` (LLVM's "+a,-b,..."), or
    None to leave numba's own (module docstring)."""
    choice = environ.get(ENV, "").strip() or "512"
    if choice not in CHOICES:
        warnings.warn(f"{ENV}={choice[:40]!r} is not one of {', '.join(CHOICES)}: the kernels "
                      "are compiled with 512-bit vectors where the CPU has AVX-512 (the "
                      "default)", stacklevel=3)
        choice = "512"
    if choice == "256" or environ.get("NUMBA_CPU_FEATURES") or environ.get("NUMBA_CPU_NAME"):
        return None
    if "+avx512f" not in host.split(","):
        return None
    return f"{host},{WIDE}"


def apply(environ=os.environ) -> str | None:
    """Set numba's CPU features for the kernels (module docstring), once, before numba's CPU
    target exists; returns the features set, or None where numba's own are kept."""
    from numba.core import codegen, config, registry

    if config.CPU_FEATURES is not None and WIDE in config.CPU_FEATURES.split(","):
        return config.CPU_FEATURES  # already applied in this process
    if "_toplevel_target_context" in vars(registry.cpu_target):
        return None  # numba's CPU target exists: its features are fixed
    chosen = features(codegen.get_host_cpu_features(), environ)
    if chosen is not None:
        config.CPU_FEATURES = chosen
    return chosen
