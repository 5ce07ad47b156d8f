"""Progress of a dynamic run, shown so that a person can read it.

Pipeline place: beside the solvers; :func:`bearingdae.api.simulate` creates one
:class:`SimulationProgress` and feeds it the simulated time of every output sample. Studies
that count runs (the work-precision study) use :class:`CountProgress`.

* **Who sees it.** ``simulate(progress=None)``, the default, shows the progress where a person
  watches: stderr is a terminal, or the code runs in a Jupyter kernel (:func:`interactive`);
  elsewhere (a script piped to a log, a test, a sweep worker) it is quiet. ``progress=True``
  always shows it, ``False`` never.

* **Cold start.** The numba kernels (system/residual.py, system/jacobian_analytic.py,
  solvers/sundials/callbacks.py) compile on the first run and load from numba's cache
  afterwards. :func:`kernels_cold` looks at the
  cache indexes (no compiling, ~1 ms); :func:`compile_notice` is the line to print at once
  when they are missing or stale, instead of a silent half minute. A run compiles every
  kernel it needs before its first sample (the projection of the samples too), so no block
  of the record stops the progress; :func:`compile_wall_s` is how long that took.
* **A terminal** gets a tqdm bar in simulated time. Its ETA is shown only once it means
  something: after ``ETA_MIN_FRACTION`` of the simulated time *and* ``ETA_MIN_S`` of wall time
  since the first sample (the first call includes compiling and the start-up transient,
  which made tqdm's own estimate read "4:30:35" for a 30 s run).
* **Not a terminal** (a log file, a pipe, CI): one line at the first sample after the start
  (the integration is under way: on a cold start that is the first sign that compiling is
  over), then one each time another ``LINE_EVERY`` of the simulated time is done, instead of
  a bar redrawn hundreds of times (the default run redrew it 802 times, 70 KB of log).
"""

from __future__ import annotations

import math
import os
import sys
import time

#: How long the first `bearingdae run` of the default scene takes against a later one (cold
#: / warm wall time: an empty numba cache, then the same command again, the load average of
#: the machine in the file beside it), what the compile notice says. Measured by ``python
#: benchmarks/run.py cold-start --write``, which writes benchmarks/results/cold-start.json
#: (the ratio rounded to a tenth); the pages that quote a first-run time quote
#: this figure, and tests/docs/test_cold_start_figure.py checks them and this constant
#: against that file. Compiling is CPU-bound: a busy machine stretches it.
COLD_START_RATIO = 2.0
#: The ETA is shown once this fraction of the simulated time is done ...
ETA_MIN_FRACTION = 0.05
#: ... and this much wall time has passed since the first sample [s].
ETA_MIN_S = 3.0
#: Not a terminal: one line per this fraction of the simulated time.
LINE_EVERY = 0.1


def kernels_cold() -> bool:
    """True when a kernel of the dynamic run has no valid entry in numba's cache (first run,
    or the source changed since), so that the run starts by compiling. Reads the cache index
    files of what a default IDA run compiles (the two C callbacks of IDA, which contain every
    kernel they call, and the two kernels called from Python: ``residual`` for the initial
    state, ``fill_jacobian_analytic`` for the projection of the samples); no compiling, ~1 ms.
    Any surprise in numba's internals counts as warm (no notice)."""
    try:
        from ..solvers.sundials import callbacks
        from ..system import jacobian_analytic, residual

        if callbacks.is_cold("residual") or callbacks.is_cold("analytic"):
            return True
        for dispatcher in (residual.residual, jacobian_analytic.fill_jacobian_analytic):
            if not dispatcher._cache._cache_file._load_index():  # {} when missing or stale
                return True
    except Exception:  # noqa: BLE001 - a notice is not worth a failure
        return False
    return False


def compile_notice() -> str | None:
    """The line announcing a cold start, or None when the kernels are cached."""
    if not kernels_cold():
        return None
    return (f"compiling kernels (first run only, ~{COLD_START_RATIO:g}x the time of a later "
            "run on idle cores); later runs load them from the cache")


_announced = False  #: this process has printed the compile notice
#: monotonic clock at the compile notice, and at the first sample of the run after it
_compile_clock: list[float] = []


_first_sample: list[float] = []  #: monotonic clock at the run's first sample
_import_clock = time.monotonic()


