"""``bearingdae spectrum RUN.nc --envelope --peaks N``: the strongest peaks of a run's
(envelope) spectrum, each matched to a characteristic order, as a printed table.

Pipeline: the cli layer over analysis/spectrum_peaks.py.
"""

from __future__ import annotations

import math


def _spectrum_table(args) -> int:
    from ..analysis.spectrum_peaks import format_table, spectrum_peaks
    from ..results.readers import open_result
    from ..scene.errors import _clip
    from ..util.atomic import shown_path
    from .plot import _band

    try:
        count = int(args.peaks)
    except ValueError:
        raise ValueError(f"--peaks {_clip(args.peaks)!r}: expected a whole number >= 1") from None
    if count < 1:
        raise ValueError(f"--peaks {count}: expected a whole number >= 1")
    if args.fmax is not None and not (math.isfinite(args.fmax) and args.fmax > 0.0):
        raise ValueError(f"--fmax {args.fmax!r}: expected a finite frequency > 0 Hz")
    band = _band(args.band, args.envelope)
    _, ds = open_result(args.file, ("run",))
    table = spectrum_peaks(ds, count, args.envelope, band, args.fmax)
    print(format_table(table, shown_path(args.file)))
    return 0
