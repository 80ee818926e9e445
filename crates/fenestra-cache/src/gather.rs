//! The caches at work at one shading point, for one block of one pass: which cache serves
//! the point (glossy surfaces: SDRC, [`crate::glossy`], or SH radiance, [`crate::harmonics`];
//! diffuse ones: the irradiance cache, [`crate::irradiance`]), each kind's record lookup and
//! creation ([`crate::kind::CacheKind`]), and what is interpolated where.

use crate::footprint::PixelFootprint;
use crate::glossy::SdrcRecords;
use crate::harmonics::{ShRadiance, ShRecords};
use crate::irradiance::{Irradiance, IrradianceRecords};
use crate::kind::CacheKind;
use crate::ltree::LTree;
use crate::options::{CacheOrPath, LambertianLobe, SdrcOptions};
use crate::photons::PhotonMap;
use crate::record_rays::{viewer_normal, RecordRays};
use crate::spatial::{Delta, SpatialCache};
use fenestra_core::stats::RayCounters;
use fenestra_core::Rgb;
use fenestra_render::bsdf::Bsdf;
use fenestra_render::integrator::{Gather, LightNextEvent, PathTracer, Shading};
use fenestra_render::RenderScene;

/// What caches indirect light on glossy surfaces.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GlossyCache {
    /// SDRC's L-trees of BRDF-sampled radiance (integrator `sdrc`).
    Directional,
    /// SH radiance caching from `rays` uniform rays per record (integrator `shrc`).
    Harmonics {
        /// Rays per record.
        rays: u32,
    },
    /// No cache: glossy surfaces path traced by BSDF sampling, the rest as sdrc (the seed's
    /// Monte Carlo baseline, §2.6: the same caches and direct light but for the glossy
    /// first bounce).
    Path,
}

/// What the caches at work read from their integrator during a render.
#[derive(Clone, Copy)]
pub struct CacheSetup<'a> {
    /// The path tracer, for the paths beyond the records' rays.
    pub tracer: &'a PathTracer<LightNextEvent>,
    /// The integrator's options.
    pub options: &'a SdrcOptions,
    /// What caches glossy surfaces.
    pub glossy: GlossyCache,
    /// Maximum path length.
    pub max_depth: u32,
    /// The camera's pixels in this render.
    pub(crate) footprint: PixelFootprint,
}

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
    /// What the integrator gives them.
    pub setup: &'a CacheSetup<'a>,
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

impl<'a> CacheGather<'a> {
    /// Which cache serves `s`, if any: points seen from the camera (`segments` 1) whose
    /// cached light comes from paths within the length limit.
    pub fn served(&self, s: &Shading, segments: u32) -> Option<Served> {
        if segments != 1 || segments + 2 > self.setup.max_depth {
            return None;
        }
        match s.bsdf {
            Bsdf::Diffuse(d) if self.setup.options.diffuse == CacheOrPath::Cache => {
                Some(Served::Diffuse(d.reflectance))
            }
            b if is_glossy(b) => match self.setup.glossy {
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
        let o = self.setup.options;
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
            (Served::Diffuse(_), _) => {
                self.diffuse(scene, s, false, rays);
            }
            (_, Some((_, lobe))) => {
                self.glossy(scene, &with_bsdf(s, &lobe), served, false, rays);
                self.diffuse(scene, s, false, rays);
            }
            (_, None) => {
                self.glossy(scene, s, served, false, rays);
            }
        }
    }

    /// The glossy cache's lookup (SDRC or SH) at `s`, creating a record if none is near;
    /// then, if `read`, the light it reflects there.
    fn glossy(
        &mut self,
        scene: &RenderScene,
        s: &Shading,
        served: Served,
        read: bool,
        rays: &mut RayCounters,
    ) -> Rgb {
        let (options, a) = (self.setup.options, self.a_scale * self.setup.options.a);
        let mut tracing = self.record_rays();
        let at = Lookup { scene, s, a, read };
        let l = if let Served::Harmonics(count) = served {
            let kind = ShRecords {
                rays: count,
                m: options.m,
            };
            let delta = &mut self.work.harmonics;
            at.run(&kind, &self.caches.harmonics, delta, &mut tracing, rays)
        } else {
            let kind = SdrcRecords {
                n: options.n,
                m: options.m,
                query_samples: options.query_samples,
                r_max: options.r_max,
            };
            at.run(
                &kind,
                &self.caches.glossy,
                &mut self.work.glossy,
                &mut tracing,
                rays,
            )
        };
        self.work.photon_scratch = tracing.photon_scratch;
        l
    }

    /// The irradiance cache's lookup at `s`, creating a record if none is near; then, if
    /// `read`, the irradiance there.
    fn diffuse(
        &mut self,
        scene: &RenderScene,
        s: &Shading,
        read: bool,
        rays: &mut RayCounters,
    ) -> Rgb {
        let options = self.setup.options;
        let a = self.a_scale * options.irradiance_a;
        let mut tracing = self.record_rays();
        let kind = IrradianceRecords {
            rays: options.irradiance_rays,
            gradients: options.irradiance_gradients,
        };
        let at = Lookup { scene, s, a, read };
        let e = at.run(
            &kind,
            &self.caches.diffuse,
            &mut self.work.diffuse,
            &mut tracing,
            rays,
        );
        self.work.photon_scratch = tracing.photon_scratch;
        e
    }

    /// The rays records are made from, with the block's photon lookup scratch (to be given
    /// back to the block's work).
    fn record_rays(&mut self) -> RecordRays<'a> {
        let (setup, caches) = (self.setup, self.caches);
        RecordRays {
            tracer: setup.tracer,
            photons: &caches.photons,
            photon_scratch: std::mem::take(&mut self.work.photon_scratch),
            footprint: setup.footprint,
            min_reach: setup.options.min_reach,
            seed: self.seed,
            phase: self.phase,
        }
    }
}

/// A lookup in one cache at a shading point.
struct Lookup<'a, 's> {
    scene: &'a RenderScene,
    s: &'a Shading<'s>,
    /// The maximum interpolation error in this phase.
    a: f32,
    /// Whether to read the records found (else only find or create them).
    read: bool,
}

impl Lookup<'_, '_> {
    /// Finds the records of `cache` near the point, creating one of `kind` if none is near,
    /// and, if the lookup reads them, what they give there (else black).
    fn run<K: CacheKind>(
        &self,
        kind: &K,
        cache: &SpatialCache<K::Payload>,
        delta: &mut Delta<K::Payload>,
        tracing: &mut RecordRays,
        rays: &mut RayCounters,
    ) -> Rgb {
        let s = self.s;
        if !cache.lookup(delta, s.si.p, viewer_normal(s), self.a) {
            let record = kind.create(tracing, delta, self.scene, s, self.a, rays);
            cache.create(delta, record);
        }
        if !self.read {
            return Rgb::ZERO;
        }
        delta.counts.points += 1;
        delta.counts.records_used += delta.near.len() as u64;
        kind.interpolate(tracing, cache, delta, self.scene, s, rays)
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
        let lambertian = std::f32::consts::FRAC_1_PI;
        Some(match (served, self.split(s)) {
            (Served::Diffuse(albedo), _) => {
                albedo * self.diffuse(scene, s, true, rays) * lambertian
            }
            (_, Some((albedo, lobe))) => {
                let l = self.glossy(scene, &with_bsdf(s, &lobe), served, true, rays);
                l + albedo * self.diffuse(scene, s, true, rays) * lambertian
            }
            (_, None) => self.glossy(scene, s, served, true, rays),
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
        sides: s.sides,
        sample: s.sample,
    }
}
