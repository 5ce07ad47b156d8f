"""Where a command's results go when the target cannot take them.

Pipeline place: after results (``results.save``), for the command line. Before computing, the
commands check their targets with :func:`bearingdae.util.atomic.check_writable`. When a write fails
after computing (a full disk, a file system gone read-only, an I/O error), the result is not
lost: :func:`save_or_keep` says what failed in one line (path and "No space left on device")
and writes the Dataset to a fallback path in the temporary folder (``$TMPDIR``, usually another
file system than the target's), whose name it prints.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

from ..results.partial_files import partial_path, remove_superseded  # noqa: F401 (the CLI's)
from ..util.atomic import fit_name, write_failure


def fallback_path(target: str | Path) -> Path:
    """``$TMPDIR/bearingdae-<pid>-<target name>``: where a result goes when its target fails."""
    return Path(tempfile.gettempdir()) / f"bearingdae-{os.getpid()}-{Path(target).name}"


def save_or_keep(ds, target: str | Path) -> tuple[Path | None, list[str]]:
    """Save ``ds`` to ``target``; returns ``(target, [])``. If that write fails: the messages
    (what failed, and where the result was kept, or that the fallback failed too) and the
    fallback path written, or None."""
    from ..results import save

    target = Path(target)
    try:
        return save(ds, target), []
    except (OSError, RuntimeError) as exc:  # RuntimeError: netCDF4's own errors
        lines = [write_failure(exc, target)]
    fallback = fallback_path(target)
    try:
        save(ds, fallback)
    except (OSError, RuntimeError) as exc:
        lines.append(f"the fallback copy failed as well ({write_failure(exc, fallback)})")
        return None, lines
    lines.append(f"the result is kept in '{fallback}'; move it where it belongs")
    return fallback, lines


def png_path(target: str | Path) -> Path:
    """The overview figure beside a NetCDF result: ``run.nc`` -> ``run.png``."""
    return fit_name(Path(target).with_suffix(".png"), ".png")
