"""Renders from Python are the command line's renders: same pixels, files and statistics."""

import json
import math

import numpy as np
import pytest

import fenestra as fe


@pytest.mark.parametrize(
    "integrator, flags, keywords",
    [
        ("af_hf", [], {}),
        ("af_hf", ["--max-depth", "3", "--light-selection", "bvh"], {"max_depth": 3, "light_selection": "bvh"}),
        ("lp_hf", ["--portals", "auto", "--no-portal-cache"], {"portals": "auto", "no_portal_cache": True}),
        ("af_hf", ["--bvh", "obvhs"], {"backend": "obvhs"}),
    ],
)
def test_a_render_is_the_command_lines_bit_for_bit(tmp_path, cli, integrator, flags, keywords):
    out = tmp_path / "cli.exr"
    cli("render", "builtin:box-hole", "--integrator", integrator, "--spp", 4,
        "--resolution", "48x32", "--seed", 7, *flags, "-q", "-o", out)
    img = fe.render("builtin:box-hole", integrator, spp=4, resolution=(48, 32), seed=7,
                    progress=False, **keywords)
    assert np.array_equal(img.array, fe.read(out).array)
    assert img.png() == (tmp_path / "cli.png").read_bytes()
    sidecar = json.loads((tmp_path / "cli.json").read_text())
    for key in ("scene", "scene_content", "integrator", "spp", "seed", "max_depth", "width", "height"):
        assert img.stats[key] == sidecar[key], key
    assert img.stats["rays"]["camera"] == sidecar["rays"]["camera"]


def test_options_given_by_key_are_options_given_by_keyword():
    scene = fe.load("builtin:cornell-box")
    by_word = fe.render(scene, spp=2, resolution=(24, 24), max_depth=2, progress=False)
    by_key = fe.render(scene, spp=2, resolution=(24, 24), options={"path.max_depth": 2},
                       progress=False)
    other = fe.render(scene, spp=2, resolution=(24, 24), progress=False)
    assert np.array_equal(by_word.array, by_key.array)
    assert not np.array_equal(by_word.array, other.array)


def test_arrays_have_the_images_shape_and_no_nan(tmp_path):
    img = fe.render("builtin:cornell-box", spp=3, resolution=(40, 30), progress=False)
    for a in (img.array, img.variance):
        assert a.shape == (30, 40, 3) and a.dtype == np.float32
        assert np.isfinite(a).all()
    assert (img.variance >= 0).all() and img.variance.max() > 0
    assert img.array.mean() > 0
    assert img.stats["spp"] == 3 and not img.interrupted
    img.write(tmp_path / "x.exr", variance=True)
    assert np.array_equal(fe.read(tmp_path / "x.exr").array, img.array)
    assert np.array_equal(fe.read(tmp_path / "x.var.exr").array, img.variance)


def test_a_scene_renders_again_the_same(tmp_path):
    scene = fe.load("builtin:box-hole")
    a = fe.render(scene, spp=2, resolution=(32, 32), seed=1, progress=False)
    b = fe.render(scene, spp=2, resolution=(32, 32), seed=1, progress=False, threads=1)
    c = fe.render(scene, spp=2, resolution=(32, 32), seed=2, progress=False)
    assert np.array_equal(a.array, b.array)
    assert not np.array_equal(a.array, c.array)


def test_pieces_of_samples_merge_into_the_whole(tmp_path):
    args = dict(spp=None, resolution=(32, 24), seed=5, progress=False)
    whole = fe.render("builtin:cornell-box", **{**args, "spp": 6})
    paths = []
    for k, (a, b) in enumerate([(0, 2), (2, 6)]):
        piece = fe.render("builtin:cornell-box", samples=(a, b), **args)
        assert piece.stats["spp"] == b - a
        paths.append(tmp_path / f"part{k}.exr")
        piece.write(paths[-1])
    merged = fe.merge(paths, total=6)
    assert np.array_equal(merged.array, whole.array)
    assert np.array_equal(merged.variance, whole.variance)


def test_tiles_merge_into_the_whole(tmp_path):
    args = dict(spp=2, resolution=(32, 24), seed=5, progress=False)
    whole = fe.render("builtin:cornell-box", **args)
    paths = []
    for k, crop in enumerate([(0, 0, 32, 10), (0, 10, 32, 24)]):
        tile = fe.render("builtin:cornell-box", crop=crop, **args)
        assert tile.array.shape == (crop[3] - crop[1], 32, 3)
        paths.append(tmp_path / f"tile{k}.exr")
        tile.write(paths[-1])
    assert np.array_equal(fe.merge(paths).array, whole.array)


def test_progress_reaches_every_sample():
    seen = []
    fe.render("builtin:cornell-box", spp=4, resolution=(16, 16),
              progress=lambda stage, done, total, notes: seen.append((stage, done, total)))
    stage, done, total = seen[-1]
    assert total == 4 * 16 * 16 and done == total
    assert all(b[1] >= a[1] for a, b in zip(seen, seen[1:]) if a[0] == b[0])


def test_time_limits_a_render():
    # A million samples per pixel take minutes: a render that stops well before them has
    # been stopped by the clock (its seconds are not checked: no timing in tests).
    img = fe.render("builtin:cornell-box", time=0.5, spp=10**6, resolution=(32, 32),
                    progress=False)
    assert not img.interrupted
    assert 1 <= img.stats["spp"] < 10**6


def test_a_renders_files_never_replace_what_it_read(tmp_path):
    est = fe.portals.estimate("builtin:box-hole", progress=False)
    est.write(tmp_path / "portals.json")
    img = fe.render("builtin:box-hole", "lp_hf", portals=str(tmp_path / "portals.json"), spp=1,
                    resolution=(16, 16), progress=False)
    with pytest.raises(fe.FenestraError, match="refusing to overwrite"):
        img.write(tmp_path / "portals.exr")     # its sidecar would be portals.json
    assert json.loads((tmp_path / "portals.json").read_text())["portals"] == est.portals
    piece = fe.render("builtin:cornell-box", samples=(0, 1), resolution=(16, 16), progress=False)
    piece.write(tmp_path / "part.exr")
    merged = fe.merge([tmp_path / "part.exr"], total=1)
    with pytest.raises(fe.FenestraError, match="refusing to overwrite"):
        merged.write(tmp_path / "part.exr")


def test_jupyter_shows_the_commands_png():
    img = fe.render("builtin:cornell-box", spp=1, resolution=(16, 16), progress=False)
    assert img._repr_png_()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "cornell-box af_hf 16x16" in repr(img)
