//! The block/pass driver: renders an image in passes over 8x8 pixel blocks (seed 004
//! §3.3.2, Fig. 3.4). Before a pass the estimator decides how many samples each pixel takes
//! (adaptive sampling: converged pixels take none); during the pass every block gathers its
//! own statistics; after it the estimator sees the film and all blocks' statistics, in block
//! order, and rebuilds what the next pass samples from.
//!
//! Blocks are rendered in parallel, each by one worker: its pixels in order and each pixel's
//! samples in index order, and the blocks' statistics are collected in block order, so the
//! film and the statistics are the same whatever the number of threads.

use super::{Blocks, BLOCK_SIZE};
use crate::control::RenderControl;
use crate::features::{feature_sample, takes_feature, Feature, FeaturePixel};
use crate::film::{Film, Pixel, Window};
use crate::render_scene::RenderScene;
use crate::sample_context::SampleContext;
use crate::settings::RenderSettings;
use crate::splat::Splats;
use fenestra_core::stats::{RayCounters, RenderStats};
use fenestra_core::{Rgb, Sampler};
use rayon::prelude::*;
use std::time::Instant;

/// Where a render stands before a pass.
#[derive(Clone, Copy, Debug)]
pub struct PassInfo {
    /// The pass about to start, from 0.
    pub index: u32,
    /// Seconds since the render began, preparation included.
    pub elapsed_s: f64,
    /// Seconds spent in the passes so far: what time limits count.
    pub render_s: f64,
    /// Pixels of the film.
    pub pixels: u64,
}

/// A pixel as the estimator sees it before a pass.
#[derive(Clone, Copy, Debug)]
pub struct PixelState<'a> {
    /// Pixel column in the image.
    pub x: u32,
    /// Pixel row in the image.
    pub y: u32,
    /// The pixel's 8x8 block.
    pub block: u32,
    /// The pass about to render.
    pub pass: u32,
    /// Its next sample's index: the samples it has taken, after the render's first
    /// ([`RenderSettings::first_sample`]).
    pub taken: u32,
    /// What the film holds for it (sums, squares, count): its estimate and variance.
    pub film: &'a Pixel,
}

/// An estimator rendered by blocks and passes.
pub trait PassEstimator: Sync {
    /// What one block learns during a pass (light statistics, ...); handed to
    /// [`PassEstimator::end_pass`].
    type BlockStats: Send;

    /// Samples the whole render will take, if known (for the progress bar).
    fn expected_samples(&self, _pixels: u64) -> Option<u64> {
        None
    }

    /// Called before each pass: whether to render it (false ends the render).
    fn begin_pass(&mut self, pass: &PassInfo) -> bool;

    /// The random stream the samples of the pass just begun draw from: each pixel counts a
    /// stream's samples from where the stream began, and streams draw independent numbers
    /// ([`Sampler::in_stream`]). An estimator that samples by what it learned from earlier
    /// passes draws each pass that uses something new from a stream of its own, so that
    /// no sample is stratified against the samples its sampling was learned from (that
    /// biases the image). 0 by default: one stream for the whole render.
    fn stream(&self) -> u32 {
        0
    }

    /// Whether the samples of the pass just begun go into the image. A pass that only
    /// feeds what the estimator learns (a learning pre-pass) keeps none: its samples are
    /// traced, counted and handed to [`PassEstimator::end_pass`]'s statistics, and the
    /// pixels' sample counts stay where they were, so that the image's samples form whole
    /// streams of their own (a Sobol sequence is balanced over its first 2^k points, and a
    /// sample of another stream in the mean costs that balance).
    fn keeps(&self) -> bool {
        true
    }

    /// A fresh statistics record for `block` in `pass`.
    fn block_stats(&self, block: u32, pass: u32) -> Self::BlockStats;

    /// How many samples the pixel takes in this pass (0: none).
    fn samples(&self, pixel: &PixelState) -> u32;

