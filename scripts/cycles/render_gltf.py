"""Renders a glTF scene with Blender's Cycles (bpy from PyPI) under an environment map, as
`scripts/gltf-vs-cycles` compares it with fenestra: Blender's own glTF importer, a box pixel
filter, 7 bounces (fenestra's path length 8), no clamping, no denoising, no adaptive sampling,
the Standard view transform, linear 32-bit EXR out.

    python render_gltf.py -- SCENE.gltf CAMERA ENV.exr WIDTH HEIGHT SPP OUT.exr

Materials that take their metalness from AMD_split_roughnessMetallic's DDS maps get metallic 0,
as fenestra gives them (neither reads the DDS). SINGLE_SCATTER=1 switches the Principled BSDFs
to single-scattering GGX (fenestra's metal is single-scattering). For equal-time runs
(scripts/interiors-vs-cycles): TIME_LIMIT=S renders for S seconds instead of SPP samples;
PORTALS=portals.json adds fenestra's estimated portals as Cycles portal lights (rectangles);
GUIDING=1 turns on Cycles' path guiding (OpenPGL, surfaces); SEED=N seeds its samples.
DENOISE=1 denoises with Open Image Denoise (Cycles' defaults: albedo and normal guides,
accurate prefilter), after the time limit.
SUN=sun.json adds the sun `fenestra scene export --sky` describes as a Sun lamp (its direction,
irradiance and angular diameter); ENV.exr is then that export's sky turned into Blender's
equirectangular convention (scripts/interiors-vs-cycles does it).
"""
import bpy, sys
scene_file, camera, env_file, width, height, spp, out = sys.argv[sys.argv.index('--')+1:]
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=scene_file)
sc = bpy.context.scene
import json
doc = json.load(open(scene_file))
amd = [m.get('name') for m in doc.get('materials', []) if 'metallicTexture' in m.get('extensions', {}).get('AMD_split_roughnessMetallic', {})]
for name in amd:
    m = bpy.data.materials.get(name)
    p = m and next((n for n in m.node_tree.nodes if n.type == 'BSDF_PRINCIPLED'), None)
    if p and not p.inputs['Metallic'].is_linked:
        p.inputs['Metallic'].default_value = 0.0   # as fenestra: the DDS metallic map is not read
print('metallic 0 for', amd)
import os
if os.environ.get('SINGLE_SCATTER'):
    for m in bpy.data.materials:
        for n in (m.node_tree.nodes if m.node_tree else []):
            if n.type == 'BSDF_PRINCIPLED':
                n.distribution = 'GGX'
    print('single-scattering GGX')
cams = [o for o in sc.objects if o.type == 'CAMERA']
cam = next((o for o in cams if o.data.name == camera or o.name == camera), cams[0])
sc.camera = cam
print('camera', cam.name, cam.data.name)
w = bpy.data.worlds.new('sky'); sc.world = w; w.use_nodes = True
nt = w.node_tree; bg = nt.nodes['Background']
env = nt.nodes.new('ShaderNodeTexEnvironment'); env.image = bpy.data.images.load(env_file)
nt.links.new(env.outputs['Color'], bg.inputs['Color']); bg.inputs['Strength'].default_value = 1.0
from mathutils import Matrix, Vector
to_blender = lambda v: Vector((v[0], -v[2], v[1]))   # glTF's y-up axes as the importer turns them
if os.environ.get('SUN'):
    import math
    sun = json.load(open(os.environ['SUN']))['sun']
    e = sun['irradiance']; k = max(e)
    light = bpy.data.lights.new('sun', 'SUN')
    light.energy = k; light.color = [c / k for c in e]; light.angle = math.radians(sun['angle_deg'])
    obj = bpy.data.objects.new('sun', light)
    # A Sun lamp shines along its -Z: its +Z points at the sun.
    obj.rotation_euler = to_blender(sun['direction']).to_track_quat('Z', 'Y').to_euler()
    sc.collection.objects.link(obj)
    print('sun from', os.environ['SUN'], 'irradiance', e)
portals = os.environ.get('PORTALS')
if portals:
    for k, rec in enumerate(json.load(open(portals))['portals']):
        if rec.get('kind') != 'quad':
            continue
        v0, v1, _, v3 = (to_blender(v) for v in rec['vertices'])
        e1, e2 = v1 - v0, v3 - v0
        centre = v0 + 0.5 * (e1 + e2)
        # A portal light emits along its -Z: into the room, towards the camera.
        if e1.cross(e2).dot(cam.location - centre) > 0:
            e1, e2 = e2, e1
        x, y = e1.normalized(), e2.normalized()
        light = bpy.data.lights.new('portal%d' % k, 'AREA')
        light.shape = 'RECTANGLE'; light.size = e1.length; light.size_y = e2.length
        light.cycles.is_portal = True
        obj = bpy.data.objects.new('portal%d' % k, light)
        obj.matrix_world = Matrix.Translation(centre) @ Matrix((x, y, x.cross(y))).transposed().to_4x4()
        sc.collection.objects.link(obj)
    print('portals from', portals)
sc.render.engine = 'CYCLES'; c = sc.cycles
c.device = 'CPU'; c.samples = int(spp); c.use_adaptive_sampling = False; c.use_denoising = False
if os.environ.get('DENOISE'):
    c.use_denoising = True; c.denoiser = 'OPENIMAGEDENOISE'
    c.denoising_input_passes = 'RGB_ALBEDO_NORMAL'; c.denoising_prefilter = 'ACCURATE'
    c.denoising_use_gpu = False
c.seed = int(os.environ.get('SEED', '0'))
if os.environ.get('TIME_LIMIT'):
    c.time_limit = float(os.environ['TIME_LIMIT']); c.samples = 1 << 24
if os.environ.get('GUIDING'):
    c.use_guiding = True; c.use_surface_guiding = True; c.use_volume_guiding = False
c.max_bounces = 7; c.diffuse_bounces = 7; c.glossy_bounces = 7; c.transmission_bounces = 7
c.transparent_max_bounces = 64; c.sample_clamp_direct = 0; c.sample_clamp_indirect = 0
c.caustics_reflective = True; c.caustics_refractive = True; c.blur_glossy = 0.0
c.pixel_filter_type = 'BOX'; c.filter_width = 1.0
sc.render.resolution_x = int(width); sc.render.resolution_y = int(height); sc.render.resolution_percentage = 100
sc.view_settings.view_transform = 'Standard'; sc.view_settings.exposure = 0.0; sc.view_settings.look = 'None'
sc.render.image_settings.file_format = 'OPEN_EXR'; sc.render.image_settings.color_depth = '32'
sc.render.filepath = out
bpy.ops.render.render(write_still=True)
