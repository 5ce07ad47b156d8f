"""Ctrl-C at any moment of the ``bearingdae`` program: one line, status 130, never a
traceback (bearingdae/cli/program.py).

The program is started as pip's console-script wrapper starts it (the same three lines,
``from bearingdae.cli.program import main``). Python's own start-up, before the wrapper's import of
bearingdae has finished, is outside the package (a SIGINT then is Python's: see
bearingdae/cli/program.py and docs/robustness.md for the measured window); the tests therefore
start their clocks when the child reports that import done (``python -X importtime`` prints a
line for every module as its import finishes) and send SIGINT at several delays after it,
through argument parsing and the command's heavy imports (numpy, xarray, numba, SUNDIALS) into
the start of the command.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from bearingdae.cli import main
from bearingdae.cli.program import INTERRUPTED

ROOT = Path(__file__).resolve().parents[2]
#: pip's console-script wrapper for `bearingdae = "bearingdae.cli.program:main"`
WRAPPER = """import re
import sys
from bearingdae.cli.program import main
if __name__ == "__main__":
    sys.argv[0] = re.sub(r"(-script\\.pyw|\\.exe)?$", "", sys.argv[0])
    sys.exit(main())
"""
DELAYS_S = (0.001, 0.003, 0.01, 0.03, 0.1, 0.3, 1.0, 2.0)


def start(tmp_path: Path, *args: str) -> subprocess.Popen:
    script = tmp_path / "bearingdae"
    script.write_text(WRAPPER)
    env = dict(os.environ, PYTHONPATH=str(ROOT), OMP_NUM_THREADS="1")
    return subprocess.Popen([sys.executable, "-X", "importtime", str(script), *args],
                            cwd=tmp_path, env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)


def wait_for_import(p: subprocess.Popen, module: str) -> list[str]:
    """Read the child's stderr up to the importtime line of ``module``; returns what was read."""
    seen = []
    while True:
        line = p.stderr.readline()
        if not line:
            pytest.fail(f"the child ended before importing {module}: {''.join(seen)[-2000:]}")
        seen.append(line)
        if line.rstrip().endswith(f"| {module}"):
            return seen


def messages(err: str) -> list[str]:
    return [ln for ln in err.splitlines() if ln.strip() and not ln.startswith("import time:")]


@pytest.mark.parametrize("command", [
    ["run", "yang20_baseline", "-o", "out.nc", "--no-plot", "--no-progress"],
    ["static", "yang20_baseline", "-o", "out.nc"]], ids=["run", "static"])
def test_ctrl_c_during_start_up_ends_with_one_line(tmp_path, command):
    outcomes = []
    for delay in DELAYS_S:
        p = start(tmp_path, *command)
        head = wait_for_import(p, "bearingdae.cli.program")
        time.sleep(delay)
        p.send_signal(signal.SIGINT)
        try:
            out, err = p.communicate(timeout=300)
        except subprocess.TimeoutExpired:
            p.kill()
            pytest.fail(f"still running 300 s after SIGINT at {delay} s")
        err = "".join(head) + err
        assert "Traceback" not in err and "Exception ignored" not in err, (delay, err[-3000:])
        kept = (tmp_path / "out_partial.nc").exists()
        if p.returncode == 0:  # the command finished before the signal (static, 1 s)
            assert command[0] == "static" and delay >= 0.3, (delay, out, err[-2000:])
        elif kept:  # interrupted while integrating: samples kept (not start-up), status 130
            assert command[0] == "run" and delay >= 0.3 and p.returncode == 130, (delay, err)
            assert any("interrupted by the user" in m for m in messages(err)), err[-2000:]
            assert not any("failure" in m for m in messages(err)), err[-2000:]  # a Ctrl-C
        else:
            assert p.returncode == 130 and messages(err) == [INTERRUPTED], (delay, err[-2000:])
        outcomes.append((delay, "130+partial" if kept else p.returncode))
        (tmp_path / "out.nc").unlink(missing_ok=True)
        (tmp_path / "out_partial.nc").unlink(missing_ok=True)
    print(f"\n{command[0]}: (delay s, exit status) {outcomes}")
    assert sum(rc == 130 for _, rc in outcomes) >= 4  # the early ones are start-up


