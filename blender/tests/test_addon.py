"""The Blender add-on end to end: renders through the engine equal the CLI's render of the
exported scene bit for bit, Esc keeps the image so far, the portal operator finds the window,
and the world arrives where Cycles puts it."""

import math
import pathlib
import shlex
import subprocess
import time

import bpy
import numpy as np
import OpenEXR
import pytest

import room
from fenestra import engine as fenestra_engine


def exr(path):
    """An EXR's RGB, top row first."""
    channels = OpenEXR.File(str(path)).channels()
    data = next(iter(channels.values())).pixels
    return np.asarray(data, dtype=np.float32)[..., :3]


def render(scene, path):
    """F12 as a script does it: the engine renders, Blender writes the result to `path`."""
    scene.render.filepath = str(path)
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    bpy.ops.render.render(write_still=True)
    return exr(path)


def kept(scene):
    """The folder Keep Files keeps `scene`'s render in."""
    return pathlib.Path(fenestra_engine.kept_folder(scene))


def kept_command(folder):
    return shlex.split((folder / "command.txt").read_text())


def test_the_engine_renders_what_the_cli_renders_of_the_exported_scene(workdir, fenestra_bin):
    scene = room.build(samples=8)
    scene.fenestra.integrator = "lp_hf"
    scene.fenestra.keep_files = str(workdir / "kept")
    shown = render(scene, workdir / "blender.exr")
    command = kept_command(kept(scene))
    assert command[1:3] == ["render", str(kept(scene) / "scene.glb")]
    # The same render by hand: the kept scene and flags, without the add-on's watching.
    cli = command[:4] + [str(workdir / "cli.exr")] + command[5:]
    cli.remove("--progress-lines")
    i = cli.index("--snapshot-every")
    del cli[i : i + 2]
    subprocess.run(cli, check=True, capture_output=True)
    by_hand = exr(workdir / "cli.exr")
    assert shown.shape == (72, 96, 3)
    assert shown.mean() > 0.05, "the room renders dark: the sky or lamp did not arrive"
    assert np.array_equal(shown, by_hand), "Blender's render result differs from the CLI's image"
    assert np.array_equal(exr(kept(scene) / "render.exr"), by_hand)
    # What the world and panel said became flags.
    assert "--sky" in command and "--portals" in command and "auto" in command
    assert command[command.index("--spp") + 1] == "8"


def test_escape_stops_fenestra_and_keeps_the_image_so_far(workdir, monkeypatch):
    scene = room.build(samples=1_000_000)
    scene.fenestra.integrator = "af_hf"
    scene.fenestra.time_limit = 60.0
    scene.fenestra.keep_files = str(workdir / "kept")
    start = time.monotonic()
    monkeypatch.setattr(
        fenestra_engine.FenestraRenderEngine,
        "stop_requested",
        lambda self: time.monotonic() > start + 1.0,
    )
    shown = render(scene, workdir / "blender.exr")
    took = time.monotonic() - start
    assert took < 5.0, f"the render went on {took:.1f} s after Esc at 1 s"
    log = (kept(scene) / "fenestra.log").read_text()
    assert "interrupted" in log
    assert shown.mean() > 0.05, "the image so far was not kept"
    assert np.array_equal(shown, exr(kept(scene) / "render.exr"))


def test_estimate_portals_adds_a_portal_light_over_the_window(fenestra_bin):
    scene = room.build()
    assert bpy.ops.fenestra.estimate_portals() == {"FINISHED"}
    lights = list(bpy.data.collections["fenestra portals"].objects)
    assert len(lights) == 1, [o.name for o in lights]
    light = lights[0]
    assert light.data.type == "AREA" and light.data.cycles.is_portal
    (x0, x1), (z0, z1), y = room.WINDOW["x"], room.WINDOW["z"], room.WINDOW["y"]
    c = light.matrix_world.translation
    assert x0 < c.x < x1 and z0 < c.z < z1 and abs(c.y - y) < 0.2, tuple(c)
    sizes = sorted([light.data.size, light.data.size_y])
    assert sizes == pytest.approx(sorted([x1 - x0, z1 - z0]), abs=0.1)
    # It emits (-Z) into the room, towards the camera's side of the wall.
    facing = -light.matrix_world.to_3x3().col[2]
    assert facing.y < -0.9, tuple(facing)
    # And a render with Portals: Scene reads it back as a portals.json of the same window.
    scene.fenestra.integrator = "lp_hf"
    scene.fenestra.portals = "scene"
    scene.fenestra.samples = 1
    assert render(scene, bpy.app.tempdir + "portals.exr").mean() > 0