    /// One sample of the pixel in `ctx`: its radiance (non-finite values, and values the film
    /// does not take, are dropped and counted). The estimator makes its own camera ray
    /// ([`SampleContext::camera_ray`]).
    fn sample(
        &self,
        scene: &RenderScene,
        ctx: &SampleContext,
        sampler: &mut Sampler,
        stats: &mut Self::BlockStats,
        rays: &mut RayCounters,
    ) -> Rgb;

    /// The samples `ctxs` (each with its stream in `samplers`) into `out`, by default one
    /// after another with [`PassEstimator::sample`]; an estimator whose samples are paths
    /// from the camera also reads their denoising features off them into `features` (as long
    /// as `ctxs`, or empty when none is asked for). A sample whose feature is left `None`
    /// takes a feature sample of its own ([`feature_sample`]).
    #[allow(clippy::too_many_arguments)]
    fn sample_many(
        &self,
        scene: &RenderScene,
        ctxs: &[SampleContext],
        samplers: &mut [Sampler],
        stats: &mut Self::BlockStats,
        rays: &mut RayCounters,
        out: &mut [Rgb],
        _features: &mut [Option<Feature>],
    ) {
        for (i, ctx) in ctxs.iter().enumerate() {
            out[i] = self.sample(scene, ctx, &mut samplers[i], stats, rays);
        }
    }

    /// The splats of light paths that a block's statistics gathered during the pass (light
    /// tracing): the film adds them after the pass, every block's, if the pass keeps its
    /// samples. None by default.
    fn take_splats(&self, _stats: &mut Self::BlockStats) -> Option<Splats> {
        None
    }

    /// Called after each completed pass with the film and every block's statistics in block
    /// order: whether to go on.
    fn end_pass(&mut self, scene: &RenderScene, film: &Film, blocks: Vec<Self::BlockStats>)
        -> bool;
}

/// Renders `estimator` pass after pass until it, the pass hook or Ctrl-C stops it. The
/// statistics say what was traced; their time runs from the control's creation.
pub fn render_passes<E: PassEstimator>(
    estimator: &mut E,
    scene: &RenderScene,
    film: &mut Film,
    settings: &RenderSettings,
    control: &RenderControl,
) -> RenderStats {
    let (width, height) = (film.width, film.height);
    let blocks = Blocks::new(width, height);
    let mut taken = vec![settings.first_sample; film.pixels.len()];
    // Each pixel's sample count where the current stream began (stream 0 from the start).
    let mut stream = 0;
    let mut stream_start = vec![0; film.pixels.len()];
    let started = Instant::now();
    control
        .progress
        .start(estimator.expected_samples(width as u64 * height as u64));
    let mut rays = RayCounters::default();
    let mut passes = 0u32;
    let mut interrupted = false;
    loop {
        let info = PassInfo {
            index: passes,
            elapsed_s: control.elapsed(),
            render_s: started.elapsed().as_secs_f64(),
            pixels: film.pixels.len() as u64,
        };
        if !estimator.begin_pass(&info) {
            break;
        }
        if estimator.stream() != stream {
            stream = estimator.stream();
            stream_start.copy_from_slice(&taken);
        }
        let keeps = estimator.keeps();
        let shared = &*estimator;
        let pass = Pass {
            index: passes,
            window: film.window,
            seed: settings.seed,
            stream,
            stream_start: &stream_start,
            keeps,
            features: film.takes_features(),
        };
        let rendered: Vec<(E::BlockStats, RayCounters)> = BlockView::all(
            blocks,
            width,
            &mut film.pixels,
            &mut taken,
            &mut film.features,
        )
        .into_par_iter()
        .map(|view| pass.render(shared, scene, control, view))
        .collect();
        let mut block_stats = Vec::with_capacity(blocks.count());
        for (mut stats, counters) in rendered {
            if let Some(splats) = estimator.take_splats(&mut stats).filter(|_| keeps) {
                rays.dropped += film.add_splats(&splats, scene.sensor_response());
            }
            block_stats.push(stats);
            rays += counters;
        }
        if control.cancelled() {
            interrupted = true;
            break;
        }
        passes += 1;
        let go_on = estimator.end_pass(scene, film, block_stats);
        // The hooks see passes that added to the film (a pre-pass adds nothing).
        if let Some(watch) = control.on_progress.filter(|_| keeps) {
            watch(film, control.elapsed());
        }
        let hook = !keeps
            || control
                .on_pass
                .is_none_or(|hook| hook(film, control.elapsed()));
        if !(go_on && hook) {
            break;
        }
    }
    let (spp, spp_max) = film.sample_count_range();
    let mut stats = RenderStats {
        scene: scene.scene.name.clone(),
        backend: scene.scene.backend.name().to_string(),
        width,
        height,
        spp,
        spp_max,
        seed: settings.seed,
        threads: rayon::current_num_threads(),
        time_s: control.elapsed(),
        passes,
        rays,
        interrupted,
        ..Default::default()
    };
    stats.derive_rates();
    stats
}

