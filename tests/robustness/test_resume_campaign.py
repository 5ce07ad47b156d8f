"""Two trials of the kill/resume campaign (tools/resume_campaign.py): `bearingdae run`
interrupted by SIGINT at a random sample, resumed, and compared with the uninterrupted run
(the samples before the resume point bit for bit, every statistic within its error bars, no
text saying the extremes before the restart come from samples). The full campaign (24 trials
over six switch combinations) is `python tools/resume_campaign.py --trials 24`."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

TOOL = Path(__file__).resolve().parents[2] / "tools" / "resume_campaign.py"


@pytest.mark.slow
def test_two_kill_resume_trials_equal_the_uninterrupted_run(tmp_path, capsys):
    spec = importlib.util.spec_from_file_location("resume_campaign", TOOL)
    tool = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(tool)
    status = tool.main(["--trials", "2", "--out", str(tmp_path), "--seed", "5"])
    out = capsys.readouterr().out
    assert status == 0 and "2/2 trials" in out, out
