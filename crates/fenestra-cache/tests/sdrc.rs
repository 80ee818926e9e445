//! The sdrc integrator against af_hf: as the interpolation errors a go to 0 every shading
//! point gets its own records and the caches' answer must become af_hf's; the irradiance
//! cache in a furnace gives the analytic radiance, and SH radiance caching there agrees with
//! path tracing; renders do not depend on the thread
//! count; bad options are refused.

use fenestra_cache::{CacheOrPath, LambertianLobe, Sdrc, SdrcOptions, ShrcOptions};
use fenestra_core::stats::RenderStats;
use fenestra_core::{Rgb, Vec3};
use fenestra_eval::ztest::agreement;
use fenestra_render::integrator::{af_hf, Integrator, LightNextEvent, PathOptions};
use fenestra_render::light::LightSelection;
use fenestra_render::{render_image, Film, RenderScene, RenderSettings};
use fenestra_scene::light::Emission;
use fenestra_scene::material;
use fenestra_scene::{
    Backend, Camera, Material, RenderDefaults, Scene, SceneDesc, Shape, ShapeKind, TriangleMesh,
};

fn teapot_box() -> RenderScene {
    let desc = fenestra_builtin::load("teapot-box").expect("built-in scene");
    RenderScene::new(Scene::build(desc, Backend::Obvhs).expect("scene"))
}

fn path() -> PathOptions {
    PathOptions {
        max_depth: 4,
        ..Default::default()
    }
}

fn sdrc(options: SdrcOptions) -> Sdrc {
    Sdrc::new(options, path(), LightNextEvent::new(LightSelection::Power)).expect("options")
}

fn render(
    integrator: &mut dyn Integrator,
    scene: &RenderScene,
    size: u32,
    spp: u32,
    seed: u64,
) -> Film {
    let settings = RenderSettings {
        spp,
        first_sample: 0,
        time_limit: None,
        seed,
    };
    render_image(integrator, scene, size, size, &settings)
        .expect("render")
        .0
}

#[test]
fn with_a_vanishing_error_the_cache_gives_af_hf_answer() {
    let scene = teapot_box();
    let reference = render(
        &mut af_hf(path(), LightSelection::Power),
        &scene,
        32,
        256,
        2,
    );
    // The kettle's Ward BSDF whole in SDRC, its Lambertian lobe apart in the irradiance
    // cache, and the kettle path traced (the seed's Monte Carlo baseline): only the walls
    // are served then.
    let mut served_pixels = Vec::new();
    for (lambertian_lobe, glossy) in [
        (LambertianLobe::Glossy, CacheOrPath::Cache),
        (LambertianLobe::Cache, CacheOrPath::Cache),
        (LambertianLobe::Glossy, CacheOrPath::Path),
    ] {
        let mut cache = sdrc(SdrcOptions {
            a: 1e-3,
            irradiance_a: 1e-3,
            min_reach: 0.0,
            n: 64,
            irradiance_rays: 16,
            lambertian_lobe,
            glossy,
            ..Default::default()
        });
        let film = render(&mut cache, &scene, 32, 16, 1);
        let cached = cache
            .work_maps()
            .into_iter()
            .find(|m| m.name == "cached")
            .expect("cached map");
        let served = cached.values.iter().filter(|&&v| v > 0.0).count();
        served_pixels.push(served);
        assert!(served > 100, "the caches served {served} pixels");
        let agree = agreement(&film.estimate(), &reference.estimate(), 0.01, 8).expect("same size");
        assert!(
            agree.passed(),
            "lambertian lobe {lambertian_lobe}, glossy {glossy}: {agree:#?}"
        );
    }
    assert!(
        served_pixels[2] + 50 < served_pixels[0],
        "with the kettle path traced, fewer pixels are served: {served_pixels:?}"
    );
}

/// A closed box whose diffuse walls (albedo `albedo`) all emit radiance 1; with a glossy
/// (Phong) panel in its middle facing the camera if `panel`.
fn furnace(albedo: f32, panel: bool) -> RenderScene {
    let wall = |c: Vec3, u: Vec3, v: Vec3| {
        Shape::new(ShapeKind::Mesh(TriangleMesh::quad(c, u, v)), 0).emitting(Emission {
            radiance: Rgb::ONE,
            two_sided: true,
        })
    };
    let (x, y, z) = (Vec3::X, Vec3::Y, Vec3::Z);
    let mut shapes = vec![
        wall(-x, y, z),
        wall(x, y, z),
        wall(-y, x, z),
        wall(y, x, z),
        wall(-z, x, y),
        wall(z, x, y),
    ];
    if panel {
        // Facing the camera: its normal (u x v) points to -x -y.
        let (u, v) = ((x - y) * 0.25, z * 0.25);
        let quad = TriangleMesh::quad(Vec3::new(0.2, 0.3, -0.05), v, u);
        shapes.push(Shape::new(ShapeKind::Mesh(quad), 1));
    }
    let desc = SceneDesc {
        name: "furnace".into(),
        shapes,
        materials: vec![
            Material::diffuse(albedo),
            Material::Phong(material::Phong {
                diffuse: Rgb::splat(0.1),
                specular: Rgb::splat(0.7),
                exponent: 20.0,
            }),
        ],
        lights: Vec::new(),
        camera: Camera::look_at(
            Vec3::new(-0.5, -0.6, 0.2),
            Vec3::new(1.0, 1.0, -0.3),
            z,
            70.0,
        )
        .expect("camera"),
        defaults: RenderDefaults::default(),
        portals: Vec::new(),
    };
    RenderScene::new(Scene::build(desc, Backend::Obvhs).expect("scene"))
}

