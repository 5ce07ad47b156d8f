"""The package's own warnings, and the one line the command line prints for each.

A warning of bearingdae (a plausibility finding, a warm-up that did not settle) is for the user,
not for a developer: the command line prints it as ``bearingdae: warning: <message>``, never
with Python's file name, line number and source line. Sweeps and skid maps collect the warnings
of each run in its worker and print them the same way, naming the run.
"""

from __future__ import annotations


PREFIX = "bearingdae: warning: "


class BearingdaeWarning(UserWarning):
    """Base of bearingdae's own warnings (analysis.guards.PlausibilityWarning,
    run.steady.NotSteadyWarning, ...): each is printed as one line by the command line."""


def one_line(message, category=None) -> str:
    """The line for a warning: bearingdae's own as they read, others with their class name."""
    text = " ".join(str(message).split())
    if category is not None and not issubclass(category, BearingdaeWarning):
        text = f"{category.__name__}: {text}"
    return PREFIX + text


def caught_lines(caught) -> list[str]:
    """The lines of recorded warnings (``warnings.catch_warnings(record=True)``), each once,
    in order."""
    out: list[str] = []
    for w in caught:
        line = one_line(w.message, w.category)
        if line not in out:
            out.append(line)
    return out


__all__ = ["BearingdaeWarning", "PREFIX", "one_line", "caught_lines"]
