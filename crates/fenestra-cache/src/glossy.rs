//! SDRC at one shading point (seed 003 Alg. 1): a new record from N BRDF-sampled rays
//! (§2.4.3), incoming radiance for the point's BRDF-sampled directions interpolated from
//! nearby records' samples (§2.4.4), samples added by tracing from a record where none is
//! near, and the outgoing radiance (eq. 2.3).

use crate::directions::{direction, sample_bsdf};
use crate::kind::CacheKind;
use crate::ltree::{LTree, Sample};
use crate::paraboloid;
use crate::record::Record;
use crate::record_rays::{viewer_geometric_normal, viewer_normal, Distances, RecordRays};
use crate::spatial::{Delta, SpatialCache};
use fenestra_core::stats::RayCounters;
use fenestra_core::{Frame, Ray, Rgb, Sampler, Vec3};
use fenestra_render::integrator::Shading;
use fenestra_render::RenderScene;

/// Seed of SDRC records' sample streams (xor-ed with the render's seed).
const RECORD_RAYS: u64 = 0x5d5c_0002;

/// SDRC's records (L-trees of BRDF-sampled radiance) and the options they follow.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SdrcRecords {
    /// Rays per record (N).
    pub(crate) n: u32,
    /// BRDF-sampled directions per point (M).
    pub(crate) m: u32,
    /// Samples of a record a directional query expects.
    pub(crate) query_samples: f32,
    /// Largest query radius in D.
    pub(crate) r_max: f32,
}

impl CacheKind for SdrcRecords {
    type Payload = LTree;

    /// A new SDRC record at `s` (§2.4.3): N BRDF-sampled rays and their radiance; R_i from
    /// their lengths and the outgoing radiance's gradient (§2.4.6).
    fn create(
        &self,
        tracing: &mut RecordRays,
        delta: &mut Delta<LTree>,
        scene: &RenderScene,
        s: &Shading,
        a: f32,
        rays: &mut RayCounters,
    ) -> Record<LTree> {
        let frame = Frame::from_normal(viewer_normal(s));
        let mut samples = Vec::with_capacity(self.n as usize);
        let mut gradient = Gradient::new(s, tracing.footprint.at(s.si.t));
        let mut distances = Distances::default();
        for k in 0..self.n {
            let mut sampler = tracing.record_stream(s, RECORD_RAYS, k);
            let Some((w, weight, pdf)) = sample_bsdf(s, &mut sampler) else {
                gradient.skip();
                continue;
            };
            delta.counts.record_rays += 1;
            let ray = Ray::new(s.si.spawn(w), w);
            let (l, t) = tracing.reflected(scene, ray, &mut sampler, s, rays);
            distances.add(t);
            gradient.add(l, w, t, weight, pdf);
            samples.push(Sample::new(paraboloid::to_disc(frame.to_local(w)), l));
        }
        Record {
            si: *s.si,
            frame,
            ng: viewer_geometric_normal(s),
            r: tracing.radius(s, a, &distances, gradient.relative()),
            payload: LTree::build(samples),
            pixel: (s.sample.x, s.sample.y),
        }
    }

    /// Outgoing radiance at `s` from M BRDF-sampled directions (eq. 2.3), interpolated from
    /// the records near (§2.4.4) or traced from one of them.
    fn interpolate(
        &self,
        tracing: &mut RecordRays,
        cache: &SpatialCache<LTree>,
        delta: &mut Delta<LTree>,
        scene: &RenderScene,
        s: &Shading,
        rays: &mut RayCounters,
    ) -> Rgb {
        let m = self.m;
        // The pixel's estimate so far averages this many directions; a query's radius follows
        // them down to the radius where it expects `query_samples` of a record's N samples
        // (N / (pi count), below).
        let floor = self.n as f32 / (std::f32::consts::PI * self.query_samples);
        let pixel_m = ((m as f32) * (s.sample.index as f32 + 1.0))
            .min(floor)
            .max(m as f32);
        let near = std::mem::take(&mut delta.near);
        let mut records = Records { cache, delta };
        let (mut sum, mut used) = (Rgb::ZERO, 0u32);
        for j in 0..m {
            let (mut sampler, direction) = direction(tracing.seed, m, s, j);
            let Some((w, weight, pdf)) = direction else {
                used += 1;
                continue;
            };
            // Query radius in D (§2.4.4): directions of density M p lie about 1/(M p) apart in
            // solid angle, so r_d = 1 / (2 pi sqrt(M p)) (docs/sdrc.md on the seed's formula).
            // It starts from the directions of the pixel's samples so far (a pixel's k-th
            // sample averages k M directions with the earlier ones; a query then expects
            // N / (pi k M) samples), and doubles up to the radius of this sample's own M
            // while nothing is found; only then is a ray traced.
            let at =
                |count: f32| (1.0 / (std::f32::consts::TAU * (count * pdf).sqrt())).min(self.r_max);
            let (mut radius, widest) = (at(pixel_m), at(m as f32));
            let (l, total) = loop {
                let (l, total) = records.interpolate(&near, w, radius);
                if total > 0.0 || radius >= widest {
                    break (l, total);
                }
                radius = (radius * 2.0).min(widest);
            };
            let lin = if total > 0.0 {
                records.delta.counts.interpolated += 1;
                l * (1.0 / total)
            } else {
                match records.update(tracing, scene, s, &near, w, &mut sampler, rays) {
                    Some(l) => l,
                    None => {
                        records.delta.counts.rejected += 1;
                        continue;
                    }
                }
            };
            sum += lin * weight;
            used += 1;
        }
        records.delta.near = near;
        if used == 0 {
            Rgb::ZERO
        } else {
            sum * (1.0 / used as f32)
        }
    }
}

