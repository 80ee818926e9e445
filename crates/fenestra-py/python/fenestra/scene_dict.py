"""Scenes described as Python dicts (as Mitsuba's `load_dict`), meshes as NumPy arrays.

A dict scene is a pbrt-v4 scene written as data: its materials, shapes and lights take
pbrt-v4's types and parameter names, so everything fenestra reads from pbrt-v4 files is
available, and `fenestra.load_dict(d)` renders what the same scene written as a pbrt-v4 file
renders (tested). The dict is written as a pbrt-v4 file, with meshes as binary PLY, into a
folder named by its content under the user's cache (~/.cache/fenestra/dict-scenes), and
loaded from there.

    scene = fe.load_dict({
        "camera": {"eye": [0, 1, 3.5], "target": [0, 1, 0], "up": [0, 1, 0], "fov": 40},
        "resolution": (256, 256), "spp": 64, "max_depth": 6,
        "materials": {
            "white": {"type": "diffuse", "reflectance": [0.8, 0.8, 0.8]},
            "gold": {"type": "conductor", "eta": "metal-Au-eta", "k": "metal-Au-k",
                     "roughness": 0.1},
        },
        "shapes": [
            {"type": "mesh", "positions": P, "indices": F, "material": "white"},  # arrays
            {"type": "sphere", "center": [0, 0.5, 0], "radius": 0.5, "material": "gold"},
            {"type": "mesh", "positions": Q, "indices": G, "emission": [10, 10, 10]},
        ],
        "lights": [{"type": "infinite", "L": [0.1, 0.1, 0.1]},
                   {"type": "point", "from": [0, 1.8, 0], "I": [2, 2, 2]}],
    })

Parameter types follow from the values: a bool is "bool", an int or float "float" (say
"integer name" to mean an integer), three numbers "rgb" for spectra (reflectance, L, I, ...)
and "point3" for positions (from, to), a text "spectrum" for eta and k (named spectra) and
"string" otherwise. A key may name its type as pbrt-v4 does ("float roughness",
"blackbody L"), which is taken as written.
"""

import hashlib
import json
import os
import re
from pathlib import Path

import numpy as np

__all__ = ["load_dict", "pbrt_text"]

# Parameters whose three numbers are a point, not a colour.
_POINTS = {"from", "to", "center", "position"}
# Parameters whose text names a spectrum.
_SPECTRA = {"eta", "k"}
# Keys of a shape that are not pbrt parameters.
_SHAPE_KEYS = {"type", "material", "emission", "positions", "indices", "normals", "uv",
               "center", "reverse_orientation", "two_sided"}
# Keys of the camera.
_CAMERA_KEYS = ("eye", "target", "up", "fov")
# What a type or a parameter's name may be: pbrt-v4's are words (a parameter's may name its
# type first). Anything else would be pasted into the scene text as a directive of its own.
_WORD = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
_TYPED = re.compile(r"[A-Za-z0-9_]+ [A-Za-z_][A-Za-z0-9_]*\Z")


def _word(text, where):
    """`text` if it is a word that may stand in the scene text, else a ValueError naming
    `where`."""
    if not isinstance(text, str) or not _WORD.match(text):
        raise ValueError(f"{where}: expected a name of letters, digits and _, got {text!r}")
    return text


def _table(value, where):
    """`value` if it is a dict with a type (a word), else a ValueError naming `where`."""
    if not isinstance(value, dict):
        raise ValueError(f"{where}: expected a dict, got {type(value).__name__}")
    if "type" not in value:
        raise ValueError(f"{where}: no 'type'")
    _word(value["type"], f"{where}: type")
    return value


def _numbers(values):
    return " ".join(repr(float(v)) for v in np.asarray(values, dtype=np.float64).ravel())


def _param(name, value):
    """One pbrt-v4 parameter: '"type name" [ values ]'."""
    if " " in name:
        kind = name.split()[0]
        if isinstance(value, str):
            body = json.dumps(value)
        elif isinstance(value, bool):
            body = "true" if value else "false"
        elif kind == "integer":
            body = " ".join(str(int(v)) for v in np.ravel(value))
        else:
            body = _numbers(value)
        return f'"{name}" [ {body} ]'
    if isinstance(value, bool):
        return f'"bool {name}" [ {"true" if value else "false"} ]'
    if isinstance(value, str):
        kind = "spectrum" if name in _SPECTRA else "string"
        return f'"{kind} {name}" [ {json.dumps(value)} ]'
    if np.ndim(value) == 0:
        return f'"float {name}" [ {_numbers([value])} ]'
    if np.size(value) == 3:
        kind = "point3" if name in _POINTS else "rgb"
        return f'"{kind} {name}" [ {_numbers(value)} ]'
    return f'"float {name}" [ {_numbers(value)} ]'


