"""Bad input: Python exceptions with the command line's messages, naming what is wrong."""

import numpy as np
import pytest

import fenestra as fe


def test_an_unknown_keyword_is_named():
    with pytest.raises(fe.FenestraError, match="^portal_sampler: no such option"):
        fe.render("builtin:cornell-box", spp=1, portal_sampler="x", progress=False)


def test_a_bad_value_is_named_by_its_keyword():
    with pytest.raises(fe.FenestraError, match="^max_depth: path.max_depth must be at least 1"):
        fe.render("builtin:cornell-box", spp=1, max_depth=0, progress=False)


def test_an_option_the_integrator_does_not_read_is_refused():
    with pytest.raises(fe.FenestraError, match="^portals: portals.source is not read by af_hf"):
        fe.render("builtin:cornell-box", "af_hf", spp=1, portals="auto", progress=False)


def test_an_unknown_integrator_lists_the_known():
    with pytest.raises(fe.FenestraError, match="lp_hf"):
        fe.render("builtin:cornell-box", "nope", spp=1, progress=False)


def test_a_value_json_cannot_hold_names_the_option():
    with pytest.raises(TypeError, match="^max_depth: expected a number"):
        fe.render("builtin:cornell-box", spp=1, max_depth=[3], progress=False)


@pytest.mark.parametrize("spp", [0, -1, 2.5, True, np.float64(2.0)])
def test_a_bad_sample_count_is_refused(spp):
    with pytest.raises(fe.FenestraError, match="^spp must be a whole number of at least 1"):
        fe.render("builtin:cornell-box", spp=spp, progress=False)


def test_numpy_integers_are_sample_counts():
    img = fe.render("builtin:cornell-box", spp=np.int64(2), resolution=(8, 8), progress=False)
    assert img.stats["spp"] == 2


@pytest.mark.parametrize("value", [float("nan"), float("inf"), np.float32("nan")])
def test_a_number_json_cannot_hold_names_the_option(value):
    with pytest.raises(fe.FenestraError, match="^max_depth: must be a finite number"):
        fe.render("builtin:cornell-box", spp=1, max_depth=value, progress=False)


def test_a_bad_time_is_refused():
    with pytest.raises(fe.FenestraError, match="time must be a positive number"):
        fe.render("builtin:cornell-box", time=float("nan"), progress=False)


def test_a_scene_files_error_names_file_line_and_column(tmp_path):
    scene = tmp_path / "broken.pbrt"
    scene.write_text('LookAt 0 0 5  0 0 0  0 1 0\nCamera "perspective"\nWorldBegin\nShape "sphere" "float radius" [ 1 \n')
    with pytest.raises(fe.FenestraError, match=r"broken\.pbrt:4:\d+"):
        fe.load(scene)


def test_a_missing_scene_is_named():
    with pytest.raises(fe.FenestraError, match="nowhere.pbrt"):
        fe.load("/nowhere.pbrt")


def test_scene_keywords_need_what_they_describe():
    with pytest.raises(fe.FenestraError, match="^sun describes sky=True's sky"):
        fe.load("builtin:box-hole", sun=(30, 200))


def test_a_wrong_piece_of_a_split_render_is_named(tmp_path):
    with pytest.raises(
        fe.FenestraError, match="^samples 0..2 says how many samples to take: not with spp$"
    ):
        fe.render("builtin:cornell-box", spp=4, samples=(0, 2), progress=False)


def test_the_sessions_refusals_name_keywords_not_flags():
    with pytest.raises(fe.FenestraError, match="^sun_strength must be 0 or more, got -1$"):
        fe.load("builtin:box-hole", sky=True, sun_strength=-1)
    with pytest.raises(fe.FenestraError, match="^environment_rotation places environment"):
        fe.load("builtin:box-hole", environment_rotation=10)
    with pytest.raises(fe.FenestraError, match="^resolution 0x4 has no pixels"):
        fe.render("builtin:cornell-box", spp=1, resolution=(0, 4), progress=False)
    with pytest.raises(fe.FenestraError, match="^crop 0,0,9,9 must be X0,Y0,X1,Y1"):
        fe.render("builtin:cornell-box", spp=1, resolution=(8, 8), crop=(0, 0, 9, 9), progress=False)
    with pytest.raises(fe.FenestraError, match="^theta: estimate.theta takes a number"):
        fe.portals.estimate("builtin:box-hole", theta="wide", progress=False)


def test_an_unknown_backend_is_named():
    with pytest.raises(fe.FenestraError, match="^backend: "):
        fe.render("builtin:cornell-box", spp=1, backend="optix", progress=False)


@pytest.mark.parametrize("exposure", [float("nan"), float("inf"), -float("inf"), 1000.0])
def test_an_exposure_beyond_numbers_is_refused_and_writes_nothing(tmp_path, exposure):
    img = fe.render(fe.load("builtin:cornell-box"), spp=1, resolution=(8, 8), progress=False)
    with pytest.raises(fe.FenestraError, match="exposure must be a finite number of stops"):
        img.write(tmp_path / "a.exr", exposure=exposure)
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(fe.FenestraError, match="exposure must be a finite number of stops"):
        img.png(exposure=exposure)
