"""Builds the screenshots' .blend (run by scripts/blender-screenshots in Blender, in the
background): the breakfast room imported with Blender's glTF importer, its main camera, a
Nishita sky with the sun at 30 degrees, rotation 100 (through the blinds)."""

import math
import sys

import bpy
import numpy as np

np.bool = bool  # Debian's Blender 3.4 glTF importer still names np.bool (NumPy >= 1.24)
gltf, out = sys.argv[sys.argv.index("--") + 1 :]
bpy.ops.wm.read_homefile(use_empty=True)
bpy.ops.import_scene.gltf(filepath=gltf)
scene = bpy.context.scene
scene.camera = bpy.data.objects["CameraMain"]
world = bpy.data.worlds.new("sky")
world.use_nodes = True
scene.world = world
nodes, links = world.node_tree.nodes, world.node_tree.links
nodes.clear()
out_node, bg, sky = (
    nodes.new(n) for n in ("ShaderNodeOutputWorld", "ShaderNodeBackground", "ShaderNodeTexSky")
)
sky.sky_type = "NISHITA"
sky.sun_elevation, sky.sun_rotation = math.radians(30), math.radians(100)
links.new(sky.outputs[0], bg.inputs[0])
links.new(bg.outputs[0], out_node.inputs[0])
scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = (
    480,
    270,
    100,
)
scene.view_settings.view_transform = "Filmic"
scene.view_settings.exposure = -3.5
bpy.ops.wm.save_as_mainfile(filepath=out)
