//! The block-to-completion driver: every 8x8 block of the image is rendered on its own from
//! start to end (seed 004 §3.3.2, Fig. 3.4): the estimator takes a block, runs its passes
//! with whatever feedback it keeps between them, and gives back each pixel's estimate and
//! variance. Blocks share nothing while they render, so the image is the same whatever the
//! number of threads and whatever order the blocks start in.
//!
//! For estimators whose passes are the block's own business (iterative adaptive sampling);
//! those whose passes span the image use [`super::passes`].

use super::{Blocks, BLOCK_SIZE};
use crate::control::RenderControl;
use crate::features::{feature_sample, FEATURE_SAMPLES};
use crate::film::Film;
use crate::render_scene::RenderScene;
use crate::sample_context::SampleContext;
use crate::settings::RenderSettings;
use fenestra_core::stats::{RayCounters, RenderStats};
use glam::{DVec3, Mat3};
use rayon::prelude::*;
use std::sync::Mutex;

/// One block to render: its place in the image (pixels `x0..x1` by `y0..y1`, in the whole
/// image's coordinates even when the film is a crop of it).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BlockTask {
    /// Index of the block, row-major over the film's blocks.
    pub index: u32,
    /// First column.
    pub x0: u32,
    /// First row.
    pub y0: u32,
    /// One past the last column.
    pub x1: u32,
    /// One past the last row.
    pub y1: u32,
    /// The whole image's width in pixels (camera rays and sample streams are the image's).
    pub width: u32,
    /// The whole image's height in pixels.
    pub height: u32,
    /// Seed of the render.
    pub seed: u64,
}

impl BlockTask {
    /// The block of the `width` x `height` image whose top-left pixel is (x0, y0).
    pub fn at(x0: u32, y0: u32, width: u32, height: u32, seed: u64) -> Self {
        BlockTask {
            index: Blocks::new(width, height).of(x0, y0),
            x0,
            y0,
            x1: (x0 + BLOCK_SIZE).min(width),
            y1: (y0 + BLOCK_SIZE).min(height),
            width,
            height,
            seed,
        }
    }
}

/// A finished pixel: its estimate and the variance of that estimate, per channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelEstimate {
    /// Pixel column in the image.
    pub x: u32,
    /// Pixel row in the image.
    pub y: u32,
    /// The estimate per channel.
    pub mean: [f64; 3],
    /// The variance of the estimate per channel.
    pub variance: [f64; 3],
}

/// An estimator that renders each block to completion on its own.
pub trait CompletionEstimator: Sync {
    /// What a block tells besides its pixels (work done, maps), collected in block order.
    type Block: Send;

    /// The order in which `blocks` blocks are started; the image does not depend on it.
    /// Block order by default.
    fn order(&self, blocks: u32) -> Vec<u32> {
        (0..blocks).collect()
    }

    /// Renders one block to completion: its pixels' estimates, and what else it tells.
    fn render_block(
        &self,
        scene: &RenderScene,
        task: &BlockTask,
        control: &RenderControl,
        rays: &mut RayCounters,
    ) -> (Vec<PixelEstimate>, Self::Block);
}

