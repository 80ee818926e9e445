//! The caches at work at one shading point, for one block of one pass: which cache serves
//! the point (glossy surfaces: SDRC, [`crate::glossy`]; diffuse ones: the irradiance cache,
//! [`crate::irradiance`]), record lookup and creation, and what both share (record frames,
//! sample streams, rays that gather reflected light).

use crate::harmonics::ShRadiance;
use crate::irradiance::Irradiance;
use crate::ltree::LTree;
use crate::options::{CacheOrPath, LambertianLobe};
use crate::photons::{PhotonGather, PhotonMap};
use crate::sdrc::{GlossyCache, Sdrc};
use crate::spatial::{Delta, SpatialCache};
use fenestra_core::stats::RayCounters;
use fenestra_core::{Frame, Ray, Rgb, Sampler, Vec3};
use fenestra_render::bsdf::Bsdf;
use fenestra_render::integrator::{Gather, NoGather, Shading, Start};
use fenestra_render::light::LightRecords;
use fenestra_render::RenderScene;
use fenestra_scene::Hit;

/// Whether SDRC serves a surface of this BSDF: glossy reflection, neither ideal (mirror,
/// glass) nor diffuse, nor transmissive.
pub fn is_glossy(b: &Bsdf) -> bool {
    !b.is_delta() && !b.is_transmissive() && !matches!(b, Bsdf::Diffuse(_))
}

/// Which cache serves a surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Served {
    /// SDRC (glossy, sdrc).
    Glossy,
    /// SH radiance caching (glossy, shrc).
    Harmonics(u32),
    /// The irradiance cache (Lambertian, of this albedo).
    Diffuse(Rgb),
}

/// Both caches, as earlier passes left them.
#[derive(Debug)]
pub struct Caches {
    /// SDRC records.
    pub glossy: SpatialCache<LTree>,
    /// SH records (shrc).
    pub harmonics: SpatialCache<ShRadiance>,
    /// Irradiance records.
    pub diffuse: SpatialCache<Irradiance>,
    /// Light beyond the records' rays (empty: their paths are traced on).
    pub photons: PhotonMap,
}

impl Caches {
    /// Merges the blocks' additions to both caches, in block order.
    pub fn merge(&mut self, works: Vec<Work>) {
        let (mut glossy, mut harmonics, mut diffuse) = (Vec::new(), Vec::new(), Vec::new());
        for w in works {
            glossy.push(w.glossy);
            harmonics.push(w.harmonics);
            diffuse.push(w.diffuse);
        }
        self.glossy.merge(glossy);
        self.harmonics.merge(harmonics);
        self.diffuse.merge(diffuse);
    }
}

/// What one block adds to both caches during a pass.
#[derive(Debug, Default)]
pub struct Work {
    /// Additions to the SDRC records.
    pub glossy: Delta<LTree>,
    /// New SH records.
    pub harmonics: Delta<ShRadiance>,
    /// Additions to the irradiance records.
    pub diffuse: Delta<Irradiance>,
    /// Pixels (x, y) of the samples whose indirect light a cache gave, one entry a sample.
    pub served: Vec<(u32, u32)>,
    /// Candidates of photon lookups (scratch).
    pub photon_scratch: Vec<(f32, u32)>,
}

/// The caches at work for one block of one pass.
pub struct CacheGather<'a> {
    /// The integrator (options, path tracer, camera footprint).
    pub sdrc: &'a Sdrc,
    /// Records of earlier passes.
    pub caches: &'a Caches,
    /// The block's additions.
    pub work: &'a mut Work,
    /// Factor on the maximum interpolation errors a (eq. 2.1): 1 when placing records, the
    /// seed's 1.3 in the render passes.
    pub a_scale: f32,
    /// Seed of the render.
    pub seed: u64,
    /// Distinguishes the streams of record rays made in different phases.
    pub phase: u64,
}

