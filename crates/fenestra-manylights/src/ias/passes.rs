//! A block's passes (seed 004 Steps 2-3, Fig. 3.4): at each pixel's points a PDF over the
//! cut from the block's and the pixel's statistics, light samples (and BSDF samples) by it,
//! the pass's estimate and its combination with the earlier passes, until every pixel is
//! done; the statistics learn between passes.

use super::block::BlockRender;
use super::block_stats::BlockStats;
use super::bsdf_samples::PassPdf;
use super::estimate::{pass_estimate, PointSums};
use super::options::{Combine, Pdf, REFERENCE_PASS_RAYS};
use super::pixel::{PdfTrace, PixelState, PixelWork};
use super::point::{largest, Point};
use fenestra_core::stats::RayCounters;
use fenestra_core::{Rgb, Sampler};
use fenestra_render::driver::{BlockTask, PixelEstimate};

/// What a block tells besides its pixels.
pub(super) struct BlockWork {
    /// Each pixel's work, in the order of its estimates.
    pub(super) pixels: Vec<PixelWork>,
    /// Cut clusters summed over its points, and its points.
    pub(super) cut_sizes: u64,
    pub(super) points: u64,
    /// The traced pixel's PDFs, if it lies in the block.
    pub(super) trace: Option<PdfTrace>,
}