def process_start_clock() -> float:
    """The monotonic clock when this process started (Linux: /proc/self/stat's start time,
    to 10 ms; elsewhere when this module was imported): what "since the command started"
    counts from, the interpreter's start and the imports included."""
    try:
        with open("/proc/self/stat") as f:
            start_ticks = int(f.read().rsplit(")", 1)[1].split()[19])  # field 22: starttime
        with open("/proc/uptime") as f:
            uptime_s = float(f.read().split()[0])
        age = uptime_s - start_ticks / os.sysconf("SC_CLK_TCK")
        if age >= 0.0:
            return time.monotonic() - age
    except (OSError, ValueError, IndexError, AttributeError):
        pass
    return _import_clock


def start_run() -> None:
    """Forget the previous run's first sample (a process that runs several)."""
    _first_sample.clear()


def mark_first_sample() -> None:
    """The run's first sample is out (run/integrate.py, at every sample; only the first
    counts): ends the compile clock and the quiet of the per-group compile notices."""
    if _first_sample:
        return
    now = time.monotonic()
    _first_sample.append(now)
    if len(_compile_clock) == 1:  # the first run after the compile notice
        _compile_clock.append(now)
        from ..util.kernel_cache import quiet

        quiet(False)


def first_sample_clock() -> float | None:
    """The monotonic clock at this run's first sample, None before it."""
    return _first_sample[0] if _first_sample else None


def compile_wall_s() -> float | None:
    """Wall time from the compile notice to the first sample of the run [s] (what a cold
    start spent compiling, every kernel the run needs: they compile before its integration
    starts, with the set-up between), or None: no notice in this process, or no sample since."""
    return _compile_clock[1] - _compile_clock[0] if len(_compile_clock) == 2 else None


def announce_compiling(stream=None) -> str | None:
    """Print :func:`compile_notice` to ``stream`` (stderr) when the kernels are cold, once per
    process (the command line announces it before :func:`bearingdae.simulate`, which would
    otherwise repeat it); returns the notice, or None when the kernels are cached."""
    global _announced
    notice = compile_notice()
    if notice is not None and not _announced:
        _announced = True
        _compile_clock[:] = [time.monotonic()]
        from ..util.kernel_cache import quiet

        quiet(True)  # this notice covers the run's kernels until its first sample
        _print_to(stream if stream is not None else sys.stderr, notice)
    return notice


def in_notebook() -> bool:
    """Running in a Jupyter kernel (a notebook, JupyterLab, VS Code's notebooks), where tqdm
    draws its bar although stderr is no terminal. Never imports IPython."""
    ipython = sys.modules.get("IPython")
    if ipython is None:
        return False
    try:
        shell = ipython.get_ipython()
        return shell is not None and "IPKernelApp" in shell.config
    except Exception:  # noqa: BLE001 - an odd IPython: no notebook
        return False


def interactive(stream=None) -> bool:
    """A person watches ``stream`` (stderr): a terminal with a size, or a notebook."""
    return is_terminal(stream if stream is not None else sys.stderr) or in_notebook()


def is_terminal(stream) -> bool:
    """A terminal with a size. A pseudo-terminal that reports 0 x 0 (measured: `script` with
    its output piped; docker -t without a size) counts as none: tqdm hides its bar there
    (its row 0 is not below the 0 rows) and would show nothing at all."""
    try:
        return bool(stream.isatty()) and os.get_terminal_size(stream.fileno()).columns > 0
    except (AttributeError, OSError, ValueError):  # closed, or not a file
        return False


def _clock(seconds: float) -> str:
    seconds = int(round(seconds))
    h, rest = divmod(seconds, 3600)
    m, s = divmod(rest, 60)
    return f"{h}:{m:02d}:{s:02d}" if h else f"{m}:{s:02d}"