def _params(table, where, skip=()):
    named = [(k, v) for k, v in table.items() if k not in skip and k != "type"]
    for k, _ in named:
        if not isinstance(k, str) or not (_WORD.match(k) or _TYPED.match(k)):
            raise ValueError(f"{where}: parameter {k!r}: expected a name (or 'type name')")
    return " ".join(_param(k, v) for k, v in named)


def _indices(indices, vertices):
    """A mesh's triangle indices as int32, refused unless they are integers in range."""
    f = np.asarray(indices)
    if f.size and not np.issubdtype(f.dtype, np.integer):
        raise ValueError(f"mesh indices must be integers, got {f.dtype}")
    f = f.astype(np.int64).reshape(-1, 3)
    if f.size and (f.min() < 0 or f.max() >= vertices):
        raise ValueError(f"mesh indices must lie in 0..{vertices - 1}, got {f.min()}..{f.max()}")
    return f.astype("<i4")


def _ply(path, positions, indices, normals=None, uv=None):
    """A binary little-endian PLY of a triangle mesh."""
    p = np.asarray(positions, dtype="<f4").reshape(-1, 3)
    f = _indices(indices, len(p))
    columns = [("x", p[:, 0]), ("y", p[:, 1]), ("z", p[:, 2])]
    if normals is not None:
        n = np.asarray(normals, dtype="<f4").reshape(-1, 3)
        if len(n) != len(p):
            raise ValueError(f"a mesh of {len(p)} positions has {len(n)} normals")
        columns += [("nx", n[:, 0]), ("ny", n[:, 1]), ("nz", n[:, 2])]
    if uv is not None:
        t = np.asarray(uv, dtype="<f4").reshape(-1, 2)
        if len(t) != len(p):
            raise ValueError(f"a mesh of {len(p)} positions has {len(t)} uv pairs")
        columns += [("u", t[:, 0]), ("v", t[:, 1])]
    vertices = np.empty(len(p), dtype=[(name, "<f4") for name, _ in columns])
    for name, column in columns:
        vertices[name] = column
    faces = np.empty(len(f), dtype=[("n", "u1"), ("i", "<i4", (3,))])
    faces["n"], faces["i"] = 3, f
    header = ["ply", "format binary_little_endian 1.0", f"element vertex {len(p)}"]
    header += [f"property float {name}" for name, _ in columns]
    header += [f"element face {len(f)}", "property list uchar int vertex_indices", "end_header"]
    with open(path, "wb") as out:
        out.write(("\n".join(header) + "\n").encode())
        out.write(vertices.tobytes())
        out.write(faces.tobytes())


