"""Turn a pbrt-v4 file written by `fenestra scene export` into a Mitsuba 3 scene dictionary.

Only the subset fenestra's exporter writes is understood (one camera, named materials,
triangle meshes, PLY meshes, spheres, diffuse area lights, point lights, a constant infinite
light); anything else stops with the file and line, so a comparison never runs on a scene
that silently differs. Materials without a Mitsuba counterpart are replaced, and each
replacement is reported by `convert`:

- `phong` (a fenestra extension) becomes `roughplastic` with the same diffuse albedo, the
  specular weight as `specular_reflectance` and Beckmann alpha = sqrt(2 / (exponent + 2));
- an `interface` shape (a light portal) is left out: it is invisible in fenestra too.
"""

import math
import os
import re

import numpy as np

TOKEN = re.compile(r'"[^"]*"|\[|\]|[^\s\[\]"]+')


INTERFACE = "interface"


class Unsupported(Exception):
    pass


def tokens(path):
    """(token, line) pairs of a pbrt file, comments dropped."""
    with open(path) as f:
        for number, line in enumerate(f, 1):
            line = line.split("#", 1)[0]
            for t in TOKEN.findall(line):
                yield t, number


def statements(path):
    """(directive, positional values, {name: (type, values)}, line) for each statement."""
    stream = list(tokens(path))
    i = 0
    while i < len(stream):
        word, line = stream[i]
        i += 1
        positional, params = [], {}
        while i < len(stream) and not re.match(r"^[A-Z][A-Za-z]*$", stream[i][0]):
            t, _ = stream[i]
            i += 1
            if t.startswith('"') and " " in t[1:-1] and i < len(stream):
                kind, name = t[1:-1].split()
                values, i = value_list(stream, i)
                params[name] = (kind, values)
            elif t == "[":
                values, i = value_list(stream, i - 1)
                positional.extend(values)
            else:
                positional.append(t.strip('"'))
        yield word, positional, params, line


def value_list(stream, i):
    if stream[i][0] != "[":
        return [stream[i][0].strip('"')], i + 1
    values = []
    i += 1
    while stream[i][0] != "]":
        values.append(stream[i][0].strip('"'))
        i += 1
    return values, i + 1


def floats(params, name, default=None):
    if name not in params:
        if default is None:
            raise KeyError(name)
        return default
    return [float(v) for v in params[name][1]]


def look_at(eye, target, up):
    """pbrt's LookAt: the camera-from-world matrix."""
    eye, target, up = (np.array(v, dtype=float) for v in (eye, target, up))
    d = target - eye
    d /= np.linalg.norm(d)
    right = np.cross(up / np.linalg.norm(up), d)
    right /= np.linalg.norm(right)
    new_up = np.cross(d, right)
    world_from_camera = np.identity(4)
    world_from_camera[:3, 0], world_from_camera[:3, 1] = right, new_up
    world_from_camera[:3, 2], world_from_camera[:3, 3] = d, eye
    return np.linalg.inv(world_from_camera)


def rgb(values):
    return {"type": "rgb", "value": [float(v) for v in values]}


def material(kind, params, replaced):
    if kind == "diffuse":
        return {"type": "diffuse", "reflectance": rgb(floats(params, "reflectance", [0.5] * 3))}
    if kind == "conductor":
        u = floats(params, "uroughness", [0.0])[0]
        v = floats(params, "vroughness", [u])[0]
        if params.get("remaproughness", ("bool", ["true"]))[1][0] != "false":
            raise Unsupported("conductor with remapped roughness")
        out = {"type": "roughconductor", "distribution": "ggx", "alpha_u": u, "alpha_v": v,
               "eta": rgb(floats(params, "eta")), "k": rgb(floats(params, "k"))}
        if max(u, v) == 0.0:
            out = {"type": "conductor", "eta": out["eta"], "k": out["k"]}
        return out
    if kind == "phong":
        n = floats(params, "exponent")[0]
        replaced.add("phong -> roughplastic (Beckmann alpha = sqrt(2 / (n + 2)))")
        return {"type": "roughplastic", "distribution": "beckmann",
                "alpha": math.sqrt(2.0 / (n + 2.0)),
                "diffuse_reflectance": rgb(floats(params, "diffuse")),
                "specular_reflectance": rgb(floats(params, "specular")), "nonlinear": False}
    if kind == "interface":
        return INTERFACE
    raise Unsupported(f"material {kind}")