impl BlockRender<'_> {
    /// Renders the block `task` to completion: its pixels' estimates and its work.
    pub(super) fn render(
        &self,
        task: &BlockTask,
        rays: &mut RayCounters,
    ) -> (Vec<PixelEstimate>, BlockWork) {
        let (x0, y0, x1, y1) = (task.x0, task.y0, task.x1, task.y1);
        let mut pixels = Vec::new();
        for y in y0..y1 {
            for x in x0..x1 {
                pixels.push(self.pixel_points((x, y), 0, rays));
            }
        }
        self.beside_light_edges(&mut pixels, (x0, y0, x1, y1), rays);
        let cuts = pixels
            .iter()
            .flat_map(|p| &p.points)
            .map(|q| q.cut.as_slice());
        let mut stats = BlockStats::new(self.clusters(), cuts);
        // Pixel statistics per class present.
        for p in &mut pixels {
            p.stats = p
                .classes()
                .into_iter()
                .map(|c| (c, stats.pixel_rows()))
                .collect();
        }
        let points = pixels.iter().flat_map(|p| &p.points);
        let cut_sizes = points.clone().map(|q| q.cut.len() as u64).sum();
        let points = points.count() as u64;
        for pass in 0..self.options.max_passes {
            if pixels.iter().all(|p| p.done) {
                break;
            }
            stats.begin_pass();
            for p in pixels.iter_mut().filter(|p| !p.done) {
                self.pixel_pass(p, pass, &mut stats, rays);
            }
            stats.end_pass();
        }
        let work = BlockWork {
            pixels: pixels.iter().map(PixelState::work).collect(),
            cut_sizes,
            points,
            trace: pixels.iter().find_map(PixelState::pdf_trace),
        };
        (pixels.iter().map(PixelState::estimate_out).collect(), work)
    }

    /// One pass of one pixel (Steps 2-3): PDFs, samples, statistics, the pass estimate and
    /// its combination with the earlier passes, termination.
    fn pixel_pass(
        &self,
        p: &mut PixelState,
        pass: u32,
        stats: &mut BlockStats,
        rays: &mut RayCounters,
    ) {
        let options = &self.options;
        // 1.5 N_C shadow rays for the pixel (N_C: the points' mean cut size), at least 50, at
        // most 150 after pass 0 (§4.6.1), shared among the points by area.
        let nc: f32 = p
            .points
            .iter()
            .map(|q| q.area * q.cut.len() as f32)
            .sum::<f32>()
            / p.points.iter().map(|q| q.area).sum::<f32>().max(1e-6);
        let mut budget = ((1.5 * nc).ceil() as u32).max(50);
        if pass > 0 {
            budget = budget.min(150);
        }
        let adaptive = options.pdf == Pdf::Adaptive;
        if !adaptive {
            budget = REFERENCE_PASS_RAYS;
        }
        // Each point's samples this pass.
        let mut sums: Vec<PointSums> = vec![PointSums::default(); p.points.len()];
        // Pass 0 only seeds the statistics (§3.5.2): under its uniform PDF a pixel beside a
        // bright light most often misses it, and its estimate, counted at its share of the
        // rays, pulled such pixels down by a quarter. With shared weights it is dropped once
        // a pass that learned from it is drawn; a pixel done after pass 0 keeps it.
        if pass == 1 && options.combine == Combine::Samples {
            p.forget_passes();
        }
        let pdfs: Vec<Vec<f32>> = (0..p.points.len())
            .map(|i| self.point_pdf(&p.points[i], p, pass, stats))
            .collect();
        if let Some(trace) = &mut p.trace {
            trace.push(pdfs[largest(&p.points)].clone());
        }
        let cdfs: Vec<Vec<f32>> = pdfs
            .iter()
            .map(|pdf| {
                pdf.iter()
                    .scan(0.0f32, |acc, &w| {
                        *acc += w;
                        Some(*acc)
                    })
                    .collect()
            })
            .collect();
        let pixel_index = u64::from(p.y) * u64::from(self.width) + u64::from(p.x);
        // Each pass draws from a stream of its own (the eye rays' is stream 0): the pass's
        // PDFs were learned from the earlier passes' samples, which the pass's samples must
        // not be stratified against (Sampler::in_stream).
        let first = p.next_sample;
        let mut drawn = 0u32;
        let mut round = budget;
        loop {
            for (i, q) in p.points.iter().enumerate() {
                let cdf = &cdfs[i];
                // No light can reach the point (the reference's PDF may say so exactly).
                if cdf.last().is_none_or(|&total| total <= 0.0) {
                    continue;
                }
                let n = ((round as f32 * q.area).round() as u32).max(1);
                for _ in 0..n {
                    let index = p.next_sample.wrapping_sub(first);
                    let mut sampler = Sampler::in_stream(self.seed, pass + 1, pixel_index, index);
                    let at = &q.hits[p.next_sample as usize % q.hits.len()];
                    p.next_sample = p.next_sample.wrapping_add(1);
                    let s = self.sample(q, at, &pdfs[i], cdf, &mut sampler, rays);
                    p.shadow_rays += 1;
                    p.seen_light |= s.visible;
                    p.visible_rays += u32::from(s.visible);
                    let bsdf = if q.lookup.is_empty() {
                        Rgb::ZERO
                    } else {
                        let pass = PassPdf {
                            pdf: &pdfs[i],
                            total: cdf[cdf.len() - 1],
                        };
                        self.bsdf_sample(q, at, pass, &mut sampler, rays)
                    };
                    p.seen_light |= !bsdf.is_black();
                    sums[i].add(s.value + bsdf);
                    let pixel = p.stats.iter_mut().find(|(c, _)| *c == q.class);
                    let stat = (s.leaf, s.contribution, s.power, s.visible);
                    let pixel = pixel.map(|(_, st)| st.as_mut_slice());
                    stats.record(self.forest, pixel, q.class, stat);
                }
                drawn += n;
            }
            let (estimate, s2, channels) = pass_estimate(&p.points, &sums);
            // Top-up (§4.6.1): when the pixel is within a factor of two of the threshold
            // with this pass, 25 more rays with the same PDFs.
            let w = p.pass_weight(s2, options.combine);
            let (mean, var) = p.with_pass(estimate, s2, w);
            let relative = var / (mean * mean).max(f64::MIN_POSITIVE);
            let t = f64::from(self.threshold);
            if adaptive && relative >= t && relative < 2.0 * t && drawn < 4 * budget {
                round = 25;
                continue;
            }
            p.finish_pass(pass, (estimate, s2, channels), options, self.threshold);
            break;
        }
    }

    /// The PDF over point `q` of pixel `p`'s cut for pass `pass` (eq. 3.2): the seed's
    /// adaptive one from the statistics, or the reference's.
    fn point_pdf(&self, q: &Point, p: &PixelState, pass: u32, stats: &BlockStats) -> Vec<f32> {
        if self.options.pdf == Pdf::Irradiance {
            return q.irradiance.clone();
        }
        let pixel = p.stats.iter().find(|(c, _)| *c == q.class);
        stats.pdf(q, pixel.map(|(_, s)| s.as_slice()), pass)
    }
}