def _look(scene, direction):
    """Points the camera from the origin along `direction` (Blender frame), Z up."""
    cam = scene.camera
    cam.location = (0, 0, 0)
    cam.rotation_euler = (math.pi / 2, 0, math.atan2(direction[1], direction[0]) - math.pi / 2)


def _empty_world_scene(width=64, height=32):
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    cam.data.angle = math.radians(90)
    scene.collection.objects.link(cam)
    scene.camera = cam
    # glTF needs a mesh: a small floor far below.
    mesh = bpy.data.meshes.new("floor")
    mesh.from_pydata([(-1, -1, -50), (1, -1, -50), (1, 1, -50), (-1, 1, -50)], [], [(0, 1, 2, 3)])
    scene.collection.objects.link(bpy.data.objects.new("floor", mesh))
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    scene.world = room.use_nodes(bpy.data.worlds.new("world"))
    return scene


def _world(scene, texture):
    nodes, links = scene.world.node_tree.nodes, scene.world.node_tree.links
    nodes.clear()
    out, bg = nodes.new("ShaderNodeOutputWorld"), nodes.new("ShaderNodeBackground")
    tex = nodes.new(texture)
    links.new(tex.outputs[0], bg.inputs[0])
    links.new(bg.outputs[0], out.inputs[0])
    return tex


def _both(scene, workdir, name):
    """The scene rendered by Cycles and by fenestra (through the engine)."""
    scene.render.engine = "CYCLES"
    scene.cycles.samples = 16
    scene.cycles.use_denoising = False
    cycles = render(scene, workdir / f"{name}-cycles.exr")
    scene.render.engine = "FENESTRA"
    scene.fenestra.integrator = "af_hf"
    scene.fenestra.samples = 16
    return cycles, render(scene, workdir / f"{name}-fenestra.exr")


def _centroid(img, channel):
    """The column and row centre of what is mostly `channel` (0 red, 2 blue)."""
    others = [c for c in range(3) if c != channel]
    mask = img[..., channel] > 4 * img[..., others].max(-1) + 0.5
    assert mask.any(), "nothing of that colour in view"
    rows, cols = np.nonzero(mask)
    return cols.mean(), rows.mean()