def test_ctrl_c_while_the_interpreter_shuts_down(tmp_path):
    """After the command has returned, a Ctrl-C (here sent by the process to itself while an
    atexit handler runs) ends the process at once with the line, after flushing its output."""
    code = ("import atexit, os, signal, sys, time\n"
            "atexit.register(lambda: (os.kill(os.getpid(), signal.SIGINT), time.sleep(30)))\n"
            "from bearingdae.cli.program import main\n"
            "sys.argv = ['bearingdae', 'keys']\n"
            "sys.exit(main())\n")
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env,
                       timeout=120)
    assert r.returncode == 130, r.stderr
    assert "Traceback" not in r.stderr and messages(r.stderr) == [INTERRUPTED], r.stderr
    assert "operating.radial_load_N" in r.stdout  # printed before, not lost by the exit


def test_library_use_keeps_the_callers_ctrl_c_handling(capsys):
    """cli.main called in-process (tests, notebooks) leaves the SIGINT handler as it was."""
    before = signal.getsignal(signal.SIGINT)
    assert main(["keys"]) == 0
    assert signal.getsignal(signal.SIGINT) is before


def test_ctrl_c_between_the_wrappers_import_and_main_ends_with_one_line(tmp_path):
    """pip's wrapper runs a line of its own after importing the program and before calling
    ``main`` (a regular expression on ``sys.argv[0]``): a SIGINT there (here the wrapper sends
    it to itself at that point) ends with the line and status 130, not a traceback; imported
    by anything else than the program, the module leaves the SIGINT handler alone."""
    lines = WRAPPER.splitlines()
    at = lines.index("from bearingdae.cli.program import main") + 1
    script = tmp_path / "bearingdae"
    script.write_text("\n".join(lines[:at] + ["import os, signal, time",
                                               "os.kill(os.getpid(), signal.SIGINT)",
                                               "time.sleep(30)"] + lines[at:]) + "\n")
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    r = subprocess.run([sys.executable, str(script), "keys"], capture_output=True, text=True,
                       env=env, timeout=120)
    assert r.returncode == 130 and messages(r.stderr) == [INTERRUPTED], r.stderr
    code = ("import signal\nfrom bearingdae.cli import program\n"
            "print(signal.getsignal(signal.SIGINT) is signal.default_int_handler)\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env,
                       timeout=120)
    assert r.stdout.strip() == "True", r.stderr


SWALLOWED = """
import os, signal, sys, time
import bearingdae.cli as cli
from bearingdae.cli import program

class Swallow:
    def __del__(self):
        os.kill(os.getpid(), signal.SIGINT)
        for _ in range(10**6):  # the KeyboardInterrupt is raised here, inside __del__, where
            pass                # Python prints "Exception ignored" and goes on

def execute(argv):
    program.raise_on_ctrl_c()  # the command phase, as cli.execute after its imports
    Swallow()
    time.sleep(10)
    print("not interrupted")
    return 0

cli.execute = execute
sys.exit(program.main())
"""


def test_a_ctrl_c_lost_in_a_callback_is_delivered_again():
    """A KeyboardInterrupt raised where Python cannot pass it on (here ``__del__``; measured in
    the wild: llvmlite's ctypes callback while numba compiles, importlib's module-lock
    clean-up) would be printed as "Exception ignored" and the command would go on; the
    program sends it again and ends with the line and status 130."""
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    r = subprocess.run([sys.executable, "-c", SWALLOWED], capture_output=True, text=True,
                       env=env, timeout=120)
    assert "not interrupted" not in r.stdout, r.stderr
    assert r.returncode == 130 and messages(r.stderr) == [INTERRUPTED], r.stderr
