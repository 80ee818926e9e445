"""Work that must run on Blender's main thread (the glTF exporter, loading images into
bpy.data) called from the render, which F12 runs in a worker thread."""

import threading
import time

import bpy


class Abandoned(RuntimeError):
    """The main thread did not get to the work before the caller gave up on it (Blender
    quitting waits for the render on the main thread, which then runs no timers)."""


def call(fn, *args, give_up=None):
    """fn(*args) on the main thread: directly when called there (a background render), else
    by a timer that the main thread runs, waiting for it until `give_up()` says to stop
    waiting (then `Abandoned`, and fn will not run). Its result, or its exception."""
    if threading.current_thread() is threading.main_thread():
        return fn(*args)
    done, outcome, lock = threading.Event(), {}, threading.Lock()

    def run():
        with lock:
            if outcome.get("abandoned"):
                return None
            try:
                outcome["value"] = fn(*args)
            except Exception as e:  # handed to the calling thread
                outcome["error"] = e
        done.set()
        return None

    bpy.app.timers.register(run, first_interval=0.0)
    while not done.wait(0.05):
        if give_up is not None and give_up():
            with lock:
                if not done.is_set():
                    outcome["abandoned"] = True
                    raise Abandoned(f"{fn.__name__} abandoned: Blender's main thread is busy")
    if "error" in outcome:
        raise outcome["error"]
    return outcome["value"]


def deadline(seconds):
    """A give_up predicate: true once `seconds` have passed."""
    end = time.monotonic() + seconds
    return lambda: time.monotonic() > end