/// SDRC's records as one point's lookups see them: the cache and the block's additions.
struct Records<'a, 'd> {
    cache: &'a SpatialCache<LTree>,
    delta: &'d mut Delta<LTree>,
}

impl Records<'_, '_> {
    /// Incoming radiance along `w` interpolated from the samples within `radius` (in D) of
    /// the records `near` (§2.4.4): the sum of their radiance weighted by spatial and
    /// directional weight, and the sum of weights.
    fn interpolate(&self, near: &[(u32, f32)], w: Vec3, radius: f32) -> (Rgb, f32) {
        let r2 = radius * radius;
        let (mut l, mut total) = (Rgb::ZERO, 0.0f32);
        for &(id, ws) in near {
            let record = self.cache.record(self.delta, id);
            let Some(d) = record.disc(w) else { continue };
            let mut take = |sample: &Sample, d2: f32| {
                let wd = ws * (1.0 - d2 / r2);
                l += sample.radiance() * wd;
                total += wd;
            };
            record.payload.within(d, radius, &mut take);
            for sample in self.cache.added(self.delta, id) {
                let d2 = sample.distance2(d);
                if d2 < r2 {
                    take(sample, d2);
                }
            }
        }
        (l, total)
    }

    /// No cached sample near `w`: trace from a record near `s` picked at random among those
    /// whose hemisphere holds `w`, add the sample to it, and return its radiance (§2.4.4).
    #[allow(clippy::too_many_arguments)]
    fn update(
        &mut self,
        tracing: &mut RecordRays,
        scene: &RenderScene,
        s: &Shading,
        near: &[(u32, f32)],
        w: Vec3,
        sampler: &mut Sampler,
        rays: &mut RayCounters,
    ) -> Option<Rgb> {
        let holds = |&&(id, _): &&(u32, f32)| self.cache.record(self.delta, id).disc(w).is_some();
        let count = near.iter().filter(holds).count();
        if count == 0 {
            return None;
        }
        let pick = ((sampler.next_1d() * count as f32) as usize).min(count - 1);
        let &(id, _) = near.iter().filter(holds).nth(pick)?;
        let record = self.cache.record(self.delta, id);
        let d = record.disc(w)?;
        let ray = Ray::new(record.si.spawn(w), w);
        self.delta.counts.update_rays += 1;
        rays.bounce += 1;
        let l = tracing.trace_from(scene, ray, None, sampler, s, rays);
        self.cache.add(self.delta, id, Sample::new(d, l));
        Some(l)
    }
}

/// Outgoing radiance of a new record's samples at the point and at points moved by one
/// footprint along the shading frame's tangents, for the gradient of §2.4.6 (the samples'
/// incoming radiance taken as unchanged by the move).
struct Gradient<'a> {
    s: &'a Shading<'a>,
    step: f32,
    eye: Vec3,
    /// Sums of L f cos / pdf at the point, moved along s and along t.
    sums: [f64; 3],
    drawn: u32,
}

impl<'a> Gradient<'a> {
    fn new(s: &'a Shading<'a>, step: f32) -> Self {
        Gradient {
            s,
            step,
            eye: s.si.p + s.wo * s.si.t,
            sums: [0.0; 3],
            drawn: 0,
        }
    }

    /// A direction that brought nothing.
    fn skip(&mut self) {
        self.drawn += 1;
    }

    /// Sample radiance `l` along `w` from a surface at distance `t`, of weight f cos / pdf.
    fn add(&mut self, l: Rgb, w: Vec3, t: f32, weight: Rgb, pdf: f32) {
        self.drawn += 1;
        let y = l.luminance() as f64;
        if y == 0.0 {
            return;
        }
        self.sums[0] += y * (weight.luminance() as f64);
        if !t.is_finite() {
            return;
        }
        let s = self.s;
        let hit = s.si.p + w * t;
        for (axis, sum) in [s.frame.s, s.frame.t].into_iter().zip(&mut self.sums[1..]) {
            let p = s.si.p + axis * self.step;
            let (wi, wo) = ((hit - p).normalize(), (self.eye - p).normalize());
            let (wi, wo) = (s.frame.to_local(wi), s.frame.to_local(wo));
            let f = s.bsdf.eval(wo, wi).luminance() * wi.z.abs() / pdf;
            *sum += y * f as f64;
        }
    }

    /// |grad L_out| / L_out, if the point reflects anything.
    fn relative(&self) -> Option<f32> {
        if self.sums[0] <= 0.0 || self.step <= 0.0 {
            return None;
        }
        let gx = (self.sums[1] - self.sums[0]) / self.step as f64;
        let gy = (self.sums[2] - self.sums[0]) / self.step as f64;
        Some(((gx * gx + gy * gy).sqrt() / self.sums[0]) as f32)
    }
}
