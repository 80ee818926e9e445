//! The block/pass driver: renders an image in passes over 8x8 pixel blocks (seed 004
//! §3.3.2, Fig. 3.4). Before a pass the estimator decides how many samples each pixel takes
//! (adaptive sampling: converged pixels take none); during the pass every block gathers its
//! own statistics; after it the estimator sees the film and all blocks' statistics, in block
//! order, and rebuilds what the next pass samples from.
//!
//! Work is split into bands of eight pixel rows (one row of blocks), rendered in parallel;
//! within a band, blocks and pixels go in order and each pixel's samples in index order, so
//! the film and the block statistics are the same whatever the number of threads.

use super::{Blocks, SampleContext, BLOCK_SIZE};
use crate::control::RenderControl;
use crate::film::{Film, Pixel};
use crate::render_scene::RenderScene;
use crate::settings::RenderSettings;
use fenestra_core::stats::{RayCounters, RenderStats};
use fenestra_core::{Rgb, Sampler};
use rayon::prelude::*;
use std::time::Instant;

/// Where a render stands before a pass.
#[derive(Clone, Copy, Debug)]
pub struct PassInfo {
    /// The pass about to start, from 0.
    pub index: u32,
    /// Seconds since the render began (preparation included): what time limits count.
    pub elapsed_s: f64,
    /// Seconds spent in the passes so far (for the cost of a sample).
    pub render_s: f64,
}

/// A pixel as the estimator sees it before a pass.
#[derive(Clone, Copy, Debug)]
pub struct PixelState<'a> {
    /// Pixel column.
    pub x: u32,
    /// Pixel row.
    pub y: u32,
    /// The pixel's 8x8 block.
    pub block: u32,
    /// The pass about to render.
    pub pass: u32,
    /// Samples the pixel has taken (its next sample's index).
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

    /// A fresh statistics record for `block` in `pass`.
    fn block_stats(&self, block: u32, pass: u32) -> Self::BlockStats;

    /// How many samples the pixel takes in this pass (0: none).
    fn samples(&self, pixel: &PixelState) -> u32;

    /// One sample of the pixel in `ctx`: its radiance (non-finite values are dropped and
    /// counted). The estimator makes its own camera ray ([`SampleContext::camera_ray`]).
    fn sample(
        &self,
        scene: &RenderScene,
        ctx: &SampleContext,
        sampler: &mut Sampler,
        stats: &mut Self::BlockStats,
        rays: &mut RayCounters,
    ) -> Rgb;

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
    let band = width as usize * BLOCK_SIZE as usize;
    let mut taken = vec![0u32; film.pixels.len()];
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
        };
        if !estimator.begin_pass(&info) {
            break;
        }
        let shared = &*estimator;
        let bands: Vec<(Vec<E::BlockStats>, RayCounters)> = film
            .pixels
            .par_chunks_mut(band.max(1))
            .zip(taken.par_chunks_mut(band.max(1)))
            .enumerate()
            .map(|(row, (pixels, taken))| {
                let band = Band {
                    row: row as u32,
                    width,
                    height,
                    blocks,
                    pass: passes,
                    seed: settings.seed,
                };
                band.render(shared, scene, control, pixels, taken)
            })
            .collect();
        let mut block_stats = Vec::with_capacity(blocks.count());
        for (stats, counters) in bands {
            block_stats.extend(stats);
            rays += counters;
        }
        if control.cancelled() {
            interrupted = true;
            break;
        }
        passes += 1;
        let go_on = estimator.end_pass(scene, film, block_stats);
        let hook = control
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

/// One row of blocks in one pass.
struct Band {
    row: u32,
    width: u32,
    height: u32,
    blocks: Blocks,
    pass: u32,
    seed: u64,
}

impl Band {
    /// Renders the band's blocks left to right into `pixels` (the band's rows of the film)
    /// and `taken` (their sample counts); returns each block's statistics and the rays.
    fn render<E: PassEstimator>(
        &self,
        estimator: &E,
        scene: &RenderScene,
        control: &RenderControl,
        pixels: &mut [Pixel],
        taken: &mut [u32],
    ) -> (Vec<E::BlockStats>, RayCounters) {
        let mut counters = RayCounters::default();
        let mut stats = Vec::with_capacity(self.blocks.columns as usize);
        let y0 = self.row * BLOCK_SIZE;
        let y1 = (y0 + BLOCK_SIZE).min(self.height);
        for column in 0..self.blocks.columns {
            let block = self.row * self.blocks.columns + column;
            let mut block_stats = estimator.block_stats(block, self.pass);
            if !control.cancelled() {
                let x0 = column * BLOCK_SIZE;
                let x1 = (x0 + BLOCK_SIZE).min(self.width);
                let mut samples = 0u64;
                for y in y0..y1 {
                    for x in x0..x1 {
                        let i = ((y - y0) * self.width + x) as usize;
                        let first = taken[i];
                        let n = estimator.samples(&PixelState {
                            x,
                            y,
                            block,
                            pass: self.pass,
                            taken: first,
                            film: &pixels[i],
                        });
                        let last = first.saturating_add(n);
                        let mut ctx = SampleContext {
                            x,
                            y,
                            width: self.width,
                            height: self.height,
                            block,
                            pass: self.pass,
                            index: first,
                        };
                        for s in first..last {
                            ctx.index = s;
                            let mut sampler = Sampler::new(self.seed, ctx.pixel(), s);
                            let l = estimator.sample(
                                scene,
                                &ctx,
                                &mut sampler,
                                &mut block_stats,
                                &mut counters,
                            );
                            if l.is_finite() {
                                pixels[i].add(l);
                            } else {
                                counters.dropped += 1;
                            }
                        }
                        taken[i] = last;
                        samples += (last - first) as u64;
                    }
                }
                control.progress.advance(samples);
            }
            stats.push(block_stats);
        }
        (stats, counters)
    }
}
