"""What glTF cannot say of a scene's materials, said to the user: Blender's glTF exporter
carries the Principled BSDF (and Emission) with image textures, and drops what else feeds it
(procedural textures, colour ramps, displacement), keeping the inputs' plain values."""

# Nodes the glTF exporter follows from a Principled BSDF's input to an image.
CARRIED = {
    "TEX_IMAGE",
    "NORMAL_MAP",
    "SEPARATE_COLOR",
    "SEPRGB",
    "SEPARATE_RGB",
    "VERTEX_COLOR",
    "ATTRIBUTE",
    "REROUTE",
    "MAPPING",
    "UVMAP",
    "TEX_COORD",
    "MIX",
    "MIX_RGB",
}
# The Principled BSDF's inputs that glTF has a place for.
INPUTS = (
    "Base Color",
    "Metallic",
    "Roughness",
    "Normal",
    "Alpha",
    "Transmission Weight",
    "Transmission",
    "Emission Color",
    "Emission",
)
SHAPED = ("MESH", "CURVE", "SURFACE", "META", "FONT", "CURVES")


def _feeding(socket):
    """The nodes upstream of `socket` (all of them, breadth first)."""
    seen, todo = [], [link.from_node for link in socket.links]
    while todo:
        node = todo.pop(0)
        if node in seen:
            continue
        seen.append(node)
        for s in node.inputs:
            todo.extend(link.from_node for link in s.links)
    return seen


def notes(scene):
    """A line per material of the renderable objects for what glTF cannot carry of it."""
    out, seen = [], set()
    for obj in scene.objects:
        if obj.hide_render or obj.type not in SHAPED:
            continue
        for slot in obj.material_slots:
            m = slot.material
            if m is None or m.name in seen or m.node_tree is None:
                continue
            seen.add(m.name)
            out.extend(f"material {m.name}: {what}" for what in _material(m))
    return out


def _missing_images(nodes):
    """The images of `nodes`' image textures whose file is not there (nor packed)."""
    import os

    import bpy

    for node in nodes:
        image = getattr(node, "image", None) if node.type == "TEX_IMAGE" else None
        if image is None or image.source not in ("FILE", "SEQUENCE") or image.packed_file:
            continue
        if not os.path.isfile(bpy.path.abspath(image.filepath, library=image.library)):
            yield image


def _material(m):
    output = next(
        (n for n in m.node_tree.nodes if n.type == "OUTPUT_MATERIAL" and n.is_active_output),
        next((n for n in m.node_tree.nodes if n.type == "OUTPUT_MATERIAL"), None),
    )
    if output is None:
        return
    if output.inputs["Displacement"].is_linked:
        yield "its displacement is not carried (glTF has none)"
    surface = output.inputs["Surface"]
    src = surface.links[0].from_node if surface.is_linked else None
    if src is None:
        return
    if src.type not in ("BSDF_PRINCIPLED", "EMISSION"):
        yield (
            f"its surface is a {src.bl_label} node, which glTF cannot express (exported as "
            "Blender's glTF exporter approximates it)"
        )
        return
    for name in INPUTS:
        socket = src.inputs.get(name)
        if socket is None or not socket.is_linked:
            continue
        for missing in _missing_images(_feeding(socket)):
            yield (
                f"its {name} image {missing.name} ({missing.filepath}) is missing: the glTF "
                "exporter leaves it out, and its plain value is used (Cycles shows it magenta)"
            )
        dropped = sorted({n.bl_label for n in _feeding(socket) if n.type not in CARRIED})
        if dropped:
            yield (
                f"its {name} comes through {', '.join(dropped)}, which glTF cannot carry "
                "(its plain value is used)"
            )
