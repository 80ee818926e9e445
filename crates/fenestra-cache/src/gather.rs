//! Algorithm 1 of seed 003 at one shading point: look up records, create one if none is near
//! (§2.4.3), interpolate incoming radiance for M BRDF-sampled directions from the records'
//! samples (§2.4.4), add samples by tracing from a record where none is near, and estimate
//! outgoing radiance (eq. 2.3).

use crate::ltree::{LTree, Sample};
use crate::paraboloid;
use crate::record::Record;
use crate::sdrc::Sdrc;
use crate::spatial::{Delta, SpatialCache};
use fenestra_core::stats::RayCounters;
use fenestra_core::{Frame, Ray, Rgb, Sampler, Vec3};
use fenestra_render::bsdf::Bsdf;
use fenestra_render::integrator::{Gather, NoGather, Shading, Start};
use fenestra_render::RenderScene;

/// Seeds of the sample streams the cache draws (xor-ed with the render's seed).
const DIRECTIONS: u64 = 0x5d5c_0001;
const RECORD_RAYS: u64 = 0x5d5c_0002;

/// Whether the cache serves a surface of this BSDF: glossy reflection, neither ideal
/// (mirror, glass) nor diffuse, nor transmissive.
pub fn is_glossy(b: &Bsdf) -> bool {
    !b.is_delta() && !b.is_transmissive() && !matches!(b, Bsdf::Diffuse(_))
}

/// The cache at work for one block of one pass: the shared cache, the block's additions,
/// the maximum error of this pass.
pub struct CacheGather<'a> {
    /// The integrator (options, path tracer, camera footprint).
    pub sdrc: &'a Sdrc,
    /// Records of earlier passes.
    pub cache: &'a SpatialCache,
    /// The block's additions.
    pub delta: &'a mut Delta,
    /// Maximum interpolation error a (eq. 2.1).
    pub a: f32,
    /// Seed of the render.
    pub seed: u64,
    /// Distinguishes the streams of record rays made in different phases.
    pub phase: u64,
    /// Samples the pixel takes: its M directions are shared among them.
    pub spp: u32,
}

