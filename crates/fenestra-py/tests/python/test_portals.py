"""Portal estimation from Python: the command's portals, arrays of its photons, usable by lp_hf."""

import json

import numpy as np
import pytest

import fenestra as fe


def test_the_estimate_is_the_commands(tmp_path, cli):
    cli("portals", "builtin:box-hole", "-o", tmp_path / "cli.json", "--plot", tmp_path / "p.svg", "-q")
    est = fe.portals.estimate("builtin:box-hole", progress=False)
    assert est.portals == json.loads((tmp_path / "cli.json").read_text())["portals"]
    assert len(est) == 1 and est.portals[0]["area"] == pytest.approx(0.0625, rel=1e-3)
    assert est.photons.shape[1] == 3 and est.photons.dtype == np.float32
    assert sum(len(c) for c in est.clusters) <= len(est.photons)
    # The photons of its cluster lie in the hole's plane.
    normal = np.array(est.portals[0]["normal"])
    center = np.array(est.portals[0]["center"])
    cluster = est.photons[est.clusters[0]]
    assert np.abs((cluster - center) @ normal).max() < 0.05


def test_written_portals_render_as_the_commands_portals_do(tmp_path):
    est = fe.portals.estimate("builtin:box-hole", progress=False)
    est.write(tmp_path / "portals.json")
    args = dict(spp=2, resolution=(32, 32), progress=False)
    a = fe.render("builtin:box-hole", "lp_hf", portals=str(tmp_path / "portals.json"), **args)
    b = fe.render("builtin:box-hole", "lp_hf", portals="auto", no_portal_cache=True, **args)
    assert np.array_equal(a.array, b.array)


def test_a_bad_flag_is_named():
    with pytest.raises(fe.FenestraError, match="^thetta: no such option"):
        fe.portals.estimate("builtin:box-hole", thetta=3, progress=False)


def test_an_estimate_is_never_written_over_its_scene(tmp_path):
    scene = tmp_path / "floor.pbrt"
    scene.write_text(
        'LookAt 0 -3 1  0 0 0  0 0 1\nCamera "perspective"\nWorldBegin\n'
        'LightSource "infinite" "rgb L" [1 1 1]\n'
        'Shape "trianglemesh" "point3 P" [-1 -1 0  1 -1 0  1 1 0  -1 1 0] '
        '"integer indices" [0 1 2 0 2 3]\n'
    )
    before = scene.read_bytes()
    est = fe.portals.estimate(str(scene), time=0.1, progress=False)
    with pytest.raises(fe.FenestraError, match="is also the scene file this command reads"):
        est.write(scene)
    assert scene.read_bytes() == before
    est.write(tmp_path / "new" / "portals.json")
    assert json.loads((tmp_path / "new" / "portals.json").read_text())["portals"] == est.portals


def test_light_paths_show_what_they_brought(tmp_path):
    est = fe.portals.estimate("builtin:glossy-room", progress=False)
    est.write(tmp_path / "window.json")
    args = dict(spp=8, resolution=(32, 18), progress=False, portals=str(tmp_path / "window.json"))
    img = fe.render("builtin:glossy-room", "lp_lt", light_paths_trial=0, **args)
    assert img.light_paths.shape == img.array.shape
    assert 0 < img.light_paths.mean() < img.array.mean()
    lum = np.array([0.2126, 0.7152, 0.0722])
    share = (img.light_paths.astype(np.float64) @ lum).sum() / (img.array.astype(np.float64) @ lum).sum()
    assert abs(img.stats["extra"]["light_path_share"] - share) < 1e-4 * share
    assert fe.render("builtin:glossy-room", "lp_hf", **args).light_paths is None
