//! The per-path driver: an estimator that maps a camera ray to radiance is rendered in passes
//! of 1, 2, 4, ... up to 32 samples per pixel until the sample count, or the time limit (of
//! rendering, preparation not included), is reached (small first passes make Ctrl-C, time
//! limits and convergence curves prompt). An estimator with a learned light sampler learns
//! from the light samples of the passes it asks for, block by block in block order; those
//! passes are pre-passes, outside the image, whose samples then all use what was learned.

use super::passes::{render_passes, PassEstimator, PassInfo, PixelState};
use crate::control::RenderControl;
use crate::features::Feature;
use crate::film::Film;
use crate::light::LightRecords;
use crate::path_sample::{PathSample, Wave};
use crate::render_scene::RenderScene;
use crate::sample_context::SampleContext;
use crate::settings::RenderSettings;
use fenestra_core::stats::{RayCounters, RenderStats};
use fenestra_core::{Ray, Rgb, Sampler};

/// One path sample: the radiance carried along a camera ray.
pub trait PathEstimator: Sync {
    /// Radiance arriving at the camera along `ray`, for `sample`; its light samples go to
    /// its records (kept if the pass learns).
    fn li(&self, scene: &RenderScene, ray: Ray, sample: &mut PathSample) -> Rgb;

    /// The radiance of each sample of `wave` into `out`; by default one after another.
    fn li_many(&self, scene: &RenderScene, wave: &mut Wave, out: &mut [Rgb]) {
        for (i, &ray) in wave.cameras.iter().enumerate() {
            wave.records.start_sample(&wave.ctxs[i]);
            out[i] = self.li(scene, ray, &mut wave.sample(i));
        }
    }

    /// Whether the estimator learns from the light samples of pass `pass`.
    fn learns(&self, _pass: u32) -> bool {
        false
    }

    /// Learns from a pass's light samples, every block's in block order.
    fn learn(&self, _blocks: &[LightRecords]) {}
}

/// Light records a path sample keeps on average when nothing has been counted yet.
const RECORDS_PER_SAMPLE: f64 = 2.0;

/// Largest number of samples per pixel added in one pass.
const MAX_PASS: u32 = 32;

/// The size of the pass after one of `size` samples per pixel: twice as many, up to 32 (small
/// first passes make Ctrl-C, time limits and convergence curves prompt).
pub fn next_pass_size(size: u32) -> u32 {
    (size * 2).min(MAX_PASS)
}

/// Renders `estimator` with `settings.spp` samples per pixel, or as many as fit in the time
/// limit (a whole number per pixel).
pub fn render_progressive(
    estimator: &impl PathEstimator,
    scene: &RenderScene,
    film: &mut Film,
    settings: &RenderSettings,
    control: &RenderControl,
) -> RenderStats {
    let mut schedule = Schedule {
        estimator,
        budget: Budget::new(settings.spp, settings.time_limit),
        size: 1,
        current: 0,
        stream: 0,
        learning: false,
        rate: 0.0,
        per_sample: RECORDS_PER_SAMPLE,
    };
    render_passes(&mut schedule, scene, film, settings, control)
}

/// Samples per pixel a render takes when every pixel takes the same number in a pass: up to
/// a count, or as many as fit in a time limit (on the render's clock, preparation included).
#[derive(Clone, Copy, Debug)]
pub struct Budget {
    /// Samples per pixel asked for.
    pub spp: u32,
    /// Seconds the passes may take.
    pub time_limit: Option<f64>,
    /// Samples per pixel of the completed passes.
    pub done: u32,
}

impl Budget {
    /// Nothing taken yet of `spp` samples per pixel within `time_limit`.
    pub fn new(spp: u32, time_limit: Option<f64>) -> Self {
        Budget {
            spp,
            time_limit,
            done: 0,
        }
    }

    /// Samples the render will take over `pixels`, if known (no time limit).
    pub fn expected_samples(&self, pixels: u64) -> Option<u64> {
        self.time_limit
            .is_none()
            .then_some(pixels * self.spp as u64)
    }

