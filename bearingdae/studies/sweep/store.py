"""The run store: one NetCDF (or failure record) per run, keyed by the scene's hash.

Pipeline place: studies; the resume cache of a sweep (``<output>_runs/<key>.nc``), written
atomically as each run completes (results.save, atomic).
"""

from __future__ import annotations

import hashlib
import json
import tomllib
from pathlib import Path

import tomli_w
import xarray as xr

from ...scene import Scene


def run_key(scene: Scene) -> str:
    """SHA-256 (16 hex digits) of the scene TOML without its title and of the contents of the
    files the scene read (``Scene.input_files``: a changed load file is another run)."""
    data = tomllib.loads(scene.to_toml())
    data.pop("title", None)
    text = tomli_w.dumps(data) + scene.inputs_text()
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:16]


# ---------------------------------------------------------------------------------------------
# The run store (resume cache)
# ---------------------------------------------------------------------------------------------
class RunStore:
    """``folder/<key>.nc`` (completed) and ``folder/<key>.failed.json`` (failed), atomic."""

    def __init__(self, folder: str | Path):
        self.folder = Path(folder)

    def result(self, key: str) -> Path:
        return self.folder / f"{key}.nc"

    def failure(self, key: str) -> Path:
        return self.folder / f"{key}.failed.json"

    def status(self, key: str) -> str | None:
        if self.result(key).is_file():
            return "completed"
        if self.failure(key).is_file():
            return "failed"
        return None

    def write_result(self, key: str, ds: xr.Dataset) -> Path:
        from ...results import save

        path = save(ds, self.result(key))
        self.failure(key).unlink(missing_ok=True)
        return path

    def write_failure(self, key: str, info: dict) -> Path:
        from ...util.atomic import atomic_write

        path = self.failure(key)
        with atomic_write(path) as tmp, open(tmp, "w", encoding="utf-8") as fh:
            json.dump(info, fh, indent=1)
        return path

    def read_failure(self, key: str) -> dict:
        try:
            return json.loads(self.failure(key).read_text(encoding="utf-8"))
        except (OSError, ValueError) as exc:
            return {"error": f"unreadable failure record: {exc}"}
