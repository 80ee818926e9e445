"""Relighting from Python: the command's frames, linear in the lights, errors named."""

import json

import numpy as np
import pytest

import fenestra as fe


@pytest.fixture(scope="module")
def precomputed(tmp_path_factory, cli):
    """A three-frame animation of the relight room, precomputed small."""
    root = tmp_path_factory.mktemp("relight")
    animation = root / "animation.json"
    animation.write_text(json.dumps({"frames": 3, "objects": {"crate": [
        {"frame": 0}, {"frame": 2, "translate": [1, 0, 0]}]}}))
    cli("relight", "precompute", "builtin:relight-room", "--animation", animation, "-o",
        root / "seq", "--resolution", "32x24", "--gather", "512", "--clusters", "8", "--keep",
        "128", "--explored", "0.5", "--schedule", "0:2,4:2", "--quiet")
    return root / "seq"


def test_frames_are_the_commands(precomputed, cli, tmp_path):
    cli("relight", "render", precomputed, "-o", tmp_path / "out", "--quiet")
    seq = fe.relight.open(precomputed)
    assert seq.frames == 3 and len(seq.lights) >= 1
    for f in range(3):
        img = seq.relight(f)
        assert img.array.shape == (24, 32, 3)
        assert np.array_equal(img.array, fe.read(tmp_path / "out" / f"frame-{f:04}.exr").array)


def test_relighting_is_linear_in_the_lights(precomputed):
    seq = fe.relight.open(precomputed)
    brighter = []
    for light in seq.lights:
        light = dict(light)
        for key in ("intensity", "irradiance"):
            if key in light:
                light[key] = [2 * v for v in light[key]]
        brighter.append(light)
    once = seq.relight(1, indirect_only=True).array
    twice = seq.relight(1, lights=brighter, indirect_only=True).array
    assert once.mean() > 0
    assert np.allclose(twice, 2 * once, rtol=1e-4, atol=1e-7)


def test_a_bad_light_is_named(precomputed):
    seq = fe.relight.open(precomputed)
    with pytest.raises(fe.FenestraError, match="lights"):
        seq.relight(0, lights=[{"type": "point", "position": [0, 1, 0]}])
    with pytest.raises(fe.FenestraError, match="frame"):
        seq.relight(7)
