"""Operators: estimate portals with fenestra and add them as Cycles portal lights; open the
last render's report."""

import json
import os
import subprocess
import tempfile
import webbrowser

import bpy

from . import export, portals, preferences, world


class FENESTRA_OT_estimate_portals(bpy.types.Operator):
    """Estimate where light enters the scene (`fenestra portals`) and add the portals as
    Cycles portal lights, which fenestra's Portals: Scene and Cycles both use"""

    bl_idname = "fenestra.estimate_portals"
    bl_label = "Estimate Portals"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        scene = context.scene
        try:
            binary = preferences.binary(context)
            with tempfile.TemporaryDirectory(prefix="fenestra-portals-") as folder:
                added = estimate(binary, scene, context.view_layer, folder)
        except (RuntimeError, world.WorldError, subprocess.CalledProcessError) as e:
            self.report({"ERROR"}, f"fenestra: {e}")
            return {"CANCELLED"}
        if not added:
            self.report(
                {"WARNING"}, "fenestra found no portal: light does not come in through openings"
            )
        else:
            self.report({"INFO"}, f"fenestra: added {len(added)} portal lights")
        return {"FINISHED"}


def estimate(binary, scene, view_layer, folder):
    """Runs `fenestra portals` on the exported scene under its world; adds the portals found
    to a collection "fenestra portals" (replacing those of an earlier estimate)."""
    exported = export.export(scene, view_layer, folder, portal_flags=False)
    out = os.path.join(folder, "estimated-portals.json")
    subprocess.run(
        [
            binary,
            "portals",
            exported.glb,
            "-o",
            out,
            "-q",
            *exported.camera_flags,
            *exported.world_flags,
        ],
        check=True,
        capture_output=True,
        text=True,
    )
    with open(out) as f:
        records = json.load(f)["portals"]
    collection = bpy.data.collections.get("fenestra portals")
    if collection is None:
        collection = bpy.data.collections.new("fenestra portals")
        scene.collection.children.link(collection)
    for obj in list(collection.objects):
        light = obj.data
        bpy.data.objects.remove(obj)
        if light and light.users == 0:
            bpy.data.lights.remove(light)
    facing = scene.camera.matrix_world.translation
    return portals.add_portal_lights(records, collection, facing)


class FENESTRA_OT_open_report(bpy.types.Operator):
    """Open the report of the last render made with a reference image"""

    bl_idname = "fenestra.open_report"
    bl_label = "Open Report"

    def execute(self, context):
        path = context.scene.fenestra.last_report
        if not path or not os.path.exists(path):
            self.report({"ERROR"}, "no report: render with a Reference image set first")
            return {"CANCELLED"}
        webbrowser.open("file://" + path)
        return {"FINISHED"}


register, unregister = bpy.utils.register_classes_factory(
    (FENESTRA_OT_estimate_portals, FENESTRA_OT_open_report)
)
