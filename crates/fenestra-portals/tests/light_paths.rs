//! Light paths from the sun through the portals (lt) must render what af_hf renders of the
//! sun's light: the glossy room without its sky (Ward floor, GGX metals: the glint paths)
//! at several path lengths, over the image and its 8x8 regions; and the same pixels for any
//! thread count. Joined to lp_hf by MIS (lp_lt), with the sky or without, from a sun that is
//! a direction or a disk (which BSDF sampling finds too), they must render what af_hf
//! renders: weights that the two sides compute differently would not sum to 1.

use fenestra_builtin as builtin;
use fenestra_core::Vec3;
use fenestra_portals::lp_lt::{LightPathOptions, LpLt};
use fenestra_portals::lt::Lt;
use fenestra_portals::{lp_hf, PortalOptions, PortalSource, Portals};
use fenestra_render::integrator::{af_hf, LightNextEvent, PathOptions};
use fenestra_render::light::LightSelection;
use fenestra_render::{render_image, Film, Integrator, RenderScene, RenderSettings};
use fenestra_scene::light::{EnvironmentDesc, LightDesc};
use fenestra_scene::{Backend, Scene, SceneDesc};

const SIZE: u32 = 32;

/// The glossy room lit by its sun alone.
fn sunlit_room() -> SceneDesc {
    let mut desc = builtin::load("glossy-room").expect("builtin");
    desc.lights
        .retain(|l| !matches!(l, LightDesc::Environment(_)));
    desc
}

/// The glossy room lit by a disk of angular radius `half_angle` in its sun's place, of the
/// same irradiance (the sky's sun is such a disk), with its sky or without: BSDF sampling
/// of the glossy floor and metals finds a disk some degrees wide about as often as light
/// sampling does.
fn disk_lit_room(half_angle: f32, sky: bool) -> SceneDesc {
    let mut desc = builtin::load("glossy-room").expect("builtin");
    desc.lights
        .retain(|l| sky || !matches!(l, LightDesc::Environment(_)));
    for light in &mut desc.lights {
        if let LightDesc::Distant {
            direction,
            irradiance,
        } = *light
        {
            let solid_angle = 2.0 * std::f32::consts::PI * (1.0 - half_angle.cos());
            *light = LightDesc::Environment(EnvironmentDesc::Sun {
                direction: -direction,
                radiance: irradiance / solid_angle,
                half_angle,
            });
        }
    }
    desc
}

/// The room's window (2 x 1.4 m in the wall y = 0), a little larger: lines through the wall
/// beside it only meet the wall's outside.
fn window() -> PortalSource {
    portal(1.1)
}

/// The window scaled by `scale` about its centre.
fn portal(scale: f32) -> PortalSource {
    let (c, h) = (Vec3::new(2.5, 0.0, 1.5), Vec3::new(1.0, 0.0, 0.7) * scale);
    PortalSource::Given(Portals::from_quads(&[[
        Vec3::new(c.x - h.x, 0.0, c.z - h.z),
        Vec3::new(c.x + h.x, 0.0, c.z - h.z),
        Vec3::new(c.x + h.x, 0.0, c.z + h.z),
        Vec3::new(c.x - h.x, 0.0, c.z + h.z),
    ]]))
}

fn render(integrator: &mut dyn Integrator, spp: u32, threads: usize) -> Film {
    render_in(sunlit_room(), SIZE, integrator, spp, threads)
}

