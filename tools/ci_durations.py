"""The durations of `.ci/run` on a fresh clone: read from its logs, kept in one file, and
README's "Duration" paragraph generated from that file (a test compares the two).

    python tools/ci_durations.py add LOG [LOG ...] [--commit SHA] [--date YYYY-MM-DD] [--cpu TEXT]
        [--note TEXT]
    python tools/ci_durations.py readme [--write]

``add`` reads each log (`bash .ci/run > LOG 2>&1` on a fresh clone with an empty kernel cache)
and appends one run to benchmarks/results/ci-durations.json: the commit, date and CPU from the
log's first line (`.ci/run` prints them; older logs need the options), each step's duration
as `.ci/run` printed it, and the tests each tier ran (pytest's summary line). ``readme`` prints
the paragraph from the last runs in that file; ``--write`` puts it into README.md.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results" / "ci-durations.json"
README = ROOT / "README.md"
#: the runs the README's paragraph quotes: the last of the file
README_RUNS = 4
#: the paragraph in README.md: this bullet, up to the next bullet or blank line
BULLET = "- Duration:"
#: what CI should take on two cores: all of `.ci/run`, and the fast tier with its install [s]
TARGET_TOTAL_S = 25 * 60
TARGET_FAST_S = 5 * 60

HEADER = re.compile(r"^\.ci/run: main (\S+) on (.+?), (\d{4}-\d{2}-\d{2})", re.M)
STEPS = {  # field: what `.ci/run` prints at the end of the step
    "fast_tier_s": r"fast tier \(install included\) took (\d+) s",
    "docs_install_s": r"docs install took (\d+) s",
    "slow_tier_s": r"slow tier, physics and documentation \(the site build beside it\) took (\d+) s",
    "site_after_s": r"site build, what it needed after the slow tier took (\d+) s",
    "total_s": r"(?:\.ci/run: all took (\d+) s|^([\d.]+) s total$)",
}
_COUNT = r"\d+ (?:passed|failed|skipped|xfailed|xpassed|errors?)"
SUMMARY = re.compile(rf"^({_COUNT}(?:, {_COUNT})*)(?:, \d+ warnings?)? in ([\d.]+)s", re.M)


def parse(text: str) -> dict:
    """One run's durations [s] and test counts from a `.ci/run` log (None: not in the log)."""
    run = {}
    for field, pattern in STEPS.items():
        m = re.search(pattern, text, re.M)
        run[field] = None if m is None else round(float(next(g for g in m.groups() if g)))
    tiers = SUMMARY.findall(text)  # the fast tier's summary, then the slow tier's
    for i, tier in enumerate(("fast", "slow")):
        counts, seconds = tiers[i] if i < len(tiers) else (None, None)
        run[f"{tier}_pytest_s"] = None if seconds is None else round(float(seconds))
        run[f"{tier}_tests"] = (None if counts is None else
                                sum(int(n) for n in re.findall(r"(\d+) ", counts)))
        run[f"{tier}_failed"] = (None if counts is None else
                                 sum(int(n) for n in re.findall(r"(\d+) (?:failed|errors?)",
                                                                counts)))
    m = HEADER.search(text)
    run["commit"], run["cpu"], run["date"] = (m.group(1), m.group(2), m.group(3)) if m else \
        (None, None, None)
    return run


def load() -> list[dict]:
    return json.loads(RESULTS.read_text())["runs"] if RESULTS.exists() else []


def span(values, unit: str = " s") -> str:
    lo, hi = min(values), max(values)
    return f"{lo}{unit}" if lo == hi else f"{lo}-{hi}{unit}"


