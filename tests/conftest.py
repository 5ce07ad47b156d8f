"""Shared fixtures: scenes built in code so each test states exactly what it runs."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from bearingdae import scene_from_dict


def make_scene(overrides=None, **sections):
    """A yang20 scene with the given sections merged in (dotted ``overrides`` on top)."""
    data = {"bearing": {"preset": "yang20"}}
    for sec, body in sections.items():
        data.setdefault(sec, {}).update(body)
    return scene_from_dict(data, overrides)


#: A bearing with many small rollers on a large pitch circle, flat profile, zero clearance: the
#: setting in which the discrete load distribution approaches Stribeck's continuous integral.
MANY_ROLLERS = {
    "rollers": 300,
    "outer_diameter_mm": 520.0,
    "bore_mm": 480.0,
    "roller_diameter_mm": 5.0,
    "roller_length_mm": 10.0,
    "effective_length_mm": 10.0,
    "profile": "flat",
    "radial_clearance_mm": 0.0,
}


#: the controller's folder for the workers' compile locks and pattern claims (xdist)
_SHARED: list[str] = []


@pytest.hookimpl(optionalhook=True)  # an xdist hook: pytest without xdist runs too
def pytest_configure_node(node):
    """xdist controller: give every worker the session's folder of compile locks."""
    import tempfile

    if not _SHARED:
        _SHARED.append(tempfile.mkdtemp(prefix="bearingdae-test-kernels-"))
    node.workerinput["bearingdae_kernel_locks"] = _SHARED[0]


def pytest_unconfigure(config):
    import shutil

    if _SHARED and not hasattr(config, "workerinput"):
        shutil.rmtree(_SHARED.pop(), ignore_errors=True)


def _shared_folder(config):
    """The session's folder of compile locks, in a worker of two or more; else None."""
    workerinput = getattr(config, "workerinput", None)
    if not workerinput or workerinput.get("workercount", 1) < 2:
        return None
    folder = workerinput.get("bearingdae_kernel_locks")
    return None if folder is None else Path(folder)


def pytest_configure(config):
    """An xdist worker compiles a kernel another worker is compiling once: it waits for it
    and loads it from numba's cache (tests/kernel_warmup.share_compiles)."""
    folder = _shared_folder(config)
    if folder is not None:
        import kernel_warmup

        kernel_warmup.share_compiles(folder / "locks")


@pytest.fixture(scope="session", autouse=True)
def _kernels_warm(request):
    """Under xdist, the switch patterns the session's tests need are compiled before the
    tests run, each by one worker, the workers at once (tests/kernel_warmup.py)."""
    folder = _shared_folder(request.config)
    if folder is None:
        return
    import kernel_warmup

    tags = kernel_warmup.needed(item.nodeid for item in request.session.items)
    done = kernel_warmup.warm_patterns(tags, folder / "claims")
    # a failed warm-up changes no result (the pattern compiles in its first test), but it
    # costs time and hides its cause: said in the session's warnings summary
    for tag, outcome in done.items():
        if outcome.startswith("failed"):
            import warnings

            warnings.warn(f"kernel warm-up of switch pattern {tag!r} {outcome}", stacklevel=1)


@pytest.fixture(scope="session")
def long_baseline(request):
    """(scene, Dataset): the baseline over 1 + 24 cage revolutions (IDA), computed once per
    session for the modules that read it, by one worker under xdist (tests/shared_runs.py)."""
    import shared_runs

    folder = _shared_folder(request.config)
    scene = shared_runs.long_baseline_scene()
    return scene, shared_runs.shared_simulate(scene, None if folder is None else folder / "runs")


@pytest.fixture
def rng():
    return np.random.default_rng(20240917)


def ar1(phi: float, n: int, rng, burn: int = 2000) -> np.ndarray:
    """n samples of the AR(1) series x_k = phi x_(k-1) + e_k (unit normal e), after ``burn``
    start-up samples: correlated data whose blocking standard error is known."""
    e = rng.standard_normal(n + burn)
    x = np.empty_like(e)
    x[0] = e[0]
    for k in range(1, e.size):
        x[k] = phi * x[k - 1] + e[k]
    return x[burn:]


def load_tool(name: str):
    """The module of tools/NAME.py (the generators of docs/data/), loaded from its file."""
    import importlib.util
    from pathlib import Path

    spec = importlib.util.spec_from_file_location(
        f"{name}_tool", Path(__file__).resolve().parents[1] / "tools" / f"{name}.py")
    tool = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(tool)
    return tool


#: test modules whose cases share nothing (no module-scoped fixture, each case in a folder of
#: its own) and are long one by one: under ``--dist loadscope`` each case is a work unit of its
#: own, so that both workers share them (by module, one worker would run every section of
#: every document in turn)
SPREAD_CASES = ("tests/docs/test_doc_blocks.py::",)

#: the slow tier's longest work units (measured CPU, the longest first): in a ``-m slow``
#: session under ``--dist loadscope`` they start before every other unit. xdist's own order
#: is by number of tests, which put the modules of one or two long tests (a fixture of
#: minutes) last, where one worker ran them alone while the other had finished; longest
#: first, the short units fill in at the end. A module missing here runs in xdist's order;
#: the order changes no result.
LONG_FIRST = (
    "tests/validation/test_catalogue_friction.py",  # 510 s of CPU (a slow-tier session, load 5-10)
    "tests/validation/test_cage_whirl.py",  # 390 s
    "tests/results/test_read_back.py",  # 240 s (compiles of switch patterns)
    "tests/robustness/test_faults.py",  # 230 s (and its processes' CPU)
    "tests/solvers/test_newmark.py",  # 160 s
    "tests/validation/test_paper_trends.py",  # 150 s
    "tests/solvers/test_cold_start.py",  # 155 s
    "tests/validation/test_flange_ring_start.py",  # 150 s
    "tests/analysis/test_engineering.py",  # 90 s
    "tests/studies/test_paper.py",  # 75 s
)


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_make_scheduler(config, log):
    """``--dist loadscope`` as xdist does it, but with SPREAD_CASES' cases one unit each and
    LONG_FIRST's units first."""
    if config.getvalue("dist") != "loadscope":
        return None
    from xdist.scheduler import LoadScopeScheduling

    long_first = LONG_FIRST if config.getoption("markexpr", "") == "slow" else ()

    class Scheduling(LoadScopeScheduling):
        def _split_scope(self, nodeid: str) -> str:
            if nodeid.startswith(SPREAD_CASES):
                return nodeid
            return super()._split_scope(nodeid)

        def _assign_work_unit(self, node) -> None:
            # the longest unit still waiting goes next (workqueue: xdist's OrderedDict)
            first = next((scope for scope in long_first if scope in self.workqueue), None)
            if first is not None:
                self.workqueue.move_to_end(first, last=False)
            super()._assign_work_unit(node)

    return Scheduling(config, log)
