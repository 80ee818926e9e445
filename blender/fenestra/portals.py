"""Light portals between Blender and fenestra: Cycles portal lights (area lights marked
`is_portal`) written as fenestra's portals.json, and fenestra's estimated portals added to a
scene as portal lights. portals.json is in the glTF file's Y-up frame."""

import json

import bpy
import numpy as np
from mathutils import Matrix, Vector


def to_gltf(v):
    """A Blender (Z-up) point or vector in the exported glTF's Y-up frame."""
    return [v[0], v[2], -v[1]]


def from_gltf(v):
    """A glTF (Y-up) point or vector in Blender's Z-up frame."""
    return Vector((v[0], -v[2], v[1]))


def is_portal(obj):
    return (
        obj.type == "LIGHT"
        and obj.data.type == "AREA"
        and getattr(getattr(obj.data, "cycles", None), "is_portal", False)
    )


def portal_record(obj):
    """The portals.json record of a portal light: its shape where it stands, in glTF's frame."""
    light, m = obj.data, obj.matrix_world
    sx = light.size
    sy = light.size_y if light.shape in ("RECTANGLE", "ELLIPSE") else light.size
    centre = m @ Vector((0, 0, 0))
    u = m.to_3x3() @ Vector((sx / 2, 0, 0))
    v = m.to_3x3() @ Vector((0, sy / 2, 0))
    normal = u.cross(v).normalized()
    area = 4 * u.cross(v).length
    record = {
        "center": to_gltf(centre),
        "normal": to_gltf(normal),
    }
    if light.shape in ("DISK", "ELLIPSE"):
        record.update(kind="ellipse", area=area * np.pi / 4, axes=[to_gltf(u), to_gltf(v)])
    else:
        corners = [centre + u + v, centre - u + v, centre - u - v, centre + u - v]
        record.update(kind="quad", area=area, vertices=[to_gltf(c) for c in corners])
    return record


def write_scene_portals(objects, path):
    """portals.json of the portal lights among `objects`; how many there were."""
    records = [portal_record(o) for o in objects if is_portal(o)]
    with open(path, "w") as f:
        json.dump({"portals": records}, f, indent=1)
    return len(records)


def add_portal_lights(records, collection, facing):
    """Adds a Cycles portal light for each portals.json record to `collection`, its emitting
    side (-Z) turned towards the point `facing` (the camera: the room's side). Returns them."""
    added = []
    for i, r in enumerate(records):
        centre = from_gltf(r["center"])
        if r["kind"] == "ellipse":
            u, v = (from_gltf(a) for a in r["axes"])
            shape, sx, sy = "ELLIPSE", 2 * u.length, 2 * v.length
        else:
            corners = [from_gltf(c) for c in r["vertices"]]
            if len(corners) != 4:
                continue  # triangles have no area-light shape
            u = (corners[1] - corners[0]) / 2
            v = (corners[2] - corners[1]) / 2
            shape, sx, sy = "RECTANGLE", 2 * u.length, 2 * v.length
        x = u.normalized()
        z = x.cross(v).normalized()
        if z.dot(facing - centre) > 0:  # the light emits along its -Z
            z = -z
        y = z.cross(x)
        light = bpy.data.lights.new(f"fenestra portal {i}", "AREA")
        light.shape, light.size, light.size_y = shape, sx, sy
        light.cycles.is_portal = True
        obj = bpy.data.objects.new(f"fenestra portal {i}", light)
        obj.matrix_world = Matrix.Translation(centre) @ Matrix((x, y, z)).transposed().to_4x4()
        collection.objects.link(obj)
        added.append(obj)
    return added