def triangle_mesh(params, path, index, folder):
    """Writes a trianglemesh as a binary PLY beside the scene (Mitsuba reads PLY directly)."""
    p = np.array(floats(params, "P"), dtype="<f4").reshape(-1, 3)
    idx = np.array([int(v) for v in params["indices"][1]], dtype="<u4").reshape(-1, 3)
    columns = [("x", p[:, 0]), ("y", p[:, 1]), ("z", p[:, 2])]
    if "N" in params:
        n = np.array(floats(params, "N"), dtype="<f4").reshape(-1, 3)
        columns += [("nx", n[:, 0]), ("ny", n[:, 1]), ("nz", n[:, 2])]
    if "uv" in params:
        uv = np.array(floats(params, "uv"), dtype="<f4").reshape(-1, 2)
        columns += [("u", uv[:, 0]), ("v", uv[:, 1])]
    name = os.path.join(folder, f"mesh-{index}.ply")
    with open(name, "wb") as f:
        f.write(b"ply\nformat binary_little_endian 1.0\n")
        f.write(b"element vertex %d\n" % len(p))
        for c, _ in columns:
            f.write(b"property float %s\n" % c.encode())
        f.write(b"element face %d\nproperty list uchar uint vertex_indices\nend_header\n" % len(idx))
        f.write(np.stack([v for _, v in columns], axis=1).astype("<f4").tobytes())
        faces = np.zeros(len(idx), dtype=[("n", "u1"), ("i", "<u4", (3,))])
        faces["n"], faces["i"] = 3, idx
        f.write(faces.tobytes())
    return name


