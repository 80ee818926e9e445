"""The render settings a scene keeps for fenestra (Render Properties panel), and the flags
of `fenestra render` they become. The integrators, light selections and which integrator
reads which options come from the binary (`catalogue`)."""

import bpy

from . import catalogue

# The integrator the add-on starts with (any of the binary's; its list comes from the binary).
START_INTEGRATOR = "lp_hf"


def _integrators(self, context):
    return catalogue.enum_items("integrators", first=START_INTEGRATOR)


def _light_selections(self, context):
    return catalogue.enum_items("light_samplers", first=catalogue.default("light.selection"))


PORTALS = [
    ("auto", "Automatic", "Estimate the portals from the scene (cached between renders)"),
    ("scene", "Scene", "The scene's Cycles portal lights"),
]


class FenestraRenderSettings(bpy.types.PropertyGroup):
    integrator: bpy.props.EnumProperty(name="Integrator", items=_integrators)
    samples: bpy.props.IntProperty(
        name="Samples", description="Samples per pixel", default=64, min=1, soft_max=16384
    )
    time_limit: bpy.props.FloatProperty(
        name="Time Limit",
        description="Render for this many seconds (0: until the samples are taken; with both, "
        "whichever comes first)",
        default=0.0,
        min=0.0,
        unit="TIME_ABSOLUTE",
    )
    max_depth: bpy.props.IntProperty(
        name="Path Length",
        description="Longest path in segments from the camera (2 = direct light only)",
        default=8,
        min=2,
        max=1024,
    )
    portals: bpy.props.EnumProperty(name="Portals", items=PORTALS, default="auto")
    # The binary's default (`light_paths.per_sample`; the add-on's tests hold them equal).
    light_paths_per_sample: bpy.props.FloatProperty(
        name="Light Paths",
        description="Light paths from the sun through the portals per camera sample, joined "
        "to the camera paths by MIS (lp_lt): they carry the sun's glints off glossy surfaces",
        default=0.25,
        min=0.0,
        max=16.0,
        soft_max=2.0,
    )
    light_selection: bpy.props.EnumProperty(name="Light Selection", items=_light_selections)
    seed: bpy.props.IntProperty(name="Seed", default=0, min=0)
    threads: bpy.props.IntProperty(
        name="Threads", description="Worker threads (0: all cores)", default=0, min=0
    )
    snapshot_every: bpy.props.FloatProperty(
        name="Refresh",
        description="Show the image so far at most this often (seconds)",
        default=1.0,
        min=0.1,
        unit="TIME_ABSOLUTE",
    )
    denoise: bpy.props.BoolProperty(
        name="Denoise",
        description="Show Intel Open Image Denoise's result (guided by fenestra's albedo and "
        "normal) as the Combined pass, snapshots too; the raw estimate goes to the Noisy "
        "Image pass",
        default=False,
    )
    denoise_mode: bpy.props.EnumProperty(
        name="Prefilter",
        items=(
            ("accurate", "Accurate", "Denoise the albedo and normal first (Cycles' default)"),
            ("fast", "Fast", "Use the albedo and normal as they are"),
        ),
        default="accurate",
    )
    denoising_data: bpy.props.BoolProperty(
        name="Denoising Data",
        description="Fill the Denoising Albedo and Denoising Normal passes (for the "
        "compositor's Denoise node)",
        default=False,
    )
    variance_pass: bpy.props.BoolProperty(
        name="Variance Pass",
        description="Add a Variance pass: the per-pixel variance of the mean",
        default=False,
    )
    reference: bpy.props.StringProperty(
        name="Reference",
        description="A reference image (EXR of the same size): fenestra then measures the "
        "render's error after every pass and writes an HTML report",
        subtype="FILE_PATH",
        default="",
    )
    keep_files: bpy.props.StringProperty(
        name="Keep Files",
        description="A folder to keep the exported scene, fenestra's images and its log in, "
        "in a folder fenestra-SCENE of the add-on's own (empty: a temporary folder, removed "
        "after the render)",
        subtype="DIR_PATH",
        default="",
    )
    last_report: bpy.props.StringProperty(
        name="Last Report", description="The HTML report of the last render", default=""
    )


def render_flags(settings):
    """The `fenestra render` flags the settings stand for (without scene, camera and world)."""
    flags = ["--integrator", settings.integrator, "--spp", str(settings.samples)]
    if settings.time_limit > 0:
        flags += ["--time", f"{settings.time_limit:g}"]
    flags += ["--seed", str(settings.seed)]
    if settings.threads > 0:
        flags += ["--threads", str(settings.threads)]
    if catalogue.reads(settings.integrator, "path"):
        flags += ["--max-depth", str(settings.max_depth)]
    if catalogue.reads(settings.integrator, "light"):
        flags += ["--light-selection", settings.light_selection]
    if catalogue.reads(settings.integrator, "light_paths"):
        flags += ["--light-paths-per-sample", f"{settings.light_paths_per_sample:g}"]
    if settings.variance_pass:
        flags.append("--variance")
    if settings.denoise:
        flags += ["--denoise", settings.denoise_mode]
    if settings.denoise or settings.denoising_data:
        # Files of their own: Blender's image loader reads no layers.
        flags += ["--features", "files"]
    return flags


def register():
    bpy.utils.register_class(FenestraRenderSettings)
    bpy.types.Scene.fenestra = bpy.props.PointerProperty(type=FenestraRenderSettings)


def unregister():
    del bpy.types.Scene.fenestra
    bpy.utils.unregister_class(FenestraRenderSettings)
