//! Exploring the light transfer tensor (seed 003 §4.4.2, Alg. 3, after Huang and Ramamoorthi
//! 2010): view samples are evaluated in batches drawn by weight; after each batch every
//! unexplored sample's weight becomes the local dimensionality of the transfer around it, the
//! numerical rank of the matrix of its nearest explored samples' transfer vectors, nearness
//! measured in space and time by eq. 4.2: d = sqrt(w1^2 |P_a - P_b|^2 + w2^2 (t_a - t_b)^2)
//! (w1 = 1 / scene size, w2 = 1 / frames, the seed's suggestion). Samples go where transfer
//! changes.

use crate::neighbours::{Point, PointTree};
use crate::sparse::SparseVec;
use faer::Mat;
use fenestra_core::{Sampler, Vec3};
use rayon::prelude::*;

/// A view sample: the point a pixel sees at a frame.
#[derive(Clone, Copy, Debug)]
pub struct ViewSample {
    /// Its position.
    pub p: Vec3,
    /// Its frame.
    pub frame: u32,
}

impl ViewSample {
    /// Its point in the space where eq. 4.2 is Euclidean.
    pub fn point(&self, w_space: f32, w_time: f32) -> Point {
        let p = self.p * w_space;
        [p.x, p.y, p.z, self.frame as f32 * w_time]
    }
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

/// The explored samples (index into the view samples, sparse wavelet image of the transfer
/// vector) in the order they were evaluated, by `transfer`, evaluated in parallel (the
/// result does not depend on the thread count).
///
/// Each batch draws `per_batch` samples without replacement with probability by weight (the
/// keys u^(1/w) of Efraimidis and Spirakis, u from each sample's own random stream); after
/// it, every explored sample's local rank is the numerical rank of its `neighbours` nearest
/// explored samples' transfer, and an unexplored sample's weight is the local rank at its
/// nearest explored sample (Alg. 3 evaluates it at every sample; at a pixel per view sample
/// the nearest explored sample's neighbourhood is nearly the same and the work falls from
/// one small SVD per pixel to one per explored sample).
pub fn explore(
    samples: &[ViewSample],
    options: &ExploreOptions,
    transfer: impl Fn(usize) -> SparseVec + Sync,
) -> Vec<(usize, SparseVec)> {
    let points: Vec<Point> = (samples.iter())
        .map(|v| v.point(options.w_space, options.w_time))
        .collect();
    let mut weights = vec![1.0f64; samples.len()];
    let mut explored: Vec<(usize, SparseVec)> = Vec::new();
    for batch in 0..options.batches {
        let mut keys: Vec<(f64, usize)> = (weights.par_iter().enumerate())
            .filter(|(_, &w)| w > 0.0)
            .map(|(i, &w)| {
                let u = Sampler::new(options.seed, i as u64, batch as u32).next_1d() as f64;
                (u.max(1e-300).ln() / w, i)
            })
            .collect();
        if keys.is_empty() {
            break;
        }
        let take = options.per_batch.min(keys.len());
        // The largest keys, ties to the lower index.
        let order = |a: &(f64, usize), b: &(f64, usize)| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1));
        if take < keys.len() {
            keys.select_nth_unstable_by(take - 1, order);
            keys.truncate(take);
        }
        keys.sort_unstable_by(order);
        let drawn: Vec<(usize, SparseVec)> =
            keys.par_iter().map(|&(_, i)| (i, transfer(i))).collect();
        for (i, _) in &drawn {
            weights[*i] = 0.0;
        }
        explored.extend(drawn);
        if batch + 1 == options.batches {
            break;
        }
        let at: Vec<Point> = explored.iter().map(|(i, _)| points[*i]).collect();
        let tree = PointTree::new(&at);
        let ranks: Vec<f64> = (0..explored.len())
            .into_par_iter()
            .map_init(
                || (Vec::new(), Vec::new()),
                |(near, dense), k| {
                    tree.nearest(&at[k], options.neighbours, near);
                    let rows: Vec<&SparseVec> =
                        near.iter().map(|&(_, r)| &explored[r as usize].1).collect();
                    rank(&rows, options.rank_tolerance, dense)
                },
            )
            .collect();
        weights
            .par_iter_mut()
            .enumerate()
            .for_each_init(Vec::new, |near, (i, w)| {
                if *w > 0.0 {
                    tree.nearest(&points[i], 1, near);
                    *w = near
                        .first()
                        .map_or(1.0, |&(_, r)| ranks[r as usize])
                        .max(0.5);
                }
            });
    }
    explored
}

/// Eq. 4.2.
pub fn distance(a: &ViewSample, b: &ViewSample, w_space: f32, w_time: f32) -> f32 {
    let dt = a.frame as f32 - b.frame as f32;
    ((w_space * w_space) * a.p.distance_squared(b.p) + (w_time * dt).powi(2)).sqrt()
}

/// The numerical rank of the matrix whose rows are `rows`, from the eigenvalues of their
/// Gram matrix (the squares of its singular values), each row's products from it laid out
/// densely in `dense` (scratch, left as zeros).
fn rank(rows: &[&SparseVec], tolerance: f64, dense: &mut Vec<f64>) -> f64 {
    let Some(first) = rows.first() else {
        return 1.0;
    };
    dense.resize(first.len, 0.0);
    let mut gram = Mat::<f64>::zeros(rows.len(), rows.len());
    for (a, x) in rows.iter().enumerate() {
        x.iter().for_each(|(i, v)| dense[i] = v);
        for (b, y) in rows.iter().enumerate().take(a + 1) {
            gram[(a, b)] = y.dot(dense);
            gram[(b, a)] = gram[(a, b)];
        }
        x.iter().for_each(|(i, _)| dense[i] = 0.0);
    }
    let Ok(eigen) = gram.singular_values() else {
        return 1.0;
    };
    let largest = eigen.iter().copied().fold(0.0, f64::max);
    // Singular values s of the rows: s^2 are the Gram's eigenvalues.
    eigen
        .iter()
        .filter(|&&e| e > tolerance * tolerance * largest && e > 0.0)
        .count() as f64
}

#[cfg(test)]
mod tests {
    use super::*;

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
        let transfer = |i: usize| -> SparseVec {
            let x = samples[i].p.x as f64;
            let mut s = Sampler::new(7, i as u64, 0);
            let dense: Vec<f64> = if x < 0.0 {
                (0..d).map(|j| (1.0 + x) * (j as f64 + 1.0)).collect()
            } else {
                (0..d).map(|_| s.next_1d() as f64).collect()
            };
            SparseVec::largest(&dense, d)
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
        let right = |batch: &[(usize, SparseVec)]| {
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
