//! One pixel of a block through its passes: its points, what its eye rays saw emitted, and
//! its pass estimates combined (seed 004 eq. 3.3, 3.4) until it is done (§3.5.3, §4.6.4).

use super::estimate::luminance;
use super::feedback::Stat;
use super::options::{Combine, IasOptions};
use super::point::{largest, Point};
use fenestra_core::Rgb;
use fenestra_render::driver::PixelEstimate;

/// The PDFs one point sampled its cut with, pass by pass (the seed's Fig. 4.10).
#[derive(Clone, Debug, PartialEq)]
pub struct PdfTrace {
    /// The clusters of the point's cut: forest nodes, and past the forest's nodes the
    /// clusters outside it (lights at infinity, sky regions).
    pub clusters: Vec<u32>,
    /// Per pass, the probability of each cluster.
    pub passes: Vec<Vec<f32>>,
}

/// What a finished pixel took (for the work maps, the seed's Fig. 4.9 and 4.11).
pub(super) struct PixelWork {
    pub(super) x: u32,
    pub(super) y: u32,
    pub(super) passes: u32,
    pub(super) shadow_rays: u32,
    pub(super) visible_rays: u32,
    /// Its anti-aliasing regions.
    pub(super) regions: u32,
    /// The size of its points' cuts, weighed by their share of the pixel.
    pub(super) clusters: f32,
}

/// One pixel of the block.
pub(super) struct PixelState {
    pub(super) x: u32,
    pub(super) y: u32,
    pub(super) points: Vec<Point>,
    /// What the eye rays see emitted (no shadow ray), and the variance of that mean over
    /// the eye rays, per channel.
    emitted: Rgb,
    emitted_variance: [f64; 3],
    /// Whether its eye rays saw the edge of a light.
    pub(super) edge: bool,
    /// Over the passes, with pass weights w: sum w, sum w I (per channel), and the sums
    /// w^2 s^2 of the luminance's and each channel's variance.
    weight: f64,
    weighted: [f64; 3],
    variance: f64,
    channel_variance: [f64; 3],
    passes: u32,
    pub(super) shadow_rays: u32,
    rays_before: u32,
    pub(super) seen_light: bool,
    pub(super) visible_rays: u32,
    pub(super) done: bool,
    /// Light samples the pixel has taken (its regions' hits take them in turn).
    pub(super) next_sample: u32,
    /// Its rows of the pixel statistics: node slot -> stat, per class present.
    pub(super) stats: Vec<(usize, Vec<Stat>)>,
    /// For the pixel whose PDFs are traced: its largest region's PDF in each pass.
    pub(super) trace: Option<Vec<Vec<f32>>>,
}

impl PixelState {
    /// Pixel (x, y) with its `points`, what its eye rays saw emitted (mean, variance of
    /// the mean), whether they saw a light's `edge`, and whether its PDFs are `traced`.
    pub(super) fn new(
        (x, y): (u32, u32),
        points: Vec<Point>,
        (emitted, emitted_variance): (Rgb, [f64; 3]),
        edge: bool,
        traced: bool,
    ) -> Self {
        PixelState {
            x,
            y,
            done: points.is_empty(),
            points,
            emitted,
            emitted_variance,
            edge,
            weight: 0.0,
            weighted: [0.0; 3],
            variance: 0.0,
            channel_variance: [0.0; 3],
            passes: 0,
            shadow_rays: 0,
            rays_before: 0,
            seen_light: false,
            visible_rays: 0,
            next_sample: 0,
            stats: Vec::new(),
            trace: traced.then(Vec::new),
        }
    }

    /// The normal classes of its points, each once, in order.
    pub(super) fn classes(&self) -> Vec<usize> {
        let mut classes: Vec<usize> = self.points.iter().map(|q| q.class).collect();
        classes.sort_unstable();
        classes.dedup();
        classes
    }

    /// The combined estimate (eq. 3.4 with the pass weights), the variance of its luminance
    /// (eq. 3.3 for inverse-variance weights) and of each channel.
    fn estimate(&self) -> ([f64; 3], f64, [f64; 3]) {
        if self.weight <= 0.0 {
            return ([0.0; 3], 0.0, [0.0; 3]);
        }
        let w2 = self.weight * self.weight;
        (
            self.weighted.map(|v| v / self.weight),
            self.variance / w2,
            self.channel_variance.map(|v| v / w2),
        )
    }

