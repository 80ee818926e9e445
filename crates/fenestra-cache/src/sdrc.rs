//! `sdrc`: spatial directional radiance caching (seed 003 ch. 2) for the first bounce of
//! indirect light on glossy surfaces seen from the camera; everything else is af_hf's path
//! tracing (direct light by light and BSDF sampling with MIS at every vertex, indirect light
//! on other surfaces and the cached samples' own paths).
//!
//! Two phases, as the seed's two passes (§2.5): records are placed from one camera ray per
//! pixel, coarse to fine (every 64th pixel, then every 32nd, ... 2nd, 1st), with maximum
//! error a;
//! then the image is rendered in passes of one sample per pixel with a x 1.3, adding samples
//! to the records (lazy updates) and records where none is near.

use crate::footprint::PixelFootprint;
use crate::gather::{CacheGather, CacheSetup, Caches, GlossyCache, Work};
use crate::options::{CacheOrPath, SdrcOptions, ShrcOptions};
use crate::photons::PhotonMap;
use crate::spatial::{Counts, SpatialCache};
use fenestra_core::stats::{RayCounters, RenderStats};
use fenestra_core::{Rgb, Sampler};
use fenestra_render::control::RenderControl;
use fenestra_render::driver::{
    render_passes, Budget, PassEstimator, PassInfo, PixelState, BLOCK_SIZE,
};
use fenestra_render::features::Feature;
use fenestra_render::film::Window;
use fenestra_render::integrator::{
    Integrator, IntegratorError, LightNextEvent, PathOptions, PathTracer, Shading, Sides, Split,
    WorkMap,
};
use fenestra_render::light::LightRecords;
use fenestra_render::options::{OptionError, Options};
use fenestra_render::path_sample::Wave;
use fenestra_render::sample_context::SampleContext;
use fenestra_render::{Film, RenderScene, RenderSettings};
use rayon::prelude::*;
use std::sync::Mutex;
use std::time::Instant;

/// Seed of the record-placement phase's camera samples (xor-ed with the render's seed).
const PLACEMENT: u64 = 0x5d5c_0003;

/// The placement phase's pixel grids, coarse to fine. Blocks of one level do not see each
/// other's new records, so a level whose grid holds a pixel in every 8x8 block would give
/// every block its own record whatever a allows: the coarse levels (one pixel in 64 blocks,
/// then 16, 4) let records spread before the block grid could set their density.
const PLACEMENT_STRIDES: [u32; 7] = [64, 32, 16, 8, 4, 2, 1];

/// The `sdrc` integrator.
pub struct Sdrc {
    pub(crate) tracer: PathTracer<LightNextEvent>,
    pub(crate) options: SdrcOptions,
    /// What caches glossy surfaces' indirect light.
    pub(crate) glossy: GlossyCache,
    path: PathOptions,
    /// The last render's pictures: records created per pixel, and the fraction of each
    /// pixel's samples whose indirect light the cache gave.
    maps: Mutex<Vec<WorkMap>>,
}

impl Sdrc {
    /// sdrc with `options`, over af_hf's path tracing with `path` and light sampling `lights`.
    pub fn new(
        options: SdrcOptions,
        path: PathOptions,
        lights: LightNextEvent,
    ) -> Result<Sdrc, IntegratorError> {
        let glossy = match options.glossy {
            CacheOrPath::Cache => GlossyCache::Directional,
            CacheOrPath::Path => GlossyCache::Path,
        };
        Self::with_glossy(options, glossy, path, lights)
    }

    /// shrc: sdrc with the SH radiance cache of `shrc` on glossy surfaces.
    pub fn harmonics(
        options: SdrcOptions,
        shrc: ShrcOptions,
        path: PathOptions,
        lights: LightNextEvent,
    ) -> Result<Sdrc, IntegratorError> {
        shrc.check()?;
        if options.glossy == CacheOrPath::Path {
            return Err(OptionError::new(
                "sdrc.glossy",
                "path leaves glossy surfaces to path tracing: that is sdrc's baseline, not shrc's",
            )
            .into());
        }
        let options = SdrcOptions {
            a: shrc.a,
            ..options
        };
        Self::with_glossy(
            options,
            GlossyCache::Harmonics { rays: shrc.rays },
            path,
            lights,
        )
    }

    fn with_glossy(
        options: SdrcOptions,
        glossy: GlossyCache,
        path: PathOptions,
        lights: LightNextEvent,
    ) -> Result<Sdrc, IntegratorError> {
        options.check()?;
        Ok(Sdrc {
            tracer: PathTracer::new(name(glossy), lights, path),
            options,
            glossy,
            path,
            maps: Mutex::new(Vec::new()),
        })
    }

