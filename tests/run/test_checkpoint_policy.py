"""When a checkpoint is written (run/checkpoint.py): by default every 50 samples but at most
once per CHECKPOINT_MIN_INTERVAL_S of wall time (and every CHECKPOINT_EVERY_S whatever the
count); a number given for ``every_samples`` means every that many samples, exactly. A fake
clock drives the samples, so the test measures the policy, not the machine."""

from __future__ import annotations

import numpy as np
import pytest

from bearingdae.run import checkpoint as cp


class Clock:
    def __init__(self):
        self.now = 1000.0

    def __call__(self):
        return self.now


def writes(monkeypatch, tmp_path, samples_per_s: float, n: int, **kwargs) -> list[int]:
    """The sample counts at which the checkpoint was written, ``n`` samples at a steady rate."""
    clock = Clock()
    monkeypatch.setattr(cp.time, "monotonic", clock)
    ck = cp.Checkpoint(tmp_path / "c.npz", **kwargs)
    ck.begin("key", 3)
    at = []
    for i in range(1, n + 1):
        clock.now += 1.0 / samples_per_s
        before = ck.writes
        ck.sample(float(i), np.zeros(3), np.zeros(3))
        if ck.writes > before:
            at.append(i)
    return at


def test_default_writes_every_50_samples_when_they_take_a_second(monkeypatch, tmp_path):
    # 20 samples per second: 50 samples take 2.5 s, more than the minimum interval
    assert writes(monkeypatch, tmp_path, 20.0, 200) == [50, 100, 150, 200]


def test_default_writes_at_most_once_a_second_when_samples_come_fast(monkeypatch, tmp_path):
    # 500 samples per second (a dense record): every 50 samples would be 10 writes per
    # second; the default writes on the first 50th sample after a second, besides the segment
    # files every SEGMENT_SAMPLES (each written once, with the checkpoint naming it)
    rate = 500.0
    at = writes(monkeypatch, tmp_path, rate, 3000)
    rolls = [i for i in at if i % cp.SEGMENT_SAMPLES == 0]
    assert rolls == [1000, 2000, 3000]
    gaps = np.diff([0] + at) / rate
    assert np.all(gaps >= cp.CHECKPOINT_MIN_INTERVAL_S - 2 / rate)  # the clock's rounding
    assert len(at) == 6  # one write between two segments: 6 instead of 60


def test_a_number_given_means_exactly_every_that_many_samples(monkeypatch, tmp_path):
    assert writes(monkeypatch, tmp_path, 4000.0, 20, every_samples=5) == [5, 10, 15, 20]


def test_slow_samples_still_write_every_10_s(monkeypatch, tmp_path):
    # one sample every 4 s: the 10 s rule writes before 50 samples have come
    at = writes(monkeypatch, tmp_path, 0.25, 9)
    assert at == [3, 6, 9]


@pytest.mark.parametrize("value", [0, -1, 2.5, True, "50"])
def test_every_samples_refuses_what_is_not_a_count(tmp_path, value):
    with pytest.raises(ValueError, match="every_samples"):
        cp.Checkpoint(tmp_path / "c.npz", every_samples=value)
