"""Ctrl-C stops a render from Python and keeps what it rendered."""

import os
import signal
import threading
import time

import numpy as np
import pytest

import fenestra as fe


def test_ctrl_c_stops_the_render_and_keeps_its_film():
    # Python leaves SIGINT ignored when it started ignored, as in a job a shell runs in the
    # background: Ctrl-C is what this test is about, so it takes its usual meaning here.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        ctrl_c_during_a_render()
    finally:
        signal.signal(signal.SIGINT, previous)


def ctrl_c_during_a_render():
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    started = time.monotonic()
    timer.start()
    with pytest.warns(UserWarning, match="render interrupted"):
        img = fe.render("builtin:cornell-box", time=60.0, resolution=(64, 64), progress=False)
    assert time.monotonic() - started < 10.0
    assert img.interrupted
    assert img.stats["spp"] >= 1
    assert np.isfinite(img.array).all() and img.array.mean() > 0


def test_an_error_in_the_progress_callback_stops_the_render_and_is_raised():
    def fails(stage, done, total, notes):
        raise RuntimeError("callback says stop")

    started = time.monotonic()
    with pytest.raises(RuntimeError, match="callback says stop"):
        fe.render("builtin:cornell-box", time=60.0, resolution=(64, 64), progress=fails)
    assert time.monotonic() - started < 10.0
