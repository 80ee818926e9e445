//! White furnace: inside a closed sphere of diffuse albedo a that emits L_e inwards, the
//! radiance everywhere is L_e / (1 - a) (the sum of the bounce series). A cosine-distributed
//! direction from a point of a sphere's inside lands uniformly over its area, so a sphere
//! whose albedo varies from point to point has the mean radiance L_e / (1 - mean albedo).

mod common;

use common::integrator;
use fenestra_core::{Rgb, Vec3};
use fenestra_render::integrator::PathOptions;
use fenestra_scene::light::Emission;
use fenestra_scene::material;
use fenestra_scene::{Camera, Material, RenderDefaults, SceneDesc, Shape, ShapeKind, TriangleMesh};

fn furnace(albedo: f32, le: f32) -> SceneDesc {
    furnace_of(vec![Material::diffuse(albedo)], le)
}

/// The furnace sphere made of the last of `materials`.
fn furnace_of(materials: Vec<Material>, le: f32) -> SceneDesc {
    let sphere = Shape::new(
        ShapeKind::Sphere {
            center: Vec3::ZERO,
            radius: 1.0,
        },
        materials.len() - 1,
    )
    .flipped()
    .emitting(Emission::radiance(Rgb::splat(le)));
    SceneDesc {
        name: "furnace".into(),
        shapes: vec![sphere],
        materials,
        lights: vec![],
        camera: Camera::look_at(
            Vec3::new(0.1, -0.3, 0.2),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::Z,
            70.0,
        )
        .expect("camera"),
        defaults: RenderDefaults::default(),
        portals: Vec::new(),
    }
}

#[test]
fn furnace_radiance_matches_the_analytic_value() {
    for albedo in [0.5f32, 0.8] {
        let expect = 1.0 / (1.0 - albedo as f64);
        for name in ["hf", "af_hf"] {
            let options = PathOptions {
                max_depth: 200,
                ..Default::default()
            };
            let mut i = integrator(name, options);
            let (film, stats) = common::render(furnace(albedo, 1.0), i.as_mut(), 16, 256, 1);
            let (mean, se) = common::region_mean(&film, 0, 16, 0, 16);
            assert_eq!(stats.rays.dropped, 0);
            assert!(
                (mean - expect).abs() < 4.0 * se + 1e-3 * expect,
                "{name}, albedo {albedo}: mean {mean:.4} +- {se:.4}, expected {expect}"
            );
            // The mean is only meaningful with a small standard error.
            assert!(
                se < 0.01 * expect,
                "{name}: standard error {se} too large to test"
            );
        }
    }
}

#[test]
fn truncated_furnace_sums_the_first_bounces() {
    // With max depth d (segments), the camera sees emission over paths of 1..=d segments:
    // L_e (1 + a + ... + a^(d-1)).
    let a = 0.6f64;
    for depth in [1u32, 2, 4] {
        let expect: f64 = (0..depth).map(|k| a.powi(k as i32)).sum();
        for name in ["hf", "af_hf"] {
            let options = PathOptions {
                max_depth: depth,
                ..Default::default()
            };
            let mut i = integrator(name, options);
            let (film, _) = common::render(furnace(a as f32, 1.0), i.as_mut(), 16, 128, 2);
            let (mean, se) = common::region_mean(&film, 0, 16, 0, 16);
            assert!(
                (mean - expect).abs() < 4.0 * se + 1e-4,
                "{name} depth {depth}: {mean} +- {se}, expected {expect}"
            );
        }
    }
}

/// Mean radiance of a 16x16 furnace image at `spp` with af_hf, checked against `expect`.
fn check_furnace(what: &str, desc: SceneDesc, expect: f64) {
    let options = PathOptions {
        max_depth: 200,
        ..Default::default()
    };
    let mut i = integrator("af_hf", options);
    let (film, _) = common::render(desc, i.as_mut(), 16, 256, 1);
    let (mean, se) = common::region_mean(&film, 0, 16, 0, 16);
    assert!(
        (mean - expect).abs() < 4.0 * se + 1e-3 * expect && se < 0.01 * expect,
        "{what}: mean {mean:.4} +- {se:.4}, expected {expect}"
    );
}

