//! Spherical-harmonic radiance caching (SHRC: Krivanek et al. 2005, as seed 003 §2.3
//! describes it and §2.6 compares against it) on glossy surfaces, the baseline of SDRC: a
//! record holds the incoming radiance over its hemisphere as SH coefficients of order 10,
//! projected from uniformly sampled rays; a point's outgoing radiance is the product of the
//! records' interpolated radiance with its BRDF lobe.
//!
//! Coefficients are kept in the record's own frame for the even extension of its hemisphere
//! (L(x, y, -z) = L(x, y, z), so only the functions even in z are used and the basis spends
//! its resolution on the hemisphere, as hemispherical bases do). Reading a record in a
//! direction given in the point's frame evaluates the basis at that direction turned into the
//! record's frame: exactly what rotating the coefficients (R_i) computes. The BRDF lobe's
//! coefficients C(p, w_out) are not tabulated per BRDF: the product R_i Lambda_i . C is
//! estimated by the point's M BRDF-sampled directions through the SH reconstruction, so any
//! BRDF that can be sampled is served, as SDRC serves it.

use crate::directions::direction;
use crate::kind::CacheKind;
use crate::record::{Payload, Record};
use crate::record_rays::{viewer_geometric_normal, viewer_normal, Distances, RecordRays};
use crate::sh;
use crate::spatial::{Delta, SpatialCache};
use fenestra_core::stats::RayCounters;
use fenestra_core::{Frame, Rgb, Vec3};
use fenestra_render::integrator::Shading;
use fenestra_render::RenderScene;
use std::f32::consts::TAU;

/// Seed of the SH records' sample streams (xor-ed with the render's seed).
const RECORD_RAYS: u64 = 0x5d5c_0005;

/// A record's incoming radiance: SH coefficients in the record's frame (zero for the
/// functions odd in z).
#[derive(Clone, Debug)]
pub struct ShRadiance {
    coeffs: Box<[Rgb; sh::COUNT]>,
}

impl Payload for ShRadiance {
    /// SH records are never added to.
    type Update = ();

    fn absorb(&mut self, _: ()) {}

    fn bytes(&self) -> usize {
        std::mem::size_of::<[Rgb; sh::COUNT]>()
    }
}

impl ShRadiance {
    /// Projects radiance samples (`local` direction in the upper hemisphere, radiance) drawn
    /// uniformly over the hemisphere onto the even functions: Lambda = 2 (2 pi / N) sum L Y.
    pub fn project(samples: impl IntoIterator<Item = (Vec3, Rgb)>, count: usize) -> Self {
        let mut coeffs = Box::new([Rgb::ZERO; sh::COUNT]);
        let mut y = [0.0f32; sh::COUNT];
        for (w, l) in samples {
            sh::eval(w, &mut y);
            for (c, &v) in coeffs.iter_mut().zip(&y) {
                *c += l * v;
            }
        }
        let scale = 2.0 * TAU / count.max(1) as f32;
        for l in 0..sh::ORDER {
            for m in -(l as i32)..=(l as i32) {
                let c = &mut coeffs[sh::index(l, m)];
                *c = if sh::even(l, m) {
                    *c * scale
                } else {
                    Rgb::ZERO
                };
            }
        }
        ShRadiance { coeffs }
    }

    /// The reconstructed radiance from the record-frame direction `local` (`y` scratch).
    pub fn radiance(&self, local: Vec3, y: &mut [f32; sh::COUNT]) -> Rgb {
        sh::eval(local, y);
        self.coeffs
            .iter()
            .zip(y.iter())
            .fold(Rgb::ZERO, |acc, (&c, &v)| acc + c * v)
    }
}

/// SH radiance records and the options they follow.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ShRecords {
    /// Rays per record.
    pub(crate) rays: u32,
    /// BRDF-sampled directions per point (M, as SDRC's).
    pub(crate) m: u32,
}

impl CacheKind for ShRecords {
    type Payload = ShRadiance;

