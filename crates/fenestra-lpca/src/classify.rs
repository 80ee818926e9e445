//! The classification step: every point to its nearest affine subspace. `full` is LPCA's
//! (and Lloyd's) exhaustive search; `sorted` is SortCluster-LPCA (Alg. 2; SortMeans when
//! the subspaces are points), which visits the subspaces in order of their distance from the
//! point's previous one and stops when the generalised triangle inequality (eq. 3.4) proves
//! no farther one can be nearer.

use crate::data::Dataset;
use crate::subspace::{subspace_distance, GramBlocks, Subspace};
use rayon::prelude::*;
use std::time::Instant;

/// What one classification step cost.
#[derive(Clone, Copy, Debug, Default, serde::Serialize)]
pub struct ClassifyStats {
    /// Seconds spent classifying, overhead included.
    pub seconds: f64,
    /// Seconds spent on the matrices D and M (SortCluster-LPCA only).
    pub overhead_seconds: f64,
    /// Point-subspace distances evaluated.
    pub distance_evals: u64,
    /// Subspace-subspace distances evaluated (for D).
    pub subspace_distance_evals: u64,
    /// Points whose cluster changed.
    pub changed: u64,
}

/// True when `candidate` (distance, index) beats `best`: smaller distance, ties to the lower
/// index, which is what an exhaustive search in index order returns.
fn better(dist: f64, idx: u32, best_dist: f64, best_idx: u32) -> bool {
    dist < best_dist || (dist == best_dist && idx < best_idx)
}

/// Runs `nearest(point, previous cluster, scratch) -> (cluster, distance, evaluations)` for
/// every point in parallel, updating `assign` and `dist`; returns (evaluations, moved points).
fn each_point(
    data: &Dataset,
    assign: &mut [u32],
    dist: &mut [f64],
    nearest: impl Fn(&[f32], u32, &mut [f64]) -> (u32, f64, u64) + Sync,
) -> (u64, u64) {
    assign
        .par_iter_mut()
        .zip(dist.par_iter_mut())
        .enumerate()
        .map_init(
            || vec![0.0; data.d],
            |s, (i, (a, d))| {
                let (best, best_dist, evals) = nearest(data.row(i), *a, s);
                let moved = (best != *a) as u64;
                (*a, *d) = (best, best_dist);
                (evals, moved)
            },
        )
        .reduce(|| (0, 0), |x, y| (x.0 + y.0, x.1 + y.1))
}

/// Exhaustive search; `assign` and `dist` are overwritten.
pub fn full(
    data: &Dataset,
    models: &[Subspace],
    assign: &mut [u32],
    dist: &mut [f64],
) -> ClassifyStats {
    let start = Instant::now();
    let (distance_evals, changed) = each_point(data, assign, dist, |x, _, s| {
        let (mut bi, mut bd) = (0u32, f64::INFINITY);
        for (j, m) in models.iter().enumerate() {
            let dj = m.distance(x, s);
            if better(dj, j as u32, bd, bi) {
                (bi, bd) = (j as u32, dj);
            }
        }
        (bi, bd, models.len() as u64)
    });
    ClassifyStats {
        seconds: start.elapsed().as_secs_f64(),
        overhead_seconds: 0.0,
        distance_evals,
        subspace_distance_evals: 0,
        changed,
    }
}

/// The distance matrix D between all subspaces and, per row, the other subspaces sorted by
/// that distance (M), as (distance, index) pairs.
pub fn sorted_neighbours(models: &[Subspace]) -> Vec<Vec<(f64, u32)>> {
    let k = models.len();
    let pairs: Vec<(usize, usize)> = (0..k)
        .flat_map(|i| (i + 1..k).map(move |j| (i, j)))
        .collect();
    let gram = GramBlocks::new(models);
    let d: Vec<f64> = pairs
        .par_iter()
        .map(|&(i, j)| subspace_distance(models, &gram, i, j))
        .collect();
    let mut rows = vec![Vec::with_capacity(k.saturating_sub(1)); k];
    for (&(i, j), &dij) in pairs.iter().zip(&d) {
        rows[i].push((dij, j as u32));
        rows[j].push((dij, i as u32));
    }
    rows.par_iter_mut()
        .for_each(|r| r.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1))));
    rows
}

/// Alg. 2 for every point, starting from its previous assignment in `assign`.
pub fn sorted(
    data: &Dataset,
    models: &[Subspace],
    assign: &mut [u32],
    dist: &mut [f64],
) -> ClassifyStats {
    let start = Instant::now();
    let neighbours = sorted_neighbours(models);
    let overhead_seconds = start.elapsed().as_secs_f64();
    let (distance_evals, changed) = each_point(data, assign, dist, |x, prev, s| {
        let model = &models[prev as usize];
        let d_i = model.distance(x, s);
        // Rounding bound for the pruning test: distances are accurate to ~1e-15 of |x - mu|
        // and D is a guaranteed lower bound; the margin is many orders larger than that.
        let scale = model.distance_to_mean(x);
        let (mut bi, mut bd) = (prev, d_i);
        let mut evals = 1u64;
        for &(dij, j) in &neighbours[prev as usize] {
            if dij - (d_i + bd) > 1e-9 * (dij + d_i + bd + scale) {
                break;
            }
            let dj = models[j as usize].distance(x, s);
            evals += 1;
            if better(dj, j, bd, bi) {
                (bi, bd) = (j, dj);
            }
        }
        (bi, bd, evals)
    });
    let k = models.len() as u64;
    ClassifyStats {
        seconds: start.elapsed().as_secs_f64(),
        overhead_seconds,
        distance_evals,
        subspace_distance_evals: k * k.saturating_sub(1) / 2,
        changed,
    }
}
