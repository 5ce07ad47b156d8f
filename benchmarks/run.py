"""The benchmark suite's one entry point, and the helpers every benchmark shares.

    python benchmarks/run.py --list                  # each benchmark and the question it answers
    python benchmarks/run.py NAME [options]          # run one (NAME --help: its options)

benchmarks/README.md says, for each benchmark, its command and where its last figures are
written (docs/performance.md). Every benchmark pins BLAS/OpenMP to one thread, prints the CPU
it ran on (model, AVX-512 or AVX2) and the load average, and compares only what it measured
side by side in one session: the machine the figures come from is shared, so absolute times
move between sessions while ratios of interleaved runs hold.
"""

from __future__ import annotations

import importlib
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("MKL_NUM_THREADS", "1")
os.environ.setdefault("MPLBACKEND", "Agg")

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
RESULTS = HERE / "results"

#: NAME: (module in benchmarks/, the question it answers)
BENCHMARKS = {
    "versions": ("versions", "How much faster or slower is the default run than at another git "
                 "revision (fresh processes alternating, ratio per repeat)?"),
    "kernels": ("kernels", "What does one call of each compiled kernel cost (residual, IDA's "
                "residual callback, analytic Jacobian, block-arrow factor and solve), and does "
                "a changed kernel agree with another tree to round-off?"),
    "profile": ("perf_profile", "Where does the CPU time of an IDA step go, by shared object "
                "(Linux perf)?"),
    "switches": ("switches", "What does each scene or solver switch cost against the default "
                 "(slices, traction law, slip, cage, linear solver, Jacobian, SuppressAlg, "
                 "tolerance, integrator)?"),
    "dense-output": ("dense_output", "What does an output sample cost (200 against 4 000 "
                     "samples per cage revolution), and how much memory does a run hold?"),
    "memory": ("dense_output", "Does the peak memory of `bearingdae run` grow with the recorded "
               "length (3 against 30 cage revolutions)?"),
    "cold-start": ("cold_start", "How long does the first `bearingdae run` after an install "
                   "take against a later one, does its progress stall, and where does the "
                   "compile CPU go?"),
    "paper": ("sweeps", "How long does the whole paper set take (24 runs, 18 figures)?"),
    "sweep-scaling": ("sweeps", "How does a sweep's wall time scale with the number of worker "
                      "processes?"),
    "skidmap": ("sweeps", "How long does a speed x load skid map take, every point until "
                "steady?"),
    "workprecision": ("workprecision", "Error against cost: IDA against Newmark-beta and the "
                      "scipy peers at equal error."),
    "static": ("static", "How long does a quasi-static solve take?"),
    "stability": ("stability", "Does every extreme scene complete, with which checks and at "
                  "what cost (IDA and Newmark-beta)?"),
    "skew-statistics": ("skew_statistics", "Do IDA and Newmark-beta agree on the skew "
                        "statistics (one pocket impact, long runs, ensembles)?"),
}


# --- helpers shared by the benchmarks ---------------------------------------------------------
def fail(message: str):
    """Bad input: one line naming the option and the value, exit status 2."""
    print(f"run.py: {message[:300]}", file=sys.stderr)
    raise SystemExit(2)


def cpu_model() -> str:
    """'AMD EPYC (AVX2, no AVX-512), 2 CPUs': the CPU the numbers were measured on."""
    name, flags = platform.processor() or platform.machine(), set()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            key, _, value = line.partition(":")
            if key.strip() == "model name":
                name = value.strip()
            elif key.strip() == "flags":
                flags = set(value.split())
    except OSError:
        pass
    vec = ("AVX-512" if "avx512f" in flags else "AVX2, no AVX-512" if "avx2" in flags
           else "no AVX2")
    return f"{name} ({vec}), {os.cpu_count()} CPUs"


def load() -> float:
    """1-minute load average (above the CPU count: the machine was shared)."""
    return os.getloadavg()[0]


def summary(doc: str) -> str:
    """A module docstring's first paragraph on one line (a command's --help description)."""
    return " ".join(doc.strip().split("\n\n")[0].split())


def header(what: str) -> None:
    print(f"{what}\nCPU: {cpu_model()}; Python {platform.python_version()}; load "
          f"{load():.1f}; BLAS/OpenMP threads {os.environ['OMP_NUM_THREADS']}", flush=True)


def median(values) -> float:
    return statistics.median(values)


