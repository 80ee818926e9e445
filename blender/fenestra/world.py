"""The world as fenestra flags: a Sky Texture becomes `--sky` with its sun, an Environment
Texture `--environment` with its turn and strength, a plain colour a constant map. glTF holds
none of them.

Directions: the glTF file is Y-up, so fenestra's environment frame (`--environment-up y`) has
its phi = 0 column along Blender's +X and phi growing towards +Y (counter-clockwise seen from
above), and its sun azimuth runs clockwise from +X. Blender's equirectangular lookup runs the
other way round (u = 0.5 - atan2(y, x) / 2 pi, +X at the image's middle), so an HDRI is
handed to fenestra mirrored left to right and turned half a turn.
"""

import math
import os

import bpy
import numpy as np


class WorldError(RuntimeError):
    """A world node setup that fenestra cannot render."""


def _linked_from(socket):
    """The node feeding `socket`, through reroutes, or None."""
    while socket.is_linked:
        node = socket.links[0].from_node
        if node.type != "REROUTE":
            return node, socket.links[0].from_socket
        socket = node.inputs[0]
    return None, None


def _background(world):
    """The Background node the active world output draws from, or None with a reason."""
    if world is None:
        return None, "no world: black"
    tree = world.node_tree
    if tree is None or (bpy.app.version < (5, 0, 0) and not world.use_nodes):
        return None, None  # the world's plain colour
    outputs = [n for n in tree.nodes if n.type == "OUTPUT_WORLD"]
    output = next((n for n in outputs if n.is_active_output), outputs[0] if outputs else None)
    if output is None:
        return None, "the world has no output node: black"
    node, _ = _linked_from(output.inputs["Surface"])
    if node is None:
        return None, "nothing drives the world output: black"
    if node.type != "BACKGROUND":
        raise WorldError(
            f"the world's surface is a {node.bl_label} node; fenestra reads a Background node "
            "fed by a Sky Texture, an Environment Texture or a colour"
        )
    return node, None


def sun_direction(sky):
    """The unit vector towards a Sky Texture's sun, in Blender's world frame (Z up)."""
    if sky.sky_type in ("PREETHAM", "HOSEK_WILKIE"):
        d = np.array(sky.sun_direction, dtype=float)
        return d / np.linalg.norm(d)
    el, rot = sky.sun_elevation, sky.sun_rotation
    # Measured with Cycles in Blender 4.2 (Nishita) and 5.0 (Single/Multiple Scattering):
    # rotation 0 puts the sun at +Y, 90 degrees at +X (clockwise seen from above).
    return np.array([math.sin(rot) * math.cos(el), math.cos(rot) * math.cos(el), math.sin(el)])


def sun_flag(direction):
    """`--sun ELEVATION,AZIMUTH` (degrees) for a direction in Blender's frame: fenestra's
    azimuth runs clockwise from +X."""
    x, y, z = direction
    elevation = math.degrees(math.asin(max(-1.0, min(1.0, z))))
    azimuth = math.degrees(math.atan2(-y, x)) % 360.0
    return f"{elevation:.4f},{azimuth:.4f}"


def _mapping_turn(texture):
    """The turn about Z (radians) of a Mapping node feeding a texture's Vector input."""
    node, _ = _linked_from(texture.inputs["Vector"])
    if node is None or node.type != "MAPPING":
        return 0.0
    rotation = node.inputs["Rotation"].default_value
    if abs(rotation[0]) > 1e-6 or abs(rotation[1]) > 1e-6:
        raise WorldError("the environment's Mapping node tilts it (X or Y rotation): unsupported")
    return rotation[2] if node.vector_type in ("POINT", "TEXTURE") else 0.0


def _write_pfm(path, rgb):
    """A little-endian PFM of an (h, w, 3) image, top row first."""
    h, w, _ = rgb.shape
    with open(path, "wb") as f:
        f.write(f"PF\n{w} {h}\n-1.0\n".encode())
        f.write(np.ascontiguousarray(rgb[::-1], dtype="<f4").tobytes())


