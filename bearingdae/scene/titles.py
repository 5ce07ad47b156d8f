"""Scene titles that stay true to the scene's values.

Pipeline stage 1 (scene). A title may hold the placeholder ``{operating}``, replaced by the
validated operating point (``800 N, 3 N·m, 2000 r/min``): the bundled cases write their titles
so, and a scene file without a title gets ``<file name>: {operating}``. A copied and edited
case then keeps a title that states its own loads and speed; a title written without the
placeholder is the user's and is kept as written.
"""

from __future__ import annotations

import os

#: the placeholder a title's operating point replaces
OPERATING = "{operating}"
#: the title of a scene given without one (a dict; a file gets its name instead)
DEFAULT_TITLE = f"bearingdae scene: {OPERATING}"


def file_title(path) -> str:
    """The title of a scene file that has none: its name and the operating point."""
    return f"{os.path.splitext(os.path.basename(path))[0]}: {OPERATING}"


def operating_text(op) -> str:
    """The operating point of a validated ``scene.si.Operating``, as a title states it:
    ``800 N, 3 N·m, 200 N axial, 2000 r/min``; loads from a history or file are its first row
    (``load history from 800 N``); a speed ramp its first and last speed."""
    if op.load_history is not None:
        what = (f"loads of {os.path.basename(op.load_file)}" if op.load_file
                else "load history")
        parts = [f"{what} from {op.radial_load_N:g} N"]
    else:
        parts = [f"{op.radial_load_N:g} N"]
    for value, text in ((op.moment_Nm, "{:g} N·m"), (op.tangential_load_N, "{:g} N tangential"),
                        (op.tangential_moment_Nm, "{:g} N·m tangential"),
                        (op.axial_load_N, "{:g} N axial"), (op.unbalance_N, "unbalance {:g} N")):
        if value:
            parts.append(text.format(value))
    rpm = op.speed_rpm
    if isinstance(rpm, tuple):  # a ramp: (times, speeds)
        parts.append(f"{rpm[1][0]:g} -> {rpm[1][-1]:g} r/min")
    else:
        parts.append(f"{rpm:g} r/min")
    return ", ".join(parts)


def expand_title(title: str, op) -> str:
    """``title`` with its ``{operating}`` placeholder replaced (other braces stay as written)."""
    return title.replace(OPERATING, operating_text(op)) if OPERATING in title else title
