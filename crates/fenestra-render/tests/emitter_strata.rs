//! An emitter made of many triangles (each a light of its own) is sampled as well as one
//! light of the same shape: the light pick and the point on the triangle picked are
//! stratified together, so that an emitter's light samples cover it as one 2D sample over
//! the whole would.

mod common;

use common::render;
use fenestra_core::{Rgb, Vec3};
use fenestra_render::integrator::{af_hf, PathOptions};
use fenestra_render::light::LightSelection;
use fenestra_scene::light::Emission;
use fenestra_scene::{Camera, Material, RenderDefaults, SceneDesc, Shape, ShapeKind, TriangleMesh};

/// A floor under a round emitter, half of it shaded by a square between them: the emitter
/// as one disk, or as a fan of `triangles` triangles of the same radius.
fn lamp_over_floor(triangles: Option<usize>) -> SceneDesc {
    let (centre, radius) = (Vec3::new(0.0, 0.0, 1.0), 0.5);
    let lamp = match triangles {
        None => ShapeKind::Disk {
            center: centre,
            normal: -Vec3::Z,
            radius,
        },
        Some(n) => {
            // The rim clockwise seen from above: the triangles face down.
            let rim = (0..n).map(|k| {
                let a = std::f32::consts::TAU * k as f32 / n as f32;
                centre + radius * Vec3::new(a.cos(), -a.sin(), 0.0)
            });
            let n = n as u32;
            ShapeKind::Mesh(TriangleMesh {
                positions: std::iter::once(centre).chain(rim).collect(),
                indices: (0..n).map(|k| [0, 1 + k, 1 + (k + 1) % n]).collect(),
                ..Default::default()
            })
        }
    };
    let glow = Emission::radiance(Rgb::splat(4.0));
    SceneDesc {
        name: "lamp over floor".into(),
        shapes: vec![
            Shape::new(
                ShapeKind::Mesh(TriangleMesh::quad(Vec3::ZERO, Vec3::X * 2.0, Vec3::Y * 2.0)),
                0,
            ),
            Shape::new(
                ShapeKind::Mesh(TriangleMesh::quad(
                    Vec3::new(0.3, 0.0, 0.5),
                    Vec3::X * 0.3,
                    Vec3::Y * 0.3,
                )),
                0,
            ),
            Shape::new(lamp, 0).emitting(glow),
        ],
        materials: vec![Material::diffuse(0.7)],
        lights: Vec::new(),
        camera: Camera::look_at(Vec3::new(0.0, -0.1, 3.0), Vec3::ZERO, Vec3::Y, 50.0)
            .expect("camera"),
        defaults: RenderDefaults::default(),
        portals: Vec::new(),
    }
}

/// Mean squared luminance error of 16-sample direct-light renders (four seeds) against a
/// 2,048-sample render of the same scene.
fn error_at_16_spp(desc: impl Fn() -> SceneDesc) -> f64 {
    let direct = PathOptions {
        max_depth: 2,
        ..Default::default()
    };
    let mut af_hf = af_hf(direct, LightSelection::Power);
    let reference = render(desc(), &mut af_hf, 32, 2048, 1).0.image();
    let mut sum = 0.0;
    for seed in 2..6 {
        let image = render(desc(), &mut af_hf, 32, 16, seed).0.image();
        let pairs = image.pixels.iter().zip(&reference.pixels);
        sum += pairs
            .map(|(a, r)| f64::from(a.luminance() - r.luminance()).powi(2))
            .sum::<f64>();
    }
    sum / (4.0 * 32.0 * 32.0)
}

#[test]
fn an_emitter_of_many_triangle_lights_is_sampled_as_well_as_one_light() {
    let disk = error_at_16_spp(|| lamp_over_floor(None));
    for triangles in [16, 64] {
        let fan = error_at_16_spp(|| lamp_over_floor(Some(triangles)));
        eprintln!("{triangles} triangles: {:.3}x the disk's error", fan / disk);
        // Measured: 1.12x (16) and 1.20x (64; its thin sectors lose the disk's radial
        // strata); 1.72x for 16 when the pick took a number of its own.
        assert!(
            fan < 1.3 * disk,
            "{triangles} triangles: error {fan:.3e}, the disk's {disk:.3e}"
        );
    }
}
