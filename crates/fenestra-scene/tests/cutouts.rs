//! Cut-outs: a quad masked by an 8x8 checkerboard, above a floor. Rays through it on a grid
//! (one per half cell) find the quad on exactly half of them and the floor, at its distance
//! along the same ray, on the other half, through every query (closest hit, occlusion, their
//! packets) on every backend; a stochastic (BLEND) alpha of 0.3 lets 70% through.

use fenestra_core::image::Image;
use fenestra_core::{Ray, Rgb, Vec3};
use fenestra_scene::material::{Alpha, AlphaMode, MetallicRoughness};
use fenestra_scene::{
    Backend, Camera, ImageTexture, Material, RenderDefaults, Scene, SceneDesc, Shape, ShapeKind,
    TriangleMesh, PACKET,
};
use std::sync::Arc;

/// The masked quad [-1, 1]^2 at z = 0 over an opaque floor at z = -1.
fn scene(backend: Backend, mode: AlphaMode, factor: f32) -> Scene {
    let mut img = Image::new(8, 8);
    for y in 0..8 {
        for x in 0..8 {
            img.set(x, y, Rgb::splat(((x + y) % 2) as f32));
        }
    }
    let alpha = Alpha {
        factor,
        texture: (mode != AlphaMode::Blend)
            .then(|| Arc::new(ImageTexture::new(Arc::new(img), "a.png".into()))),
        mode,
    };
    let quad = |z: f32, m: usize| {
        Shape::new(
            ShapeKind::Mesh(TriangleMesh::quad(Vec3::Z * z, Vec3::X, Vec3::Y)),
            m,
        )
    };
    let desc = SceneDesc {
        name: "cutout".into(),
        shapes: vec![quad(0.0, 0), quad(-1.0, 1)],
        materials: vec![
            Material::MetallicRoughness(MetallicRoughness {
                alpha: Some(alpha),
                ..MetallicRoughness::new()
            }),
            Material::diffuse(0.5),
        ],
        lights: vec![],
        camera: Camera::look_at(Vec3::Z * 3.0, Vec3::ZERO, Vec3::Y, 60.0).expect("camera"),
        defaults: RenderDefaults::default(),
        portals: Vec::new(),
    };
    Scene::build(desc, backend).expect("scene")
}

/// Rays straight down from z = 1 through the centres of a 32x32 grid over the quad.
fn rays() -> Vec<Ray> {
    (0..32 * 32)
        .map(|i| {
            let (x, y) = ((i % 32) as f32 + 0.5, (i / 32) as f32 + 0.5);
            Ray::new(Vec3::new(x / 16.0 - 1.0, y / 16.0 - 1.0, 1.0), -Vec3::Z)
        })
        .collect()
}

#[test]
fn a_checkerboard_mask_stops_half_the_rays_in_every_query() {
    for backend in Backend::available() {
        let s = scene(backend, AlphaMode::Mask { cutoff: 0.5 }, 1.0);
        let rays = rays();
        let (mut quad, mut floor) = (0, 0);
        for r in &rays {
            let hit = s
                .intersect(r, f32::INFINITY)
                .expect("the floor is below everything");
            match hit.shape {
                0 => {
                    quad += 1;
                    assert!(
                        (hit.t - 1.0).abs() < 1e-4,
                        "{backend:?}: quad at t {}",
                        hit.t
                    );
                }
                _ => {
                    floor += 1;
                    assert!(
                        (hit.t - 2.0).abs() < 1e-4,
                        "{backend:?}: floor at t {}",
                        hit.t
                    );
                    let si = s.interaction(r, &hit);
                    assert!((si.p.z + 1.0).abs() < 1e-5, "{backend:?}: {}", si.p);
                }
            }
            // A shadow ray to just above the floor is blocked exactly where the quad is there.
            assert_eq!(s.occluded(r, 1.9), hit.shape == 0, "{backend:?}: {r:?}");
        }
        assert_eq!((quad, floor), (512, 512), "{backend:?}");
        for chunk in rays.chunks_exact(PACKET) {
            let packet: &[Ray; PACKET] = chunk.try_into().expect("packet");
            let hits = s.intersect8(packet, [f32::INFINITY; PACKET]);
            let blocked = s.occluded8(packet, [1.9; PACKET]);
            for (i, r) in packet.iter().enumerate() {
                let one = s.intersect(r, f32::INFINITY).map(|h| (h.shape, h.prim));
                assert_eq!(hits[i].map(|h| (h.shape, h.prim)), one, "{backend:?}");
                assert_eq!(blocked[i], s.occluded(r, 1.9), "{backend:?}");
            }
        }
        // An alpha factor of 0.4 puts every texel below the cutoff: the quad is not there.
        let solid = scene(backend, AlphaMode::Mask { cutoff: 0.5 }, 0.4);
        assert!(rays
            .iter()
            .all(|r| solid.intersect(r, 10.0).is_some_and(|h| h.shape == 1)));
    }
}

#[test]
fn blended_alpha_lets_its_complement_through() {
    for backend in Backend::available() {
        let s = scene(backend, AlphaMode::Blend, 0.3);
        let n = 200 * 200;
        let through = (0..n)
            .filter(|i| {
                let (x, y) = ((i % 200) as f32 + 0.5, (i / 200) as f32 + 0.5);
                let r = Ray::new(Vec3::new(x / 100.0 - 1.0, y / 100.0 - 1.0, 1.0), -Vec3::Z);
                s.intersect(&r, 10.0).is_some_and(|h| h.shape == 1)
            })
            .count();
        let p = through as f64 / n as f64;
        // Binomial standard error at n = 40000: 0.0023.
        assert!((p - 0.7).abs() < 0.01, "{backend:?}: {p}");
    }
}
