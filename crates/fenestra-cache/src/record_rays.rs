//! The rays a cache record is made from: traced from the record's point, each brings back the
//! light reflected towards it by a path one segment longer than the point's (ended by the
//! photon map at diffuse surfaces, if there is one); their hit distances set the record's
//! validity radius R_i. What every kind of cache shares.

use crate::footprint::PixelFootprint;
use crate::photons::{PhotonGather, PhotonMap};
use fenestra_core::stats::RayCounters;
use fenestra_core::{Frame, Ray, Rgb, Sampler, Vec3};
use fenestra_render::integrator::{Gather, LightNextEvent, NoGather, PathTracer, Shading, Start};
use fenestra_render::light::LightRecords;
use fenestra_render::path_sample::PathSample;
use fenestra_render::RenderScene;
use fenestra_scene::Hit;

/// What records' rays read, and the scratch they use.
pub(crate) struct RecordRays<'a> {
    /// The integrator's path tracer, for the paths beyond a record's rays.
    pub(crate) tracer: &'a PathTracer<LightNextEvent>,
    /// Light beyond the records' rays (empty: their paths are traced on).
    pub(crate) photons: &'a PhotonMap,
    /// Candidates of photon lookups (scratch).
    pub(crate) photon_scratch: Vec<(f32, u32)>,
    /// The camera's pixels, and the least R_i in them.
    pub(crate) footprint: PixelFootprint,
    pub(crate) min_reach: f32,
    /// Seed of the render.
    pub(crate) seed: u64,
    /// Distinguishes the streams of record rays made in different phases.
    pub(crate) phase: u64,
}