def convert(path, spp, max_depth, rr_depth, folder, resolution=None):
    """Mitsuba scene dictionary of the pbrt file at `path`, and the replacements made.

    `resolution` (width, height) replaces the file's, as fenestra's --resolution does (the
    field of view stays that of the shorter side).
    Triangle meshes are written as PLY files into `folder`; max_depth counts path segments
    (2 = direct light), as fenestra's --max-depth and Mitsuba's path integrator do.
    """
    base = os.path.dirname(os.path.abspath(path))
    scene = {"type": "scene"}
    replaced = set()
    ctm = np.identity(4)
    named, stack = {}, []
    state = {"material": None, "area": None, "ctm": ctm}
    width = height = 256
    fov = None
    for word, pos, params, line in statements(path):
        where = f"{path}:{line}"
        try:
            if word == "Film":
                width = int(params["xresolution"][1][0])
                height = int(params["yresolution"][1][0])
            elif word in ("Sampler", "Integrator", "PixelFilter", "WorldBegin"):
                if word == "WorldBegin":
                    camera_from_world = state["ctm"]
                    state["ctm"] = np.identity(4)
                elif word == "PixelFilter" and pos[0] != "box":
                    raise Unsupported(f"pixel filter {pos[0]}")
            elif word == "Scale":
                state["ctm"] = state["ctm"] @ np.diag([float(v) for v in pos] + [1.0])
            elif word == "Translate":
                t = np.identity(4)
                t[:3, 3] = [float(v) for v in pos]
                state["ctm"] = state["ctm"] @ t
            elif word == "LookAt":
                v = [float(x) for x in pos]
                state["ctm"] = state["ctm"] @ look_at(v[0:3], v[3:6], v[6:9])
            elif word == "Camera":
                if pos[0] != "perspective":
                    raise Unsupported(f"camera {pos[0]}")
                fov = floats(params, "fov", [90.0])[0]
            elif word == "MakeNamedMaterial":
                named[pos[0]] = material(params["type"][1][0], params, replaced)
            elif word == "NamedMaterial":
                state["material"] = named[pos[0]]
            elif word == "Material":
                state["material"] = material(pos[0], params, replaced)
            elif word == "AttributeBegin":
                stack.append(dict(state))
            elif word == "AttributeEnd":
                state = stack.pop()
            elif word == "AreaLightSource":
                if pos[0] != "diffuse" or params.get("twosided", ("", ["false"]))[1][0] != "false":
                    raise Unsupported("area light other than one-sided diffuse")
                state["area"] = {"type": "area", "radiance": rgb(floats(params, "L"))}
            elif word == "LightSource":
                name = f"light-{len(scene)}"
                if pos[0] == "point":
                    at = state["ctm"] @ np.array(floats(params, "from", [0, 0, 0]) + [1.0])
                    scene[name] = {"type": "point", "position": at[:3].tolist(),
                                   "intensity": rgb(floats(params, "I"))}
                elif pos[0] == "infinite" and "filename" not in params:
                    scene[name] = {"type": "constant", "radiance": rgb(floats(params, "L"))}
                else:
                    raise Unsupported(f"light {pos[0]}")
            elif word == "Shape":
                if state["material"] is INTERFACE:
                    continue  # a light portal: invisible
                shape = shape_dict(pos[0], params, base, len(scene), folder, state["ctm"])
                shape["bsdf"] = state["material"] or {"type": "diffuse"}
                if state["area"] is not None:
                    shape["emitter"] = state["area"]
                scene[f"shape-{len(scene)}"] = shape
            else:
                raise Unsupported(f"directive {word}")
        except Unsupported as e:
            raise Unsupported(f"{where}: {e} (not in what fenestra's exporter writes)") from None
    if resolution:
        width, height = resolution
    # pbrt's camera looks down +z with +x to the image's right; Mitsuba's +x is the image's left.
    to_world = np.linalg.inv(camera_from_world) @ np.diag([-1.0, 1.0, 1.0, 1.0])
    import mitsuba as mi
    scene["sensor"] = {
        "type": "perspective", "fov": fov, "fov_axis": "smaller",
        "to_world": mi.ScalarTransform4f(to_world.tolist()),
        "film": {"type": "hdrfilm", "width": width, "height": height,
                 "rfilter": {"type": "box"}, "pixel_format": "rgb"},
        "sampler": {"type": "independent", "sample_count": spp},
    }
    scene["integrator"] = {"type": "path", "max_depth": max_depth, "rr_depth": rr_depth}
    return scene, sorted(replaced)


def ply_has_normals(filename):
    with open(filename, "rb") as f:
        header = b""
        while not header.endswith(b"end_header\n"):
            line = f.readline()
            if not line:
                raise Unsupported(f"{filename}: not a PLY file")
            header += line
    return b"property float nx" in header


def shape_dict(kind, params, base, index, folder, ctm):
    import mitsuba as mi
    to_world = mi.ScalarTransform4f(ctm.tolist())
    if kind in ("trianglemesh", "plymesh"):
        if kind == "trianglemesh":
            filename = triangle_mesh(params, base, index, folder)
        else:
            filename = os.path.join(base, params["filename"][1][0])
        # Without vertex normals fenestra (and pbrt) shade with the face normal; Mitsuba would
        # compute smooth vertex normals unless told not to.
        return {"type": "ply", "filename": filename, "to_world": to_world,
                "face_normals": not ply_has_normals(filename)}
    if kind == "sphere":
        return {"type": "sphere", "radius": floats(params, "radius", [1.0])[0],
                "to_world": to_world}
    raise Unsupported(f"shape {kind}")
