//! Direct light through the ceiling hole of the seed-000 box against its integral. Seen from
//! the floor, every ray through the hole meets the panel above it, so the floor's irradiance
//! is that of the hole as a Lambertian source of the panel's radiance L: with the floor and
//! the hole horizontal and h apart, E(x) = L h^2 * integral over the hole of dA / r^4. A
//! camera looking straight down at the floor then sees rho / pi * E at each hit. Light lost or
//! gained at the hole's edges, at the panel or along shadow rays shows as a biased mean.

use fenestra_builtin as builtin;
use fenestra_core::{Rgb, Vec2, Vec3};
use fenestra_portals::{lp_hf, PortalOptions, PortalSource};
use fenestra_render::integrator::{af_hf, LightNextEvent, PathOptions};
use fenestra_render::light::{LightHit, LightSelection};
use fenestra_render::{render_image, Integrator, RenderScene, RenderSettings};
use fenestra_scene::light::EnvironmentDesc;
use fenestra_scene::material;
use fenestra_scene::sky::Sky;
use fenestra_scene::{Backend, Camera, LightDesc, Material, Scene, SceneDesc};

const SIZE: u32 = 48;
/// The box's floor and ceiling heights, the hole's half-width.
const FLOOR: f32 = -0.5;
const CEILING: f32 = 0.5;
const HOLE: f32 = 0.125;

/// The built-in box `name` seen from under the ceiling, looking straight down at the floor
/// (50 degrees: the view stays on the floor), and the floor's albedo.
fn looking_at_the_floor(name: &str) -> (SceneDesc, f64) {
    let mut desc = builtin::load(name).expect("builtin");
    desc.camera = Camera::look_at(
        Vec3::new(0.0, 0.0, 0.4),
        Vec3::new(0.0, 0.0, FLOOR),
        Vec3::Y,
        50.0,
    )
    .expect("camera");
    let albedo = match &desc.materials[0] {
        Material::Diffuse(material::Diffuse { reflectance }) => red(*reflectance),
        m => panic!("walls of {m:?}"),
    };
    (desc, albedo)
}

/// box-hole's floor under the hole, with the panel's radiance and the floor's albedo.
fn floor_under_the_hole() -> (RenderScene, f64, f64) {
    let (desc, albedo) = looking_at_the_floor("box-hole");
    let radiance = desc
        .shapes
        .iter()
        .find_map(|s| s.emission.map(|e| e.radiance))
        .expect("the panel");
    let scene = RenderScene::new(Scene::build(desc, Backend::default()).expect("scene"));
    (scene, red(radiance), albedo)
}

fn red(c: Rgb) -> f64 {
    c.r as f64
}

/// The image mean the integral gives: rho / pi * E at the floor point of each of 8 x 8
/// positions per pixel (box filter), E by the midpoint rule over 48 x 48 cells of the hole.
fn expected_mean(scene: &RenderScene, radiance: f64, albedo: f64) -> f64 {
    let (sub, cells) = (8u32, 48usize);
    let h = (CEILING - FLOOR) as f64;
    let cell = 2.0 * HOLE as f64 / cells as f64;
    let centres: Vec<f64> = (0..cells)
        .map(|i| -HOLE as f64 + (i as f64 + 0.5) * cell)
        .collect();
    let irradiance = |x: f64, y: f64| {
        let mut sum = 0.0;
        for &u in &centres {
            for &v in &centres {
                let r2 = (x - u).powi(2) + (y - v).powi(2) + h * h;
                sum += 1.0 / (r2 * r2);
            }
        }
        radiance * h * h * sum * cell * cell
    };
    let mut total = 0.0;
    for py in 0..SIZE * sub {
        for px in 0..SIZE * sub {
            let film = Vec2::new(
                (px as f32 + 0.5) / sub as f32,
                (py as f32 + 0.5) / sub as f32,
            );
            let ray = scene.scene.camera.generate_ray(film, SIZE, SIZE);
            let t = (FLOOR - ray.o.z) / ray.d.z;
            let p = ray.o + ray.d * t;
            total += irradiance(p.x as f64, p.y as f64);
        }
    }
    albedo / std::f64::consts::PI * total / (SIZE * SIZE * sub * sub) as f64
}

/// The image mean of the red channel and its standard error.
fn render(integrator: &mut dyn Integrator, scene: &RenderScene, spp: u32) -> (f64, f64) {
    let settings = RenderSettings {
        first_sample: 0,
        spp,
        time_limit: None,
        seed: 5,
    };
    let (film, _) = render_image(integrator, scene, SIZE, SIZE, &settings).expect("render");
    let n = film.pixels.len() as f64;
    let mean = film.pixels.iter().map(|p| p.mean()[0]).sum::<f64>() / n;
    let var = film
        .pixels
        .iter()
        .map(|p| p.variance_of_mean()[0])
        .sum::<f64>();
    (mean, var.sqrt() / n)
}