/// The film's pixels of one block, their sample counts and their denoising features (if the
/// film takes them): up to eight row pieces of up to eight pixels (disjoint slices of the
/// row-major film, so blocks render in parallel).
struct BlockView<'a> {
    index: u32,
    x0: u32,
    y0: u32,
    rows: [Option<Row<'a>>; BLOCK_SIZE as usize],
}

/// One row piece of a block.
struct Row<'a> {
    pixels: &'a mut [Pixel],
    taken: &'a mut [u32],
    /// Empty if the film takes no features.
    features: &'a mut [FeaturePixel],
}

impl<'a> BlockView<'a> {
    /// Every block of the film, in block order (`features` empty if the film takes none).
    fn all(
        blocks: Blocks,
        width: u32,
        pixels: &'a mut [Pixel],
        taken: &'a mut [u32],
        features: &'a mut [FeaturePixel],
    ) -> Vec<BlockView<'a>> {
        let mut views: Vec<BlockView> = (0..blocks.count() as u32)
            .map(|index| BlockView {
                index,
                x0: (index % blocks.columns) * BLOCK_SIZE,
                y0: (index / blocks.columns) * BLOCK_SIZE,
                rows: std::array::from_fn(|_| None),
            })
            .collect();
        let w = width.max(1) as usize;
        let b = BLOCK_SIZE as usize;
        let rows = pixels.chunks_mut(w).zip(taken.chunks_mut(w));
        let mut feature_rows = features.chunks_mut(w);
        for (y, (pixels, taken)) in rows.enumerate() {
            let first = (y / b) * blocks.columns as usize;
            let mut features = feature_rows.next().unwrap_or_default().chunks_mut(b);
            for (column, (pixels, taken)) in
                pixels.chunks_mut(b).zip(taken.chunks_mut(b)).enumerate()
            {
                let features = features.next().unwrap_or_default();
                views[first + column].rows[y % b] = Some(Row {
                    pixels,
                    taken,
                    features,
                });
            }
        }
        views
    }
}

/// What every block of one pass shares.
struct Pass<'a> {
    index: u32,
    /// The film's window of the image: block and pixel positions are the film's, samples
    /// and camera rays the image's.
    window: Window,
    seed: u64,
    /// The random stream of the pass, and each film pixel's sample count where it began.
    stream: u32,
    stream_start: &'a [u32],
    /// Whether the pass's samples go into the film.
    keeps: bool,
    /// Whether the film takes denoising features.
    features: bool,
}

