"""The long-run statistics of tests/validation/test_statistical_equivalence.py with
``IDA(suppress_alg=True)`` as the integrator (docs/performance.md, "IDASetSuppressAlg").

Run on demand (several minutes):  python benchmarks/suppress_alg_statistics.py

Replaces the test module's ``ida.integrate`` by ``IDA(suppress_alg=True)``, computes its
statistics (baseline, 1 + 24 cage revolutions) and compares each with the documented run as
the test does (3 combined standard errors); prints IDA's counts and the restarts.
"""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests" / "validation"))

import bearingdae.solvers.ida as ida  # noqa: E402
from bearingdae.solvers.ida import IDA  # noqa: E402


def integrate(m, y0, yp0, t_out, **kw):
    r = IDA(suppress_alg=True).integrate(m, y0, yp0, t_out)
    print("IDA:", json.dumps({k: r.stats.get(k) for k in
                              ("steps", "residual_calls", "jacobian_calls", "restarts")}),
          flush=True)
    return r


def main() -> None:
    ida.integrate = integrate
    import test_statistical_equivalence as t

    s = t.long_run_statistics()
    print(json.dumps(s))
    for key, doc in (("skew_rms_mrad", t.DOC_SKEW_RMS_MRAD),
                     ("amplitude_mrad", t.DOC_AMPLITUDE_MRAD),
                     ("inner_slice_max_N", t.DOC_INNER_SLICE_MAX_N),
                     ("outer_slice_max_N", t.DOC_OUTER_SLICE_MAX_N),
                     ("cage_speed_rad_s", t.DOC_CAGE_SPEED_RAD_S)):
        ok, msg = t._within(s[key], doc)
        print(f"{key}: {'within' if ok else 'OUTSIDE'}: {msg}")


if __name__ == "__main__":
    main()