/// Renders every block of `film` with `estimator`, in parallel, until all are done or Ctrl-C
/// stops the render (blocks not started then stay black and are `None`). The statistics say
/// what was traced, with the eye rays per pixel as its samples per pixel; their time runs
/// from the control's creation.
pub fn render_to_completion<E: CompletionEstimator>(
    estimator: &E,
    scene: &RenderScene,
    film: &mut Film,
    settings: &RenderSettings,
    control: &RenderControl,
) -> (RenderStats, Vec<Option<E::Block>>) {
    // A cropped film renders the blocks of its window (which lies on the block grid).
    let (width, height) = (film.width, film.height);
    let window = film.window;
    let blocks = Blocks::new(width, height);
    control.progress.start(Some(blocks.count() as u64));
    // Finished blocks go into the film at once, for whoever watches the render.
    let features = film.takes_features();
    let shared = Mutex::new(&mut *film);
    let response = scene.sensor_response();
    let mut rendered: Vec<(u32, Option<Rendered<E::Block>>)> = estimator
        .order(blocks.count() as u32)
        .into_par_iter()
        .map(|b| {
            if control.cancelled() {
                return (b, None);
            }
            let x0 = window.x0 + (b % blocks.columns) * BLOCK_SIZE;
            let y0 = window.y0 + (b / blocks.columns) * BLOCK_SIZE;
            let task = BlockTask {
                index: b,
                ..BlockTask::at(x0, y0, window.full_width, window.full_height, settings.seed)
            };
            let mut rays = RayCounters::default();
            let (pixels, block) = estimator.render_block(scene, &task, control, &mut rays);
            // The block's feature samples, every pixel's first ones (the block takes its own
            // samples, so none are cut by a sample range).
            let taken = |px: &PixelEstimate| {
                let ctx = SampleContext {
                    x: px.x,
                    y: px.y,
                    width: task.width,
                    height: task.height,
                    block: b,
                    pass: 0,
                    index: 0,
                };
                (0..FEATURE_SAMPLES).map(move |index| {
                    feature_sample(scene, &SampleContext { index, ..ctx }, task.seed)
                })
            };
            let block_features: Vec<(usize, Vec<_>)> = (pixels.iter().filter(|_| features))
                .filter_map(|px| Some((window.index((px.x, px.y))?, taken(px).collect())))
                .collect();
            let mut film = shared.lock().unwrap_or_else(|e| e.into_inner());
            for px in &pixels {
                if let Some(i) = window.index((px.x, px.y)) {
                    let (mean, variance) = match response {
                        Some(m) => responded(m, px.mean, px.variance),
                        None => (px.mean, px.variance),
                    };
                    film.pixels[i].set_estimate(mean, variance);
                }
            }
            for (i, samples) in block_features {
                samples.iter().for_each(|f| film.features[i].add(f));
            }
            if let Some(watch) = control.on_progress {
                watch(&film, control.elapsed());
            }
            drop(film);
            control.progress.advance(1);
            (b, Some((block, rays)))
        })
        .collect();
    rendered.sort_unstable_by_key(|(b, _)| *b);
    let mut stats = RenderStats {
        scene: scene.scene.name.clone(),
        backend: scene.scene.backend.name().to_string(),
        width,
        height,
        seed: settings.seed,
        threads: rayon::current_num_threads(),
        ..Default::default()
    };
    let mut out = Vec::with_capacity(rendered.len());
    for (_, r) in rendered {
        let Some((block, rays)) = r else {
            stats.interrupted = true;
            out.push(None);
            continue;
        };
        stats.rays += rays;
        out.push(Some(block));
    }
    // Eye rays per pixel stand for samples per pixel.
    let pixels = f64::from(width * height).max(1.0);
    stats.spp = (stats.rays.camera as f64 / pixels).round() as u32;
    stats.spp_max = stats.spp;
    stats.time_s = control.elapsed();
    stats.derive_rates();
    (stats, out)
}

/// A rendered block (its pixels already in the film): what it tells, and the rays it traced.
type Rendered<T> = (T, RayCounters);

/// A pixel's estimate seen through the film's sensor response `m` (its white balance): the
/// mean transformed, the variance of the mean as if its channels' errors were independent
/// (an estimate keeps no covariance).
fn responded(m: Mat3, mean: [f64; 3], variance: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let m = m.as_dmat3().transpose(); // rows
    let (mean, variance) = (DVec3::from(mean), DVec3::from(variance));
    let squared = |row: DVec3| row * row;
    let rows = [m.x_axis, m.y_axis, m.z_axis];
    (
        rows.map(|r| r.dot(mean)),
        rows.map(|r| squared(r).dot(variance)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_estimate_seen_through_a_response_transforms_mean_and_variance() {
        let m = Mat3::from_cols_array(&[1.0, 0.5, 0.0, -0.25, 2.0, 0.0, 0.0, 0.0, 3.0]); // columns
        let (mean, variance) = responded(m, [1.0, 2.0, 3.0], [0.1, 0.2, 0.3]);
        // Rows of m: (1, -0.25, 0), (0.5, 2, 0), (0, 0, 3).
        assert_eq!(mean, [0.5, 4.5, 9.0]);
        let expected = [0.1 + 0.0625 * 0.2, 0.25 * 0.1 + 4.0 * 0.2, 9.0 * 0.3];
        for (v, e) in variance.iter().zip(expected) {
            assert!((v - e).abs() < 1e-12, "{variance:?} vs {expected:?}");
        }
    }
}
