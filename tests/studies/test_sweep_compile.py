"""A sweep's first run after installation compiles the kernels once, in its client, before
the worker processes start: each kernel variant its scenes need, and only those
(studies/sweep/cluster.py ``_compile_before_workers``). Decisions, and the cache a worker
finds; no timing."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from bearingdae.scene import load_scene, scene_from_dict
from bearingdae.studies.sweep import cluster

ROOT = Path(__file__).resolve().parents[2]
SPALL = [{"on": "outer", "angle_deg": 0.0, "length_mm": 1.0, "width_mm": 4.0, "depth_um": 10.0}]


def _scene(defects=(), **overrides):
    data = tomllib.loads(load_scene("yang20_baseline").to_toml())
    if defects:
        data["defects"] = list(defects)
    return scene_from_dict(data, overrides)


@pytest.mark.parametrize("scheduler, workers, cold, compiles", [
    (None, 2, True, True),           # a LocalCluster on a fresh install: once, here
    (None, 2, False, False),         # the cache holds the kernels: the workers load them
    (None, 1, True, False),          # one worker compiles them once anyway
    ("synchronous", 2, True, False),  # no workers: the first run compiles them
    ("tcp://127.0.0.1:8786", 2, True, False),  # a remote cluster's workers: their own cache
])
def test_kernels_compile_once_before_a_local_cluster_starts(monkeypatch, scheduler, workers,
                                                            cold, compiles):
    calls = []
    monkeypatch.setattr(cluster, "_cold", lambda optional: cold)
    monkeypatch.setattr(cluster, "_compile_run", calls.append)
    scene = _scene()
    assert cluster._compile_before_workers(scheduler, workers, [scene, scene]) is compiles
    assert calls == ([scene] if compiles else [])  # one variant: one compiling run


def test_one_compiling_run_per_cold_variant_the_scenes_use(monkeypatch):
    default, mixed = _scene(), _scene(**{"physics.lubrication": "mixed"})
    faster = _scene(**{"physics.lubrication": "mixed", "operating.speed_rpm": 4000.0})
    spall = _scene(defects=SPALL)
    spall_mixed = _scene(defects=SPALL, **{"physics.lubrication": "mixed"})
    scenes = [mixed, faster, default, spall, spall_mixed, default]
    variants = cluster._variants(scenes)
    assert len(variants) == 4  # default, mixed, the spall, the spall with mixed
    assert [variants[k] for k in variants] == [mixed, default, spall, spall_mixed]
    assert False in variants  # the default scene's variant: nothing compiled apart
    calls = []
    monkeypatch.setattr(cluster, "_compile_run", calls.append)
    cold = {k for k, s in variants.items() if s is not default}  # the default's is cached
    monkeypatch.setattr(cluster, "_cold", lambda optional: optional in cold)
    assert cluster._compile_before_workers(None, 2, scenes) is True
    assert calls == [mixed, spall, spall_mixed]


def test_a_failed_compilation_leaves_it_to_the_workers(monkeypatch):
    def fail(scene):
        raise RuntimeError("numba failed")

    monkeypatch.setattr(cluster, "_cold", lambda optional: True)
    monkeypatch.setattr(cluster, "_compile_run", fail)
    assert cluster._compile_before_workers(None, 2, [_scene()]) is False


# A worker's run of a mixed-lubrication scene after the client compiled: the numba functions
# it compiles (numba's compile events), and whether the default's kernels are still cold.
_WORKER = """
import json, sys
from numba.core import event
compiled = []
class Count(event.Listener):
    def on_start(self, e): pass
    def on_end(self, e): compiled.append(str((e.data or {}).get("dispatcher", "")))
event.register("numba:compile", Count())
from bearingdae.api import simulate
from bearingdae.run.progress import kernels_cold
from bearingdae.scene import load_scene, scene_from_dict
scene = load_scene("yang20_baseline", overrides={"physics.lubrication": "mixed",
    "numerics.warmup_cage_revolutions": 0.0, "numerics.cage_revolutions": 0.005,
    "operating.speed_rpm": 3000.0})
simulate(scene, progress=False)
print(json.dumps({"compiled": compiled, "default_cold": kernels_cold()}))
"""


@pytest.mark.slow  # cold compiles in fresh processes (≈ 20 s)
def test_a_worker_finds_every_kernel_of_its_run_and_the_default_stays_uncompiled(tmp_path):
    env = {**os.environ, "PYTHONPATH": str(ROOT), "NUMBA_CACHE_DIR": str(tmp_path / "numba"),
           "OMP_NUM_THREADS": "1", "BEARINGDAE_COMPILE_ASIDE": "auto"}
    client = ("from bearingdae.scene import load_scene\n"
              "from bearingdae.studies.sweep import cluster\n"
              "scene = load_scene('yang20_baseline', "
              "overrides={'physics.lubrication': 'mixed'})\n"
              "assert cluster._compile_before_workers(None, 2, [scene]) is True\n"
              "assert cluster._compile_before_workers(None, 2, [scene]) is False\n")
    r = subprocess.run([sys.executable, "-c", client], env=env, capture_output=True,
                       text=True, timeout=900)
    assert r.returncode == 0, r.stderr[-3000:]
    assert "compiling kernels once for the workers" in r.stderr
    r = subprocess.run([sys.executable, "-c", _WORKER], env=env, capture_output=True,
                       text=True, timeout=900)
    assert r.returncode == 0, r.stderr[-3000:]
    worker = json.loads(r.stdout.strip().splitlines()[-1])
    assert worker["compiled"] == []  # the residual, Jacobian, projection, hooks: all cached
    assert worker["default_cold"] is True  # the sweep's scenes do not use the default's
