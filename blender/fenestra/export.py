"""A Blender scene as a fenestra render: the evaluated scene exported with Blender's own glTF
exporter (modifiers applied, instances kept as shared meshes), plus the command line that
carries what glTF cannot hold (world, portals, resolution, camera)."""

import os
from dataclasses import dataclass, field

import bpy

from . import area_lights, catalogue, glb, mainthread, materials, portals, properties, world


@dataclass
class Export:
    """A scene exported for fenestra: its .glb, the flags beside it and what was left out."""

    glb: str
    width: int
    height: int
    camera_flags: list
    world_flags: list
    portal_flags: list = field(default_factory=list)
    notes: list = field(default_factory=list)

    @property
    def scene_flags(self):
        """Everything `fenestra render` needs beside the file to render what Blender would."""
        size = ["--resolution", f"{self.width}x{self.height}"]
        return size + self.camera_flags + self.world_flags + self.portal_flags


def resolution(scene):
    """The render's size in pixels (resolution times percentage)."""
    r = scene.render
    return (
        max(1, r.resolution_x * r.resolution_percentage // 100),
        max(1, r.resolution_y * r.resolution_percentage // 100),
    )


def _camera_flag(path, camera):
    """`--camera NAME` picking the active camera in the exported file."""
    doc = glb.read(path)[1]
    cams = doc.get("cameras", [])
    nodes = [n for n in doc.get("nodes", []) if "camera" in n]
    mine = [n for n in nodes if n.get("name") == camera.name]
    if not mine:
        raise RuntimeError(f"the active camera {camera.name} was not exported (is it renderable?)")
    name = cams[mine[0]["camera"]].get("name", "")
    sharing = [n for n in nodes if cams[n["camera"]].get("name", "") == name]
    if not name or len(sharing) > 1:
        raise RuntimeError(
            f"cameras share the camera data {name!r}: give the active camera ({camera.name}) "
            "camera data of its own"
        )
    return ["--camera", name]


def _export_glb(scene, view_layer, path):
    """Blender's glTF exporter on `scene` (main thread only: in F12's worker thread its
    context is missing)."""
    window = (
        bpy.context.window_manager.windows[0]
        if bpy.context.window_manager and bpy.context.window_manager.windows
        else None
    )
    override = {"scene": scene, "view_layer": view_layer}
    if window is not None:
        override["window"] = window
    options = dict(
        filepath=path,
        export_format="GLB",
        use_active_scene=True,
        use_renderable=True,
        export_apply=True,
        export_cameras=True,
        export_lights=True,
        export_yup=True,
        export_animations=False,
        export_extras=False,
        # Blender 3.6+: lights in physical units (W -> lm at 683 lm/W), as fenestra reads them.
        export_import_convert_lighting_mode="SPEC",
    )
    known = bpy.ops.export_scene.gltf.get_rna_type().properties.keys()
    with bpy.context.temp_override(**override):
        result = bpy.ops.export_scene.gltf(**{k: v for k, v in options.items() if k in known})
    if "FINISHED" not in result:
        raise RuntimeError(f"Blender's glTF exporter did not finish ({result})")


def export(scene, view_layer, folder, portal_flags=True, give_up=None):
    """Exports `scene` into `folder` for a render: the flags of its camera and world, and
    with `portal_flags` those of its portals as the settings ask. `give_up` ends the wait
    for the main thread (see mainthread.call)."""
    if scene.camera is None:
        raise RuntimeError("the scene has no active camera")
    if scene.camera.data.type != "PERSP":
        raise RuntimeError(
            f"the active camera is {scene.camera.data.type.lower()}; fenestra renders perspective cameras"
        )
    scene_file = os.path.join(folder, "scene.glb")
    mainthread.call(_export_glb, scene, view_layer, scene_file, give_up=give_up)
    width, height = resolution(scene)
    # On the main thread too: an environment image's pixels may have to be loaded.
    world_flags, notes = mainthread.call(world.world_flags, scene.world, folder, give_up=give_up)
    notes += materials.notes(scene) + area_lights.append_to_glb(scene_file, scene.objects)
    cam = scene.camera.data
    if cam.shift_x or cam.shift_y:
        notes.append("the camera's shift is not carried over (glTF has no lens shift)")
    exported = Export(
        scene_file, width, height, _camera_flag(scene_file, scene.camera), world_flags, notes=notes
    )
    settings = scene.fenestra
    if portal_flags and catalogue.reads(settings.integrator, "portals"):
        if settings.portals == "scene":
            portal_file = os.path.join(folder, "portals.json")
            if portals.write_scene_portals(scene.objects, portal_file) == 0:
                raise RuntimeError(
                    "Portals is set to Scene but the scene has no Cycles portal light"
                )
            exported.portal_flags = ["--portals", portal_file]
        else:
            exported.portal_flags = ["--portals", "auto"]
    return exported


def render_command(binary, exported, settings, output):
    """The `fenestra render` command line for an export, writing `output`."""
    return [
        binary,
        "render",
        exported.glb,
        "-o",
        output,
        *exported.scene_flags,
        *properties.render_flags(settings),
        *(["--reference", bpy.path.abspath(settings.reference)] if settings.reference else []),
        "--snapshot-every",
        f"{settings.snapshot_every:g}",
        "--progress-lines",
    ]
