"""Cold start: a streamed run compiles (or loads from numba's cache) every kernel it needs
before its integration starts, so that no block of samples stops the progress to compile
(bearingdae/results/streamed_record.py ``begin``, solvers/algebraic.py ``prepare``)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

# In a fresh process (nothing compiled or loaded yet): a short default run, streamed; while a
# block is projected and written (StreamedRecord.flush, the last one included), count numba's
# compile events and the specialisations any dispatcher gains (a compile or a cache load: on
# a cold start either is a stall of the progress). The same counts over the whole run say
# that the watch works. Without the pre-compile step the blocks load or compile the projection
# and the film's loop (checked when this test was written).
PROGRAM = r"""
import json, sys
from numba.core import event
from numba.core.dispatcher import Dispatcher
from bearingdae import load_scene
from bearingdae.api import simulate_to_file
from bearingdae.results import streamed_record as record

state = {"in_block": False, "compiled": [], "all_compiled": 0, "blocks": 0}

class Watch(event.Listener):
    def on_start(self, e):
        pass
    def on_end(self, e):
        state["all_compiled"] += 1
        if state["in_block"]:
            state["compiled"].append(str(e.data["dispatcher"]))

event.register("numba:compile", Watch())

def dispatchers():  # bearingdae's compiled functions, by "module.name"
    return {f"{m}.{k}": v for m, mod in list(sys.modules.items()) if m.startswith("bearingdae")
            for k, v in list(vars(mod).items()) if isinstance(v, Dispatcher)}

def overloads():
    return {k: len(d.overloads) for k, d in dispatchers().items()}

flush = record.StreamedRecord.flush
gained = []

def watched(self, *args, **kwargs):
    before = overloads()
    state["in_block"] = True
    try:
        return flush(self, *args, **kwargs)
    finally:
        state["in_block"] = False
        state["blocks"] += 1
        after = overloads()
        gained.extend(k for k, n in after.items() if n > before.get(k, 0))

record.StreamedRecord.flush = watched
start = overloads()
scene = load_scene("yang20_baseline", overrides={
    "numerics.warmup_cage_revolutions": 0.0, "numerics.cage_revolutions": 0.01})
result = simulate_to_file(scene, sys.argv[1], progress=False)
state["gained"] = gained
end = overloads()
state["run_gained"] = sorted(k for k, n in end.items() if n > start.get(k, 0))
state["success"] = result.success
print(json.dumps(state))
"""


def test_streamed_blocks_compile_nothing(tmp_path):
    # this process compiles the projection before the integration (no second process: with
    # one, the samples wait for its projection instead, tests/results/test_streamed.py)
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""),
               BEARINGDAE_COMPILE_ASIDE="0")
    out = subprocess.run([sys.executable, "-c", PROGRAM, str(tmp_path / "run.nc")], env=env,
                         cwd=tmp_path, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr[-2000:]
    state = json.loads(out.stdout.strip().splitlines()[-1])
    assert state["success"]
    assert state["blocks"] >= 1  # the record's samples went through at least one block
    # the watch sees the run's kernels arrive (the projection among them)
    assert "bearingdae.solvers.projection_kernel.project_batch" in state["run_gained"]
    assert state["compiled"] == [], state["compiled"]
    assert state["gained"] == [], state["gained"]
