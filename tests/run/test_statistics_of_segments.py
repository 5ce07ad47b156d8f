"""The solver statistics of a run integrated in segments (solvers/base.merge_statistics): warm-up
blocks (``until_steady``) and a resume from a checkpoint. References: balances and bounds the
merged numbers must meet whatever the segments, not the merge's own rules: IDA's order at an
output is 1 to 5 (its maximum order), the histogram of those orders counts every output time
the run integrated to (warm-up and record, the start excepted), and Newmark's step is the
scene's (a setting, whatever the number of segments). Before, every number was summed: an
order of 12 over four blocks, 7 after one resume, a Newmark step of twice the scene's."""

from __future__ import annotations

import json
import warnings

import pytest

from bearingdae import SimulationError, simulate
from bearingdae.run.checkpoint import Checkpoint

from conftest import make_scene

OPERATING = {"speed_rpm": 2000.0, "radial_load_N": 800.0}
NUMERICS = {"cage_revolutions": 0.2, "samples_per_cage_revolution": 200,
            "warmup_cage_revolutions": 0.2}
#: output times integrated to after the start: 0.2 + 0.2 revolutions at 200 per revolution
OUTPUTS = 80


class StopAfter(Checkpoint):
    """A checkpoint that interrupts the run (as Ctrl-C) at its 40th sample."""

    def sample(self, t, y, yp):
        super().sample(t, y, yp)
        if len(self.T) == 40:
            raise KeyboardInterrupt


def _stats(ds) -> dict:
    return json.loads(ds.attrs["solver_statistics"])


def _assert_ida_orders(st: dict) -> None:
    assert 1 <= st["last_order"] <= 5 and 1 <= st["current_order"] <= 5, st
    assert sum(st["order_at_outputs"].values()) == OUTPUTS, st["order_at_outputs"]
    assert set(st["order_at_outputs"]) <= {"1", "2", "3", "4", "5"}


def test_a_warm_up_in_blocks_reports_orders_ida_can_have():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = simulate(make_scene(operating=OPERATING,
                                 numerics={**NUMERICS, "until_steady": True,
                                           "steady_tolerance": 0.1,
                                           "steady_block_cage_revolutions": 0.05}),
                      progress=False)
    assert ds.sizes["warmup_block"] == 4
    _assert_ida_orders(_stats(ds))


@pytest.mark.parametrize("solver", ["ida", "newmark"])
def test_a_resumed_run_reports_the_statistics_of_one_run(tmp_path, solver):
    scene = make_scene(operating=OPERATING, numerics=NUMERICS)
    path = tmp_path / "run.nc.checkpoint.npz"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(SimulationError, match="interrupted"):
            simulate(scene, solver=solver, progress=False,
                     checkpoint=StopAfter(path, every_samples=5))
        ds = simulate(scene, solver=solver, progress=False,
                      checkpoint=Checkpoint(path, resume=True))
    st = _stats(ds)
    assert st["segments"] == 2
    if solver == "ida":
        _assert_ida_orders(st)
    else:
        dyn = scene.dynamics
        assert st["step_s"] == dyn.newmark_step_s and st["beta"] == dyn.newmark_beta
        assert st["gamma"] == dyn.newmark_gamma
        assert 1.0 <= st["newton_iterations_per_step"] <= 10.0