def overrides(pairs) -> dict:
    """``KEY=VALUE`` strings -> scene overrides (true/false and numbers parsed)."""
    out = {}
    for pair in pairs or ():
        key, sep, text = pair.partition("=")
        if not sep:
            fail(f"--set {pair[:100]!r}: expected KEY=VALUE, e.g. numerics.slices=20")
        value = {"true": True, "false": False}.get(text.lower(), text)
        if isinstance(value, str):
            try:
                value = int(text) if text.lstrip("+-").isdigit() else float(text)
            except ValueError:
                pass
        out[key] = value
    return out


def tree(spec: str) -> Path:
    """A source tree with ``bearingdae/`` in it: ``spec`` itself if it is a folder, else a git
    revision of this repository exported once (``git archive``) to a folder kept in the temp
    directory, so that its numba cache stays warm for the next benchmark that uses it."""
    p = Path(spec)
    if (p / "bearingdae").is_dir():
        return p.resolve()
    try:
        sha = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--verify", "--short=10",
                              f"{spec}^{{commit}}"], check=True, capture_output=True,
                             text=True).stdout.strip()
    except subprocess.CalledProcessError:
        fail(f"--old {spec[:100]!r}: neither a folder holding bearingdae/ nor a git revision of "
             "this repository (e.g. main, HEAD~3, c15baa7)")
    out = Path(tempfile.gettempdir()) / f"bearingdae-tree-{sha}"
    if not (out / "bearingdae").is_dir():
        part = out.with_name(out.name + f".part{os.getpid()}")
        part.mkdir(parents=True, exist_ok=True)
        archive = subprocess.run(["git", "-C", str(ROOT), "archive", sha], check=True,
                                 capture_output=True).stdout
        subprocess.run(["tar", "-x", "-C", str(part)], input=archive, check=True)
        part.rename(out)
    return out


def run_process(path, case: str, over: dict, out: str, plot: bool = True,
                extra_env: dict | None = None):
    """``bearingdae run CASE -o OUT`` of the tree at ``path`` in a process of its own (scene
    overrides ``over``, environment variables ``extra_env`` added): (resource usage of the
    process from wait4, wall time [s]); exits with the run's stderr if it fails."""
    import time

    env = {**os.environ, "PYTHONPATH": str(path), "PYTHONWARNINGS": "ignore",
           **(extra_env or {})}
    sets = [f"--set={k}={v}" for k, v in over.items()]
    args = [sys.executable, "-m", "bearingdae.cli", "run", case, "-o", out, "--no-progress",
            *([] if plot else ["--no-plot"]), *sets]
    t0 = time.perf_counter()
    p = subprocess.Popen(args, env=env, cwd=path, stdout=subprocess.DEVNULL,
                         stderr=subprocess.PIPE)
    _, status, ru = os.wait4(p.pid, 0)
    wall = time.perf_counter() - t0
    err = p.stderr.read().decode()
    p.stderr.close()
    if status != 0:
        raise SystemExit(f"bearingdae run failed ({status}): {err[-2000:]}")
    return ru, wall


def write_json(path, data) -> None:
    """Write a benchmark's result with the CPU, the date and the load average at its end
    (the page that quotes it says on which machine and how loaded)."""
    if path:
        import datetime

        Path(path).parent.mkdir(parents=True, exist_ok=True)
        head = {"cpu": cpu_model(), "date": datetime.date.today().isoformat(),
                "load_1min_at_end": round(load(), 2)}
        Path(path).write_text(json.dumps({**head, **data}, indent=1, default=str) + "\n")
        print(f"wrote {path}")


# --- the entry point --------------------------------------------------------------------------
def listing() -> str:
    width = max(map(len, BENCHMARKS))
    rows = [f"  {name:{width}s}  {question}" for name, (_, question) in BENCHMARKS.items()]
    return ("usage: python benchmarks/run.py NAME [options]   (NAME --help: its options)\n"
            "benchmarks:\n" + "\n".join(rows))


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if not argv or argv[0] in ("--list", "-l", "-h", "--help"):
        print(listing())
        return 0
    name, rest = argv[0], argv[1:]
    if name not in BENCHMARKS:
        print(f"unknown benchmark {name!r}\n{listing()}", file=sys.stderr)
        return 2
    sys.path.insert(0, str(HERE))
    module = importlib.import_module(BENCHMARKS[name][0])
    return module.main(rest, name) or 0


if __name__ == "__main__":
    sys.exit(main())