impl Pass<'_> {
    /// Renders one block: its pixels row by row, each pixel's samples in index order (and
    /// their denoising features); returns the block's statistics and the rays traced.
    fn render<E: PassEstimator>(
        &self,
        estimator: &E,
        scene: &RenderScene,
        control: &RenderControl,
        view: BlockView,
    ) -> (E::BlockStats, RayCounters) {
        let mut counters = RayCounters::default();
        let block = view.index;
        let mut stats = estimator.block_stats(block, self.index);
        if control.cancelled() {
            return (stats, counters);
        }
        // Whether each sample takes a denoising feature (empty if the pass takes none).
        let mut wanted: Vec<bool> = Vec::new();
        // Every sample of the block's pass, pixel by pixel, each pixel's in index order.
        let mut ctxs = Vec::new();
        let mut starts = Vec::new();
        let mut counts = Vec::with_capacity((BLOCK_SIZE * BLOCK_SIZE) as usize);
        for (dy, row) in view.rows.iter().enumerate() {
            let Some(Row { pixels, taken, .. }) = row else {
                continue;
            };
            let y = self.window.y0 + view.y0 + dy as u32;
            for (dx, (pixel, &first)) in pixels.iter().zip(taken.iter()).enumerate() {
                let x = self.window.x0 + view.x0 + dx as u32;
                let n = estimator.samples(&PixelState {
                    x,
                    y,
                    block,
                    pass: self.index,
                    taken: first,
                    film: pixel,
                });
                let n = n.min(u32::MAX - first);
                counts.push(n);
                let ctx = SampleContext {
                    x,
                    y,
                    width: self.window.full_width,
                    height: self.window.full_height,
                    block,
                    pass: self.index,
                    index: first,
                };
                ctxs.extend((first..first + n).map(|index| SampleContext { index, ..ctx }));
                let film_width = self.window.x1 - self.window.x0;
                let film_pixel = (view.y0 + dy as u32) * film_width + view.x0 + dx as u32;
                let start = self.stream_start[film_pixel as usize];
                starts.extend(std::iter::repeat_n(start, n as usize));
                if self.features && self.keeps {
                    wanted.extend((first..first + n).map(takes_feature));
                }
            }
        }
        let mut samplers: Vec<Sampler> = ctxs
            .iter()
            .zip(&starts)
            .map(|(ctx, &start)| {
                Sampler::in_stream(self.seed, self.stream, ctx.pixel(), ctx.index - start)
            })
            .collect();
        let mut out = vec![Rgb::ZERO; ctxs.len()];
        // The features read off the samples' paths (empty if none is wanted).
        let mut read = vec![
            None;
            if wanted.contains(&true) {
                ctxs.len()
            } else {
                0
            }
        ];
        estimator.sample_many(
            scene,
            &ctxs,
            &mut samplers,
            &mut stats,
            &mut counters,
            &mut out,
            &mut read,
        );
        let mut values = out.into_iter();
        let mut counts = counts.into_iter();
        let mut next = 0;
        let rows = view.rows.into_iter().flatten().filter(|_| self.keeps);
        let response = scene.sensor_response();
        for row in rows {
            for (dx, (pixel, taken)) in row.pixels.iter_mut().zip(row.taken.iter_mut()).enumerate()
            {
                let n = counts.next().unwrap_or(0);
                // The pixel's features: read off its paths, or feature samples of their own.
                for i in (next..next + n as usize).filter(|&i| wanted.get(i) == Some(&true)) {
                    let f = read[i].unwrap_or_else(|| feature_sample(scene, &ctxs[i], self.seed));
                    row.features[dx].add(&f);
                }
                next += n as usize;
                for l in values.by_ref().take(n as usize) {
                    // The film's sensor sees each sample, as pbrt-v4's does.
                    let l = response.map_or(l, |m| l.transformed(m));
                    if Pixel::accepts(l) {
                        pixel.add(l);
                    } else {
                        counters.dropped += 1;
                    }
                }
                *taken += n;
            }
        }
        control.progress.advance(ctxs.len() as u64);
        (stats, counters)
    }
}
