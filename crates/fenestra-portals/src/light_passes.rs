//! The pass schedule of renders with light paths (lt, lp_lt): passes of 1, 2, 4, ... up to 32
//! samples per pixel, each camera sample tracing its camera path (lp_lt's; none for lt) and
//! its share of the light paths, whose splats the film adds after the pass. Before them, a
//! pilot of light paths can learn where on the portals they should start
//! ([`crate::emission`]).

use crate::emission::Tally;
use crate::light_paths::{Joined, LightTracer, SunPaths};
use crate::lp_hf::PortalNextEvent;
use fenestra_core::rng::Rng;
use fenestra_core::stats::{RayCounters, RenderStats};
use fenestra_core::{Rgb, Sampler};
use fenestra_render::driver::{
    next_pass_size, render_passes, Budget, PassEstimator, PassInfo, PixelState,
};
use fenestra_render::features::Feature;
use fenestra_render::film::Film;
use fenestra_render::integrator::{NextEvent, NoGather, PathOptions, PathTracer, Start};
use fenestra_render::light::{LightContext, LightRecords};
use fenestra_render::path_sample::{PathSample, Wave};
use fenestra_render::sample_context::SampleContext;
use fenestra_render::settings::RenderSettings;
use fenestra_render::splat::Splats;
use fenestra_render::{RenderControl, RenderScene};
use rayon::prelude::*;

/// The random stream of the emission pilot's light paths (the render's use stream 0).
const PILOT_STREAM: u32 = 0x1ea7;

/// Light paths a pilot traces at once (one task each).
const PILOT_CHUNK: u32 = 512;

/// What a block gathers in a pass: its light paths' splats (and the camera paths' light
/// records, which nothing learns from).
pub(crate) struct LightBlock {
    records: LightRecords,
    splats: Splats,
    /// The light paths' [`Splats::handed_moment`] of the splats taken, and their rays.
    handed_moment: f64,
    light_rays: RayCounters,
}

/// Passes of camera samples that trace light paths.
pub(crate) struct LightPasses<'a> {
    /// The path tracer the light paths are joined to (`None`: light paths alone).
    pub camera: Option<&'a PathTracer<PortalNextEvent>>,
    pub suns: &'a SunPaths,
    pub options: &'a PathOptions,
    /// Light paths per camera sample.
    pub per_sample: f32,
    budget: Budget,
    size: u32,
    current: u32,
    /// Over the passes rendered: the light paths' [`Splats::handed_moment`] and their rays.
    pub handed_moment: f64,
    pub light_rays: RayCounters,
}

impl<'a> LightPasses<'a> {
    /// Passes of `options`' paths: light paths of `suns`, `per_sample` per camera sample,
    /// joined to `camera` if given.
    pub fn new(
        camera: Option<&'a PathTracer<PortalNextEvent>>,
        suns: &'a SunPaths,
        options: &'a PathOptions,
        per_sample: f32,
    ) -> Self {
        LightPasses {
            camera,
            suns,
            options,
            per_sample,
            budget: Budget::new(0, None),
            size: 1,
            current: 0,
            handed_moment: 0.0,
            light_rays: RayCounters::default(),
        }
    }

    /// Renders the passes into `film` within `settings`' samples or time; the statistics
    /// count the light paths.
    pub fn render(
        &mut self,
        scene: &RenderScene,
        film: &mut Film,
        settings: &RenderSettings,
        control: &RenderControl,
    ) -> RenderStats {
        self.budget = Budget::new(settings.spp, settings.time_limit);
        let mut stats = render_passes(self, scene, film, settings, control);
        stats.max_depth = Some(self.options.max_depth);
        if let Some(pt) = self.camera {
            pt.next_event().report(&mut stats);
        }
        let light_paths = film.light_paths as f64;
        stats.extra.insert("light_paths".into(), light_paths);
        if let Some(share) = film.light_path_share() {
            stats.extra.insert("light_path_share".into(), share);
        }
        if let Some(share) = film.light_path_variance_share() {
            stats
                .extra
                .insert("light_path_variance_share".into(), share);
        }
        stats
    }

    /// The light that `paths` light paths drawn uniformly over the portals (from the
    /// stream [`PILOT_STREAM`] of `seed`) bring to the pixels of a `width` x `height` image,
    /// after their MIS weights, summed where they started; in a fixed order, so the same for
    /// any thread count.
    pub fn pilot(
        &self,
        scene: &RenderScene,
        (width, height): (u32, u32),
        seed: u64,
        paths: u32,
        rays: &mut RayCounters,
    ) -> Tally {
        let ctx = SampleContext {
            width,
            height,
            ..SampleContext::SINGLE
        };
        let chunks: Vec<_> = (0..paths.div_ceil(PILOT_CHUNK))
            .into_par_iter()
            .map(|chunk| {
                let (mut splats, mut rays) = (Splats::default(), RayCounters::default());
                let first = chunk * PILOT_CHUNK;
                let traced: Vec<_> = (first..(first + PILOT_CHUNK).min(paths))
                    .filter_map(|i| {
                        let mut sampler = Sampler::in_stream(seed, PILOT_STREAM, u64::from(i), 0);
                        splats.entries.clear();
                        let start = self.with_tracer(scene, &ctx, |tracer| {
                            tracer.trace(&ctx, &mut sampler, &mut splats, &mut rays)
                        })?;
                        let light: f64 = (splats.entries.iter())
                            .map(|s| f64::from(s.value.luminance()))
                            .sum();
                        Some((start, light))
                    })
                    .collect();
                (traced, rays)
            })
            .collect();
        let mut tally = self.suns.tally();
        for (traced, chunk_rays) in chunks {
            for (start, light) in traced {
                tally.add(start.sun, start.portal, start.unit, light);
            }
            *rays += chunk_rays;
        }
        tally
    }