    /// What the caches at work read in a render whose camera's pixels are `footprint`.
    fn setup(&self, footprint: PixelFootprint) -> CacheSetup<'_> {
        CacheSetup {
            tracer: &self.tracer,
            options: &self.options,
            glossy: self.glossy,
            max_depth: self.path.max_depth,
            footprint,
        }
    }

    /// Places records from one camera ray per pixel, coarse to fine (the seed's first pass).
    fn place_records(
        &self,
        setup: &CacheSetup,
        scene: &RenderScene,
        film: &Film,
        caches: &mut Caches,
        seed: u64,
        control: &RenderControl,
    ) -> RayCounters {
        let window = film.window;
        let blocks = fenestra_render::driver::Blocks::new(film.width, film.height);
        control
            .progress
            .start(Some(film.width as u64 * film.height as u64));
        let mut rays = RayCounters::default();
        for stride in PLACEMENT_STRIDES {
            if control.cancelled() {
                break;
            }
            // The pixels on this level's grid that no coarser level took.
            let on = |x: u32, y: u32, s: u32| x.is_multiple_of(s) && y.is_multiple_of(s);
            let first = stride == PLACEMENT_STRIDES[0];
            let level = |x: u32, y: u32| on(x, y, stride) && (first || !on(x, y, 2 * stride));
            let done: Vec<(Work, RayCounters)> = (0..blocks.count() as u32)
                .into_par_iter()
                .map(|b| {
                    let mut work = Work::default();
                    let mut rays = RayCounters::default();
                    if control.cancelled() {
                        return (work, rays);
                    }
                    let (bx, by) = (
                        (b % blocks.columns) * BLOCK_SIZE,
                        (b / blocks.columns) * BLOCK_SIZE,
                    );
                    let mut pixels = 0;
                    for y in by..(by + BLOCK_SIZE).min(film.height) {
                        for x in bx..(bx + BLOCK_SIZE).min(film.width) {
                            let (x, y) = (window.x0 + x, window.y0 + y);
                            if !level(x, y) {
                                continue;
                            }
                            pixels += 1;
                            let ctx = SampleContext {
                                x,
                                y,
                                width: window.full_width,
                                height: window.full_height,
                                block: b,
                                pass: 0,
                                index: 0,
                            };
                            let mut gather = CacheGather {
                                setup,
                                caches,
                                work: &mut work,
                                a_scale: 1.0,
                                seed,
                                phase: PLACEMENT,
                            };
                            place_at(scene, &ctx, seed, self.path.sides, &mut gather, &mut rays);
                        }
                    }
                    control.progress.advance(pixels);
                    (work, rays)
                })
                .collect();
            let mut works = Vec::with_capacity(done.len());
            for (work, r) in done {
                works.push(work);
                rays += r;
            }
            caches.merge(works);
        }
        rays
    }
}

/// The record lookup (and creation) at the glossy surface a placement camera ray finds.
fn place_at(
    scene: &RenderScene,
    ctx: &SampleContext,
    seed: u64,
    sides: Sides,
    gather: &mut CacheGather,
    rays: &mut RayCounters,
) {
    let mut sampler = Sampler::new(seed ^ PLACEMENT, ctx.pixel(), 0);
    let ray = ctx.camera_ray(&scene.scene.camera, &mut sampler, rays);
    let Some(hit) = scene.scene.intersect(&ray, f32::INFINITY) else {
        return;
    };
    let si = scene.scene.interaction(&ray, &hit);
    let bsdf = scene.bsdf_at(&si);
    let frame = si.shading_frame();
    let wo = -ray.d;
    let shading = Shading {
        si: &si,
        bsdf: &bsdf,
        frame,
        wo,
        wo_local: frame.to_local(wo),
        sides,
        sample: ctx,
    };
    if let Some(served) = gather.served(&shading, 1) {
        gather.ensure_records(scene, &shading, served, rays);
    }
}

impl Integrator for Sdrc {
    fn name(&self) -> &str {
        name(self.glossy)
    }

    fn settings(&self) -> serde_json::Value {
        let mut s = self.tracer.settings();
        if let Some(all) = s.as_object_mut() {
            all.insert(
                "sdrc".into(),
                serde_json::to_value(self.options).unwrap_or_default(),
            );
            if let GlossyCache::Harmonics { rays } = self.glossy {
                all.insert("shrc".into(), serde_json::json!({ "rays": rays }));
            }
        }
        s
    }

