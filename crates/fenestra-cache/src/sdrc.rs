//! `sdrc`: spatial directional radiance caching (seed 003 ch. 2) for the first bounce of
//! indirect light on glossy surfaces seen from the camera; everything else is af_hf's path
//! tracing (direct light by light and BSDF sampling with MIS at every vertex, indirect light
//! on other surfaces and the cached samples' own paths).
//!
//! Two phases, as the seed's two passes (§2.5): records are placed from one camera ray per
//! pixel, coarse to fine (every 8th pixel, then every 4th, 2nd, 1st), with maximum error a;
//! then the image is rendered in passes of one sample per pixel with a x 1.3, adding samples
//! to the records (lazy updates) and records where none is near.

use crate::gather::{is_glossy, CacheGather};
use crate::spatial::{Delta, SpatialCache};
use fenestra_core::stats::{RayCounters, RenderStats};
use fenestra_core::{Rgb, Sampler, Vec2};
use fenestra_render::control::RenderControl;
use fenestra_render::driver::{
    render_passes, PassEstimator, PassInfo, PixelState, SampleContext, BLOCK_SIZE,
};
use fenestra_render::film::Window;
use fenestra_render::integrator::{
    Integrator, IntegratorError, LightNextEvent, PathOptions, PathTracer, Shading, Start, WorkMap,
};
use fenestra_render::{Film, RenderScene, RenderSettings};
use rayon::prelude::*;
use std::sync::Mutex;
use std::time::Instant;

/// Seed of the record-placement phase's camera samples (xor-ed with the render's seed).
const PLACEMENT: u64 = 0x5d5c_0003;

/// Largest validity radius a R_i of a record, in pixel footprints at its point.
const MAX_REACH_PX: f32 = 40.0;

/// Options of `sdrc`.
#[derive(Clone, Copy, Debug)]
pub struct SdrcOptions {
    /// Maximum interpolation error a (eq. 2.1) of record placement; the render passes use
    /// `a * a_scale`.
    pub a: f32,
    /// Factor on a in the render passes (the seed's 1.3).
    pub a_scale: f32,
    /// Rays traced to create a record (N).
    pub n: u32,
    /// Directions per pixel, shared among its samples (0: 4 N / 12, the seed's M ~ N / 12
    /// per camera ray with its 4 camera rays per pixel).
    pub m: u32,
    /// Largest directional query radius in the paraboloid disc (the seed's r_max).
    pub r_max: f32,
    /// Smallest validity radius a R_i of a record, in pixel footprints at its point (0: none).
    pub min_reach: f32,
}

impl Default for SdrcOptions {
    fn default() -> Self {
        SdrcOptions {
            a: 0.22,
            a_scale: 1.3,
            n: 512,
            m: 0,
            r_max: 0.15,
            min_reach: 4.0,
        }
    }
}

impl SdrcOptions {
    /// Directions per pixel.
    pub fn directions(&self) -> u32 {
        if self.m > 0 {
            self.m
        } else {
            (4 * self.n / 12).max(1)
        }
    }

    /// Directions per shading point when a pixel takes `spp` samples: M over the samples,
    /// at least one.
    pub fn directions_per_sample(&self, spp: u32) -> u32 {
        self.directions().div_ceil(spp.max(1))
    }
}