class SimulationProgress:
    """Progress in simulated time up to ``total_s``: a bar on a terminal, else a line every
    ``LINE_EVERY``. ``update(t)`` with the simulated time of each sample; ``close()`` at the
    end. ``stream`` defaults to stderr; ``tty`` defaults to whether it is a terminal (with a
    size)."""

    def __init__(self, total_s: float, stream=None, tty: bool | None = None,
                 desc: str = "simulated time"):
        self.total_s = float(total_s)
        self.stream = stream if stream is not None else sys.stderr
        self.tty = interactive(self.stream) if tty is None else tty
        self.desc = desc
        self.start = time.monotonic()
        self._first: tuple[float, float] | None = None  # (wall, simulated) at the first sample
        self._next_line = LINE_EVERY
        self._moved = False  #: a sample after the first one has come (the first line printed)
        self._done = 0.0
        self._bar = None
        if self.tty:
            from tqdm.auto import tqdm

            self._bar = tqdm(total=self.total_s, unit="s", desc=desc, file=self.stream,
                             bar_format="{l_bar}{bar}| {n:.4f}/{total:.4f} s "
                                        "[{elapsed}{postfix}]")

    def eta_s(self, t: float, now: float | None = None) -> float | None:
        """Wall time left [s], or None while an estimate would mean nothing."""
        now = time.monotonic() if now is None else now
        if self._first is None or self.total_s <= 0:
            return None
        wall0, t0 = self._first
        if t / self.total_s < ETA_MIN_FRACTION or now - wall0 < ETA_MIN_S or t <= t0:
            return None
        return (self.total_s - t) * (now - wall0) / (t - t0)

    def set_total(self, total_s: float) -> None:
        """A new estimate of the end [s] (until-steady: the warm-up's end follows the trend of
        the block means, not the cap); the ETA and the fraction use it from the next update."""
        self.total_s = max(float(total_s), self._done)
        if self._bar is not None:
            self._bar.total = self.total_s
        fraction = self._done / self.total_s if self.total_s > 0 else 1.0
        self._next_line = LINE_EVERY * (math.floor(fraction / LINE_EVERY + 1e-12) + 1)

    def update(self, t: float) -> None:
        now = time.monotonic()
        if self._first is None:
            self._first = (now, float(t))
        self._done = float(t)
        fraction = t / self.total_s if self.total_s > 0 else 1.0
        eta = self.eta_s(t, now) if fraction < 1 else None
        if self._bar is not None:
            self._bar.n = t
            self._bar.postfix = f"ETA {_clock(eta)}" if eta is not None else ""  # tqdm adds ", "
            self._bar.refresh()
            return
        first_move = not self._moved and t > self._first[1]
        if first_move:
            self._moved = True
        if first_move or fraction + 1e-12 >= self._next_line:
            while self._next_line <= fraction + 1e-12:
                self._next_line += LINE_EVERY
            left = f", about {_clock(eta)} left" if eta is not None else ""
            self._print(f"{self.desc} {t:.4f}/{self.total_s:.4f} s ({100 * fraction:.0f} %), "
                        f"{_clock(now - self.start)} elapsed{left}")

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()
            self._bar = None

    def _print(self, line: str) -> None:
        _print_to(self.stream, line)


def _print_to(stream, line: str) -> None:
    try:
        print(line, file=stream, flush=True)
    except (OSError, ValueError):  # a closed or broken stream: progress is not worth it
        pass


class CountProgress:
    """Progress over ``total`` items (runs of a study): a tqdm bar where a person watches
    (:func:`interactive`), else one line per :meth:`update`, never a carriage return (a log
    file gets "work-precision: 3/12 runs done (last: ida rtol=1e-05 (1/3))"). The subset of
    tqdm's interface the studies use: ``update``, ``set_description``, ``close``."""

    def __init__(self, total: int, name: str, unit: str = "run", stream=None,
                 tty: bool | None = None):
        self.total, self.name, self.unit = int(total), name, unit
        self.stream = stream if stream is not None else sys.stderr
        self.tty = interactive(self.stream) if tty is None else tty
        self.n = 0
        self.desc = ""
        self._bar = None
        if self.tty:
            from tqdm.auto import tqdm

            self._bar = tqdm(total=self.total, unit=unit, desc=name, file=self.stream)

    def set_description(self, desc: str) -> None:
        self.desc = desc
        if self._bar is not None:
            self._bar.set_description(f"{self.name}: {desc}")

    def update(self, n: int = 1) -> None:
        if n <= 0:
            return
        self.n += n
        if self._bar is not None:
            self._bar.update(n)
            return
        what = f" (last: {self.desc})" if self.desc else ""
        _print_to(self.stream, f"{self.name}: {self.n}/{self.total} {self.unit}s done{what}")

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()
            self._bar = None