#[test]
fn records_resolve_the_same_scene_at_any_image_size() {
    // The reach bounds are in pixels of the view at 256 pixels across: at twice the size
    // the caches hold about as many records (with bounds in the image's own pixels they
    // held 2.04x as many here).
    let scene = teapot_box();
    let records = |size: u32| {
        let settings = RenderSettings {
            spp: 1,
            first_sample: 0,
            time_limit: None,
            seed: 1,
        };
        let mut cache = sdrc(SdrcOptions::default());
        let (_, stats) = render_image(&mut cache, &scene, size, size, &settings).expect("render");
        stats.extra["sdrc_records"] + stats.extra["sdrc_irradiance_records"]
    };
    let (small, large) = (records(256), records(512));
    assert!(
        large < 1.6 * small,
        "{small} records at 256x256, {large} at 512x512"
    );
}

#[test]
fn a_time_budget_the_placement_uses_up_still_renders_a_sample_per_pixel() {
    // On a real interior (Bitterli's classroom at 640x360, --time 20) the placement took
    // longer than the budget and the image came out black.
    let scene = teapot_box();
    let settings = RenderSettings {
        spp: 64,
        first_sample: 0,
        time_limit: Some(1e-9),
        seed: 1,
    };
    let mut cache = sdrc(SdrcOptions::default());
    let (film, stats) = render_image(&mut cache, &scene, 32, 32, &settings).expect("render");
    assert_eq!(stats.spp, 1, "one pass of one sample per pixel");
    let lit = film
        .pixels
        .iter()
        .filter(|p| p.mean().iter().sum::<f64>() > 0.0)
        .count();
    assert!(
        lit > film.pixels.len() / 2,
        "{lit} of {} pixels lit",
        film.pixels.len()
    );
}

/// sdrc with `options` in the furnace of albedo 0.5 at path length 4, 32x32: the integrator,
/// the image, the statistics, and the exact radiance every path sees (1 + rho + ... +
/// rho^(max_depth - 1)).
fn in_furnace(options: SdrcOptions, spp: u32, seed: u64) -> (Sdrc, Film, RenderStats, f32) {
    let (albedo, max_depth) = (0.5f32, 4u32);
    let exact: f32 = (0..max_depth).map(|k| albedo.powi(k as i32)).sum();
    let mut cache = Sdrc::new(
        options,
        PathOptions {
            max_depth,
            ..Default::default()
        },
        LightNextEvent::new(LightSelection::Power),
    )
    .expect("options");
    let settings = RenderSettings {
        spp,
        first_sample: 0,
        time_limit: None,
        seed,
    };
    let scene = furnace(albedo, false);
    let (film, stats) = render_image(&mut cache, &scene, 32, 32, &settings).expect("render");
    (cache, film, stats, exact)
}

#[test]
fn the_irradiance_cache_in_a_furnace_gives_the_analytic_radiance() {
    let options = SdrcOptions {
        irradiance_rays: 1024,
        ..Default::default()
    };
    let (cache, film, _, exact) = in_furnace(options, 16, 3);
    let cached = &cache.work_maps()[1];
    assert!(
        cached.values.iter().all(|&v| v == 1.0),
        "every sample cached"
    );
    let image = film.image();
    let mean = image.mean();
    for c in [mean.r, mean.g, mean.b] {
        assert!((c - exact).abs() < 0.01 * exact, "mean {c}, exact {exact}");
    }
    // Nor anywhere in the image by much: 8x8-pixel regions (path tracing's next-event noise
    // leaves them about 1% off; the translation gradient of noisy radiance, 2%).
    let mut worst = 0.0f32;
    for (bx, by) in (0..4).flat_map(|i| (0..4).map(move |j| (i * 8, j * 8))) {
        let region = image.crop(bx, by, 8, 8).mean();
        worst = worst.max((region.g - exact).abs() / exact);
    }
    assert!(worst < 0.015, "a region {worst} off");
}