impl RecordRays<'_> {
    /// R_i of a record under maximum error `a` from its rays' hit distances (their harmonic
    /// mean), limited to 1 / `relative_gradient` where the outgoing light changes faster
    /// (§2.4.6), and clamped to the bounds of its reach in pixels.
    pub(crate) fn radius(
        &self,
        s: &Shading,
        a: f32,
        distances: &Distances,
        relative_gradient: Option<f32>,
    ) -> f32 {
        let (lo, hi) = self.footprint.radius_bounds(s.si.t, a, self.min_reach);
        let mut r = if distances.hits > 0 {
            (distances.hits as f64 / distances.inverse) as f32
        } else {
            hi
        };
        if let Some(g) = relative_gradient.filter(|g| g * r > 1.0) {
            r = 1.0 / g;
        }
        r.clamp(lo, hi)
    }

    /// The ray of a record at `s` (hemisphere `frame`, geometric normal `ng` on its side)
    /// along the record-frame direction `local`: the light reflected back along it and its
    /// hit distance, noted in `distances`; nothing for directions below the geometric surface.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn record_ray(
        &mut self,
        scene: &RenderScene,
        s: &Shading,
        (frame, ng): (&Frame, Vec3),
        local: Vec3,
        sampler: &mut Sampler,
        rays: &mut RayCounters,
        distances: &mut Distances,
    ) -> (Rgb, f32) {
        let w = frame.to_world(local);
        if w.dot(ng) <= 0.0 {
            return (Rgb::ZERO, f32::INFINITY);
        }
        let (l, t) = self.reflected(scene, Ray::new(s.si.spawn(w), w), sampler, s, rays);
        distances.add(t);
        (l, t)
    }

    /// A record's rays over its stratified hemisphere (`frame`, geometric normal `ng`):
    /// `rings` x `sectors` cells, ring j's (sin, cos) of theta from `ring((j + u) / rings)`,
    /// phi jittered in its sector; per cell, ring-major: (local direction, radiance,
    /// distance, sin theta, phi). Stream `tag`; hit distances go to `distances`.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn stratified(
        &mut self,
        scene: &RenderScene,
        s: &Shading,
        (frame, ng): (&Frame, Vec3),
        tag: u64,
        (rings, sectors): (usize, usize),
        ring: impl Fn(f32) -> (f32, f32),
        rays: &mut RayCounters,
        distances: &mut Distances,
    ) -> Vec<Cell> {
        let mut cells = Vec::with_capacity(rings * sectors);
        for j in 0..rings {
            for k in 0..sectors {
                let mut sampler = self.record_stream(s, tag, (j * sectors + k) as u32);
                let u = sampler.next_2d();
                let (sin, cos) = ring((j as f32 + u.x) / rings as f32);
                let phi = std::f32::consts::TAU * (k as f32 + u.y) / sectors as f32;
                let local = Vec3::new(sin * phi.cos(), sin * phi.sin(), cos);
                let (l, t) =
                    self.record_ray(scene, s, (frame, ng), local, &mut sampler, rays, distances);
                cells.push(Cell {
                    local,
                    l,
                    t,
                    sin,
                    phi,
                });
            }
        }
        cells
    }

    /// The sample stream `k` of a record made at `s` (`tag` tells the caches apart).
    pub(crate) fn record_stream(&self, s: &Shading, tag: u64, k: u32) -> Sampler {
        let key = s.sample.pixel() << 32 | s.sample.index as u64;
        Sampler::new(self.seed ^ tag ^ self.phase, key, k)
    }

    /// Light reflected towards `origin` by the surface a ray from `origin` along `w` finds
    /// (emitted light excluded: next events count it), by a path one segment longer than the
    /// point's (ended by the photon map at diffuse surfaces, if there is one), and the hit's
    /// distance (infinite for rays that escape: the environment is
    /// direct light).
    pub(crate) fn reflected(
        &mut self,
        scene: &RenderScene,
        ray: Ray,
        sampler: &mut Sampler,
        s: &Shading,
        rays: &mut RayCounters,
    ) -> (Rgb, f32) {
        rays.bounce += 1;
        let Some(hit) = scene.scene.intersect(&ray, f32::INFINITY) else {
            return (Rgb::ZERO, f32::INFINITY);
        };
        let t = hit.t;
        let l = self.trace_from(scene, ray, Some(hit), sampler, s, rays);
        (l, t)
    }

    /// [`Self::reflected`] without the distance, for a ray not yet intersected (`hit` None).
    pub(crate) fn trace_from(
        &mut self,
        scene: &RenderScene,
        ray: Ray,
        hit: Option<Hit>,
        sampler: &mut Sampler,
        s: &Shading,
        rays: &mut RayCounters,
    ) -> Rgb {
        let start = Start {
            segments: 1,
            emitted: false,
            hit,
        };
        // Cache rays teach no light sampler.
        let off = &mut LightRecords::off();
        let (mut none, mut photons);
        let gather: &mut dyn Gather = if self.photons.is_empty() {
            none = NoGather;
            &mut none
        } else {
            photons = PhotonGather {
                map: self.photons,
                scratch: &mut self.photon_scratch,
            };
            &mut photons
        };
        let sample = &mut PathSample {
            ctx: s.sample,
            sampler,
            records: off,
            rays,
        };
        self.tracer.trace(scene, ray, start, sample, gather)
    }
}

/// A cell of a record's stratified hemisphere and what its ray brought back.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Cell {
    /// The ray's direction in the record's frame.
    pub local: Vec3,
    /// Radiance reflected back along it.
    pub l: Rgb,
    /// Its hit distance (infinite: it escaped or went below the surface).
    pub t: f32,
    /// sin theta and phi of the direction.
    pub sin: f32,
    pub phi: f32,
}

/// Hit distances of a record's rays, for R_i (their harmonic mean).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Distances {
    hits: u32,
    inverse: f64,
}

impl Distances {
    /// A ray that went `t` (infinite: it escaped).
    pub(crate) fn add(&mut self, t: f32) {
        if t.is_finite() && t > 0.0 {
            self.hits += 1;
            self.inverse += 1.0 / t as f64;
        }
    }
}

/// The shading normal on the side the point is seen from.
pub(crate) fn viewer_normal(s: &Shading) -> Vec3 {
    if s.wo_local.z < 0.0 {
        -s.si.ns
    } else {
        s.si.ns
    }
}

/// The geometric normal on the side the point is seen from.
pub(crate) fn viewer_geometric_normal(s: &Shading) -> Vec3 {
    if s.si.ng.dot(s.wo) < 0.0 {
        -s.si.ng
    } else {
        s.si.ng
    }
}
