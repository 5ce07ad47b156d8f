"""Progress of `simulate()` in Python: shown where a person watches (a terminal, a notebook),
quiet elsewhere or with progress=False; the compile notice once; progress of a study in a log
file one line per update, never a carriage return."""

from __future__ import annotations

import io
import sys
import types

import pytest

from bearingdae import load_scene, simulate
from bearingdae.run import progress as progress_mod

TINY = {"numerics.warmup_cage_revolutions": 0.0, "numerics.cage_revolutions": 0.02,
        "numerics.samples_per_cage_revolution": 200}


@pytest.fixture(scope="module")
def scene():
    sc = load_scene("yang20_baseline", TINY)
    simulate(sc, progress=False)  # compile (or load) the kernels outside the tests
    return sc


def test_quiet_with_progress_false(scene, capfd, monkeypatch):
    monkeypatch.setattr(progress_mod, "interactive", lambda stream=None: True)
    simulate(scene, progress=False)
    out, err = capfd.readouterr()
    assert out == "" and err == ""


def test_quiet_by_default_where_nobody_watches(scene, capfd):
    """Under pytest stderr is no terminal (a pipe to the capture) and there is no notebook:
    the default shows nothing, not even the compile notice."""
    assert not progress_mod.interactive()
    simulate(scene)
    out, err = capfd.readouterr()
    assert out == "" and err == ""


def test_a_bar_by_default_where_a_person_watches(scene, capsys, monkeypatch):
    """A terminal or a notebook (interactive() True): the compile notice, when the kernels are
    cold, once per process, then tqdm's bar in simulated time."""
    monkeypatch.setattr(progress_mod, "interactive", lambda stream=None: True)
    monkeypatch.setattr(progress_mod, "kernels_cold", lambda: True)
    monkeypatch.setattr(progress_mod, "_announced", False)
    simulate(scene)
    err = capsys.readouterr().err
    assert err.startswith("compiling kernels (first run only")
    assert "simulated time" in err and "100%" in err  # tqdm's bar, drawn to the end
    simulate(scene)
    err = capsys.readouterr().err
    assert "compiling" not in err and "simulated time" in err  # the notice came once


def test_progress_true_without_a_terminal_is_lines(scene, capsys):
    simulate(scene, progress=True)
    err = capsys.readouterr().err
    assert "\r" not in err
    lines = err.splitlines()
    assert lines and all(ln.startswith("simulated time ") for ln in lines), err
    assert lines[-1].startswith("simulated time") and "(100 %)" in lines[-1]


def test_progress_must_be_true_false_or_none(scene):
    with pytest.raises(TypeError, match=r"progress = 'yes': expected True, False or None"):
        simulate(scene, progress="yes")


def test_a_notebook_is_recognised_without_importing_ipython(monkeypatch):
    """A Jupyter kernel: IPython imported and its shell's config holds IPKernelApp (as
    tqdm.autonotebook tests it); a terminal IPython or none at all is no notebook."""
    monkeypatch.delitem(sys.modules, "IPython", raising=False)
    assert progress_mod.in_notebook() is False

    def fake_ipython(config):
        shell = types.SimpleNamespace(config=config)
        return types.SimpleNamespace(get_ipython=lambda: shell)

    monkeypatch.setitem(sys.modules, "IPython", fake_ipython({"IPKernelApp": {}}))
    assert progress_mod.in_notebook() is True
    assert progress_mod.interactive(io.StringIO()) is True
    monkeypatch.setitem(sys.modules, "IPython", fake_ipython({"TerminalIPythonApp": {}}))
    assert progress_mod.in_notebook() is False
    monkeypatch.setitem(sys.modules, "IPython",
                        types.SimpleNamespace(get_ipython=lambda: None))
    assert progress_mod.in_notebook() is False


def test_count_progress_in_a_log_is_one_line_per_update():
    stream = io.StringIO()
    bar = progress_mod.CountProgress(4, "work-precision", stream=stream)
    assert bar.tty is False
    bar.set_description("ida rtol=1e-06 (1/2)")
    bar.update(1)
    bar.update(0)  # nothing done: no line
    bar.set_description("scipy-BDF rtol=1e-06 (1/2)")
    bar.update(3)  # a failed rung and its skipped repeats count at once
    bar.close()
    text = stream.getvalue()
    assert "\r" not in text
    assert text.splitlines() == [
        "work-precision: 1/4 runs done (last: ida rtol=1e-06 (1/2))",
        "work-precision: 4/4 runs done (last: scipy-BDF rtol=1e-06 (1/2))"]


def test_count_progress_on_a_terminal_is_a_bar():
    stream = io.StringIO()
    bar = progress_mod.CountProgress(2, "work-precision", stream=stream, tty=True)
    bar.set_description("ida rtol=1e-06 (1/1)")
    bar.update(2)
    bar.close()
    assert "work-precision: ida rtol=1e-06 (1/1)" in stream.getvalue()
    assert "2/2" in stream.getvalue()
