"""Dict scenes (as Mitsuba's load_dict): the same scene as a pbrt-v4 file renders the same."""

import numpy as np
import pytest

import fenestra as fe


def quad(corner, u, v):
    c, u, v = map(np.asarray, (corner, u, v))
    return np.array([c, c + u, c + u + v, c + v], np.float32), np.array([[0, 1, 2], [0, 2, 3]])


def box_scene():
    floor = quad([-1, 0, -1], [0, 0, 2], [2, 0, 0])
    back = quad([-1, 0, -1], [2, 0, 0], [0, 2, 0])
    lamp = quad([-0.3, 1.99, -0.3], [0.6, 0, 0], [0, 0, 0.6])
    return {
        "camera": {"eye": [0, 1, 3.5], "target": [0, 1, 0], "up": [0, 1, 0], "fov": 40},
        "resolution": (40, 30),
        "spp": 8,
        "max_depth": 4,
        "materials": {
            "white": {"type": "diffuse", "reflectance": [0.7, 0.7, 0.7]},
            "gold": {"type": "conductor", "eta": "metal-Au-eta", "k": "metal-Au-k", "roughness": 0.2},
        },
        "shapes": [
            {"type": "mesh", "positions": floor[0], "indices": floor[1], "material": "white"},
            {"type": "mesh", "positions": back[0], "indices": back[1], "material": "white"},
            {"type": "sphere", "center": [0.2, 0.4, -0.2], "radius": 0.4, "material": "gold"},
            {"type": "mesh", "positions": lamp[0], "indices": lamp[1], "material": "white",
             "emission": [8, 8, 8]},
        ],
        "lights": [{"type": "infinite", "L": [0.05, 0.06, 0.08]}],
    }


def inline(name, positions, indices):
    """A trianglemesh written by hand, as a pbrt-v4 author would."""
    p = " ".join(repr(float(x)) for x in np.asarray(positions, np.float32).ravel())
    i = " ".join(str(int(x)) for x in np.ravel(indices))
    return f'Shape "trianglemesh" "point3 P" [ {p} ] "integer indices" [ {i} ]'


def test_a_dict_scene_renders_as_the_same_pbrt_file(tmp_path):
    d = box_scene()
    s = d["shapes"]
    text = f"""LookAt 0 1 3.5  0 1 0  0 1 0
Camera "perspective" "float fov" [ 40 ]
Film "rgb" "integer xresolution" [ 40 ] "integer yresolution" [ 30 ]
Sampler "zsobol" "integer pixelsamples" [ 8 ]
Integrator "path" "integer maxdepth" [ 3 ]
WorldBegin
LightSource "infinite" "rgb L" [ 0.05 0.06 0.08 ]
MakeNamedMaterial "white" "string type" [ "diffuse" ] "rgb reflectance" [ 0.7 0.7 0.7 ]
MakeNamedMaterial "gold" "string type" [ "conductor" ] "spectrum eta" [ "metal-Au-eta" ] "spectrum k" [ "metal-Au-k" ] "float roughness" [ 0.2 ]
NamedMaterial "white"
{inline("floor", s[0]["positions"], s[0]["indices"])}
{inline("back", s[1]["positions"], s[1]["indices"])}
AttributeBegin
NamedMaterial "gold"
Translate 0.2 0.4 -0.2
Shape "sphere" "float radius" [ 0.4 ]
AttributeEnd
AttributeBegin
AreaLightSource "diffuse" "rgb L" [ 8 8 8 ]
{inline("lamp", s[3]["positions"], s[3]["indices"])}
AttributeEnd
"""
    (tmp_path / "box.pbrt").write_text(text)
    from_file = fe.render(fe.load(tmp_path / "box.pbrt"), progress=False)
    from_dict = fe.render(fe.load_dict(d), progress=False)
    assert from_dict.stats["spp"] == 8 and from_dict.stats["max_depth"] == 4
    assert from_dict.array.shape == (30, 40, 3)
    assert from_dict.array.mean() > 0.01
    assert np.array_equal(from_dict.array, from_file.array)