    /// How many of `wanted` samples per pixel the pass about to start may take: what is left
    /// of the count, and, after the first pass, what fits in the time left at the passes'
    /// rate so far (0: the render is done).
    pub fn next_pass(&self, pass: &PassInfo, wanted: u32) -> u32 {
        let mut n = wanted.min(self.spp.saturating_sub(self.done));
        match (self.time_limit, self.done) {
            (Some(limit), 0) if limit <= 0.0 => n = 0,
            (Some(limit), done) if done > 0 => {
                let per_sample = pass.render_s / done as f64;
                n = n.min(((limit - pass.elapsed_s) / per_sample).floor().max(0.0) as u32);
            }
            _ => {}
        }
        n
    }
}

/// The pass schedule: every pixel takes `current` samples in a pass.
struct Schedule<'a, E> {
    estimator: &'a E,
    budget: Budget,
    /// Size of the next pass before the sample count and time limit cut it.
    size: u32,
    current: u32,
    /// The random stream of the pass: a new one after each pass the estimator learned from.
    stream: u32,
    /// Whether the estimator learns from the pass (which then stays out of the image).
    learning: bool,
    /// Share of this pass's path samples whose light samples are kept (0: none).
    rate: f32,
    /// Light records kept per path sample in the last pass that kept any.
    per_sample: f64,
}

