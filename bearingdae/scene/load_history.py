"""The scene's loads as one history (pipeline stage 1): its load keys' tables merged on one time
grid, or its load file (scene/loadfile.py), with the axial load from the scene where the file
has none; checked for what only the whole scene shows (a load file beside given load keys, an
axial load given twice, a table whose times and values differ in length).
"""

from __future__ import annotations

import numpy as np

from .errors import SceneError
from .histories import RADIAL_LOAD_KEYS
from .loadfile import file_sha256, merge_histories, read_load_file
from .schema import LOAD_KEYS, LoadTable, MomentTable, OperatingInput
from .si import LoadHistory


def axial_history(o: OperatingInput, history, axial_in_file: bool):
    """(key, times [s] or None, values [N]) of the axial load as the scene gives it, for the
    flange checks of every value (scene/flanges.py)."""
    if history is None or not (axial_in_file or isinstance(o.axial_load_N, LoadTable)):
        return "operating.axial_load_N", None, [o.axial_load_N or 0.0]
    key = ("operating.load_file' variable 'axial_load_N" if axial_in_file
           else "operating.axial_load_N")
    return key, history.rows[:, 0], history.rows[:, 5]


def load_history(o: OperatingInput, origin: str):
    """(rows (t, F_r, F_t, M, M_t, F_a) of the load history or None, the load file's path or
    None, whether the load file gives the axial load, the SHA-256 of the load file's bytes or
    None): the scene's tables merged on one time grid (physics/loads.py), or the load file
    (with the scene's axial load where the file has none)."""
    values = [getattr(o, k) for k in LOAD_KEYS]
    values[4] = 0.0 if values[4] is None else values[4]  # axial: absent (no flanges) is 0
    if o.load_file is not None:
        given = [k for k, v in zip(RADIAL_LOAD_KEYS, values)
                 if isinstance(v, (LoadTable, MomentTable)) or v != 0.0]
        if given:
            raise SceneError(
                f"invalid scene ({origin}): 'operating.load_file' = {o.load_file!r} replaces "
                f"the load keys, but {', '.join(f'operating.{k}' for k in given)} "
                f"{'is' if len(given) == 1 else 'are'} given too; set them to 0 or drop the "
                "load file (unbalance_N may be added to a file).")
        try:
            # the bytes' digest first: a file rewritten while it is read then differs from
            # its digest, and the next resume or sweep reads it again
            digest = file_sha256(o.load_file)
        except (OSError, ValueError):  # ValueError: a NUL in the path
            digest = None  # read_load_file names the problem
        try:
            times, loads, names = read_load_file(o.load_file)
        except SceneError as exc:  # the key too, on the same line
            raise SceneError(f"invalid scene ({origin}): 'operating.load_file': {exc}") from None
        axial = values[4]
        in_file = "axial_load_N" in names
        if in_file and (isinstance(axial, LoadTable) or axial != 0.0):
            raise SceneError(
                f"invalid scene ({origin}): 'operating.load_file' = {o.load_file!r} gives "
                "axial_load_N, but 'operating.axial_load_N' is given too; set it to 0 (drop "
                "it) or drop the file's axial_load_N.")
        if isinstance(axial, LoadTable):  # the file's loads and the scene's axial history
            _same_length(axial, "axial_load_N", origin)
            table = merge_histories([(times, loads[:, c]) for c in range(4)]
                                    + [(tuple(axial.times_s), tuple(axial.values_N))])
        else:  # the file's axial column, or the scene's constant
            table = np.column_stack([times, loads])
            if not in_file:
                table[:, 5] = float(axial)
        return LoadHistory(table), str(o.load_file), in_file, digest
    tables = []
    for key, v in zip(LOAD_KEYS, values):
        if isinstance(v, (LoadTable, MomentTable)):
            tables.append((tuple(v.times_s), _same_length(v, key, origin)))
        else:
            tables.append(float(v))
    if all(not isinstance(v, tuple) for v in tables):
        return None, None, False, None
    return LoadHistory(merge_histories(tables)), None, False, None


def _same_length(v, key: str, origin: str) -> tuple[float, ...]:
    """The values of the history table ``v`` of ``operating.key``, one per time."""
    vals = v.values_N if isinstance(v, LoadTable) else v.values_Nm
    if len(v.times_s) != len(vals):
        raise SceneError(
            f"invalid scene ({origin}): 'operating.{key}' history has "
            f"{len(v.times_s)} times_s but {len(vals)} values; they must have the "
            "same length.")
    return tuple(vals)


