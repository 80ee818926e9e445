//! A glossy point's M BRDF-sampled directions (seed 003 eq. 2.3), in which the glossy
//! caches read their records: a pixel's directions are one Sobol sequence over its samples.

use fenestra_core::{Rgb, Sampler, Vec3};
use fenestra_render::integrator::Shading;

/// Seed of the directions' sample streams (xor-ed with the render's seed).
const DIRECTIONS: u64 = 0x5d5c_0001;

/// The `j`-th of the `m` BRDF-sampled directions of the point `s` of a render with `seed`
/// (direction, weight f cos / pdf, density), and the rest of its sample stream.
pub(crate) fn direction(
    seed: u64,
    m: u32,
    s: &Shading,
    j: u32,
) -> (Sampler, Option<(Vec3, Rgb, f32)>) {
    let first = s.sample.index.wrapping_mul(m);
    let mut sampler = Sampler::new(seed ^ DIRECTIONS, s.sample.pixel(), first + j);
    let direction = sample_bsdf(s, &mut sampler);
    (sampler, direction)
}

/// A BSDF-sampled direction at `s` (world), its weight f cos / pdf and density; `None` where
/// sampling fails or the direction leaves through the wrong side.
pub(crate) fn sample_bsdf(s: &Shading, sampler: &mut Sampler) -> Option<(Vec3, Rgb, f32)> {
    let uc = sampler.next_1d();
    let u = sampler.next_2d();
    let bs = s.bsdf.sample(s.wo_local, uc, u)?;
    let w = s.frame.to_world(bs.wi);
    (s.sides_agree(w, bs.wi.z) && bs.pdf > 0.0).then_some((w, bs.weight, bs.pdf))
}