#[test]
fn a_mix_furnace_has_the_mean_albedo() {
    // pbrt-v4's mix picks one material per point: 0.2 where it picks the first, 0.8 where
    // the second (a quarter of the points), so the mean albedo is 0.35.
    let materials = vec![
        Material::diffuse(0.2),
        Material::diffuse(0.8),
        Material::Mix(material::Mix {
            materials: [0, 1],
            amount: 0.25,
        }),
    ];
    check_furnace("mix", furnace_of(materials, 1.0), 1.0 / (1.0 - 0.35));
}

#[test]
fn diffuse_transmission_loses_what_it_transmits_out_of_the_furnace() {
    // Light transmitted through the sphere leaves it for good; what is reflected stays.
    let dt = Material::DiffuseTransmission(material::DiffuseTransmission {
        reflectance: Rgb::splat(0.5),
        transmittance: Rgb::splat(0.4),
    });
    check_furnace("diffusetransmission", furnace_of(vec![dt], 1.0), 2.0);
}

/// The seed-000 box (walls of zero thickness meeting at its edges, a ceiling with a hole) with
/// the hole closed by a quad of its own and the panel above removed, every wall emitting
/// radiance 1 on both sides with albedo 1/2. Light is lost only where a ray slips out
/// between two walls.
fn furnace_box() -> SceneDesc {
    let mut desc = fenestra_builtin::load("box-hole").expect("builtin");
    desc.shapes.retain(|s| s.emission.is_none());
    let hole = TriangleMesh::quad(Vec3::new(0.0, 0.0, 0.5), Vec3::X * 0.125, Vec3::Y * 0.125);
    desc.shapes.push(Shape::new(ShapeKind::Mesh(hole), 0));
    desc.materials = vec![Material::diffuse(0.5)];
    let glow = Emission {
        radiance: Rgb::ONE,
        two_sided: true,
    };
    for shape in &mut desc.shapes {
        shape.material = 0;
        shape.emission = Some(glow);
    }
    desc.portals.clear();
    desc
}

#[test]
fn no_light_leaks_out_of_the_box_between_its_walls() {
    // hf with no Russian roulette: every path inside a closed furnace brings exactly
    // 1 + 1/2 + ... + 1/2^(d-1); a path that leaves between two walls brings less.
    let depth = 20;
    let expect = (0..depth).map(|k| 0.5f64.powi(k)).sum::<f64>();
    let options = PathOptions {
        max_depth: depth as u32,
        rr_depth: 1000,
        ..Default::default()
    };
    let (film, _) = common::render(furnace_box(), integrator("hf", options).as_mut(), 64, 64, 3);
    let values: Vec<f64> = film.pixels.iter().map(|p| p.mean()[0]).collect();
    let mean = values.iter().sum::<f64>() / values.len() as f64;
    let short = values
        .iter()
        .filter(|&&v| v < expect * (1.0 - 1e-4))
        .count();
    assert!(
        (mean - expect).abs() < 1e-5 * expect && short <= 2,
        "mean {mean:.7} of the exact {expect:.7}; {short} of {} pixels short",
        values.len()
    );
}

/// Russian roulette by the square root of the throughput (the default) and by the throughput
/// itself both leave the furnace's radiance as it is: paths of every length (up to 200), the
/// roulette deciding most of them, means within 4 standard errors below 0.05%.
#[test]
fn either_roulette_keeps_the_furnace_radiance() {
    use fenestra_render::integrator::Roulette;
    let (albedo, expect) = (0.8f32, 5.0f64);
    for roulette in [Roulette::Sqrt, Roulette::Throughput] {
        let options = PathOptions {
            max_depth: 200,
            roulette,
            ..Default::default()
        };
        let mut i = integrator("af_hf", options);
        let (film, _) = common::render(furnace(albedo, 1.0), i.as_mut(), 16, 16384, 1);
        let (mean, se) = common::region_mean(&film, 0, 16, 0, 16);
        assert!(
            (mean - expect).abs() < 4.0 * se && se < 5e-4 * expect,
            "{roulette:?}: mean {mean:.5} +- {se:.5}, expected {expect}"
        );
    }
}
