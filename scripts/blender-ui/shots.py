"""Screenshots of the add-on at work (run by scripts/blender-screenshots in Blender's
window under Xvfb): F12 as a user presses it, the windows captured 3, 15 and 45 s later;
then a second F12 and Blender quit 5 s into it, to show nothing is left running."""

import sys
import time

import addon_utils
import bpy

out = sys.argv[sys.argv.index("--") + 1]
addon_utils.enable("fenestra", default_set=True)
scene = bpy.context.scene
scene.render.engine = "FENESTRA"
s = scene.fenestra
s.integrator, s.samples, s.time_limit, s.snapshot_every = "lp_hf", 1_000_000, 40.0, 1.0
log = open(f"{out}/log.txt", "w")
state = {"t0": None, "shots": []}
SHOTS = [3.0, 15.0, 45.0]


def setup_views():
    for win in bpy.context.window_manager.windows:
        for area in win.screen.areas:
            if area.type == "PROPERTIES":
                area.spaces[0].context = "RENDER"
            if area.type == "VIEW_3D":
                area.spaces[0].region_3d.view_perspective = "CAMERA"


def shoot(name):
    for i, win in enumerate(bpy.context.window_manager.windows):
        with bpy.context.temp_override(window=win, screen=win.screen, area=win.screen.areas[0]):
            bpy.ops.screen.screenshot(filepath=f"{out}/{name}-window{i}.png")


def step():
    if state["t0"] is None:
        setup_views()
        state["t0"] = time.monotonic()
        bpy.ops.render.render("INVOKE_DEFAULT")  # F12
        return 0.5
    t = time.monotonic() - state["t0"]
    if len(state["shots"]) < len(SHOTS) and t >= SHOTS[len(state["shots"])]:
        shoot(f"at{SHOTS[len(state['shots'])]:g}s")
        state["shots"].append(t)
        log.write(f"screenshot at {t:.1f} s\n")
        log.flush()
    if len(state["shots"]) == len(SHOTS):
        if "again" not in state:
            state["again"] = t
            bpy.ops.render.render("INVOKE_DEFAULT")
        elif t > state["again"] + 5:
            log.write(f"quit at {t:.1f} s, 5 s into a second render\n")
            log.flush()
            bpy.ops.wm.quit_blender()
            return None
    return 0.25


bpy.app.timers.register(step, first_interval=2.0)