/// The `sdrc` integrator.
pub struct Sdrc {
    pub(crate) tracer: PathTracer<LightNextEvent>,
    pub(crate) options: SdrcOptions,
    path: PathOptions,
    /// Angle between neighbouring pixels' camera rays, and the distance between their
    /// origins (orthographic cameras): a pixel's footprint at distance t is
    /// `spacing + t * angle`.
    camera: Mutex<(f32, f32)>,
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
        let bad = |what: &str| Err(IntegratorError::Options(what.to_string()));
        if !(options.a > 0.0 && options.a.is_finite()) {
            return bad("--sdrc-a must be positive");
        }
        if !(options.a_scale >= 1.0 && options.a_scale.is_finite()) {
            return bad("--sdrc-a-scale must be at least 1");
        }
        if options.n == 0 {
            return bad("--sdrc-n must be at least 1");
        }
        if !(options.min_reach >= 0.0 && options.min_reach <= MAX_REACH_PX) {
            return bad(&format!(
                "--sdrc-min-reach must lie in [0, {MAX_REACH_PX}] pixels"
            ));
        }
        if !(options.r_max > 0.0 && options.r_max <= 2.0) {
            return bad("--sdrc-r-max must lie in (0, 2] (the disc's diameter)");
        }
        Ok(Sdrc {
            tracer: PathTracer::new("sdrc", lights, path),
            options,
            path,
            camera: Mutex::new((0.0, 0.0)),
            maps: Mutex::new(Vec::new()),
        })
    }

    /// Maximum path length.
    pub(crate) fn max_depth(&self) -> u32 {
        self.path.max_depth
    }

    /// A pixel's size at distance `t` from the camera.
    pub(crate) fn footprint(&self, t: f32) -> f32 {
        let (angle, spacing) = *self.camera.lock().unwrap_or_else(|e| e.into_inner());
        spacing + t * angle
    }

    /// Bounds of R_i for a record of pixel footprint `footprint` under maximum error `a`.
    pub(crate) fn radius_bounds(&self, footprint: f32, a: f32) -> (f32, f32) {
        (
            self.options.min_reach * footprint / a,
            MAX_REACH_PX * footprint / a,
        )
    }

    /// Measures the camera's pixel footprint from two neighbouring pixels' rays.
    fn measure_camera(&self, scene: &RenderScene, width: u32, height: u32) {
        let camera = &scene.scene.camera;
        let c = Vec2::new(width as f32 * 0.5, height as f32 * 0.5);
        let (a, b) = (
            camera.generate_ray(c, width, height),
            camera.generate_ray(c + Vec2::X, width, height),
        );
        let angle = a.d.dot(b.d).clamp(-1.0, 1.0).acos();
        let spacing = (a.o - b.o).length();
        *self.camera.lock().unwrap_or_else(|e| e.into_inner()) = (angle, spacing);
    }

    /// Places records from one camera ray per pixel, coarse to fine (the seed's first pass).
    fn place_records(
        &self,
        scene: &RenderScene,
        film: &Film,
        cache: &mut SpatialCache,
        seed: u64,
        control: &RenderControl,
    ) -> RayCounters {
        let window = film.window;
        let blocks = fenestra_render::driver::Blocks::new(film.width, film.height);
        control
            .progress
            .start(Some(film.width as u64 * film.height as u64));
        let mut rays = RayCounters::default();
        for stride in [8u32, 4, 2, 1] {
            if control.cancelled() {
                break;
            }
            // The pixels on this level's grid that no coarser level took.
            let on = |x: u32, y: u32, s: u32| x.is_multiple_of(s) && y.is_multiple_of(s);
            let level = |x: u32, y: u32| on(x, y, stride) && (stride == 8 || !on(x, y, 2 * stride));
            let done: Vec<(Delta, RayCounters)> = (0..blocks.count() as u32)
                .into_par_iter()
                .map(|b| {
                    let mut delta = Delta::default();
                    let mut rays = RayCounters::default();
                    if control.cancelled() {
                        return (delta, rays);
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
                                sdrc: self,
                                cache,
                                delta: &mut delta,
                                a: self.options.a,
                                seed,
                                phase: PLACEMENT,
                                spp: 1,
                            };
                            place_at(scene, &ctx, seed, &mut gather, &mut rays);
                        }
                    }
                    control.progress.advance(pixels);
                    (delta, rays)
                })
                .collect();
            let mut deltas = Vec::with_capacity(done.len());
            for (delta, r) in done {
                deltas.push(delta);
                rays += r;
            }
            cache.merge(deltas);
        }
        rays
    }
}

/// The record lookup (and creation) at the glossy surface a placement camera ray finds.
fn place_at(
    scene: &RenderScene,
    ctx: &SampleContext,
    seed: u64,
    gather: &mut CacheGather,
    rays: &mut RayCounters,
) {
    let mut sampler = Sampler::new(seed ^ PLACEMENT, ctx.pixel(), 0);
    let ray = ctx.camera_ray(scene, &mut sampler, rays);
    let Some(hit) = scene.scene.intersect(&ray, f32::INFINITY) else {
        return;
    };
    let si = scene.scene.interaction(&ray, &hit);
    let bsdf = scene.bsdf_at(&si);
    if !is_glossy(&bsdf) || gather.sdrc.max_depth() < 3 {
        return;
    }
    let frame = si.shading_frame();
    let wo = -ray.d;
    let shading = Shading {
        si: &si,
        bsdf: &bsdf,
        frame,
        wo,
        wo_local: frame.to_local(wo),
        sample: ctx,
    };
    gather.ensure_records(scene, &shading, rays);
}

impl Integrator for Sdrc {
    fn name(&self) -> &str {
        "sdrc"
    }