    fn prepare(
        &mut self,
        scene: &RenderScene,
        control: &RenderControl,
    ) -> Result<(), IntegratorError> {
        self.tracer.prepare(scene, control)
    }

    /// Records and their samples come from every pixel, and each pixel's estimate from the
    /// records near it: a piece of the render would not render as in the whole.
    fn split(&self) -> Split {
        Split::Whole
    }

    fn work_maps(&self) -> Vec<WorkMap> {
        self.maps.lock().unwrap_or_else(|e| e.into_inner()).clone()
    }

    fn render(
        &self,
        scene: &RenderScene,
        film: &mut Film,
        settings: &RenderSettings,
        control: &RenderControl,
    ) -> RenderStats {
        let started = Instant::now();
        let window = film.window;
        let footprint = PixelFootprint::measure(scene, window.full_width, window.full_height);
        let setup = self.setup(footprint);
        let (lo, hi) = scene.scene.bounds();
        let reach = |a: f32| a * self.options.a_scale;
        let photons = PhotonMap::trace(
            scene,
            self.options.photons,
            self.options.photon_k as usize,
            self.options.photon_radius * scene.scene.bounding_sphere().1,
            self.path.max_depth,
            settings.seed,
        );
        let photon_s = started.elapsed().as_secs_f64();
        if !photons.is_empty() {
            control.progress.note(&format!(
                "photon map: {} of {} photons stored in {photon_s:.2} s",
                photons.len(),
                photons.emitted
            ));
        }
        let mut caches = Caches {
            photons,
            glossy: SpatialCache::new(lo, hi, reach(self.options.a)),
            harmonics: SpatialCache::new(lo, hi, reach(self.options.a)),
            diffuse: SpatialCache::new(lo, hi, reach(self.options.irradiance_a)),
        };
        let placement_rays =
            self.place_records(&setup, scene, film, &mut caches, settings.seed, control);
        let placed = (
            caches.glossy.len(),
            caches.harmonics.len(),
            caches.diffuse.len(),
        );
        let placement_s = started.elapsed().as_secs_f64();
        // A time budget the placement used up still gets a sample per pixel: an image, not
        // a black frame.
        let time_left = settings.time_limit.map(|t| t - control.elapsed());
        if time_left.is_some_and(|t| t <= 0.0) {
            control.progress.note(&format!(
                "placing records took {placement_s:.1} s, the whole time budget: rendering one \
                 sample per pixel (a larger sdrc.min_reach places fewer records)"
            ));
        }
        let mut passes = Passes {
            sdrc: self,
            setup: &setup,
            caches,
            window: film.window,
            served: vec![0.0; film.pixels.len()],
            seed: settings.seed,
            // The render's clock runs from before the placement, which the limit covers.
            budget: Budget::new(
                settings.spp,
                settings.time_limit.map(|t| t.max(f64::MIN_POSITIVE)),
            ),
        };
        let mut stats = render_passes(&mut passes, scene, film, settings, control);
        stats.rays += placement_rays;
        stats.max_depth = Some(self.path.max_depth);
        let caches = passes.caches;
        match self.glossy {
            GlossyCache::Directional => figures(&mut stats, "sdrc", &caches.glossy, placed.0, true),
            GlossyCache::Harmonics { .. } => {
                figures(&mut stats, "shrc", &caches.harmonics, placed.1, false)
            }
            GlossyCache::Path => {}
        }
        figures(
            &mut stats,
            "sdrc_irradiance",
            &caches.diffuse,
            placed.2,
            false,
        );
        let memory = (caches.glossy.bytes()
            + caches.harmonics.bytes()
            + caches.diffuse.bytes()
            + caches.photons.bytes()) as f64
            / 1e6;
        stats.extra.insert("sdrc_photon_s".into(), photon_s);
        stats
            .extra
            .insert("sdrc_photons_stored".into(), caches.photons.len() as f64);
        stats
            .extra
            .insert("sdrc_photon_rays".into(), caches.photons.rays as f64);
        stats.extra.insert("sdrc_memory_mb".into(), memory);
        stats.extra.insert("sdrc_placement_s".into(), placement_s);
        let mut records = vec![0.0f32; film.pixels.len()];
        let pixels = (caches.glossy.records().iter().map(|r| r.pixel))
            .chain(caches.harmonics.records().iter().map(|r| r.pixel))
            .chain(caches.diffuse.records().iter().map(|r| r.pixel));
        for pixel in pixels {
            if let Some(i) = film.window.index(pixel) {
                records[i] += 1.0;
            }
        }
        let spp = passes.budget.done.max(1) as f32;
        let cached = passes.served.iter().map(|&n| n / spp).collect();
        *self.maps.lock().unwrap_or_else(|e| e.into_inner()) = vec![
            WorkMap {
                name: "records",
                what: "cache records (glossy and irradiance) created at the pixel",
                values: records,
            },
            WorkMap {
                name: "cached",
                what: "fraction of the pixel's samples whose indirect light came from a cache",
                values: cached,
            },
        ];
        stats
    }
}

