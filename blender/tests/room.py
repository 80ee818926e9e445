"""The add-on tests' scene, built with bpy: a 4 x 4 x 2.6 m room with a window opening in
one wall, under a Sky Texture with its sun outside the window; a ceiling lamp (point
light), a glossy metal block, a glass sphere and a white floor; a camera looking at the
window wall."""

import math

import bpy
import bmesh
from mathutils import Matrix


def use_nodes(datablock):
    """Blender 4 needs node trees switched on (Blender 5 always has them)."""
    if bpy.app.version < (5, 0, 0):
        datablock.use_nodes = True
    return datablock


def _material(name, color, metallic=0.0, roughness=0.5, transmission=0.0):
    m = use_nodes(bpy.data.materials.new(name))
    bsdf = m.node_tree.nodes.get("Principled BSDF")
    bsdf.inputs["Base Color"].default_value = (*color, 1.0)
    bsdf.inputs["Metallic"].default_value = metallic
    bsdf.inputs["Roughness"].default_value = roughness
    # "Transmission" before Blender 4.0.
    bsdf.inputs.get("Transmission Weight", bsdf.inputs.get("Transmission")).default_value = (
        transmission
    )
    return m


def _object(name, mesh_builder, material):
    mesh = bpy.data.meshes.new(name)
    bm = bmesh.new()
    mesh_builder(bm)
    bm.to_mesh(mesh)
    bm.free()
    mesh.materials.append(material)
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def _box(bm, lo, hi):
    m = Matrix.Translation([(a + b) / 2 for a, b in zip(lo, hi)]) @ Matrix.Diagonal(
        [b - a for a, b in zip(lo, hi)] + [1.0]
    )
    bmesh.ops.create_cube(bm, size=1.0, matrix=m)


# The window: 1.2 m wide, 1.0 m high, in the wall at y = +2, its sill 0.9 m up.
WINDOW = {"x": (-0.6, 0.6), "z": (0.9, 1.9), "y": 2.0}


def build(sun_elevation=35.0, sun_rotation=20.0, samples=16, size=(96, 72)):
    """Empties the file and builds the room; returns the scene."""
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    white = _material("white wall", (0.8, 0.8, 0.8))
    t = 0.1  # wall thickness

    def walls(bm):
        _box(bm, (-2 - t, -2 - t, -t), (2 + t, 2 + t, 0))  # floor
        _box(bm, (-2 - t, -2 - t, 2.6), (2 + t, 2 + t, 2.6 + t))  # ceiling
        _box(bm, (-2 - t, -2 - t, 0), (-2, 2 + t, 2.6))  # -x
        _box(bm, (2, -2 - t, 0), (2 + t, 2 + t, 2.6))  # +x
        _box(bm, (-2, -2 - t, 0), (2, -2, 2.6))  # -y
        (x0, x1), (z0, z1), y = WINDOW["x"], WINDOW["z"], WINDOW["y"]
        _box(bm, (-2, y, 0), (x0, y + t, 2.6))  # +y wall left of the window
        _box(bm, (x1, y, 0), (2, y + t, 2.6))  # right of it
        _box(bm, (x0, y, 0), (x1, y + t, z0))  # below
        _box(bm, (x0, y, z1), (x1, y + t, 2.6))  # above

    _object("room", walls, white)
    metal = _material("glossy metal", (0.9, 0.6, 0.3), metallic=1.0, roughness=0.25)
    _object("block", lambda bm: _box(bm, (0.8, -0.2, 0), (1.4, 0.4, 0.7)), metal)
    glass = _material("glass", (1, 1, 1), roughness=0.0, transmission=1.0)
    sphere = _object(
        "sphere",
        lambda bm: bmesh.ops.create_uvsphere(bm, u_segments=32, v_segments=16, radius=0.35),
        glass,
    )
    sphere.location = (-0.8, 0.5, 0.35)

    lamp = bpy.data.lights.new("lamp", "POINT")
    lamp.energy = 60.0
    lamp_obj = bpy.data.objects.new("lamp", lamp)
    lamp_obj.location = (0, -0.5, 2.3)
    scene.collection.objects.link(lamp_obj)

    world = use_nodes(bpy.data.worlds.new("sky"))
    scene.world = world
    nodes = world.node_tree.nodes
    nodes.clear()
    out = nodes.new("ShaderNodeOutputWorld")
    bg = nodes.new("ShaderNodeBackground")
    sky = nodes.new("ShaderNodeTexSky")
    sky.sky_type = "MULTIPLE_SCATTERING" if bpy.app.version >= (5, 0, 0) else "NISHITA"
    sky.sun_elevation = math.radians(sun_elevation)
    sky.sun_rotation = math.radians(sun_rotation)
    world.node_tree.links.new(sky.outputs[0], bg.inputs[0])
    world.node_tree.links.new(bg.outputs[0], out.inputs[0])

    cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    cam.location = (0.3, -1.8, 1.3)
    cam.rotation_euler = (math.radians(88), 0, math.radians(-5))
    cam.data.lens = 20
    scene.collection.objects.link(cam)
    scene.camera = cam

    scene.render.resolution_x, scene.render.resolution_y = size
    scene.render.resolution_percentage = 100
    scene.render.engine = "FENESTRA"
    scene.fenestra.samples = samples
    scene.fenestra.snapshot_every = 0.2
    return scene
