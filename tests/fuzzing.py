"""What the fuzz tests share: hypothesis settings that replay the same cases on every machine,
and the command line run in-process with its output captured."""

from __future__ import annotations

import contextlib
import io
import warnings

from hypothesis import HealthCheck, settings

from bearingdae.cli import main


def fuzz(n: int):
    """Settings for ``n`` derandomised examples (the same cases every run, no example
    database, no deadline: a case that compiles or solves may take seconds)."""
    return settings(derandomize=True, database=None, deadline=None, max_examples=n,
                    print_blob=False, suppress_health_check=list(HealthCheck))


def run_cli(argv: list[str]) -> tuple[int, str, str]:
    """``bearingdae ARGV`` in this process: (exit status, stdout, stderr), warnings silenced."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err), \
            warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rc = main(argv)
    return rc, out.getvalue(), err.getvalue()