def _hdri_for_fenestra(image, folder):
    """The image as fenestra reads environments (EXR/HDR/PFM), mirrored left to right: a PFM
    in `folder` written from Blender's float pixels (any format Blender reads)."""
    w, h = image.size
    if w == 0:
        raise WorldError(f"environment image {image.name} could not be loaded ({image.filepath})")
    if w != 2 * h:
        raise WorldError(
            f"environment image {image.name} is {w}x{h}; fenestra needs a 2:1 lat-long image"
        )
    pixels = np.empty(w * h * 4, dtype=np.float32)
    image.pixels.foreach_get(pixels)
    rgb = pixels.reshape(h, w, 4)[::-1, ::-1, :3]  # top row first, mirrored
    path = os.path.join(folder, "environment.pfm")
    _write_pfm(path, rgb)
    return path


def world_flags(world, folder):
    """fenestra flags for `world`, and notes on what is approximated or left out."""
    background, note = _background(world)
    notes = [note] if note else []
    if background is None:
        color = (0.0, 0.0, 0.0) if world is None or note else tuple(world.color)
        return _constant(color, 1.0, folder), notes
    strength = background.inputs["Strength"].default_value
    if background.inputs["Strength"].is_linked:
        notes.append("the world's Strength is driven by nodes: its value field is used")
    texture, _ = _linked_from(background.inputs["Color"])
    if texture is None:
        return (
            _constant(tuple(background.inputs["Color"].default_value)[:3], strength, folder),
            notes,
        )
    if texture.type == "TEX_SKY":
        flags = ["--sky", "--sun", sun_flag(sun_direction(texture))]
        if texture.sky_type in ("PREETHAM", "HOSEK_WILKIE"):
            # Cycles draws these skies without a sun disk: the sun only shapes the sky.
            flags += ["--sky-turbidity", f"{texture.turbidity:g}", "--sun-strength", "0"]
        else:
            sun = texture.sun_intensity if texture.sun_disc else 0.0
            if sun != 1.0:
                flags += ["--sun-strength", f"{sun:g}"]
            notes.append(
                f"Sky Texture {texture.sky_type.lower()}: rendered as fenestra's Hosek-Wilkie "
                "sky (fenestra's default turbidity) and SPECTRL2 sun in the same direction; air, "
                "aerosol and ozone densities and the sun's size are not read"
            )
        if texture.sky_type == "HOSEK_WILKIE":
            flags += ["--sky-albedo", f"{texture.ground_albedo:g}"]
        if strength != 1.0:
            flags += ["--environment-strength", f"{strength:g}"]
        return flags + ["--environment-up", "y"], notes
    if texture.type == "TEX_ENVIRONMENT":
        if texture.image is None:
            raise WorldError("the world's Environment Texture has no image")
        if texture.projection != "EQUIRECTANGULAR":
            raise WorldError(
                "the world's Environment Texture is a mirror ball; fenestra reads equirectangular"
            )
        turn = math.degrees(_mapping_turn(texture))
        flags = [
            "--environment",
            _hdri_for_fenestra(texture.image, folder),
            "--environment-rotation",
            f"{(-180.0 - turn) % 360.0:.6f}",
            "--environment-up",
            "y",
        ]
        if strength != 1.0:
            flags += ["--environment-strength", f"{strength:g}"]
        return flags, notes
    raise WorldError(
        f"the world's colour comes from a {texture.bl_label} node; fenestra reads a Sky "
        "Texture, an Environment Texture or a plain colour"
    )


def _constant(color, strength, folder):
    """Flags for a constant environment of `color` x `strength` (none if black)."""
    rgb = np.array(color[:3], dtype=np.float32) * strength
    if not rgb.any():
        return []
    path = os.path.join(folder, "environment.pfm")
    _write_pfm(path, np.broadcast_to(rgb, (4, 8, 3)))
    return ["--environment", path, "--environment-up", "y"]
