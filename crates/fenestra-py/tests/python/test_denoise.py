"""Denoising from Python: the command line's features and denoised image, arrays in and out."""

import json

import numpy as np
import pytest

import fenestra as fe


@pytest.fixture(scope="module")
def reference():
    return fe.render("builtin:cornell-box", spp=1024, resolution=(48, 48), seed=100, progress=False)


def test_a_denoised_render_is_the_command_lines_and_closer_to_the_reference(tmp_path, cli, reference):
    out = tmp_path / "cli.exr"
    cli("render", "builtin:cornell-box", "--spp", 4, "--resolution", "48x48", "--seed", 1,
        "--denoise", "-q", "-o", out)
    img = fe.render("builtin:cornell-box", spp=4, resolution=(48, 48), seed=1, denoise=True,
                    progress=False)
    assert img.albedo.shape == img.normal.shape == img.array.shape == (48, 48, 3)
    denoised = img.denoised()
    assert np.array_equal(denoised, fe.read(tmp_path / "cli.denoised.exr").array)
    assert img.stats["denoiser"]["mode"] == "accurate"
    raw = fe.compare(img, reference).rel_mse
    clean = fe.compare(denoised, reference).rel_mse
    assert clean < raw / 3, (raw, clean)
    written = img.write(tmp_path / "py.exr")
    assert (tmp_path / "py.denoised.exr").exists() and (tmp_path / "py.denoised.png").exists()
    assert json.loads(written.with_suffix(".json").read_text())["denoiser"]["version"] == "2.5.1"


def test_features_alone_leave_the_pixels_and_denoise_on_demand(tmp_path):
    plain = fe.render("builtin:box-hole", spp=4, resolution=(24, 16), progress=False)
    featured = fe.render("builtin:box-hole", spp=4, resolution=(24, 16), features=True,
                         progress=False)
    assert plain.albedo is None and plain.normal is None
    assert np.array_equal(plain.array, featured.array)
    assert "denoiser" not in featured.stats
    assert np.all((featured.albedo >= 0) & (featured.albedo <= 1))
    assert np.all(np.abs(featured.normal) <= 1)
    fast = featured.denoised("fast")
    assert fast.shape == featured.array.shape and np.all(np.isfinite(fast))
    assert not np.array_equal(fast, featured.denoised("accurate"))
    featured.write(tmp_path / "f.exr")
    assert not (tmp_path / "f.denoised.exr").exists()
    # The written EXR's layers come back with it.
    back = fe.read(tmp_path / "f.exr")
    assert np.array_equal(back.albedo, featured.albedo)
    assert np.array_equal(back.normal, featured.normal)
    assert fe.read(tmp_path / "f.png").albedo is None


def test_denoise_takes_arrays_and_refuses_what_does_not_fit():
    rng = np.random.default_rng(3)
    noisy = (0.5 + 0.2 * rng.standard_normal((32, 40, 3))).astype(np.float32).clip(0)
    out = fe.denoise(noisy)
    assert out.shape == noisy.shape and out.dtype == np.float32
    # A flat grey under noise comes back flatter.
    assert out.std() < noisy.std() / 2
    with pytest.raises(ValueError, match="both albedo and normal"):
        fe.denoise(noisy, albedo=np.ones_like(noisy))
    with pytest.raises(ValueError, match="albedo is 4x4"):
        fe.denoise(noisy, albedo=np.ones((4, 4, 3), np.float32), normal=np.ones((4, 4, 3), np.float32))
    with pytest.raises(fe.FenestraError, match="unknown denoise mode"):
        fe.denoise(noisy, mode="best")
    with pytest.raises(fe.FenestraError, match="unknown denoise mode"):
        fe.render("builtin:box-hole", spp=1, resolution=(8, 8), denoise="best", progress=False)
    with pytest.raises(fe.FenestraError, match="denoise must be"):
        fe.render("builtin:box-hole", spp=1, resolution=(8, 8), denoise=2, progress=False)
