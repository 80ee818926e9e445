//! A relit frame's image (seed 003 §4.6): at run time the lights' direct light reaches the
//! gather samples (ray-traced shadows) and makes their radiosity; the compressed transfer
//! turns it into one-bounce indirect light at the view samples ([`FrameTransfer::relight`]);
//! direct light at the view samples, and emitters and the environment seen directly, are
//! added by tracing the same pixel-centre rays as the precomputation.

use crate::frame::{view, FrameTransfer};
use crate::gather::Gather;
use crate::transfer::{direct, radiosity};
use fenestra_core::{Rgb, Sampler, Vec2};
use fenestra_render::light::LightHit;
use fenestra_render::RenderScene;
use rayon::prelude::*;

/// Light samples per light: one for Dirac lights is exact, area lights and environments get
/// `samples`.
#[derive(Clone, Copy, Debug)]
pub struct Relighting {
    pub light_samples: u32,
    pub seed: u64,
}

/// The image of `frame` (precomputed on `scene`'s geometry, with `gather` posed on it) under
/// `scene`'s lights: (direct, indirect), row-major.
pub fn relit_image(
    scene: &RenderScene,
    gather: &Gather,
    frame: &FrameTransfer,
    o: &Relighting,
) -> (Vec<Rgb>, Vec<Rgb>) {
    let b = radiosity(scene, gather, o.light_samples, o.seed);
    let indirect = frame.relight(&b);
    let (w, h) = (frame.width, frame.height);
    // Each pixel's view sample made, used and dropped (a frame's views held at once are
    // tens of megabytes, fresh pages every frame).
    let direct_light: Vec<Rgb> = (0..w * h)
        .into_par_iter()
        .map(|i| {
            let Some(v) = view(scene, i, w, h) else {
                return seen_directly(scene, i, w, h);
            };
            let shading = v.si.shading_frame();
            let wo = shading.to_local(v.wo);
            let mut sampler = Sampler::new(o.seed ^ 0xd1ec7, i as u64, 0);
            direct(
                scene,
                v.si.p,
                v.si.ng,
                o.light_samples,
                &mut sampler,
                |wi| {
                    let local = shading.to_local(wi);
                    // Light and viewer on the sides the geometric surface says.
                    let sides =
                        (wi.dot(v.si.ng) * v.wo.dot(v.si.ng) > 0.0) == (local.z * wo.z > 0.0);
                    let f = v.bsdf.eval(wo, local) * local.z.abs();
                    (sides && !f.is_black()).then_some(f)
                },
            )
        })
        .collect();
    (direct_light, indirect)
}

/// What the pixel-centre ray of pixel `i` sees when it finds no surface to relight: an
/// emitter's radiance, the environment, or black.
fn seen_directly(scene: &RenderScene, i: u32, w: u32, h: u32) -> Rgb {
    let c = Vec2::new((i % w) as f32 + 0.5, (i / w) as f32 + 0.5);
    let ray = scene.scene.camera.generate_ray(c, w, h);
    match scene.scene.intersect(&ray, f32::INFINITY) {
        Some(hit) => {
            let si = scene.scene.interaction(&ray, &hit);
            (scene.lights.surface_emission(&si, ray.d)).map_or(Rgb::ZERO, |(_, le)| le)
        }
        None => (scene.lights.environments.iter())
            .map(|&e| scene.lights.lights[e].le(LightHit::Escaped, ray.d))
            .fold(Rgb::ZERO, |a, b| a + b),
    }
}