/// The integrator's name for its glossy cache.
fn name(glossy: GlossyCache) -> &'static str {
    match glossy {
        GlossyCache::Directional | GlossyCache::Path => "sdrc",
        GlossyCache::Harmonics { .. } => "shrc",
    }
}

/// The render passes: one sample per pixel each, the cache merged between passes.
struct Passes<'a> {
    sdrc: &'a Sdrc,
    setup: &'a CacheSetup<'a>,
    caches: Caches,
    window: Window,
    /// Samples per pixel whose indirect light the cache gave (the film's pixels).
    served: Vec<f32>,
    seed: u64,
    /// One sample per pixel a pass, within the time left once records are placed.
    budget: Budget,
}

impl Passes<'_> {
    /// The caches at work for a block's samples in a render pass.
    fn gather<'w>(&'w self, work: &'w mut Work) -> CacheGather<'w> {
        CacheGather {
            setup: self.setup,
            caches: &self.caches,
            work,
            a_scale: self.sdrc.options.a_scale,
            seed: self.seed,
            phase: 0,
        }
    }
}

impl PassEstimator for Passes<'_> {
    type BlockStats = Work;

    fn expected_samples(&self, pixels: u64) -> Option<u64> {
        self.budget.expected_samples(pixels)
    }

    fn begin_pass(&mut self, pass: &PassInfo) -> bool {
        self.budget.next_pass(pass, 1) > 0
    }

    fn block_stats(&self, _: u32, _: u32) -> Work {
        Work::default()
    }

    fn samples(&self, _: &PixelState) -> u32 {
        1
    }

    fn sample(
        &self,
        scene: &RenderScene,
        ctx: &SampleContext,
        sampler: &mut Sampler,
        work: &mut Work,
        rays: &mut RayCounters,
    ) -> Rgb {
        // A wave of one: the passes trace a block's samples together (below).
        let mut out = [Rgb::ZERO];
        let (ctxs, samplers) = (std::slice::from_ref(ctx), std::slice::from_mut(sampler));
        self.sample_many(scene, ctxs, samplers, work, rays, &mut out, &mut []);
        out[0]
    }

    /// A block's samples traced together in waves, as af_hf's are (the pixels of one path
    /// at a time: the caches are asked at the camera's hits in the same order), their
    /// denoising features read off their paths.
    fn sample_many(
        &self,
        scene: &RenderScene,
        ctxs: &[SampleContext],
        samplers: &mut [Sampler],
        work: &mut Work,
        rays: &mut RayCounters,
        out: &mut [Rgb],
        features: &mut [Option<Feature>],
    ) {
        let cameras = SampleContext::camera_rays(ctxs, &scene.scene.camera, samplers, rays);
        let wave = &mut Wave {
            cameras: &cameras,
            ctxs,
            samplers,
            records: &mut LightRecords::off(),
            rays,
            features,
        };
        let tracer = &self.sdrc.tracer;
        tracer.trace_wave(scene, wave, &mut self.gather(work), out);
    }

    fn end_pass(&mut self, _: &RenderScene, _: &Film, mut blocks: Vec<Work>) -> bool {
        for b in &mut blocks {
            for pixel in b.served.drain(..) {
                if let Some(i) = self.window.index(pixel) {
                    self.served[i] += 1.0;
                }
            }
        }
        self.caches.merge(blocks);
        self.budget.done += 1;
        true
    }
}

/// A cache's figures for the render's statistics, under `prefix`; `lazy`: the cache adds
/// samples to its records and interpolates directions (SDRC).
fn figures<P: crate::record::Payload>(
    stats: &mut RenderStats,
    prefix: &str,
    cache: &SpatialCache<P>,
    placed: usize,
    lazy: bool,
) {
    let c: Counts = cache.counts;
    let mut add = |what: &str, v: f64| stats.extra.insert(format!("{prefix}_{what}"), v);
    add("records", cache.len() as f64);
    add("records_placed", placed as f64);
    add("record_rays", c.record_rays as f64);
    add(
        "records_per_point",
        c.records_used as f64 / c.points.max(1) as f64,
    );
    if lazy {
        add("update_rays", c.update_rays as f64);
        add("interpolated", c.interpolated as f64);
        add("rejected", c.rejected as f64);
    }
}