    fn settings(&self) -> serde_json::Value {
        let mut s = self.tracer.settings();
        if let Some(all) = s.as_object_mut() {
            all.insert(
                "sdrc".into(),
                serde_json::json!({
                    "a": self.options.a,
                    "a_scale": self.options.a_scale,
                    "n": self.options.n,
                    "m": self.options.directions(),
                    "r_max": self.options.r_max,
                    "min_reach": self.options.min_reach,
                }),
            );
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
        self.measure_camera(scene, film.window.full_width, film.window.full_height);
        let (lo, hi) = scene.scene.bounds();
        let a_render = self.options.a * self.options.a_scale;
        let mut cache = SpatialCache::new(lo, hi, a_render);
        let placement_rays = self.place_records(scene, film, &mut cache, settings.seed, control);
        let placed = cache.len();
        let placement_s = started.elapsed().as_secs_f64();
        let mut passes = Passes {
            sdrc: self,
            cache,
            window: film.window,
            served: vec![0.0; film.pixels.len()],
            a: a_render,
            seed: settings.seed,
            spp: settings.spp,
            time_limit: settings.time_limit.map(|t| (t - placement_s).max(0.0)),
            done: 0,
            pixel_samples: 1,
        };
        let mut stats = render_passes(&mut passes, scene, film, settings, control);
        stats.rays += placement_rays;
        stats.max_depth = Some(self.path.max_depth);
        let cache = passes.cache;
        let counts = cache.counts;
        let extra = [
            ("sdrc_records", cache.len() as f64),
            ("sdrc_records_placed", placed as f64),
            ("sdrc_samples", cache.samples() as f64),
            ("sdrc_record_rays", counts.record_rays as f64),
            ("sdrc_update_rays", counts.update_rays as f64),
            ("sdrc_interpolated", counts.interpolated as f64),
            ("sdrc_rejected", counts.rejected as f64),
            (
                "sdrc_records_per_point",
                counts.records_used as f64 / counts.points.max(1) as f64,
            ),
            ("sdrc_memory_mb", cache.bytes() as f64 / 1e6),
            ("sdrc_placement_s", placement_s),
        ];
        for (k, v) in extra {
            stats.extra.insert(k.into(), v);
        }
        let mut records = vec![0.0f32; film.pixels.len()];
        for r in cache.records() {
            if let Some(i) = film.window.index(r.pixel) {
                records[i] += 1.0;
            }
        }
        let spp = passes.done.max(1) as f32;
        let cached = passes.served.iter().map(|&n| n / spp).collect();
        *self.maps.lock().unwrap_or_else(|e| e.into_inner()) = vec![
            WorkMap {
                name: "records",
                what: "cache records created at the pixel",
                values: records,
            },
            WorkMap {
                name: "cached",
                what: "fraction of the pixel's samples whose indirect light came from the cache",
                values: cached,
            },
        ];
        stats
    }
}

/// The render passes: one sample per pixel each, the cache merged between passes.
struct Passes<'a> {
    sdrc: &'a Sdrc,
    cache: SpatialCache,
    window: Window,
    /// Samples per pixel whose indirect light the cache gave (the film's pixels).
    served: Vec<f32>,
    a: f32,
    seed: u64,
    spp: u32,
    /// Seconds left for the passes once records are placed.
    time_limit: Option<f64>,
    done: u32,
    /// Samples a pixel will have taken at the end of this pass, or of the render: what the
    /// directions per sample are planned for.
    pixel_samples: u32,
}

impl PassEstimator for Passes<'_> {
    type BlockStats = Delta;

    fn expected_samples(&self, pixels: u64) -> Option<u64> {
        self.time_limit
            .is_none()
            .then_some(pixels * self.spp as u64)
    }

    fn begin_pass(&mut self, pass: &PassInfo) -> bool {
        if self.done >= self.spp {
            return false;
        }
        // Under a time limit the render's sample count is not known: plan for the samples
        // taken by the end of this pass.
        self.pixel_samples = match self.time_limit {
            None => self.spp,
            Some(_) => self.done + 1,
        };
        match (self.time_limit, self.done) {
            (Some(limit), 0) => limit > 0.0,
            (Some(limit), done) => pass.render_s + pass.render_s / done as f64 <= limit,
            (None, _) => true,
        }
    }

    fn block_stats(&self, _: u32, _: u32) -> Delta {
        Delta::default()
    }

    fn samples(&self, _: &PixelState) -> u32 {
        1
    }

    fn sample(
        &self,
        scene: &RenderScene,
        ctx: &SampleContext,
        sampler: &mut Sampler,
        delta: &mut Delta,
        rays: &mut RayCounters,
    ) -> Rgb {
        let ray = ctx.camera_ray(scene, sampler, rays);
        let mut gather = CacheGather {
            sdrc: self.sdrc,
            cache: &self.cache,
            delta,
            a: self.a,
            seed: self.seed,
            phase: 0,
            spp: self.pixel_samples,
        };
        self.sdrc
            .tracer
            .trace(scene, ray, Start::CAMERA, sampler, ctx, rays, &mut gather)
    }

    fn end_pass(&mut self, _: &RenderScene, _: &Film, mut blocks: Vec<Delta>) -> bool {
        for b in &mut blocks {
            for pixel in b.served.drain(..) {
                if let Some(i) = self.window.index(pixel) {
                    self.served[i] += 1.0;
                }
            }
        }
        self.cache.merge(blocks);
        self.done += 1;
        true
    }
}