/// lp_hf through the scene's portals and af_hf, both for direct light only (path length 2).
fn direct_light_integrators() -> [(&'static str, Box<dyn Integrator>); 2] {
    let direct = PathOptions {
        max_depth: 2,
        ..Default::default()
    };
    let portals = lp_hf(
        direct,
        kept_portals(),
        PortalSource::Scene,
        LightNextEvent::new(LightSelection::Power),
    )
    .expect("lp_hf");
    [
        ("lp_hf", Box::new(portals)),
        ("af_hf", Box::new(af_hf(direct, LightSelection::Power))),
    ]
}

#[test]
fn direct_light_through_the_hole_matches_its_integral() {
    let (scene, radiance, albedo) = floor_under_the_hole();
    let expect = expected_mean(&scene, radiance, albedo);
    // lp_hf through the scene's portal resolves a few parts in a million; af_hf, whose light
    // samples mostly meet the ceiling, a few parts in a thousand.
    for ((name, mut integrator), spp) in direct_light_integrators().into_iter().zip([1024, 256]) {
        let (mean, se) = render(integrator.as_mut(), &scene, spp);
        let off = (mean - expect) / expect;
        assert!(
            (mean - expect).abs() < 4.0 * se + 2e-5 * expect,
            "{name}: image mean {mean:.7} against the integral's {expect:.7} \
             ({off:+.2e} relative, standard error {:.1e})",
            se / expect
        );
    }
}

/// The image mean the integral gives for box-hole under `--sky`'s sky or sun (whichever the
/// scene has): at the floor point of each film position, the sky's radiance (as the
/// renderer's map gives it) over 48 x 48 cells of the hole (2 x 2 positions per pixel: it
/// varies slowly), and the sun's disk as 8 x 8 equal-solid-angle directions, each seen or
/// not through the hole (8 x 8 positions per pixel: the sun's patch has sharp edges).
fn expected_sky_mean(scene: &RenderScene, albedo: f64) -> f64 {
    let lights = &scene.lights;
    let (sky, sun): (Vec<_>, Vec<_>) = (lights.environments.iter())
        .map(|&e| &lights.lights[e])
        .partition(|l| !l.is_compact());
    let h = (CEILING - FLOOR) as f64;
    let cells = 48usize;
    let cell = 2.0 * HOLE as f64 / cells as f64;
    let centres: Vec<f64> = (0..cells)
        .map(|i| -HOLE as f64 + (i as f64 + 0.5) * cell)
        .collect();
    let sky_irradiance = |p: Vec3| {
        let mut sum = 0.0;
        for &u in &centres {
            for &v in &centres {
                let d = Vec3::new(u as f32 - p.x, v as f32 - p.y, h as f32);
                let r2 = d.length_squared() as f64;
                let l: f64 = sky
                    .iter()
                    .map(|s| s.le(LightHit::Escaped, d.normalize()).r as f64)
                    .sum();
                sum += l / (r2 * r2);
            }
        }
        h * h * sum * cell * cell
    };
    // The disk's directions: a sample of the sun light at stratum centres, each carrying
    // radiance times its share of the solid angle.
    let k = 8;
    let disk: Vec<(Vec3, f64)> = (0..k * k)
        .flat_map(|i| {
            let u = Vec2::new(
                ((i % k) as f32 + 0.5) / k as f32,
                ((i / k) as f32 + 0.5) / k as f32,
            );
            sun.iter().filter_map(move |sun| {
                let s = sun.sample_li(&scene.scene, Vec3::ZERO, u)?;
                Some((s.wi, s.li.r as f64 / s.pdf as f64 / (k * k) as f64))
            })
        })
        .collect();
    let sun_irradiance = |p: Vec3| {
        let mut sum = 0.0;
        for &(d, w) in &disk {
            let q = p + d * ((CEILING - p.z) / d.z);
            if q.x.abs() < HOLE && q.y.abs() < HOLE {
                sum += w * d.z as f64;
            }
        }
        sum
    };
    let floor_point = |px: u32, py: u32, sub: u32| {
        let film = Vec2::new(
            (px as f32 + 0.5) / sub as f32,
            (py as f32 + 0.5) / sub as f32,
        );
        let ray = scene.scene.camera.generate_ray(film, SIZE, SIZE);
        ray.o + ray.d * ((FLOOR - ray.o.z) / ray.d.z)
    };
    let mean_over = |sub: u32, e: &dyn Fn(Vec3) -> f64| {
        let mut total = 0.0;
        for py in 0..SIZE * sub {
            for px in 0..SIZE * sub {
                total += e(floor_point(px, py, sub));
            }
        }
        total / (SIZE * SIZE * sub * sub) as f64
    };
    let e = mean_over(2, &sky_irradiance) + mean_over(8, &sun_irradiance);
    albedo / std::f64::consts::PI * e
}

/// `--sky`'s sky and sun through the hole onto the floor, against their integral: the sun
/// (lp_hf's own light sampling, af_hf's light sampling with MIS against the BSDF) and the
/// sky (lp_hf through the portal) to a standard error of 3-5e-4; af_hf's sky, whose light
/// samples mostly meet the ceiling, to 1e-2.
#[test]
fn direct_sky_and_sun_through_the_hole_match_their_integral() {
    let (desc, albedo) = looking_at_the_floor("box-hole-sky");
    // The sun 75 degrees up: its patch lands on the floor in view.
    let sky = Sky {
        turbidity: 3.0,
        albedo: 0.3,
        elevation_deg: 75.0,
        azimuth_deg: 30.0,
    };
    let desc = desc.with_sky(&sky, Vec3::Z, 0.0, 1.0).expect("a valid sky");
    // The sky and the sun apart: each estimate's noise is then its own, small enough to see
    // a bias of a few parts in a thousand.
    for (part, compact, spp) in [("sun", true, 1024), ("sky", false, 256)] {
        let mut only = desc.clone();
        only.lights.retain(|l| match l {
            LightDesc::Environment(EnvironmentDesc::Sun { .. }) => compact,
            _ => !compact,
        });
        let scene = RenderScene::new(Scene::build(only, Backend::default()).expect("scene"));
        let expect = expected_sky_mean(&scene, albedo);
        for (name, mut integrator) in direct_light_integrators() {
            let (mean, se) = render(integrator.as_mut(), &scene, spp);
            let off = (mean - expect) / expect;
            eprintln!(
                "{part} {name}: {mean:.6} vs {expect:.6} ({off:+.2e}, se {:.1e})",
                se / expect
            );
            assert!(
                (mean - expect).abs() < 4.0 * se + 3e-4 * expect,
                "{part}, {name}: image mean {mean:.6} against the integral's {expect:.6} \
                 ({off:+.2e} relative, standard error {:.1e})",
                se / expect
            );
        }
    }
}

/// The sky and the sun together, lp_hf sampling the sun or else the portal at each vertex
/// (portal.compact_share): each strategy's estimate is divided by its probability and its MIS
/// weights use its density times that probability. With the sun 20 degrees up its light falls
/// outside the view, and the sky through the portal (taken at 20% or 70% of the vertices) is
/// checked at the strength of the tests above (a standard error of 2-3e-4); with the sun 75
/// degrees up, in view, the sun's share of the estimate is checked to its standard error of
/// 2e-3 (a one-in-five choice of the brightest light is noisy; a missing division by the share
/// would be 25% off).
#[test]
fn sun_or_portal_per_vertex_matches_the_integral() {
    let direct = PathOptions {
        max_depth: 2,
        ..Default::default()
    };
    for (elevation_deg, share, spp) in [(20.0, 0.3, 1024), (20.0, 0.8, 2048), (75.0, 0.8, 2048)] {
        let (desc, albedo) = looking_at_the_floor("box-hole-sky");
        let sky = Sky {
            turbidity: 3.0,
            albedo: 0.3,
            elevation_deg,
            azimuth_deg: 30.0,
        };
        let desc = desc.with_sky(&sky, Vec3::Z, 0.0, 1.0).expect("a valid sky");
        let scene = RenderScene::new(Scene::build(desc, Backend::default()).expect("scene"));
        let expect = expected_sky_mean(&scene, albedo);
        let options = PortalOptions {
            compact_share: Some(share),
            ..kept_portals()
        };
        let lights = LightNextEvent::new(LightSelection::Power);
        let mut lp = lp_hf(direct, options, PortalSource::Scene, lights).expect("lp_hf");
        let (mean, se) = render(&mut lp, &scene, spp);
        let off = (mean - expect) / expect;
        let what = format!("sun {elevation_deg} degrees up, sampled at {share} of the vertices");
        eprintln!(
            "{what}: {mean:.6} vs {expect:.6} ({off:+.2e}, se {:.1e})",
            se / expect
        );
        assert!(
            (mean - expect).abs() < 4.0 * se + 3e-4 * expect,
            "{what}: image mean {mean:.6} against the integral's {expect:.6} \
             ({off:+.2e} relative, standard error {:.1e})",
            se / expect
        );
    }
}

/// Default portal options, the portals kept whatever lp_hf's measurement before rendering
/// finds (these tests are about sampling them).
fn kept_portals() -> PortalOptions {
    PortalOptions {
        keep: true,
        ..PortalOptions::default()
    }
}
