"""Helpers shared by the command handlers: --set overrides, the scene of CASE, notices.

Pipeline: the cli layer; turns command-line text into the scene API's arguments.
"""

from __future__ import annotations

import sys

def _overrides(pairs: list[str]) -> dict:
    import tomllib

    from ..scene.errors import _show

    out = {}
    for pair in pairs:
        if "=" not in pair:
            raise ValueError(f"--set {_show(pair)}: expected KEY=VALUE, e.g. "
                             "operating.speed_rpm=6000")
        key, value = pair.split("=", 1)
        try:
            parsed = tomllib.loads(f"v = {value}")
        except (ValueError, RecursionError):  # TOMLDecodeError, > 4300 digits, deep nesting
            parsed = {}
        # A bare string such as a profile name (or text that is more than one TOML value) is
        # passed on as a string; the scene validation then names the key.
        out[key.strip()] = parsed["v"] if list(parsed) == ["v"] else value
    return out


def _scene(args, more: dict | None = None):
    """The scene of CASE with the --set overrides (and ``more``, e.g. from --until-steady);
    an error caused by a --set names it."""
    from .. import load_scene

    return load_scene(args.case, {**_overrides(args.set), **(more or {})},
                      override_origin=_set_origin(args.set))


def _notice(line: str | None) -> None:
    if line:
        print(line, file=sys.stderr, flush=True)


def _check_workers(args) -> None:
    if args.workers is not None and args.workers < 1:
        raise ValueError(f"--workers {args.workers}: allowed range is [1, 4096]")
    from ..studies.sweep.cluster import check_scheduler_timeout

    check_scheduler_timeout(args.scheduler_timeout, "--scheduler-timeout")


def _set_origin(pairs: list[str]) -> str:
    """The --set options as the user typed them, each cut to ~100 characters for messages."""
    from ..scene.errors import _clip

    return " ".join(f"--set {_clip(pair)}" for pair in pairs) or "--set"