def test_an_hdri_stands_where_cycles_shows_it(workdir):
    scene = _empty_world_scene()
    # A lat-long image with a red patch at u = 0.25 and a blue one at u = 0.375 (both on the
    # horizon): Cycles shows red towards +Y and blue between +X and +Y, right of red.
    w, h = 256, 128
    px = np.full((h, w, 4), 0.02, dtype=np.float32)
    px[..., 3] = 1
    px[h // 2 - 4 : h // 2 + 4, 60:68, :3] = (20, 0, 0)
    px[h // 2 - 4 : h // 2 + 4, 92:100, :3] = (0, 0, 20)
    image = bpy.data.images.new("hdri", w, h, float_buffer=True)
    image.pixels.foreach_set(px.ravel())  # rows bottom up: the patches sit on the horizon
    image.filepath_raw = str(workdir / "hdri.exr")
    image.file_format = "OPEN_EXR"
    image.save()
    tex = _world(scene, "ShaderNodeTexEnvironment")
    tex.image = bpy.data.images.load(str(workdir / "hdri.exr"))
    for turn in (0.0, 30.0):
        nodes, links = scene.world.node_tree.nodes, scene.world.node_tree.links
        coords, mapping = nodes.new("ShaderNodeTexCoord"), nodes.new("ShaderNodeMapping")
        mapping.inputs["Rotation"].default_value[2] = math.radians(turn)
        links.new(coords.outputs["Generated"], mapping.inputs["Vector"])
        links.new(mapping.outputs[0], tex.inputs["Vector"])
        _look(scene, (math.cos(math.radians(75 - turn)), math.sin(math.radians(75 - turn)), 0))
        cycles, ours = _both(scene, workdir, f"hdri-{turn:g}")
        for colour in (0, 2):
            assert _centroid(ours, colour) == pytest.approx(
                _centroid(cycles, colour), abs=1.5
            ), f"turn {turn}: colour {colour} not where Cycles puts it"


def test_the_sun_stands_where_cycles_puts_it(workdir):
    scene = _empty_world_scene()
    sky = _world(scene, "ShaderNodeTexSky")
    sky.sky_type = "MULTIPLE_SCATTERING" if bpy.app.version >= (5, 0, 0) else "NISHITA"
    sky.sun_elevation = math.radians(12)
    sky.sun_rotation = math.radians(60)
    sky.sun_size = math.radians(6)  # a sun Cycles' 16 samples find in a few pixels
    # The sun clockwise from +Y by 60 degrees; the camera looks 20 degrees to its left.
    azimuth = math.radians(90 - 60 + 20)
    _look(scene, (math.cos(azimuth), math.sin(azimuth), 0.2))
    cycles, ours = _both(scene, workdir, "sun")
    brightest = [np.unravel_index(np.argmax(img.sum(-1)), img.shape[:2]) for img in (cycles, ours)]
    assert brightest[0][1] > 32, "Cycles' sun is not right of the middle: the camera setup is off"
    assert (
        abs(brightest[0][0] - brightest[1][0]) <= 2 and abs(brightest[0][1] - brightest[1][1]) <= 2
    ), brightest


def test_a_variance_pass_and_a_report_against_a_reference(workdir, fenestra_bin):
    scene = room.build(samples=4, size=(48, 36))
    scene.fenestra.integrator = "af_hf"
    scene.fenestra.keep_files = str(workdir / "ref")
    scene.fenestra.samples = 64
    render(scene, workdir / "reference.exr")
    scene.fenestra.samples = 4
    scene.fenestra.variance_pass = True
    scene.fenestra.reference = str(kept(scene) / "render.exr")
    scene.fenestra.keep_files = str(workdir / "kept")
    scene.render.filepath = str(workdir / "layers.exr")
    settings = scene.render.image_settings
    if hasattr(settings, "media_type"):  # Blender 5
        settings.media_type = "MULTI_LAYER_IMAGE"
    settings.file_format = "OPEN_EXR_MULTILAYER"
    scene.render.image_settings.color_depth = "32"
    bpy.ops.render.render(write_still=True)
    # Blender 5 writes a part per pass, Blender 4 one part with "ViewLayer.Variance.R" etc.
    channels = {
        name: c
        for part in OpenEXR.File(str(workdir / "layers.exr")).parts
        for name, c in part.channels.items()
    }
    variance = [name for name in channels if name.startswith("ViewLayer.Variance")]
    assert variance, list(channels)
    shown = channels[variance[0]].pixels
    ours = exr(kept(scene) / "render.var.exr")
    assert ours.mean() > 0
    assert np.array_equal(
        np.asarray(shown)[..., :3], ours
    ), "the Variance pass differs from fenestra's"
    report = scene.fenestra.last_report
    assert report.endswith("report.html")
    page = open(report).read()
    assert "rel_mse" in page and "<svg" in page and "render.error.png" in page


def layer_channels(scene, workdir, name):
    """F12 written as a multilayer EXR: its channels by name, every part's."""
    scene.render.filepath = str(workdir / name)
    settings = scene.render.image_settings
    if hasattr(settings, "media_type"):  # Blender 5
        settings.media_type = "MULTI_LAYER_IMAGE"
    settings.file_format = "OPEN_EXR_MULTILAYER"
    settings.color_depth = "32"
    bpy.ops.render.render(write_still=True)
    return {
        name: c
        for part in OpenEXR.File(str(workdir / name)).parts
        for name, c in part.channels.items()
    }


def test_denoise_shows_oidns_image_and_fills_the_denoising_passes(workdir, fenestra_bin):
    scene = room.build(samples=4, size=(48, 36))
    scene.fenestra.integrator = "af_hf"
    scene.fenestra.denoise = True
    scene.fenestra.keep_files = str(workdir / "kept")
    channels = layer_channels(scene, workdir, "denoised.exr")
    folder = kept(scene)
    command = kept_command(folder)
    assert command[command.index("--denoise") + 1] == "accurate"
    assert command[command.index("--features") + 1] == "files"

    def shown(prefix):
        # OpenEXR groups R, G, B (and A) into one channel; X, Y, Z stay apart.
        name = f"ViewLayer.{prefix}"
        if name in channels:
            return np.asarray(channels[name].pixels, dtype=np.float32)[..., :3]
        axes = [np.asarray(channels[f"{name}.{a}"].pixels) for a in "XYZ"]
        return np.stack(axes, -1).astype(np.float32)

    combined = shown("Combined")
    assert np.array_equal(combined, exr(folder / "render.denoised.exr"))
    assert not np.array_equal(combined, exr(folder / "render.exr"))
    assert np.array_equal(shown("Noisy Image"), exr(folder / "render.exr"))
    assert np.array_equal(shown("Denoising Albedo"), exr(folder / "render.albedo.exr"))
    assert np.array_equal(shown("Denoising Normal"), exr(folder / "render.normal.exr"))
    albedo = exr(folder / "render.albedo.exr")
    assert 0 < albedo.mean() <= 1
    # Denoising Data alone: the passes, and the raw image as Combined.
    scene.fenestra.denoise = False
    scene.fenestra.denoising_data = True
    channels = layer_channels(scene, workdir, "data.exr")
    assert "--denoise" not in kept_command(folder)
    assert np.array_equal(shown("Combined"), exr(folder / "render.exr"))
    assert not any(n.startswith("ViewLayer.Noisy Image.") for n in channels)
    assert np.array_equal(shown("Denoising Albedo"), exr(folder / "render.albedo.exr"))


def test_world_flags_for_each_kind_of_world(workdir):
    from fenestra import world

    scene = _empty_world_scene()
    sky = _world(scene, "ShaderNodeTexSky")
    sky.sky_type = "HOSEK_WILKIE"
    sky.sun_direction = (0.0, -1.0, 1.0)  # south-ish, 45 degrees up
    sky.turbidity = 4.5
    flags, _ = world.world_flags(scene.world, str(workdir))
    assert flags[flags.index("--sun") + 1] == "45.0000,90.0000"
    assert (
        flags[flags.index("--sun-strength") + 1] == "0"
    ), "Cycles' Hosek-Wilkie sky has no sun disk"
    assert flags[flags.index("--sky-turbidity") + 1] == "4.5"

    nodes = scene.world.node_tree.nodes
    nodes.remove(sky)
    background = next(n for n in nodes if n.type == "BACKGROUND")
    background.inputs["Color"].default_value = (0.2, 0.4, 0.8, 1.0)
    background.inputs["Strength"].default_value = 2.0
    flags, _ = world.world_flags(scene.world, str(workdir))
    pfm = flags[flags.index("--environment") + 1]
    with open(pfm, "rb") as f:
        assert f.readline() == b"PF\n"
        f.readline(), f.readline()
        rgb = np.frombuffer(f.read(), dtype="<f4").reshape(-1, 3)
    assert np.allclose(rgb, (0.4, 0.8, 1.6))

    noise = nodes.new("ShaderNodeTexNoise")
    scene.world.node_tree.links.new(noise.outputs["Color"], background.inputs["Color"])
    with pytest.raises(world.WorldError, match="Noise Texture"):
        world.world_flags(scene.world, str(workdir))


def test_work_for_a_busy_main_thread_is_given_up():
    # F12 renders in a worker thread and hands image loads to the main thread; when Blender
    # quits mid-render its main thread waits for the render and runs no timers (as here, in
    # a background process): the render must give up on the load, and the load never run.
    import threading

    from fenestra import mainthread

    ran, outcome = [], []

    def render_thread():
        try:
            mainthread.call(ran.append, 1, give_up=mainthread.deadline(0.3))
        except mainthread.Abandoned as e:
            outcome.append(e)

    worker = threading.Thread(target=render_thread)
    worker.start()
    worker.join(5.0)
    assert not worker.is_alive(), "the render thread waited for the main thread for good"
    assert outcome and not ran


def _lit_floor():
    """A rough grey floor seen from above by a camera beside the lights' spot, no world."""
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    floor = bpy.data.meshes.new("floor")
    floor.from_pydata([(-5, -5, 0), (5, -5, 0), (5, 5, 0), (-5, 5, 0)], [], [(0, 1, 2, 3)])
    grey = room.use_nodes(bpy.data.materials.new("grey"))
    bsdf = grey.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (0.5, 0.5, 0.5, 1.0)
    bsdf.inputs["Roughness"].default_value = 1.0
    floor.materials.append(grey)
    scene.collection.objects.link(bpy.data.objects.new("floor", floor))
    camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    camera.location, camera.data.lens = (1.0, 0.0, 3.0), 50  # looks down beside the lights
    scene.collection.objects.link(camera)
    scene.camera = camera
    scene.render.resolution_x = scene.render.resolution_y = 32
    scene.render.resolution_percentage = 100
    return scene


def _add_light(scene, kind, location, energy, colour, **settings):
    light = bpy.data.lights.new(kind.lower(), kind)
    light.energy, light.color = energy, colour
    for key, value in settings.items():
        setattr(light, key, value)
    obj = bpy.data.objects.new(kind.lower(), light)
    obj.location = location  # pointing down (-Z), as new lights do
    scene.collection.objects.link(obj)


def _fenestra_over_cycles(scene, workdir, name):
    """Each channel's mean, fenestra's over Cycles', direct light only (the lights' units,
    not the materials')."""
    scene.render.engine = "CYCLES"
    scene.cycles.samples, scene.cycles.max_bounces, scene.cycles.use_denoising = 512, 0, False
    cycles = render(scene, workdir / f"{name}-cycles.exr")
    scene.render.engine = "FENESTRA"
    scene.fenestra.integrator, scene.fenestra.samples, scene.fenestra.max_depth = "af_hf", 512, 2
    ours = render(scene, workdir / f"{name}-fenestra.exr")
    assert cycles.max() < 50, "a light is in view: the test's setup is off"
    assert cycles.mean() > 0.05, "Cycles sees no light: the test's setup is off"
    return ours.mean(axis=(0, 1)) / cycles.mean(axis=(0, 1))


def test_area_lights_light_a_floor_as_cycles_lights_it(workdir):
    # glTF has no area lights: the add-on adds each as an emitting polygon (colour x power /
    # (pi x area), facing the light's -Z). A warm rectangle and a blue disk, out of view
    # (Cycles hides lights from camera rays by default; fenestra's polygons are seen).
    scene = _lit_floor()
    _add_light(
        scene,
        "AREA",
        (0.0, 0.4, 1.0),
        100.0,
        (1.0, 0.8, 0.5),
        size=0.5,
        size_y=0.25,
        shape="RECTANGLE",
    )
    _add_light(scene, "AREA", (0.0, -0.6, 0.8), 40.0, (0.6, 0.8, 1.0), size=0.5, shape="DISK")
    ratio = _fenestra_over_cycles(scene, workdir, "area")
    assert np.all(np.abs(ratio - 1) < 0.02), f"fenestra/Cycles per channel: {ratio}"


@pytest.mark.parametrize(
    "kind, energy, settings, tolerance",
    [
        ("POINT", 100.0, {}, 0.02),
        ("SUN", 3.0, {}, 0.02),
        # Measured 3.3% dark: the cone's soft edge (spot_blend) reaches glTF as an inner
        # cone angle, and the two renderers fade between the cones by other curves.
        ("SPOT", 100.0, {"spot_size": math.radians(90)}, 0.05),
    ],
)
def test_lamps_light_a_floor_as_cycles_lights_it(workdir, kind, energy, settings, tolerance):
    # Point, spot and sun lamps go through glTF's KHR_lights_punctual in physical units
    # (W -> lm at 683 lm/W, which fenestra reads back).
    scene = _lit_floor()
    _add_light(scene, kind, (0.0, 0.0, 1.5), energy, (1.0, 0.8, 0.6), **settings)
    ratio = _fenestra_over_cycles(scene, workdir, kind.lower())
    assert np.all(np.abs(ratio - 1) < tolerance), f"fenestra/Cycles per channel: {ratio}"


@pytest.mark.parametrize("base, roughness", [(0.8, 0.2), (0.8, 0.5), (0.5, 1.0)])
def test_principled_dielectrics_reflect_as_in_cycles(workdir, base, roughness):
    # The Principled BSDF reaches fenestra as glTF's metallic-roughness material: a floor of
    # it under a white area light, direct light only, within 2% of Cycles (measured 0.998-1.001).
    scene = _lit_floor()
    bsdf = bpy.data.materials["grey"].node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (base, base, base, 1.0)
    bsdf.inputs["Roughness"].default_value = roughness
    _add_light(scene, "AREA", (0.0, 0.4, 1.0), 100.0, (1.0, 1.0, 1.0), size=0.5)
    ratio = _fenestra_over_cycles(scene, workdir, f"principled-{base}-{roughness}")
    assert np.all(np.abs(ratio - 1) < 0.02), f"fenestra/Cycles per channel: {ratio}"


def test_the_zip_installs_as_a_blender_4_2_extension_too(tmp_path):
    # Blender 4.2+ installs add-ons as extensions (the zip's blender_manifest.toml), under
    # a dotted module name: in a process of its own, so as not to register fenestra twice.
    import os
    import sys

    zip_path = tmp_path / "fenestra.zip"
    subprocess.run(
        [str(conftest_repo() / "scripts/blender-addon-zip"), str(zip_path)],
        check=True,
        capture_output=True,
    )
    script = f"""
import bpy
result = bpy.ops.extensions.package_install_files(
    filepath={str(zip_path)!r}, repo="user_default", enable_on_install=True)
assert result == {{"FINISHED"}}, result
assert "bl_ext.user_default.fenestra" in bpy.context.preferences.addons.keys()
bpy.context.scene.render.engine = "FENESTRA"
print("installed as an extension")
"""
    env = dict(os.environ, BLENDER_USER_RESOURCES=str(tmp_path / "user"))
    out = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True)
    assert "installed as an extension" in out.stdout, out.stdout + out.stderr


def conftest_repo():
    import conftest

    return conftest.REPO


def test_what_gltf_cannot_carry_of_a_material_is_said(workdir):
    from fenestra import materials

    scene = room.build()
    white = bpy.data.materials["white wall"]
    nodes, links = white.node_tree.nodes, white.node_tree.links
    principled = nodes["Principled BSDF"]
    noise = nodes.new("ShaderNodeTexNoise")
    links.new(noise.outputs["Color"], principled.inputs["Base Color"])
    output = next(n for n in nodes if n.type == "OUTPUT_MATERIAL")
    displacement = nodes.new("ShaderNodeDisplacement")
    links.new(displacement.outputs[0], output.inputs["Displacement"])
    glass = bpy.data.materials["glass"]
    image = glass.node_tree.nodes.new("ShaderNodeTexImage")
    image.image = bpy.data.images.new("paint", 4, 4)
    glass.node_tree.links.new(
        image.outputs["Color"], glass.node_tree.nodes["Principled BSDF"].inputs["Base Color"]
    )
    metal = bpy.data.materials["glossy metal"]
    diffuse = metal.node_tree.nodes.new("ShaderNodeBsdfDiffuse")
    metal_out = next(n for n in metal.node_tree.nodes if n.type == "OUTPUT_MATERIAL")
    metal.node_tree.links.new(diffuse.outputs[0], metal_out.inputs["Surface"])
    # An image whose file went away: the exporter leaves it out without a word.
    gone = workdir / "gone.png"
    made = bpy.data.images.new("made", 4, 4)
    made.filepath_raw, made.file_format = str(gone), "PNG"
    made.save()
    texture = nodes.new("ShaderNodeTexImage")
    texture.image = bpy.data.images.load(str(gone))
    links.new(texture.outputs["Color"], principled.inputs["Roughness"])
    gone.unlink()
    said = materials.notes(scene)
    missing = "white wall: its Roughness image gone.png"
    assert any(missing in n and "is missing" in n for n in said), said
    assert any("white wall: its Base Color comes through Noise Texture" in n for n in said), said
    assert any("white wall: its displacement is not carried" in n for n in said), said
    assert any("glossy metal: its surface is a Diffuse BSDF node" in n for n in said), said
    assert not any(n.startswith("material glass") for n in said), "an image texture is carried"


def test_a_kept_folder_shows_the_new_renders_snapshots(workdir, monkeypatch):
    # A kept folder holds the last complete render; fenestra never overwrites a complete
    # render with a partial one, so unless the engine clears the folder the new render's
    # snapshots go beside it and the Render window shows nothing until the end.
    scene = room.build(samples=4)
    scene.fenestra.integrator = "af_hf"
    scene.fenestra.keep_files = str(workdir / "kept")
    # The user's own files in the chosen folder are not the add-on's to clear.
    (workdir / "kept").mkdir()
    (workdir / "kept" / "render.png").write_bytes(b"the user's")
    render(scene, workdir / "first.exr")
    scene.fenestra.samples, scene.fenestra.time_limit = 1_000_000, 3.0
    shown = []
    show = fenestra_engine.FenestraRenderEngine._show_snapshot

    def counting(self, result, output, last):
        new = show(self, result, output, last)
        if new != last:
            shown.append(new)
        return new

    monkeypatch.setattr(fenestra_engine.FenestraRenderEngine, "_show_snapshot", counting)
    render(scene, workdir / "second.exr")
    assert len(shown) >= 2, f"{len(shown)} images shown during a 3 s render refreshed every 0.2 s"
    assert (workdir / "kept" / "render.png").read_bytes() == b"the user's"


def test_an_area_light_that_emits_nothing_is_left_out_and_said(workdir):
    from fenestra import area_lights

    scene = room.build(samples=1)
    scene.fenestra.keep_files = str(workdir / "kept")
    render(scene, workdir / "one.exr")
    glb_file = kept(scene) / "scene.glb"
    before = glb_file.read_bytes()
    light = bpy.data.lights.new("dark", "AREA")
    light.energy = 0.0
    scene.collection.objects.link(bpy.data.objects.new("dark", light))
    notes = area_lights.append_to_glb(str(glb_file), scene.objects)
    assert any("area light dark emits nothing" in n for n in notes), notes
    assert glb_file.read_bytes() == before


def test_the_settings_are_the_binarys_integrators_and_options(fenestra_bin):
    import json

    from fenestra import properties

    listed = json.loads(
        subprocess.run([fenestra_bin, "list", "--json"], capture_output=True, check=True).stdout
    )
    scene = bpy.context.scene
    offered = [i[0] for i in properties._integrators(scene.fenestra, bpy.context)]
    assert sorted(offered) == sorted(e["name"] for e in listed["integrators"])
    # The add-on's starting integrator first (a new scene's), the binary's default selection.
    assert offered[0] == properties.START_INTEGRATOR
    selections = [i[0] for i in properties._light_selections(scene.fenestra, bpy.context)]
    assert sorted(selections) == sorted(e["name"] for e in listed["light_samplers"])
    assert selections[0] == "auto"
    # Each integrator gets the flags of the option groups it reads, and no others.
    for entry in listed["integrators"]:
        scene.fenestra.integrator = entry["name"]
        flags = properties.render_flags(scene.fenestra)
        assert ("--max-depth" in flags) == ("path" in entry["groups"]), entry
        assert ("--light-selection" in flags) == ("light" in entry["groups"]), entry
        light_paths = "light_paths" in entry["groups"]
        assert ("--light-paths-per-sample" in flags) == light_paths, entry
    per_sample = next(o for o in listed["options"] if o["key"] == "light_paths.per_sample")
    assert scene.fenestra.light_paths_per_sample == per_sample["default"]
    scene.fenestra.integrator = properties.START_INTEGRATOR


def test_a_keep_files_folder_that_cannot_be_made_is_reported(workdir):
    """A regular file where the folder should be: the render fails with the engine's error,
    and Blender lives (an exception escaping the engine's render crashed bpy)."""
    blocker = workdir / "a-file"
    blocker.write_text("not a folder")
    scene = room.build(samples=1)
    scene.fenestra.keep_files = str(blocker)
    scene.render.filepath = str(workdir / "never.exr")
    with pytest.raises(RuntimeError, match="fenestra: cannot make the Keep Files folder .*a-file"):
        bpy.ops.render.render(write_still=False)
    assert blocker.read_text() == "not a folder"
