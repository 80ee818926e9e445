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
use fenestra_render::light::LightSelection;
use fenestra_render::{render_image, Integrator, RenderScene, RenderSettings};
use fenestra_scene::material;
use fenestra_scene::{Backend, Camera, Material, Scene};

const SIZE: u32 = 48;
/// The box's floor and ceiling heights, the hole's half-width.
const FLOOR: f32 = -0.5;
const CEILING: f32 = 0.5;
const HOLE: f32 = 0.125;

/// box-hole seen from under the ceiling, looking straight down at the floor (50 degrees:
/// the view stays on the floor), with the panel's radiance and the floor's albedo.
fn floor_under_the_hole() -> (RenderScene, f64, f64) {
    let mut desc = builtin::load("box-hole").expect("builtin");
    desc.camera = Camera::look_at(
        Vec3::new(0.0, 0.0, 0.4),
        Vec3::new(0.0, 0.0, FLOOR),
        Vec3::Y,
        50.0,
    )
    .expect("camera");
    let radiance = desc
        .shapes
        .iter()
        .find_map(|s| s.emission.map(|e| e.radiance))
        .expect("the panel");
    let albedo = match &desc.materials[0] {
        Material::Diffuse(material::Diffuse { reflectance }) => *reflectance,
        m => panic!("walls of {m:?}"),
    };
    let scene = RenderScene::new(Scene::build(desc, Backend::default()).expect("scene"));
    (scene, red(radiance), red(albedo))
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

#[test]
fn direct_light_through_the_hole_matches_its_integral() {
    let (scene, radiance, albedo) = floor_under_the_hole();
    let expect = expected_mean(&scene, radiance, albedo);
    let direct = PathOptions {
        max_depth: 2,
        ..Default::default()
    };
    let portals = lp_hf(
        direct,
        PortalOptions::default(),
        PortalSource::Scene,
        LightNextEvent::new(LightSelection::Power),
    )
    .expect("lp_hf");
    // lp_hf through the scene's portal resolves a few parts in a million; af_hf, whose light
    // samples mostly meet the ceiling, a few parts in a thousand.
    for (name, mut integrator, spp) in [
        ("lp_hf", Box::new(portals) as Box<dyn Integrator>, 1024),
        (
            "af_hf",
            Box::new(af_hf(direct, LightSelection::Power)) as Box<dyn Integrator>,
            256,
        ),
    ] {
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
