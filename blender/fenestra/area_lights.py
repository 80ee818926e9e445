"""Blender's area lights as emitting polygons in the exported glTF, which has no area lights:
each becomes a one-sided square, rectangle, disk or ellipse (a 32-gon) where the light is,
facing its -Z, emitting the radiance Cycles gives it: its colour times its power over pi
times its area. They are appended to the .glb the exporter wrote."""

import math

import numpy as np

from . import glb, portals

# Sides of the polygon standing for a disk or an ellipse.
ROUND_SIDES = 32


def carried(obj):
    """Whether `obj` is an area light that goes into the scene as an emitting polygon."""
    return (
        obj.type == "LIGHT"
        and obj.data.type == "AREA"
        and not obj.hide_render
        and not portals.is_portal(obj)
    )


def polygon(obj):
    """The light's outline in Blender's world frame, wound so that its front faces the
    light's -Z (where it emits); and its area."""
    light = obj.data
    sx = light.size
    sy = light.size_y if light.shape in ("RECTANGLE", "ELLIPSE") else light.size
    if light.shape in ("DISK", "ELLIPSE"):
        angles = [2 * math.pi * k / ROUND_SIDES for k in range(ROUND_SIDES)]
        local = [(sx / 2 * math.cos(a), sy / 2 * math.sin(a)) for a in angles]
        area = math.pi * sx * sy / 4
    else:
        local = [(sx / 2, sy / 2), (-sx / 2, sy / 2), (-sx / 2, -sy / 2), (sx / 2, -sy / 2)]
        area = sx * sy
    # Counter-clockwise seen from +Z faces +Z: reversed, the front faces -Z.
    m = np.array(obj.matrix_world)
    points = [m @ np.array([x, y, 0.0, 1.0]) for x, y in reversed(local)]
    # Scaled objects scale the light's area as Cycles scales it.
    world_area = area * np.linalg.norm(np.cross(m[:3, 0], m[:3, 1]))
    return np.array([p[:3] for p in points]), world_area


def radiance(obj, area):
    """The radiance Cycles gives an area light: colour x power / (pi x area)."""
    light = obj.data
    return np.array(light.color[:3]) * light.energy / (math.pi * area)


def append_to_glb(path, objects):
    """Appends the carried area lights among `objects` to the .glb at `path` as emitting
    meshes; notes on what of them is not carried."""
    lights = [o for o in objects if carried(o)]
    if not lights:
        return []
    version, doc, blob = glb.read(path)
    blob = bytearray(blob)
    notes = []
    added = 0
    for obj in lights:
        points, area = polygon(obj)
        if not (area > 0 and obj.data.energy > 0):
            notes.append(f"area light {obj.name} emits nothing (zero size or power): left out")
            continue
        gltf_points = np.array([portals.to_gltf(p) for p in points], dtype=np.float32)
        n = len(gltf_points)
        indices = np.array([(0, k, k + 1) for k in range(1, n - 1)], dtype=np.uint32).ravel()
        L = radiance(obj, area)
        strength = float(L.max()) or 1.0
        mesh = _add_mesh(doc, blob, gltf_points, indices, obj.name, L / strength, strength)
        doc.setdefault("nodes", []).append({"name": f"{obj.name} (area light)", "mesh": mesh})
        doc["scenes"][doc.get("scene", 0)].setdefault("nodes", []).append(len(doc["nodes"]) - 1)
        added += 1
        if obj.data.spread < math.pi - 1e-4:
            notes.append(
                f"area light {obj.name}: its spread ({math.degrees(obj.data.spread):.0f} "
                "degrees) is not carried: it emits as a Lambertian polygon"
            )
        if obj.data.use_nodes:
            notes.append(f"area light {obj.name}: its node setup is not read (colour x power)")
    if not added:
        return notes
    used = doc.setdefault("extensionsUsed", [])
    if "KHR_materials_emissive_strength" not in used:
        used.append("KHR_materials_emissive_strength")
    if doc.get("buffers"):
        doc["buffers"][0]["byteLength"] = len(blob)
    else:
        doc["buffers"] = [{"byteLength": len(blob)}]
    glb.write(path, version, doc, blob)
    return notes


def _add_mesh(doc, blob, points, indices, name, colour, strength):
    """A mesh of one primitive (positions, triangle indices) with a black, emitting,
    one-sided material; its index."""

    def view(array):
        while len(blob) % 4:
            blob.append(0)
        doc.setdefault("bufferViews", []).append(
            {"buffer": 0, "byteOffset": len(blob), "byteLength": array.nbytes}
        )
        blob.extend(array.tobytes())
        return len(doc["bufferViews"]) - 1

    accessors = doc.setdefault("accessors", [])
    accessors.append(
        {
            "bufferView": view(points),
            "componentType": 5126,
            "count": len(points),
            "type": "VEC3",
            "min": points.min(0).tolist(),
            "max": points.max(0).tolist(),
        }
    )
    accessors.append(
        {
            "bufferView": view(indices),
            "componentType": 5125,
            "count": len(indices),
            "type": "SCALAR",
        }
    )
    materials = doc.setdefault("materials", [])
    materials.append(
        {
            "name": f"{name} (area light)",
            "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0},
            "emissiveFactor": [float(c) for c in colour],
            "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": strength}},
        }
    )
    doc.setdefault("meshes", []).append(
        {
            "name": f"{name} (area light)",
            "primitives": [
                {
                    "attributes": {"POSITION": len(accessors) - 2},
                    "indices": len(accessors) - 1,
                    "material": len(materials) - 1,
                }
            ],
        }
    )
    return len(doc["meshes"]) - 1