#[test]
fn with_a_photon_map_the_furnace_still_gives_the_analytic_radiance() {
    // The records' rays end at the walls in photon-map estimates of the light beyond:
    // photons carry their lights' power, and path lengths stay within the limit.
    let options = SdrcOptions {
        irradiance_rays: 256,
        photons: 100_000,
        ..Default::default()
    };
    let (_, film, stats, exact) = in_furnace(options, 8, 4);
    let stored = stats.extra["sdrc_photons_stored"];
    assert!(stored > 20_000.0, "{stored} photons stored");
    let mean = film.image().mean();
    for c in [mean.r, mean.g, mean.b] {
        assert!((c - exact).abs() < 0.01 * exact, "mean {c}, exact {exact}");
    }
}

#[test]
fn sh_radiance_caching_agrees_with_af_hf_where_incoming_light_is_smooth() {
    // In the furnace the panel's incoming light is nearly uniform, which order-10 SH holds
    // exactly: shrc's glossy panel must agree with path tracing within its noise.
    let scene = furnace(0.5, true);
    let path = PathOptions {
        max_depth: 3,
        ..Default::default()
    };
    let mut shrc = Sdrc::harmonics(
        SdrcOptions::default(),
        ShrcOptions { a: 0.22, rays: 256 },
        path,
        LightNextEvent::new(LightSelection::Power),
    )
    .expect("options");
    let settings = RenderSettings {
        spp: 16,
        first_sample: 0,
        time_limit: None,
        seed: 7,
    };
    let (film, stats) = render_image(&mut shrc, &scene, 32, 32, &settings).expect("render");
    let records = stats.extra["shrc_records"];
    assert!(records >= 4.0, "{records} SH records");
    let reference = render(&mut af_hf(path, LightSelection::Power), &scene, 32, 256, 8);
    let agree = agreement(&film.estimate(), &reference.estimate(), 0.01, 8).expect("same size");
    assert!(agree.passed(), "{agree:#?}");
}

#[test]
fn renders_do_not_depend_on_the_thread_count() {
    let scene = teapot_box();
    let image = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool");
        pool.install(|| {
            let mut cache = sdrc(SdrcOptions {
                n: 32,
                ..Default::default()
            });
            render(&mut cache, &scene, 24, 4, 5).image().pixels
        })
    };
    let one = image(1);
    assert!(one.iter().any(|p| p.r > 0.0));
    assert!(one == image(2), "1 and 2 threads differ");
}

#[test]
fn bad_options_are_refused_with_the_option_named() {
    let refused = |options: SdrcOptions| match Sdrc::new(
        options,
        path(),
        LightNextEvent::new(LightSelection::Power),
    ) {
        Ok(_) => panic!("accepted {options:?}"),
        Err(e) => e.to_string(),
    };
    let d = SdrcOptions::default();
    let named = |options, key: &str| {
        let e = refused(options);
        assert!(e.starts_with(&format!("{key} must ")), "{key}: {e}");
    };
    named(SdrcOptions { a: 0.0, ..d }, "sdrc.a");
    named(SdrcOptions { a_scale: 0.5, ..d }, "sdrc.a_scale");
    named(SdrcOptions { n: 0, ..d }, "sdrc.n");
    named(SdrcOptions { m: 0, ..d }, "sdrc.m");
    named(
        SdrcOptions {
            irradiance_a: -1.0,
            ..d
        },
        "sdrc.irradiance_a",
    );
    named(
        SdrcOptions {
            irradiance_rays: 5,
            ..d
        },
        "sdrc.irradiance_rays",
    );
    named(SdrcOptions { r_max: 3.0, ..d }, "sdrc.r_max");
    named(
        SdrcOptions {
            min_reach: -1.0,
            ..d
        },
        "sdrc.min_reach",
    );
    for query_samples in [-1.0, f32::NAN, f32::INFINITY] {
        named(SdrcOptions { query_samples, ..d }, "sdrc.query_samples");
    }
    let shrc = |shrc: ShrcOptions, options| match Sdrc::harmonics(
        options,
        shrc,
        path(),
        LightNextEvent::new(LightSelection::Power),
    ) {
        Ok(_) => panic!("accepted {shrc:?}"),
        Err(e) => e.to_string(),
    };
    let e = shrc(
        ShrcOptions {
            rays: 0,
            ..Default::default()
        },
        d,
    );
    assert_eq!(e, "shrc.rays must be at least 1");
    let e = shrc(
        ShrcOptions::default(),
        SdrcOptions {
            glossy: CacheOrPath::Path,
            ..d
        },
    );
    assert!(
        e.starts_with("sdrc.glossy path leaves glossy surfaces"),
        "{e}"
    );
}