    /// A new SH record at `s`: `rays` directions stratified uniformly over the hemisphere
    /// (rings of equal height, sectors), their reflected radiance projected onto the basis;
    /// R_i from the hit distances.
    fn create(
        &self,
        tracing: &mut RecordRays,
        delta: &mut Delta<ShRadiance>,
        scene: &RenderScene,
        s: &Shading,
        a: f32,
        rays: &mut RayCounters,
    ) -> Record<ShRadiance> {
        let frame = Frame::from_normal(viewer_normal(s));
        let ng = viewer_geometric_normal(s);
        let rings = ((self.rays as f32).sqrt().round() as usize).max(1);
        let sectors = (self.rays as usize / rings).max(1);
        let mut distances = Distances::default();
        // Uniform: cos theta uniform over the ring's share.
        let uniform = |cos: f32| ((1.0 - cos * cos).max(0.0).sqrt(), cos);
        let cells = tracing.stratified(
            scene,
            s,
            (&frame, ng),
            RECORD_RAYS,
            (rings, sectors),
            uniform,
            rays,
            &mut distances,
        );
        delta.counts.record_rays += cells.len() as u64;
        let samples: Vec<(Vec3, Rgb)> = cells.iter().map(|c| (c.local, c.l)).collect();
        let count = samples.len();
        Record {
            si: *s.si,
            frame,
            ng,
            r: tracing.radius(s, a, &distances, None),
            payload: ShRadiance::project(samples, count),
            pixel: (s.sample.x, s.sample.y),
        }
    }

    /// Outgoing radiance at `s` (§2.3): the records near interpolated with their weights,
    /// read in the point's M BRDF-sampled directions.
    fn interpolate(
        &self,
        tracing: &mut RecordRays,
        cache: &SpatialCache<ShRadiance>,
        delta: &mut Delta<ShRadiance>,
        _: &RenderScene,
        s: &Shading,
        _: &mut RayCounters,
    ) -> Rgb {
        let near = &delta.near;
        let total: f32 = near.iter().map(|&(_, w)| w).sum();
        if total <= 0.0 {
            return Rgb::ZERO;
        }
        let m = self.m;
        let mut y = [0.0f32; sh::COUNT];
        let mut sum = Rgb::ZERO;
        for j in 0..m {
            let Some((w, weight, _)) = direction(tracing.seed, m, s, j).1 else {
                continue;
            };
            let mut l = Rgb::ZERO;
            for &(id, ws) in near {
                let r = cache.record(delta, id);
                l += r.payload.radiance(r.frame.to_local(w), &mut y) * ws;
            }
            sum += l * weight;
        }
        (sum * (1.0 / (total * m as f32))).map(|v| v.max(0.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smooth_hemispherical_radiance_is_reconstructed() {
        // L = 1 + 0.5 x + z^2 over the upper hemisphere, from 64 x 64 stratified midpoints.
        let f = |w: Vec3| 1.0 + 0.5 * w.x + w.z * w.z;
        let (rings, sectors) = (64, 64);
        let mut samples = Vec::new();
        for j in 0..rings {
            for k in 0..sectors {
                let cos = (j as f32 + 0.5) / rings as f32;
                let sin = (1.0 - cos * cos).sqrt();
                let phi = TAU * (k as f32 + 0.5) / sectors as f32;
                let w = Vec3::new(sin * phi.cos(), sin * phi.sin(), cos);
                samples.push((w, Rgb::splat(f(w))));
            }
        }
        let record = ShRadiance::project(samples, rings * sectors);
        let mut y = [0.0f32; sh::COUNT];
        // The even extension of 0.5 x is 0.5 x; of 1 + z^2 the same: degree 2, exact.
        for w in [
            Vec3::Z,
            Vec3::new(0.6, 0.0, 0.8),
            Vec3::new(-0.3, 0.7, 0.648),
        ] {
            let got = record.radiance(w.normalize(), &mut y).r;
            let want = f(w.normalize());
            assert!((got - want).abs() < 0.02 * want, "{got} vs {want} at {w:?}");
        }
    }
}
