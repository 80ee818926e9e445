//! Light samples of a large emitter close over a floor, far from the origin: most of them
//! leave the floor at grazing angles, where a shadow ray that leaves the point moved off the
//! surface parallel to the sampled direction meets the emitter's plane short of its point
//! and was counted blocked. The floor's radiance has a closed form.

mod common;

use common::render;
use fenestra_core::{Rgb, Vec3};
use fenestra_render::integrator::{af_hf, PathOptions};
use fenestra_render::light::LightSelection;
use fenestra_scene::light::Emission;
use fenestra_scene::{Camera, Material, RenderDefaults, SceneDesc, Shape, ShapeKind, TriangleMesh};
use std::f64::consts::PI;

/// Half the emitter's side.
const HALF: f32 = 20.0;
/// The emitter's height over the floor.
const HEIGHT: f32 = 0.5;
/// The floor's albedo.
const ALBEDO: f32 = 0.5;

/// The form factor from a point to a rectangle in a parallel plane, one of whose corners
/// lies straight above it, of sides x and y in units of the planes' distance.
fn corner_form_factor(x: f64, y: f64) -> f64 {
    let (sx, sy) = ((1.0 + x * x).sqrt(), (1.0 + y * y).sqrt());
    (x / sx * (y / sx).atan() + y / sy * (x / sy).atan()) / (2.0 * PI)
}

#[test]
fn a_floor_under_a_large_close_emitter_renders_its_closed_form() {
    // 1 km from the origin, where points are moved off surfaces by more than near it.
    let centre = Vec3::new(1000.0, 1000.0, 0.0);
    let scene = SceneDesc {
        name: "floor under a ceiling of light".into(),
        shapes: vec![
            Shape::new(
                ShapeKind::Mesh(TriangleMesh::quad(centre, Vec3::X * 30.0, Vec3::Y * 30.0)),
                0,
            ),
            // Facing down (Y x X = -Z).
            Shape::new(
                ShapeKind::Mesh(TriangleMesh::quad(
                    centre + Vec3::Z * HEIGHT,
                    Vec3::Y * HALF,
                    Vec3::X * HALF,
                )),
                0,
            )
            .emitting(Emission::radiance(Rgb::ONE)),
        ],
        materials: vec![Material::diffuse(ALBEDO)],
        lights: Vec::new(),
        // Between the two planes, looking straight down at a spot 2.6 mm across.
        camera: Camera::look_at(centre + Vec3::Z * 0.3, centre, Vec3::Y, 0.5).expect("camera"),
        defaults: RenderDefaults::default(),
        portals: Vec::new(),
    };
    let direct = PathOptions {
        max_depth: 2,
        ..Default::default()
    };
    let film = render(
        scene,
        &mut af_hf(direct, LightSelection::Power),
        32,
        1024,
        3,
    )
    .0;
    let (mean, se) = common::region_mean(&film, 0, 32, 0, 32);
    // Radiance rho / pi x irradiance, the irradiance pi L x the four corners' form factors.
    let side = f64::from(HALF / HEIGHT);
    let expected = f64::from(ALBEDO) * 4.0 * corner_form_factor(side, side);
    let z = (mean - expected) / se;
    assert!(
        se < 2.5e-4 * expected && z.abs() < 4.0,
        "{mean:.6} against {expected:.6}: {:+.4}%, z {z:.2} (standard error {:.4}%)",
        100.0 * (mean / expected - 1.0),
        100.0 * se / expected
    );
}