    /// Calls `f` with the light tracer of these passes for an image of `ctx`'s size.
    fn with_tracer<T>(
        &self,
        scene: &RenderScene,
        ctx: &SampleContext,
        f: impl FnOnce(&LightTracer) -> T,
    ) -> T {
        let light_pick = (self.camera).map(|pt| {
            move |at: &LightContext, light: usize| pt.next_event().light_pick(scene, at, light)
        });
        let tracer = LightTracer {
            scene,
            camera: &scene.scene.camera,
            suns: self.suns,
            options: self.options,
            width: ctx.width,
            height: ctx.height,
            joined: self
                .camera
                .zip(light_pick.as_ref())
                .map(|(pt, light_pick)| Joined {
                    mis: pt.options().mis,
                    light_pick,
                }),
        };
        f(&tracer)
    }

    /// The light paths of camera sample `ctx`, from `sampler`'s stream: the sample's share,
    /// floor((i + 1) k + u) - floor(i k + u) for its index i, k per sample and an offset u
    /// in [0, 1) of its pixel's own, so that a pixel's first n samples trace floor(n k + u)
    /// - floor(u), k per sample on average however few they are (without u, a render of
    /// fewer than 1 / k samples per pixel would trace none, and lose the light MIS hands to
    /// them). Their rays count in `rays` and the block's.
    fn trace_light_paths(
        &self,
        scene: &RenderScene,
        ctx: &SampleContext,
        sampler: &mut Sampler,
        block: &mut LightBlock,
        rays: &mut RayCounters,
    ) {
        let (k, i) = (f64::from(self.per_sample), f64::from(ctx.index));
        let u = Rng::new(ctx.pixel()).next_f64();
        let count = ((i + 1.0) * k + u).floor() - (i * k + u).floor();
        let mut light_rays = RayCounters::default();
        self.with_tracer(scene, ctx, |tracer| {
            for _ in 0..count as u32 {
                tracer.trace(ctx, sampler, &mut block.splats, &mut light_rays);
            }
        });
        *rays += light_rays;
        block.light_rays += light_rays;
    }
}

impl PassEstimator for LightPasses<'_> {
    type BlockStats = LightBlock;

    fn expected_samples(&self, pixels: u64) -> Option<u64> {
        self.budget.expected_samples(pixels)
    }

    fn begin_pass(&mut self, pass: &PassInfo) -> bool {
        self.current = self.budget.next_pass(pass, self.size);
        self.current > 0
    }

    fn block_stats(&self, _: u32, _: u32) -> LightBlock {
        LightBlock {
            records: LightRecords::off(),
            splats: Splats::default(),
            handed_moment: 0.0,
            light_rays: RayCounters::default(),
        }
    }

    fn samples(&self, _: &PixelState) -> u32 {
        self.current
    }

    /// The camera path's radiance (none for light paths alone), then the sample's light
    /// paths, whose light comes to the pixels as splats.
    fn sample(
        &self,
        scene: &RenderScene,
        ctx: &SampleContext,
        sampler: &mut Sampler,
        block: &mut LightBlock,
        rays: &mut RayCounters,
    ) -> Rgb {
        let l = match self.camera {
            Some(pt) => {
                let ray = ctx.camera_ray(&scene.scene.camera, sampler, rays);
                let sample = &mut PathSample {
                    ctx,
                    sampler,
                    records: &mut block.records,
                    rays,
                };
                pt.trace(scene, ray, Start::CAMERA, sample, &mut NoGather)
            }
            None => Rgb::ZERO,
        };
        self.trace_light_paths(scene, ctx, sampler, block, rays);
        l
    }

    /// The camera paths traced together ([`PathTracer::trace_wave`], which reads their
    /// denoising features), then each sample's light paths.
    fn sample_many(
        &self,
        scene: &RenderScene,
        ctxs: &[SampleContext],
        samplers: &mut [Sampler],
        block: &mut LightBlock,
        rays: &mut RayCounters,
        out: &mut [Rgb],
        features: &mut [Option<Feature>],
    ) {
        if let Some(pt) = self.camera {
            let records = &mut block.records;
            Wave::of_cameras(scene, ctxs, samplers, records, rays, features, |wave| {
                pt.trace_wave(scene, wave, &mut NoGather, out)
            });
        } else {
            out.fill(Rgb::ZERO);
        }
        for (ctx, sampler) in ctxs.iter().zip(samplers.iter_mut()) {
            self.trace_light_paths(scene, ctx, sampler, block, rays);
        }
    }

    fn take_splats(&self, block: &mut LightBlock) -> Option<Splats> {
        let splats = std::mem::take(&mut block.splats);
        block.handed_moment += splats.handed_moment;
        Some(splats)
    }

    fn end_pass(&mut self, _: &RenderScene, _: &Film, blocks: Vec<LightBlock>) -> bool {
        for block in blocks {
            self.handed_moment += block.handed_moment;
            self.light_rays += block.light_rays;
        }
        self.budget.done += self.current;
        self.size = next_pass_size(self.size);
        true
    }
}
