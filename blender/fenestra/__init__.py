"""fenestra inside Blender: a render engine that exports the evaluated scene with Blender's
own glTF exporter, runs the fenestra binary on it and shows the image as it refines.

What a Blender scene carries over is in docs/blender.md: geometry with modifiers applied,
the Principled BSDF through glTF, point, spot and sun lamps, the active camera, the world
(Sky Texture, Environment Texture or a plain colour) and Cycles portal lights.
"""

bl_info = {
    "name": "fenestra",
    "author": "The fenestra authors",
    "version": (0, 1, 0),
    "blender": (4, 2, 0),
    "location": "Render Properties > Render Engine > fenestra",
    "description": "Render with fenestra: automatic light portals, live progress",
    "category": "Render",
}

# The add-on's module name: "fenestra" installed as a legacy add-on, a dotted name as an
# extension (bl_ext.REPO.fenestra); preferences are kept under it.
ADDON_ID = __package__

from . import engine, operators, preferences, properties, ui  # noqa: E402

_modules = (preferences, properties, operators, engine, ui)


def register():
    for m in _modules:
        m.register()


def unregister():
    for m in reversed(_modules):
        m.unregister()
