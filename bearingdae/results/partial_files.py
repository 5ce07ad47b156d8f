"""Where the samples of a failed or interrupted run go (``TARGET_partial.nc``, and the CLI's
``TARGET_partial.png``), and their removal once a complete run of the same target is written:
a partial file left beside a complete result would read as the latest run of that target."""

from __future__ import annotations

from pathlib import Path

from ..util.atomic import fit_name


def partial_path(target: str | Path, suffix: str = ".nc") -> Path:
    """``TARGET_partial.nc`` (or ``.png``) beside ``target``, shortened to the file system's
    name length as the target is."""
    target = Path(target)
    return fit_name(target.with_name(target.stem + "_partial" + suffix), "_partial" + suffix)


def remove_superseded(target: str | Path, suffixes=(".nc", ".png")) -> list[Path]:
    """Remove the partial files an earlier, incomplete run of ``target`` left, now that the
    complete result is written; returns what was removed."""
    removed = []
    for suffix in suffixes:
        partial = partial_path(target, suffix)
        try:
            partial.unlink()
            removed.append(partial)
        except FileNotFoundError:
            pass
        except OSError:  # not ours to remove (permissions): leave it, it is only stale
            pass
    return removed