impl CacheGather<'_> {
    /// The record lookup of `s`, creating a record there if none is near; `delta.near`
    /// holds the records found.
    pub fn ensure_records(&mut self, scene: &RenderScene, s: &Shading, rays: &mut RayCounters) {
        let n = viewer_normal(s);
        self.cache.lookup(self.delta, s.si.p, n, self.a);
        if self.delta.near.is_empty() {
            let record = self.new_record(scene, s, n, rays);
            let id = self.cache.create(self.delta, record);
            self.delta.near.push((id, 1.0));
        }
    }

    /// A new record at `s` (§2.4.3): N BRDF-sampled rays, their radiance, R_i from their
    /// lengths, clamped by the outgoing radiance's gradient (§2.4.6) and to the pixel
    /// footprint's bounds.
    fn new_record(
        &mut self,
        scene: &RenderScene,
        s: &Shading,
        n: Vec3,
        rays: &mut RayCounters,
    ) -> Record {
        let frame = Frame::from_normal(n);
        let ng = if s.si.ng.dot(s.wo) < 0.0 {
            -s.si.ng
        } else {
            s.si.ng
        };
        let key = stream_key(s);
        let count = self.sdrc.options.n;
        let mut samples = Vec::with_capacity(count as usize);
        let mut gradient = Gradient::new(s, self.sdrc.footprint(s.si.t));
        let (mut hits, mut inverse) = (0u32, 0.0f64);
        for k in 0..count {
            let mut sampler = Sampler::new(self.seed ^ RECORD_RAYS ^ self.phase, key, k);
            let Some((w, weight, pdf)) = sample_bsdf(s, &mut sampler) else {
                gradient.skip();
                continue;
            };
            let ray = Ray::new(s.si.spawn(w), w);
            rays.bounce += 1;
            self.delta.counts.record_rays += 1;
            let (l, t) = match scene.scene.intersect(&ray, f32::INFINITY) {
                // Escaping rays bring the environment: direct light, counted by next events.
                None => (Rgb::ZERO, f32::INFINITY),
                Some(hit) => {
                    let start = Start {
                        segments: 1,
                        emitted: false,
                        hit: Some(hit),
                    };
                    let ctx = s.sample;
                    let l = self.sdrc.tracer.trace(
                        scene,
                        ray,
                        start,
                        &mut sampler,
                        ctx,
                        rays,
                        &mut NoGather,
                    );
                    (l, hit.t)
                }
            };
            if t.is_finite() && t > 0.0 {
                hits += 1;
                inverse += 1.0 / t as f64;
            }
            gradient.add(l, w, t, weight, pdf);
            samples.push(Sample::new(paraboloid::to_disc(frame.to_local(w)), l));
        }
        let footprint = self.sdrc.footprint(s.si.t);
        let (lo, hi) = self.sdrc.radius_bounds(footprint, self.a);
        let mut r = if hits > 0 {
            (hits as f64 / inverse) as f32
        } else {
            hi
        };
        // §2.4.6: R_i := 1/Delta_i where the outgoing radiance changes faster than 1/R_i.
        if let Some(delta) = gradient.relative() {
            if delta * r > 1.0 {
                r = 1.0 / delta;
            }
        }
        Record {
            si: *s.si,
            frame,
            ng,
            r: r.clamp(lo, hi),
            ltree: LTree::build(samples),
            pixel: (s.sample.x, s.sample.y),
        }
    }

    /// Outgoing radiance at `s` from its share of the pixel's M directions (eq. 2.3),
    /// interpolated from the records in `delta.near` (§2.4.4) or traced from one of them.
    /// The directions of a pixel's samples are one Sobol sequence.
    fn outgoing(&mut self, scene: &RenderScene, s: &Shading, rays: &mut RayCounters) -> Rgb {
        let m = self.sdrc.options.directions_per_sample(self.spp);
        let pixel_m = (m * self.spp) as f32;
        let first = s.sample.index.wrapping_mul(m);
        let near = std::mem::take(&mut self.delta.near);
        self.delta.counts.points += 1;
        self.delta.counts.records_used += near.len() as u64;
        let (mut sum, mut used) = (Rgb::ZERO, 0u32);
        for j in 0..m {
            let mut sampler = Sampler::new(self.seed ^ DIRECTIONS, s.sample.pixel(), first + j);
            let Some((w, weight, pdf)) = sample_bsdf(s, &mut sampler) else {
                used += 1;
                continue;
            };
            // Query radius in D (§2.4.4): directions of density M p lie about 1/(M p) apart in
            // solid angle, so r_d = 1 / (2 pi sqrt(M p)) (docs/sdrc.md on the seed's formula).
            // It starts from the pixel's M, so that the pixel's directions see disjoint
            // samples, and doubles up to the sample's own share of M while nothing is found;
            // only then is a ray traced.
            let at = |count: f32| {
                (1.0 / (std::f32::consts::TAU * (count * pdf).sqrt())).min(self.sdrc.options.r_max)
            };
            let (mut radius, widest) = (at(pixel_m), at(m as f32));
            let (l, total) = loop {
                let (l, total) = self.interpolate(&near, w, radius);
                if total > 0.0 || radius >= widest {
                    break (l, total);
                }
                radius = (radius * 2.0).min(widest);
            };
            let lin = if total > 0.0 {
                self.delta.counts.interpolated += 1;
                l * (1.0 / total)
            } else {
                match self.update(scene, s, &near, w, &mut sampler, rays) {
                    Some(l) => l,
                    None => {
                        self.delta.counts.rejected += 1;
                        continue;
                    }
                }
            };
            sum += lin * weight;
            used += 1;
        }
        self.delta.near = near;
        if used == 0 {
            Rgb::ZERO
        } else {
            sum * (1.0 / used as f32)
        }
    }

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
            record.ltree.within(d, radius, &mut take);
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
    fn update(
        &mut self,
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
        rays.bounce += 1;
        self.delta.counts.update_rays += 1;
        let start = Start {
            segments: 1,
            emitted: false,
            hit: None,
        };
        let l = self
            .sdrc
            .tracer
            .trace(scene, ray, start, sampler, s.sample, rays, &mut NoGather);
        self.cache.add(self.delta, id, Sample::new(d, l));
        Some(l)
    }
}

impl Gather for CacheGather<'_> {
    fn indirect(
        &mut self,
        scene: &RenderScene,
        s: &Shading,
        segments: u32,
        rays: &mut RayCounters,
    ) -> Option<Rgb> {
        // The first bounce of indirect light on glossy surfaces seen from the camera; the
        // cached samples are paths one segment longer than the point's.
        if segments != 1 || segments + 2 > self.sdrc.max_depth() || !is_glossy(s.bsdf) {
            return None;
        }
        self.ensure_records(scene, s, rays);
        self.delta.served.push((s.sample.x, s.sample.y));
        Some(self.outgoing(scene, s, rays))
    }
}

/// The shading normal on the side the point is seen from.
fn viewer_normal(s: &Shading) -> Vec3 {
    if s.wo_local.z < 0.0 {
        -s.si.ns
    } else {
        s.si.ns
    }
}

/// The stream key of the sample at `s`: its pixel and index.
fn stream_key(s: &Shading) -> u64 {
    s.sample.pixel() << 32 | s.sample.index as u64
}

/// A BSDF-sampled direction at `s` (world), its weight f cos / pdf and density; `None` where
/// sampling fails or the direction leaves through the wrong side.
fn sample_bsdf(s: &Shading, sampler: &mut Sampler) -> Option<(Vec3, Rgb, f32)> {
    let uc = sampler.next_1d();
    let u = sampler.next_2d();
    let bs = s.bsdf.sample(s.wo_local, uc, u)?;
    let w = s.frame.to_world(bs.wi);
    (s.sides_agree(w, bs.wi.z) && bs.pdf > 0.0).then_some((w, bs.weight, bs.pdf))
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
