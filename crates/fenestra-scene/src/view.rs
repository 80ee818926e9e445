//! What the camera sees around it: the surface points met by a grid of rays over the image and
//! as many rays over the sphere of directions (the room behind the camera holds windows and
//! lights too). Preparations that measure or aim at "the part of the scene that matters" (portal
//! estimation, the pilots choosing a sampling strategy) start from these points.

use crate::{Scene, SurfaceInteraction};
use fenestra_core::{warp, Ray, Sampler, Vec2};

/// Rays per side of the grid over the image; as many again go over the sphere.
const GRID: u32 = 48;

/// The surface points the camera's grid of rays over the image meets, and those that as many
/// rays from it over the sphere meet (rays that leave the scene give none).
pub fn camera_hits(scene: &Scene) -> (Vec<SurfaceInteraction>, Vec<SurfaceInteraction>) {
    let camera = &scene.camera;
    let (w, h) = (scene.defaults.width.max(1), scene.defaults.height.max(1));
    let mut sampler = Sampler::new(0, 0x4149_4d00, 0);
    let image = (0..GRID * GRID).map(|k| {
        let cell = Vec2::new((k % GRID) as f32 + 0.5, (k / GRID) as f32 + 0.5) / GRID as f32;
        camera.generate_ray(cell * Vec2::new(w as f32, h as f32), w, h)
    });
    let around = (0..GRID * GRID).map(|_| {
        Ray::new(
            camera.position,
            warp::square_to_uniform_sphere(sampler.next_2d()),
        )
    });
    let hits = |rays: &mut dyn Iterator<Item = Ray>| -> Vec<SurfaceInteraction> {
        rays.filter_map(|ray| {
            let hit = scene.intersect(&ray, f32::INFINITY)?;
            Some(scene.interaction(&ray, &hit))
        })
        .collect()
    };
    (hits(&mut image.into_iter()), hits(&mut around.into_iter()))
}