fn render_in(
    desc: SceneDesc,
    size: u32,
    integrator: &mut dyn Integrator,
    spp: u32,
    threads: usize,
) -> Film {
    let scene = RenderScene::new(Scene::build(desc, Backend::default()).expect("scene"));
    let settings = RenderSettings {
        first_sample: 0,
        spp,
        time_limit: None,
        seed: 5,
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("pool");
    pool.install(|| render_image(integrator, &scene, size, size, &settings))
        .expect("render")
        .0
}

fn path(depth: u32) -> PathOptions {
    PathOptions {
        max_depth: depth,
        ..PathOptions::default()
    }
}

#[test]
fn light_paths_render_what_path_tracing_renders_of_the_sun() {
    for (depth, spp_af, spp_lt) in [(2, 512, 1024), (3, 1024, 2048), (5, 2048, 2048)] {
        let af = render(&mut af_hf(path(depth), LightSelection::Power), spp_af, 2);
        let lt = render(&mut Lt::new(path(depth), window()), spp_lt, 2);
        let mean = |f: &Film| {
            f.image()
                .pixels
                .iter()
                .map(|p| p.luminance() as f64)
                .sum::<f64>()
        };
        let t = fenestra_eval::agreement(&af.estimate(), &lt.estimate(), 0.01, 8).expect("sizes");
        assert!(
            t.passed(),
            "path length {depth}: lt/af_hf {:.4}: {t:?}",
            mean(&lt) / mean(&af)
        );
        assert!(lt.light_paths == (SIZE * SIZE * spp_lt) as u64);
    }
    // From a disk, whose lines cross the window in a cone of directions.
    let disk = || disk_lit_room(0.05, false);
    let af = af_hf(path(3), LightSelection::Power);
    let af = render_in(disk(), SIZE, &mut { af }, 1024, 2);
    let lt = render_in(disk(), SIZE, &mut Lt::new(path(3), window()), 2048, 2);
    let t = fenestra_eval::agreement(&af.estimate(), &lt.estimate(), 0.01, 8).expect("sizes");
    assert!(t.passed(), "a disk: {t:?}");
    // The test sees light missing: a portal of 0.9 times the window leaves a tenth of its
    // edges' sunlight out.
    let af = render(&mut af_hf(path(2), LightSelection::Power), 512, 2);
    let lt = render(&mut Lt::new(path(2), portal(0.9)), 1024, 2);
    let t = fenestra_eval::agreement(&af.estimate(), &lt.estimate(), 0.01, 8).expect("sizes");
    assert!(!t.passed(), "a small portal: {t:?}");
}

/// Pilot light paths that learn where on the portals light paths start.
const PILOT: u32 = 32768;

/// lp_hf through the window (kept: the sky's paths sample it) joined to light paths.
fn lp_lt(depth: u32, per_sample: f32) -> LpLt {
    lp_lt_piloted(depth, per_sample, 0)
}

/// lp_hf through the window joined to light paths whose emission a pilot of `pilot` paths
/// learns (0: uniform).
fn lp_lt_piloted(depth: u32, per_sample: f32, pilot: u32) -> LpLt {
    let portals = PortalOptions {
        keep: true,
        ..PortalOptions::default()
    };
    let lights = LightNextEvent::new(LightSelection::Power);
    let camera = lp_hf(path(depth), portals, window(), lights).expect("lp_hf");
    let trial = 0; // light paths always: what they render is under test
    let options = LightPathOptions {
        per_sample,
        pilot,
        trial,
    };
    LpLt::new(camera, options).expect("lp_lt")
}

/// At path length 5 the ceiling's light comes by glints that af_hf finds rarely (its
/// estimate is heavy-tailed: at 2048 spp a region read 5% low with a third of its spread),
/// so that case takes 4x the samples per pixel on a smaller image.
#[test]
fn joined_light_paths_render_what_path_tracing_renders() {
    let with_sky = || builtin::load("glossy-room").expect("builtin");
    // (sky, the sun a disk, path length, image size, samples per pixel of af_hf and lp_lt,
    // pilot paths learning the emission: 0 for uniform)
    for (sky, disk, depth, size, spp_af, spp_lp, pilot) in [
        (false, false, 3, 32, 1024, 512, 0),
        (false, false, 5, 16, 8192, 2048, PILOT),
        (true, false, 4, 32, 2048, 1024, 0),
        (false, true, 3, 32, 1024, 512, PILOT),
        (true, true, 4, 32, 2048, 1024, 0),
    ] {
        let desc = || match (sky, disk) {
            (_, true) => disk_lit_room(0.15, sky),
            (true, false) => with_sky(),
            (false, false) => sunlit_room(),
        };
        let af = af_hf(path(depth), LightSelection::Power);
        let af = render_in(desc(), size, &mut { af }, spp_af, 2);
        let lp = lp_lt_piloted(depth, 0.5, pilot);
        let lp = render_in(desc(), size, &mut { lp }, spp_lp, 2);
        let t = fenestra_eval::agreement(&af.estimate(), &lp.estimate(), 0.01, 8).expect("sizes");
        assert!(
            t.passed(),
            "sky {sky}, disk {disk}, path length {depth}, pilot {pilot}: {t:?}"
        );
        assert_eq!(lp.light_paths, (size * size * spp_lp / 2) as u64);
    }
}

#[test]
fn light_paths_splat_the_same_pixels_for_any_thread_count() {
    let one = render(&mut Lt::new(path(4), window()), 8, 1);
    let two = render(&mut Lt::new(path(4), window()), 8, 2);
    assert_eq!(one.splats, two.splats);
    assert!(
        one.splats.iter().any(|p| p.sum != [0; 3]),
        "the sun is seen"
    );
    let one = render(&mut lp_lt_piloted(4, 1.5, PILOT), 4, 1);
    let two = render(&mut lp_lt_piloted(4, 1.5, PILOT), 4, 2);
    assert_eq!(one.splats, two.splats);
    assert_eq!(one.pixels, two.pixels);
}

/// Light paths start at the portals: where these miss the sunlight the camera sees (a portal
/// in the window's wall beside the window), lp_lt traces none and renders as lp_hf.
#[test]
fn no_light_paths_where_the_portals_miss_the_sunlight_the_camera_sees() {
    let beside = PortalSource::Given(Portals::from_quads(&[[
        Vec3::new(0.2, 0.0, 0.8),
        Vec3::new(1.2, 0.0, 0.8),
        Vec3::new(1.2, 0.0, 2.2),
        Vec3::new(0.2, 0.0, 2.2),
    ]]));
    let portals = PortalOptions {
        keep: true,
        ..PortalOptions::default()
    };
    let lights = LightNextEvent::new(LightSelection::Power);
    let camera = lp_hf(path(4), portals, beside, lights).expect("lp_hf");
    let mut beside = LpLt::new(
        camera,
        LightPathOptions {
            per_sample: 1.0,
            ..LightPathOptions::default()
        },
    )
    .expect("lp_lt");
    assert_eq!(render(&mut beside, 4, 2).light_paths, 0);
    assert_eq!(render(&mut lp_lt(4, 1.0), 4, 2).light_paths, 32 * 32 * 4);
}

#[test]
fn light_paths_need_portals_and_a_sun() {
    let settings = RenderSettings {
        first_sample: 0,
        spp: 1,
        time_limit: None,
        seed: 1,
    };
    let error = |desc: SceneDesc| {
        let scene = RenderScene::new(Scene::build(desc, Backend::default()).expect("scene"));
        let mut lt = Lt::new(path(3), PortalSource::Scene);
        match render_image(&mut lt, &scene, 8, 8, &settings) {
            Ok(_) => panic!("rendered"),
            Err(e) => e.to_string(),
        }
    };
    // The glossy room's window is no portal of the scene's own.
    assert_eq!(
        error(sunlit_room()),
        "lt needs light portals and the scene has none"
    );
    // The box's hole is, but a panel lights it, not a sun.
    let box_hole = builtin::load("box-hole").expect("builtin");
    assert!(error(box_hole).contains("no sun"), "a sun is asked for");
}

/// lp_lt with its trial (the default options) through the window, without the sky.
fn lp_lt_tried(depth: u32) -> LpLt {
    let portals = PortalOptions {
        keep: true,
        ..PortalOptions::default()
    };
    let lights = LightNextEvent::new(LightSelection::Power);
    let camera = lp_hf(path(depth), portals, window(), lights).expect("lp_lt");
    LpLt::new(camera, LightPathOptions::default()).expect("lp_lt")
}

/// The trial traces light paths where the sun's glints off the Ward floor and the metals
/// light the room, and where its bounce off the sunlit floor of an all-diffuse room does
/// (which camera paths find by BSDF sampling alone); none in a dark room (every surface's
/// albedo 0.05), whose sunlit floor the camera sees lit straight, which is the path
/// tracer's alone, and whose bounce is too faint to pay for light paths.
#[test]
fn the_trial_traces_light_paths_only_where_they_pay() {
    let diffuse = |albedo: f32| {
        let mut desc = sunlit_room();
        for m in &mut desc.materials {
            *m = fenestra_scene::Material::diffuse(albedo);
        }
        desc
    };
    let gain = |desc: SceneDesc| {
        let mut lp = lp_lt_tried(8);
        let film = render_in(desc, 48, &mut lp, 1, 2);
        let gain = lp.trial_gain().expect("a trial ran");
        (gain, film.light_paths)
    };
    for (room, desc, pays) in [
        ("glossy", sunlit_room(), true),
        ("diffuse", diffuse(0.6), true),
        ("dark", diffuse(0.05), false),
    ] {
        let (gain, traced) = gain(desc);
        eprintln!("{room}: {gain:.3}x");
        assert_eq!(gain > 1.0, pays, "{room}: {gain:.3}x");
        assert_eq!(traced > 0, pays, "{room}: {traced} light paths");
    }
}

/// Fewer samples per pixel than 1 / k still trace k light paths per sample on average (a
/// pixel's own offset spreads them), so a 1-spp preview keeps the light MIS hands to them.
#[test]
fn renders_of_few_samples_trace_their_share_of_light_paths() {
    for (spp, per_sample) in [(1, 0.25), (3, 0.25), (1, 0.1)] {
        let film = render(&mut lp_lt(4, per_sample), spp, 2);
        let expected = f64::from(SIZE * SIZE * spp) * f64::from(per_sample);
        let traced = film.light_paths as f64;
        assert!(
            (traced - expected).abs() < 4.0 * expected.sqrt(),
            "{spp} spp, {per_sample} per sample: {traced} light paths, {expected} expected"
        );
    }
}