impl CacheGather<'_> {
    /// Which cache serves `s`, if any: points seen from the camera (`segments` 1) whose
    /// cached light comes from paths within the length limit.
    pub fn served(&self, s: &Shading, segments: u32) -> Option<Served> {
        if segments != 1 || segments + 2 > self.sdrc.max_depth() {
            return None;
        }
        match s.bsdf {
            Bsdf::Diffuse(d) if self.sdrc.options.diffuse == CacheOrPath::Cache => {
                Some(Served::Diffuse(d.reflectance))
            }
            b if is_glossy(b) => match self.sdrc.glossy {
                GlossyCache::Directional => Some(Served::Glossy),
                GlossyCache::Harmonics { rays } => Some(Served::Harmonics(rays)),
                GlossyCache::Path => None,
            },
            _ => None,
        }
    }

    /// The Lambertian albedo of a glossy point's BSDF and its glossy lobe, when the
    /// irradiance cache serves the one and the glossy cache the other.
    fn split(&self, s: &Shading) -> Option<(Rgb, Bsdf)> {
        let o = &self.sdrc.options;
        (o.lambertian_lobe == LambertianLobe::Cache && o.diffuse == CacheOrPath::Cache)
            .then(|| s.bsdf.lambertian_split())
            .flatten()
    }

    /// The record lookups at `s` in the caches that serve it, creating records where none
    /// is near; each cache's delta holds the records found in `near`.
    pub fn ensure_records(
        &mut self,
        scene: &RenderScene,
        s: &Shading,
        served: Served,
        rays: &mut RayCounters,
    ) {
        match (served, self.split(s)) {
            (Served::Diffuse(_), _) => self.ensure_irradiance(scene, s, rays),
            (_, Some((_, lobe))) => {
                self.ensure_glossy(scene, &with_bsdf(s, &lobe), served, rays);
                self.ensure_irradiance(scene, s, rays);
            }
            (_, None) => self.ensure_glossy(scene, s, served, rays),
        }
    }

    /// The glossy cache's lookup (SDRC or SH) at `s`, creating a record if none is near.
    fn ensure_glossy(
        &mut self,
        scene: &RenderScene,
        s: &Shading,
        served: Served,
        rays: &mut RayCounters,
    ) {
        let (n, a) = (viewer_normal(s), self.a_glossy());
        if let Served::Harmonics(count) = served {
            if !self
                .caches
                .harmonics
                .lookup(&mut self.work.harmonics, s.si.p, n, a)
            {
                let record = self.new_sh_record(scene, s, n, count, rays);
                self.caches
                    .harmonics
                    .create(&mut self.work.harmonics, record);
            }
        } else if !self
            .caches
            .glossy
            .lookup(&mut self.work.glossy, s.si.p, n, a)
        {
            let record = self.new_glossy_record(scene, s, n, rays);
            self.caches.glossy.create(&mut self.work.glossy, record);
        }
    }

    /// The irradiance cache's lookup at `s`, creating a record if none is near.
    fn ensure_irradiance(&mut self, scene: &RenderScene, s: &Shading, rays: &mut RayCounters) {
        let (n, a) = (viewer_normal(s), self.a_diffuse());
        if !self
            .caches
            .diffuse
            .lookup(&mut self.work.diffuse, s.si.p, n, a)
        {
            let record = self.new_irradiance_record(scene, s, n, rays);
            self.caches.diffuse.create(&mut self.work.diffuse, record);
        }
    }

    /// Light of the glossy cache reflected at `s` (its records looked up).
    fn glossy_at(
        &mut self,
        scene: &RenderScene,
        s: &Shading,
        served: Served,
        rays: &mut RayCounters,
    ) -> Rgb {
        if let Served::Harmonics(_) = served {
            let counts = &mut self.work.harmonics.counts;
            counts.points += 1;
            counts.records_used += self.work.harmonics.near.len() as u64;
            self.sh_outgoing(s)
        } else {
            let counts = &mut self.work.glossy.counts;
            counts.points += 1;
            counts.records_used += self.work.glossy.near.len() as u64;
            self.glossy_outgoing(scene, s, rays)
        }
    }

    /// Light of the irradiance cache reflected by a Lambertian lobe of `albedo` at `s` (its
    /// records looked up).
    fn diffuse_at(&mut self, s: &Shading, albedo: Rgb) -> Rgb {
        let counts = &mut self.work.diffuse.counts;
        counts.points += 1;
        counts.records_used += self.work.diffuse.near.len() as u64;
        albedo * self.irradiance(s) * std::f32::consts::FRAC_1_PI
    }

    /// SDRC's maximum interpolation error in this phase.
    pub fn a_glossy(&self) -> f32 {
        self.a_scale * self.sdrc.options.a
    }

    /// The irradiance cache's maximum interpolation error in this phase.
    pub fn a_diffuse(&self) -> f32 {
        self.a_scale * self.sdrc.options.irradiance_a
    }

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
        let (lo, hi) = self.sdrc.radius_bounds(s.si.t, a);
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
        let gather: &mut dyn Gather = if self.caches.photons.is_empty() {
            none = NoGather;
            &mut none
        } else {
            photons = PhotonGather {
                map: &self.caches.photons,
                scratch: &mut self.work.photon_scratch,
            };
            &mut photons
        };
        let tracer = &self.sdrc.tracer;
        tracer.trace(scene, ray, start, sampler, s.sample, off, rays, gather)
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
        let served = self.served(s, segments)?;
        self.work.served.push((s.sample.x, s.sample.y));
        Some(match (served, self.split(s)) {
            (Served::Diffuse(albedo), _) => {
                self.ensure_irradiance(scene, s, rays);
                self.diffuse_at(s, albedo)
            }
            (_, Some((albedo, lobe))) => {
                let glossy = with_bsdf(s, &lobe);
                self.ensure_glossy(scene, &glossy, served, rays);
                let l = self.glossy_at(scene, &glossy, served, rays);
                self.ensure_irradiance(scene, s, rays);
                l + self.diffuse_at(s, albedo)
            }
            (_, None) => {
                self.ensure_glossy(scene, s, served, rays);
                self.glossy_at(scene, s, served, rays)
            }
        })
    }
}

/// `s` with the BSDF `bsdf` (a lobe of its own).
fn with_bsdf<'a>(s: &Shading<'a>, bsdf: &'a Bsdf) -> Shading<'a> {
    Shading {
        si: s.si,
        bsdf,
        frame: s.frame,
        wo: s.wo,
        wo_local: s.wo_local,
        sample: s.sample,
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