def test_a_dict_scene_is_cached_by_its_content(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    a = fe.load_dict(box_scene())
    b = fe.load_dict(box_scene())
    assert a.source == b.source
    brighter = box_scene()
    brighter["shapes"][3]["emission"] = [9, 9, 9]
    assert fe.load_dict(brighter).source != a.source
    assert not any((tmp_path / "fenestra" / "dict-scenes" / "staging").iterdir())


def test_bad_dicts_are_named():
    d = box_scene()
    d["shapes"][0]["material"] = "chalk"
    with pytest.raises(ValueError, match="shape 0: no material 'chalk'"):
        fe.load_dict(d)
    d = box_scene()
    d["shapes"][0]["indices"] = np.array([[0, 1, 7]])
    with pytest.raises(ValueError, match="indices must lie in 0..3"):
        fe.load_dict(d)
    with pytest.raises(ValueError, match="unknown scene keys"):
        fe.load_dict({"cameras": {}})
    d = box_scene()
    d["materials"]["white"]["type"] = "chalky"
    assert any("chalky" in w for w in fe.load_dict(d).warnings)
    with pytest.raises(fe.FenestraError, match="chalky"):
        fe.load_dict(d, strict=True)


def test_a_dict_cannot_write_directives_of_its_own(tmp_path):
    """Types and parameter names stand in the scene text unquoted or between quotes: one that
    is not a word could add any directive (an Include of any file), so it is refused."""
    secret = tmp_path / "other.pbrt"
    secret.write_text('Shape "sphere" "float radius" [ 9 ]\n')
    injected = f'infinite" "rgb L" [ 1 1 1 ]\nInclude "{secret}"\nLightSource "infinite'
    d = box_scene()
    d["lights"][0]["type"] = injected
    with pytest.raises(ValueError, match=r"lights\[0\]: type: expected a name"):
        fe.load_dict(d)
    d = box_scene()
    d["shapes"][2]["type"] = 'sphere" "float radius" [ 1 ]\nInclude "x'
    with pytest.raises(ValueError, match=r"shapes\[2\]: type"):
        fe.load_dict(d)
    d = box_scene()
    d["materials"]["white"]['roughness" [ 0 ] "float x'] = 1.0
    with pytest.raises(ValueError, match=r"materials\['white'\]: parameter"):
        fe.load_dict(d)


def test_mesh_indices_are_integers_in_range_before_any_cast():
    for bad, message in (
        (np.array([[0, 1, 2**32 + 1]]), r"shapes\[0\]: mesh indices must lie in 0..3, got 0..4294967297"),
        (np.array([[0.0, 1.0, 2.5]]), r"shapes\[0\]: mesh indices must be integers, got float64"),
    ):
        d = box_scene()
        d["shapes"][0]["indices"] = bad
        with pytest.raises(ValueError, match=message):
            fe.load_dict(d)


def test_unknown_camera_keys_and_malformed_entries_are_named():
    d = box_scene()
    d["camera"]["eyes"] = [0, 1, 3.5]
    with pytest.raises(ValueError, match=r"camera: unknown keys \['eyes'\]"):
        fe.load_dict(d)
    for key, entry, message in (
        ("lights", [{"L": [1, 1, 1]}], r"lights\[0\]: no 'type'"),
        ("lights", ["infinite"], r"lights\[0\]: expected a dict, got str"),
        ("materials", {"white": "diffuse"}, r"materials\['white'\]: expected a dict, got str"),
        ("materials", ["white"], r"materials: expected a dict"),
    ):
        d = box_scene()
        d[key] = entry
        if key == "materials":
            for shape in d["shapes"]:
                shape.pop("material", None)
        with pytest.raises(ValueError, match=message):
            fe.load_dict(d)
    d = box_scene()
    del d["shapes"][0]["indices"]
    with pytest.raises(ValueError, match=r"shapes\[0\]: a mesh needs 'indices'"):
        fe.load_dict(d)