def pbrt_text(scene, folder):
    """The pbrt-v4 text of the dict `scene`; its meshes are written as PLY into `folder`."""
    cam = scene.get("camera", {})
    if not isinstance(cam, dict):
        raise ValueError(f"camera: expected a dict, got {type(cam).__name__}")
    unknown = set(cam) - set(_CAMERA_KEYS)
    if unknown:
        raise ValueError(f"camera: unknown keys {sorted(map(str, unknown))} (known: {', '.join(_CAMERA_KEYS)})")
    eye, target, up = cam.get("eye", [0, 0, 5]), cam.get("target", [0, 0, 0]), cam.get("up", [0, 1, 0])
    width, height = scene.get("resolution", (512, 512))
    lines = [
        f"LookAt {_numbers(eye)}  {_numbers(target)}  {_numbers(up)}",
        f'Camera "perspective" "float fov" [ {float(cam.get("fov", 45.0))!r} ]',
        f'Film "rgb" "integer xresolution" [ {int(width)} ] "integer yresolution" [ {int(height)} ]',
        f'Sampler "zsobol" "integer pixelsamples" [ {int(scene.get("spp", 64))} ]',
    ]
    if "max_depth" in scene:
        # pbrt-v4 counts bounces, fenestra path segments (2 = direct light).
        lines.append(f'Integrator "path" "integer maxdepth" [ {int(scene["max_depth"]) - 1} ]')
    lines += [
        "WorldBegin",
    ]
    for k, light in enumerate(scene.get("lights", [])):
        where = f"lights[{k}]"
        light = _table(light, where)
        lines.append(f'LightSource "{light["type"]}" {_params(light, where)}')
    materials = scene.get("materials", {})
    if not isinstance(materials, dict):
        raise ValueError(f"materials: expected a dict of name: material, got {type(materials).__name__}")
    for name, material in materials.items():
        where = f"materials[{name!r}]"
        if not isinstance(name, str):
            raise ValueError(f"{where}: a material's name must be a string")
        material = _table(material, where)
        lines.append(f'MakeNamedMaterial {json.dumps(name)} "string type" [ {json.dumps(material["type"])} ] {_params(material, where)}')
    for k, shape in enumerate(scene.get("shapes", [])):
        where = f"shapes[{k}]"
        if not isinstance(shape, dict):
            raise ValueError(f"{where}: expected a dict, got {type(shape).__name__}")
        kind = _word(shape.get("type", "mesh"), f"{where}: type")
        lines.append("AttributeBegin")
        if "material" in shape:
            if shape["material"] not in materials:
                raise ValueError(f"shape {k}: no material {shape['material']!r} (materials: {', '.join(materials) or 'none'})")
            lines.append(f"NamedMaterial {json.dumps(shape['material'])}")
        if "emission" in shape:
            two = ' "bool twosided" [ true ]' if shape.get("two_sided") else ""
            lines.append(f'AreaLightSource "diffuse" "rgb L" [ {_numbers(shape["emission"])} ]{two}')
        if shape.get("reverse_orientation"):
            lines.append("ReverseOrientation")
        if kind == "mesh":
            ply = f"mesh{k}.ply"
            try:
                _ply(folder / ply, shape["positions"], shape["indices"], shape.get("normals"), shape.get("uv"))
            except KeyError as missing:
                raise ValueError(f"{where}: a mesh needs {missing}") from None
            except ValueError as e:
                raise ValueError(f"{where}: {e}") from None
            lines.append(f'Shape "plymesh" "string filename" [ "{ply}" ] {_params(shape, where, _SHAPE_KEYS)}')
        elif kind == "sphere":
            lines.append(f"Translate {_numbers(shape.get('center', [0, 0, 0]))}")
            lines.append(f'Shape "sphere" {_params(shape, where, _SHAPE_KEYS)}')
        else:
            lines.append(f'Shape "{kind}" {_params(shape, where, _SHAPE_KEYS)}')
        lines.append("AttributeEnd")
    return "\n".join(lines) + "\n"


def _cache():
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "fenestra" / "dict-scenes"


def load_dict(scene, **scene_options):
    """Loads the dict `scene` (see the module's help), with `load`'s keywords: what the
    pbrt-v4 reader replaces or leaves out is in the scene's `.warnings` (strict=True refuses
    it)."""
    from . import load

    keys = ["camera", "resolution", "spp", "max_depth", "materials", "shapes", "lights"]
    unknown = set(scene) - set(keys)
    if unknown:
        raise ValueError(f"unknown scene keys {sorted(unknown)} (known: {', '.join(keys)})")
    staging = _cache() / "staging"
    staging.mkdir(parents=True, exist_ok=True)
    work = Path(os.path.join(staging, f"{os.getpid()}-{id(scene)}"))
    work.mkdir(exist_ok=True)
    text = pbrt_text(scene, work)
    (work / "scene.pbrt").write_text(text)
    digest = hashlib.sha256()
    for path in sorted(work.iterdir()):
        digest.update(path.name.encode())
        digest.update(path.read_bytes())
    final = _cache() / digest.hexdigest()[:16]
    if not final.exists():
        try:
            os.replace(work, final)
        except OSError:
            if not final.exists():
                raise
            # Another process stored the same scene meanwhile.
    if work.exists():
        for path in work.iterdir():
            path.unlink()
        work.rmdir()
    return load(final / "scene.pbrt", **scene_options)
