"""Reading the files a user names as input (scene and sweep TOML): regular files up to a size
cap, refused before anything is read otherwise (pipeline stage 1, scene).

A scene file is a few kB of TOML (the largest bundled case is under 4 kB). A path to a FIFO
(reading it blocks until some writer comes), a device such as ``/dev/zero`` (it never ends), a
directory or a file larger than :data:`MAX_INPUT_BYTES` is refused with one line naming the
path and what it is, before reading it: the file is opened without blocking, checked with
``fstat`` on the open descriptor (no race with a rename), and read up to the cap only.
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

from ..util.atomic import shown_path
from .errors import SceneError

#: Largest scene or sweep file read (1 MiB): hundreds of times any real scene.
MAX_INPUT_BYTES = 1 << 20

_KINDS = ((stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
          (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
          (stat.S_ISSOCK, "a socket"))


def read_input(path: str | Path, what: str = "scene file") -> bytes:
    """The bytes of the regular file ``path`` (at most :data:`MAX_INPUT_BYTES`); anything else
    is a :class:`SceneError` naming ``what`` and the path."""
    shown = shown_path(path)
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except (OSError, ValueError) as exc:  # ValueError: a NUL byte in the name
        reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
        raise SceneError(f"cannot read {what} '{shown}': {reason}") from None
    try:
        mode = os.fstat(fd).st_mode
    except OSError:
        mode = 0
    if not stat.S_ISREG(mode):
        os.close(fd)
        kind = next((name for test, name in _KINDS if test(mode)), "not a regular file")
        raise SceneError(f"{what} '{shown}' is {kind}, not a regular file; give the path of a "
                         "TOML file")
    with open(fd, "rb", closefd=True) as fh:
        try:
            data = fh.read(MAX_INPUT_BYTES + 1)
        except OSError as exc:
            raise SceneError(f"cannot read {what} '{shown}': {exc.strerror or exc}") from None
    if len(data) > MAX_INPUT_BYTES:
        raise SceneError(f"{what} '{shown}' is larger than {MAX_INPUT_BYTES} bytes (1 MiB), the "
                         f"most a {what} may have; is it the right file?")
    return data
