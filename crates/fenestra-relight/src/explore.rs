//! Exploring the light transfer tensor (seed 003 §4.4.2, Alg. 3, after Huang and Ramamoorthi
//! 2010): view samples are evaluated in batches drawn by weight; after each batch every
//! unexplored sample's weight becomes the local dimensionality of the transfer around it, the
//! numerical rank of the matrix of its nearest explored samples' transfer vectors, nearness
//! measured in space and time by eq. 4.2: d = sqrt(w1^2 |P_a - P_b|^2 + w2^2 (t_a - t_b)^2)
//! (w1 = 1 / scene size, w2 = 1 / frames, the seed's suggestion). Samples go where transfer
//! changes.

use faer::Mat;
use fenestra_core::{Rng, Vec3};

/// A view sample: the point a pixel sees at a frame.
#[derive(Clone, Copy, Debug)]
pub struct ViewSample {
    /// Its position.
    pub p: Vec3,
    /// Its frame.
    pub frame: u32,
}

/// How the exploration runs.
#[derive(Clone, Debug)]
pub struct ExploreOptions {
    /// Batches (Alg. 3's iterations).
    pub batches: usize,
    /// Samples evaluated per batch.
    pub per_batch: usize,
    /// Nearby explored samples whose rank sets a weight (|S|).
    pub neighbours: usize,
    /// Singular values below this fraction of the largest do not count to the rank.
    pub rank_tolerance: f64,
    /// Eq. 4.2's weights: 1 / scene size and 1 / frames.
    pub w_space: f32,
    pub w_time: f32,
    /// Seed of the weighted draws.
    pub seed: u64,
}

/// The explored samples (index into the view samples, transfer vector) in the order they
/// were evaluated, by `transfer` (the transfer vector of a view sample).
pub fn explore(
    samples: &[ViewSample],
    options: &ExploreOptions,
    mut transfer: impl FnMut(usize) -> Vec<f64>,
) -> Vec<(usize, Vec<f64>)> {
    let mut rng = Rng::new(options.seed);
    let mut weights = vec![1.0f64; samples.len()];
    let mut explored: Vec<(usize, Vec<f64>)> = Vec::new();
    for _ in 0..options.batches {
        for _ in 0..options.per_batch {
            if weights.iter().all(|&w| w <= 0.0) {
                return explored;
            }
            let i = rng.weighted(&weights);
            weights[i] = 0.0;
            explored.push((i, transfer(i)));
        }
        for (i, w) in weights.iter_mut().enumerate() {
            if *w > 0.0 {
                *w = local_rank(&samples[i], samples, &explored, options).max(0.5);
            }
        }
    }
    explored
}

/// Eq. 4.2.
pub fn distance(a: &ViewSample, b: &ViewSample, w_space: f32, w_time: f32) -> f32 {
    let dt = a.frame as f32 - b.frame as f32;
    ((w_space * w_space) * a.p.distance_squared(b.p) + (w_time * dt).powi(2)).sqrt()
}

/// The numerical rank of the transfer vectors of the explored samples nearest `v`.
fn local_rank(
    v: &ViewSample,
    samples: &[ViewSample],
    explored: &[(usize, Vec<f64>)],
    options: &ExploreOptions,
) -> f64 {
    let mut near: Vec<(f32, usize)> = (explored.iter().enumerate())
        .map(|(k, (i, _))| {
            (
                distance(v, &samples[*i], options.w_space, options.w_time),
                k,
            )
        })
        .collect();
    let count = options.neighbours.min(near.len());
    if count == 0 {
        return 1.0;
    }
    near.select_nth_unstable_by(count - 1, |a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    near.truncate(count);
    let d = explored[0].1.len();
    let m = Mat::<f64>::from_fn(count, d, |r, c| explored[near[r].1].1[c]);
    let Ok(singular) = m.singular_values() else {
        return 1.0;
    };
    let largest = singular.iter().copied().fold(0.0, f64::max);
    singular
        .iter()
        .filter(|&&s| s > options.rank_tolerance * largest && s > 0.0)
        .count() as f64
}

#[cfg(test)]
mod tests {
    use super::*;
    use fenestra_core::Sampler;

    #[test]
    fn exploration_goes_where_transfer_changes() {
        // 2,000 view samples over 10 frames on a line x in [-1, 1]. Left of 0 every transfer
        // vector is a multiple of one (rank 1); right of 0 they differ (full rank).
        let samples: Vec<ViewSample> = (0..2000u32)
            .map(|i| ViewSample {
                p: Vec3::new((i % 200) as f32 / 100.0 - 1.0, 0.0, 0.0),
                frame: i / 200,
            })
            .collect();
        let d = 16;
        let transfer = |i: usize| -> Vec<f64> {
            let x = samples[i].p.x as f64;
            let mut s = Sampler::new(7, i as u64, 0);
            if x < 0.0 {
                (0..d).map(|j| (1.0 + x) * (j as f64 + 1.0)).collect()
            } else {
                (0..d).map(|_| s.next_1d() as f64).collect()
            }
        };
        let options = ExploreOptions {
            batches: 6,
            per_batch: 40,
            neighbours: 8,
            rank_tolerance: 1e-6,
            w_space: 0.5,
            w_time: 0.1,
            seed: 1,
        };
        let explored = explore(&samples, &options, transfer);
        assert_eq!(explored.len(), 240);
        // The first batch is uniform; later ones favour the changing half.
        let right = |batch: &[(usize, Vec<f64>)]| {
            batch.iter().filter(|(i, _)| samples[*i].p.x >= 0.0).count() as f64 / batch.len() as f64
        };
        let later = right(&explored[80..]);
        assert!(
            later > 0.75,
            "{later} of the later samples where transfer changes"
        );
        let mut seen: Vec<usize> = explored.iter().map(|e| e.0).collect();
        seen.sort_unstable();
        seen.dedup();
        assert_eq!(seen.len(), 240, "no sample is evaluated twice");
    }
}
