"""Long computations stop when asked: Ctrl-C (SIGINT) during a call raises
KeyboardInterrupt promptly, and so does an exception raised by a progress
callback, which propagates; both on the MNI template's crease surface and crest
lines. How long the stop took is printed (``pytest -s``)."""

import os
import signal
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import crestline

MNI = Path(__file__).resolve().parents[3] / "volumes" / "mni152_t1_1mm.nii.gz"

# The slowest stop allowed after the request: between two checkpoints of the
# library (its stages) on this template, on a machine that may be loaded.
PROMPT = 10.0


@pytest.fixture(scope="module")
def brain():
    return crestline.read_volume(MNI)


CALLS = {
    "crease_surface": lambda brain, **kw: crestline.crease_surface(brain, **kw),
    "crest_lines": lambda brain, **kw: crestline.crest_lines(brain, 80.0, **kw),
}
# The last stage of each.
LAST = {"crease_surface": "pairing and triangulation", "crest_lines": "valleys"}


def interrupted_after(seconds):
    """Send this process SIGINT after ``seconds``; the time it was sent."""
    sent = []

    def interrupt():
        sent.append(time.perf_counter())
        os.kill(os.getpid(), signal.SIGINT)

    timer = threading.Timer(seconds, interrupt)
    timer.start()
    return timer, sent


def interrupt_delay(brain, name):
    """When to interrupt ``name``: 0.5 s into a crease surface (about 10 s long),
    a third of the way through crest lines as long as they take here (0.6 s on two
    idle cores, less on more)."""
    if name == "crease_surface":
        return 0.5
    started = time.perf_counter()
    CALLS[name](brain)
    return (time.perf_counter() - started) / 3


@pytest.mark.parametrize("name", CALLS)
def test_ctrl_c_stops_the_computation_with_keyboard_interrupt(brain, name):
    stages = []
    timer, sent = interrupted_after(interrupt_delay(brain, name))
    try:
        with pytest.raises(KeyboardInterrupt):
            CALLS[name](brain, progress=lambda stage, seconds: stages.append((stage, seconds)))
    finally:
        timer.cancel()
    took = time.perf_counter() - sent[0]
    print(f"{name}: stopped {took:.2f} s after SIGINT, in stage {stages[-1][0]!r}")
    assert took < PROMPT
    # It stopped before the end: the last stage never finished.
    assert not any(stage == LAST[name] and seconds is not None for stage, seconds in stages)


class Stop(Exception):
    pass


@pytest.mark.parametrize("name", CALLS)
def test_a_progress_callback_that_raises_stops_the_computation_and_its_exception_propagates(brain, name):
    stages = []

    def progress(stage, seconds):
        stages.append((stage, seconds))
        if seconds is not None:  # the first stage has ended
            raise Stop(stage)

    started = time.perf_counter()
    with pytest.raises(Stop) as raised:
        CALLS[name](brain, progress=progress)
    took = time.perf_counter() - started
    print(f"{name}: stopped after its first stage ({raised.value}), {took:.2f} s in all")
    # No stage started after the one whose end raised.
    assert stages[-1][1] is not None and str(raised.value) == stages[-1][0]
    assert len(stages) == 2


def test_a_computation_without_a_callback_also_stops_on_ctrl_c():
    data = np.random.default_rng(1).random((120, 120, 120), dtype=np.float32)
    timer, sent = interrupted_after(0.3)
    try:
        with pytest.raises(KeyboardInterrupt):
            crestline.crease_surface(data)
    finally:
        timer.cancel()
    assert time.perf_counter() - sent[0] < PROMPT