def paragraph(runs: list[dict]) -> str:
    """README's Duration bullet from the last :data:`README_RUNS` runs (wrapped at 95)."""
    last = runs[-README_RUNS:]
    dates = sorted({r["date"] for r in last})
    cpus = sorted({r["cpu"] for r in last})
    total = [r["total_s"] for r in last]
    text = (
        f"{BULLET} the tiers run in one process per core (pytest-xdist, `-n auto`); `.ci/run` "
        f"prints each step's duration. The last {len(last)} runs of all of `.ci/run` on a "
        f"fresh clone with a cold kernel cache ({', '.join(dates)}; mains "
        f"{', '.join(r['commit'] for r in last)}; {' / '.join(cpus)}) took "
        f"{span(total)} ({span([round(t / 60) for t in total], ' min')}): the fast tier "
        f"{span([r['fast_tier_s'] for r in last])} with its install (pytest "
        f"{span([r['fast_pytest_s'] for r in last])}, {span([r['fast_tests'] for r in last], '')}"
        f" tests), the slow and documentation checks {span([r['slow_tier_s'] for r in last])} "
        f"with the site built beside them ({span([r['slow_tests'] for r in last], '')} tests). "
        f"Targets: all of it within {TARGET_TOTAL_S // 60} min, met by "
        f"{sum(r['total_s'] <= TARGET_TOTAL_S for r in last)} of {len(last)}; the fast tier "
        f"within {TARGET_FAST_S // 60} min, met by "
        f"{sum(r['fast_tier_s'] <= TARGET_FAST_S for r in last)} of {len(last)}. "
        f"The host is shared: its speed varies within hours and between machines of one kind "
        f"(a run's note in the file says so). Every run measured "
        f"is in benchmarks/results/ci-durations.json (tools/ci_durations.py).")
    words, lines, line = text.split(), [], ""
    for w in words:
        if line and len(line) + 1 + len(w) > 95:
            lines.append(line)
            line = "  " + w
        else:
            line = f"{line} {w}" if line else w
    return "\n".join(lines + [line]) + "\n"


def readme_bullet(text: str) -> tuple[int, int]:
    """(start, end) of the Duration bullet in README's text."""
    start = text.index(f"\n{BULLET}") + 1
    m = re.compile(r"\n(?=- |\n)").search(text, start)
    return start, (m.start() + 1 if m else len(text))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="ci_durations.py", description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="command", required=True)
    add = sub.add_parser("add", help="append the runs of these logs")
    add.add_argument("logs", nargs="+", type=Path)
    add.add_argument("--commit", help="main's commit (older logs do not print it)")
    add.add_argument("--date", help="YYYY-MM-DD (older logs do not print it)")
    add.add_argument("--cpu", help="the CPU, as `.ci/run` prints it (older logs do not)")
    add.add_argument("--note", help="what else ran beside it, if anything (kept, not quoted)")
    rd = sub.add_parser("readme", help="print README's Duration paragraph")
    rd.add_argument("--write", action="store_true", help="put it into README.md")
    a = ap.parse_args(argv)
    if a.command == "add":
        runs = load()
        for log in a.logs:
            run = parse(log.read_text(errors="replace"))
            for key in ("commit", "date", "cpu"):
                run[key] = getattr(a, key) or run[key]
            if a.note:
                run["note"] = a.note
            missing = [k for k, v in run.items() if v is None]
            if missing:
                print(f"ci_durations.py: {log}: no {', '.join(missing)} in the log (an "
                      f"incomplete run, or give --commit/--date/--cpu)", file=sys.stderr)
                return 2
            if run["fast_failed"] or run["slow_failed"]:
                print(f"ci_durations.py: {log}: a failed run is no duration of CI",
                      file=sys.stderr)
                return 2
            runs.append(run)
            print(json.dumps(run))
        RESULTS.write_text(json.dumps({"runs": runs}, indent=1) + "\n")
        return 0
    runs = load()
    if not runs:
        print(f"ci_durations.py: no runs in {RESULTS}", file=sys.stderr)
        return 2
    text = paragraph(runs)
    if a.write:
        readme = README.read_text()
        start, end = readme_bullet(readme)
        README.write_text(readme[:start] + text + readme[end:])
    print(text, end="")
    return 0


if __name__ == "__main__":
    sys.exit(main())
