"""Work that must run on Blender's main thread (the glTF exporter, loading images into
bpy.data) called from the render, which F12 runs in a worker thread."""

import threading

import bpy


def call(fn, *args):
    """fn(*args) on the main thread: directly when called there (a background render), else
    by a timer that the main thread runs, waiting for it. Its result, or its exception."""
    if threading.current_thread() is threading.main_thread():
        return fn(*args)
    done, outcome = threading.Event(), {}

    def run():
        try:
            outcome["value"] = fn(*args)
        except Exception as e:  # handed to the calling thread
            outcome["error"] = e
        done.set()
        return None

    bpy.app.timers.register(run, first_interval=0.0)
    done.wait()
    if "error" in outcome:
        raise outcome["error"]
    return outcome["value"]
