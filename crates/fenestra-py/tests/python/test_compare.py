"""Comparisons: metrics, efficiency, the z-test, as fenestra compare makes them."""

import json

import numpy as np
import pytest

import fenestra as fe


def test_two_seeds_agree_and_a_brighter_image_does_not():
    scene = fe.load("builtin:cornell-box")
    a = fe.render(scene, spp=16, resolution=(32, 32), seed=1, progress=False)
    b = fe.render(scene, spp=16, resolution=(32, 32), seed=2, progress=False)
    same = fe.compare(a, b)
    assert same.agrees and abs(same.z) < 4
    assert same.efficiency is not None and same.efficiency > 0
    brighter = fe.Image(a.array * np.float32(1.2), a.variance, a.stats)
    off = fe.compare(brighter, b)
    assert not off.agrees and off.z > 4
    assert abs(off.mean_shift - 0.2) < 0.05
    # A significance or region that would make any image agree is refused, by its keyword.
    for alpha in [float("nan"), 2, -1, 0]:
        with pytest.raises(fe.FenestraError, match="^alpha"):
            fe.compare(brighter, b, alpha=alpha)
    with pytest.raises(fe.FenestraError, match="^region: no 0x0-pixel region fits"):
        fe.compare(brighter, b, region=0)


def test_metrics_are_the_command_lines(tmp_path, cli):
    scene = fe.load("builtin:cornell-box")
    a = fe.render(scene, spp=4, resolution=(32, 32), seed=1, progress=False)
    r = fe.render(scene, spp=16, resolution=(32, 32), seed=2, progress=False)
    a.write(tmp_path / "a.exr")
    r.write(tmp_path / "r.exr")
    done = cli("compare", tmp_path / "a.exr", "--ref", tmp_path / "r.exr", "--json")
    [row] = json.loads(done.stdout)
    c = fe.compare(a, r)
    for name in ("mse", "rel_mse", "mae", "mean", "ref_mean", "region_error", "efficiency"):
        assert np.isclose(getattr(c, name), row[name], rtol=1e-12, atol=0), name
    assert c.error_map.shape == (32, 32)
    assert np.isclose(c.error_map.mean(), c.mse, rtol=1e-5)


def test_plain_arrays_compare_too():
    x = np.ones((4, 6, 3), np.float32)
    c = fe.compare(x * 2, x)
    assert c.mse == 1.0 and c.agrees is None and c.efficiency is None