    /// The estimate and luminance variance if a pass (`estimate`, `s2`) of weight `w` joined.
    pub(super) fn with_pass(&self, estimate: [f64; 3], s2: f64, w: f64) -> (f64, f64) {
        let weight = self.weight + w;
        let mean = (luminance(self.weighted) + w * luminance(estimate)) / weight;
        (mean, (self.variance + w * w * s2) / (weight * weight))
    }

    /// Drops the passes combined so far (pass 0's, which only seeds the statistics).
    pub(super) fn forget_passes(&mut self) {
        self.weight = 0.0;
        self.weighted = [0.0; 3];
        self.variance = 0.0;
        self.channel_variance = [0.0; 3];
    }

    /// The weight of a pass of luminance variance `s2` with the pixel's rays since its last
    /// pass: 1/s2 (eq. 3.3), or the rays.
    pub(super) fn pass_weight(&self, s2: f64, combine: Combine) -> f64 {
        let rays = f64::from((self.shadow_rays - self.rays_before).max(1));
        match combine {
            Combine::Samples => rays,
            // A pass whose samples were all alike has no variance of its own: after passes
            // that had one it counts as informative per ray as they were (eq. 3.3 would give
            // it infinite weight); before any, it is all there is.
            Combine::InverseVariance if s2 > 0.0 => 1.0 / s2,
            Combine::InverseVariance if self.weight > 0.0 => {
                self.weight * rays / f64::from(self.rays_before.max(1))
            }
            Combine::InverseVariance => 1.0,
        }
    }

    /// Adds pass `pass`'s estimate (its luminance variance `s2`, its channels' `channels`)
    /// to the pixel (eq. 3.3, 3.4) and decides whether it is done at `threshold`.
    pub(super) fn finish_pass(
        &mut self,
        pass: u32,
        (estimate, s2, channels): ([f64; 3], f64, [f64; 3]),
        options: &IasOptions,
        threshold: f32,
    ) {
        self.passes = pass + 1;
        let w = self.pass_weight(s2, options.combine);
        self.rays_before = self.shadow_rays;
        self.weight += w;
        self.variance += w * w * s2;
        for c in 0..3 {
            self.weighted[c] += w * estimate[c];
            self.channel_variance[c] += w * w * channels[c];
        }
        let (mean, var, _) = self.estimate();
        let m = luminance(mean);
        // Termination on relative variance (§3.5.3); samples all alike and lit are exact.
        let converged = m > 0.0 && var / (m * m) < f64::from(threshold);
        // The black-pixel rule (§4.6.4).
        let black =
            !self.seen_light && self.passes >= 3 && self.shadow_rays >= options.black_after();
        self.done = converged || black || self.passes >= options.max_passes;
    }

    /// The pixel's value: its passes' estimate plus what its eye rays saw emitted, and the
    /// variance of both.
    pub(super) fn estimate_out(&self) -> PixelEstimate {
        let (mean, _, shading) = self.estimate();
        let e = self.emitted;
        PixelEstimate {
            x: self.x,
            y: self.y,
            mean: [
                mean[0] + e.r as f64,
                mean[1] + e.g as f64,
                mean[2] + e.b as f64,
            ],
            variance: std::array::from_fn(|c| shading[c] + self.emitted_variance[c]),
        }
    }

    /// What the pixel took.
    pub(super) fn work(&self) -> PixelWork {
        PixelWork {
            x: self.x,
            y: self.y,
            passes: self.passes,
            shadow_rays: self.shadow_rays,
            visible_rays: self.visible_rays,
            regions: self.points.len() as u32,
            clusters: self
                .points
                .iter()
                .map(|q| q.area * q.cut.len() as f32)
                .sum(),
        }
    }

    /// The PDFs of its largest region pass by pass, if they were traced.
    pub(super) fn pdf_trace(&self) -> Option<PdfTrace> {
        let passes = self.trace.as_ref().filter(|_| !self.points.is_empty())?;
        Some(PdfTrace {
            clusters: self.points[largest(&self.points)].cut.clone(),
            passes: passes.clone(),
        })
    }
}
