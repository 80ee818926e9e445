//! DBSCAN(eps, m) over the photons (seed 000 §4.3, Alg. 2), by petal-clustering with a
//! ball tree for the region queries: each spatially separate group of photons becomes one
//! cluster, and so one portal.

use fenestra_core::Vec3;
use petal_clustering::{Dbscan, Fit};
use petal_neighbors::distance::Euclidean;

/// DBSCAN(eps, m) of seed 000 Alg. 2.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct DbscanParams {
    /// Neighbourhood radius eps in metres (seed §5.2: 0.125).
    pub eps: f32,
    /// Minimum neighbourhood size m of a core point (16).
    pub min_points: usize,
}

impl Default for DbscanParams {
    fn default() -> Self {
        DbscanParams {
            eps: 0.125,
            min_points: 16,
        }
    }
}

/// Clusters of `points` as lists of indices, largest first (ties by first index); points in
/// no cluster are noise.
pub fn dbscan(points: &[Vec3], params: DbscanParams) -> Vec<Vec<usize>> {
    if points.is_empty() {
        return Vec::new();
    }
    let data = ndarray::Array2::from_shape_fn((points.len(), 3), |(i, k)| points[i][k] as f64);
    let (clusters, _noise) =
        Dbscan::new(params.eps as f64, params.min_points, Euclidean::default()).fit(&data, None);
    let mut clusters: Vec<Vec<usize>> = clusters
        .into_values()
        .map(|mut c| {
            c.sort_unstable();
            c
        })
        .collect();
    clusters.sort_by(|a, b| b.len().cmp(&a.len()).then(a[0].cmp(&b[0])));
    clusters
}

#[cfg(test)]
mod tests {
    use super::*;
    use fenestra_core::Rng;

    #[test]
    fn separated_blobs_are_found_and_scattered_points_are_noise() {
        let mut rng = Rng::new(7);
        let mut r = || rng.next_f64() as f32;
        let centres = [
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 3.0, 1.0),
        ];
        let mut points = Vec::new();
        let mut truth = Vec::new();
        for (k, c) in centres.iter().enumerate() {
            for _ in 0..100 + 50 * k {
                let d = Vec3::new(r() - 0.5, r() - 0.5, r() - 0.5) * 0.4;
                points.push(*c + d);
                truth.push(Some(k));
            }
        }
        // Noise: isolated points far from the blobs and from one another.
        for i in 0..20 {
            points.push(Vec3::new(10.0 + i as f32, -5.0, 7.0));
            truth.push(None);
        }
        let clusters = dbscan(
            &points,
            DbscanParams {
                eps: 0.15,
                min_points: 8,
            },
        );
        assert_eq!(clusters.len(), 3);
        // Largest first: blob 2 (200 points), then 1, then 0; each cluster is one blob exactly.
        for (c, blob) in clusters.iter().zip([2, 1, 0]) {
            let expected: Vec<usize> = (0..points.len())
                .filter(|&i| truth[i] == Some(blob))
                .collect();
            assert_eq!(c, &expected, "blob {blob}");
        }
    }

    #[test]
    fn chains_join_into_one_cluster_and_sparse_sets_give_none() {
        // Points 0.1 apart on a line: density-reachable end to end with eps 0.15, m 3.
        let line: Vec<Vec3> = (0..50).map(|i| Vec3::X * (0.1 * i as f32)).collect();
        let c = dbscan(
            &line,
            DbscanParams {
                eps: 0.15,
                min_points: 3,
            },
        );
        assert_eq!(c.len(), 1);
        assert_eq!(c[0].len(), 50);
        assert!(dbscan(
            &line,
            DbscanParams {
                eps: 0.05,
                min_points: 3
            }
        )
        .is_empty());
        assert!(dbscan(&[], DbscanParams::default()).is_empty());
    }
}
