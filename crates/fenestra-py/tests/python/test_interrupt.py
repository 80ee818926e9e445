"""Ctrl-C stops a render from Python and keeps what it rendered."""

import os
import signal
import threading
import time

import numpy as np
import pytest

import fenestra as fe


def test_ctrl_c_stops_the_render_and_keeps_its_film(tmp_path):
    # Python leaves SIGINT ignored when it started ignored, as in a job a shell runs in the
    # background: Ctrl-C is what this test is about, so it takes its usual meaning here.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        img = ctrl_c_during_a_render()
    finally:
        signal.signal(signal.SIGINT, previous)
    # Its files never replace a complete render's: they go beside it, as the CLI's do.
    complete = fe.render("builtin:cornell-box", spp=1, resolution=(16, 16), progress=False)
    out = tmp_path / "out.exr"
    assert complete.write(out) == out
    before = out.read_bytes()
    with pytest.warns(UserWarning, match="holds a complete render"):
        written = img.write(out)
    assert written == tmp_path / "out.interrupted.exr" and written.exists()
    assert out.read_bytes() == before


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
    return img


def test_an_error_in_the_progress_callback_stops_the_render_and_is_raised():
    def fails(stage, done, total, notes):
        raise RuntimeError("callback says stop")

    started = time.monotonic()
    with pytest.raises(RuntimeError, match="callback says stop"):
        fe.render("builtin:cornell-box", time=60.0, resolution=(64, 64), progress=fails)
    assert time.monotonic() - started < 10.0