impl<E: PathEstimator> PassEstimator for Schedule<'_, E> {
    type BlockStats = LightRecords;

    /// The image's samples and the learning pre-passes' (1, 2, 4, ... per pixel).
    fn expected_samples(&self, pixels: u64) -> Option<u64> {
        let learning = (0..u32::BITS)
            .take_while(|&pass| self.estimator.learns(pass))
            .map(|pass| u64::from((1u32 << pass).min(MAX_PASS).min(self.budget.spp)))
            .sum::<u64>();
        Some(self.budget.expected_samples(pixels)? + pixels * learning)
    }

    fn begin_pass(&mut self, pass: &PassInfo) -> bool {
        // The time limit counts rendering: preparation (portal estimation, caches) comes on
        // top, and the statistics' total time shows it.
        self.current = self.budget.next_pass(pass, self.size);
        self.learning = self.estimator.learns(pass.index);
        self.rate = if self.learning {
            LightRecords::rate_for(pass.pixels * self.current as u64, self.per_sample)
        } else {
            0.0
        };
        self.current > 0
    }

    fn stream(&self) -> u32 {
        self.stream
    }

    /// A pass the estimator learns from is a pre-pass: the image's samples, all drawn with
    /// what was learned, then fill streams of their own from their first index.
    fn keeps(&self) -> bool {
        !self.learning
    }

    fn block_stats(&self, _: u32, _: u32) -> LightRecords {
        LightRecords::new(self.rate)
    }

    fn samples(&self, _: &PixelState) -> u32 {
        self.current
    }

    fn sample(
        &self,
        scene: &RenderScene,
        ctx: &SampleContext,
        sampler: &mut Sampler,
        records: &mut LightRecords,
        rays: &mut RayCounters,
    ) -> Rgb {
        records.start_sample(ctx);
        let ray = ctx.camera_ray(&scene.scene.camera, sampler, rays);
        let sample = &mut PathSample {
            ctx,
            sampler,
            records,
            rays,
        };
        self.estimator.li(scene, ray, sample)
    }

    fn sample_many(
        &self,
        scene: &RenderScene,
        ctxs: &[SampleContext],
        samplers: &mut [Sampler],
        records: &mut LightRecords,
        rays: &mut RayCounters,
        out: &mut [Rgb],
        features: &mut [Option<Feature>],
    ) {
        Wave::of_cameras(scene, ctxs, samplers, records, rays, features, |wave| {
            self.estimator.li_many(scene, wave, out)
        });
    }

    fn end_pass(&mut self, _: &RenderScene, film: &Film, blocks: Vec<LightRecords>) -> bool {
        if self.learning {
            let kept: usize = blocks.iter().map(|b| b.records.len()).sum();
            let samples = film.pixels.len() as f64 * self.current as f64 * self.rate as f64;
            self.per_sample = (kept as f64 / samples.max(1.0)).max(1e-3);
            self.estimator.learn(&blocks);
            self.stream += 1;
        }
        if !self.learning {
            self.budget.done += self.current;
        }
        self.size = next_pass_size(self.size);
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::NoProgress;
    use fenestra_builtin as builtin;
    use fenestra_scene::{Backend, Scene};
    use std::sync::atomic::AtomicBool;

    /// Returns NaN, +inf or 1 depending on the sample's first random number.
    struct Faulty;
    impl PathEstimator for Faulty {
        fn li(&self, _: &RenderScene, _: Ray, sample: &mut PathSample) -> Rgb {
            match (sample.sampler.next_1d() * 4.0) as u32 {
                0 => Rgb::new(f32::NAN, 0.0, 0.0),
                1 => Rgb::splat(f32::INFINITY),
                _ => Rgb::ONE,
            }
        }
    }

    fn render(settings: &RenderSettings, size: u32) -> (Film, RenderStats) {
        let scene = Scene::build(builtin::load("box-hole").expect("builtin"), Backend::Obvhs)
            .expect("scene");
        let scene = RenderScene::new(scene);
        let mut film = Film::new(size, size);
        let cancel = AtomicBool::new(false);
        let control = RenderControl::new(&cancel, &NoProgress);
        let stats = render_progressive(&Faulty, &scene, &mut film, settings, &control);
        (film, stats)
    }

    #[test]
    fn non_finite_samples_are_dropped_and_counted() {
        let settings = RenderSettings {
            first_sample: 0,
            spp: 16,
            time_limit: None,
            seed: 3,
        };
        // 12 is not a multiple of the 8-pixel blocks: partial blocks at the edges.
        let (film, stats) = render(&settings, 12);
        let kept: u64 = film.pixels.iter().map(|p| p.count as u64).sum();
        assert!(stats.rays.dropped > 0);
        assert_eq!(kept + stats.rays.dropped, 12 * 12 * 16);
        assert_eq!(stats.rays.camera, 12 * 12 * 16);
        // Passes of 1, 2, 4, 8 and the remaining 1.
        assert_eq!(stats.passes, 5);
        assert!(
            film.image().pixels.iter().all(|p| *p == Rgb::ONE),
            "only finite samples reach the film"
        );
    }

    /// Learns from passes 0 and 1, and tells their samples apart (1000) from the image's (1).
    struct Learning;
    impl PathEstimator for Learning {
        fn li(&self, _: &RenderScene, _: Ray, sample: &mut PathSample) -> Rgb {
            Rgb::splat(if sample.ctx.pass < 2 { 1000.0 } else { 1.0 })
        }

        fn learns(&self, pass: u32) -> bool {
            pass < 2
        }
    }

    #[test]
    fn learning_passes_stay_out_of_the_image_and_its_hooks() {
        let scene = Scene::build(builtin::load("box-hole").expect("builtin"), Backend::Obvhs)
            .expect("scene");
        let scene = RenderScene::new(scene);
        let mut film = Film::new(10, 10);
        let cancel = AtomicBool::new(false);
        let counts = std::sync::Mutex::new(Vec::new());
        let hook = |film: &Film, _: f64| {
            counts
                .lock()
                .expect("counts")
                .push(film.sample_count_range());
            true
        };
        let mut control = RenderControl::new(&cancel, &NoProgress);
        control.on_pass = Some(&hook);
        let settings = RenderSettings {
            first_sample: 0,
            spp: 16,
            time_limit: None,
            seed: 3,
        };
        let stats = render_progressive(&Learning, &scene, &mut film, &settings, &control);
        // Pre-passes of 1 and 2 samples, then 4, 8 and the remaining 4 in the image.
        assert_eq!(stats.rays.camera, 10 * 10 * (1 + 2 + 16));
        assert!(film.pixels.iter().all(|p| p.count == 16));
        assert!(film.image().pixels.iter().all(|p| *p == Rgb::ONE));
        assert_eq!(
            counts.into_inner().expect("counts"),
            [(4, 4), (12, 12), (16, 16)],
            "the hook sees the image's passes only"
        );
    }
}
