//! The fitting step of LPCA: per cluster, the mean and the leading principal directions of
//! its points (thin SVD of the centred points, through faer).

use crate::data::Dataset;
use crate::subspace::Subspace;
use rayon::prelude::*;

/// Members of each cluster.
pub fn members(assign: &[u32], k: usize) -> Vec<Vec<usize>> {
    let mut m = vec![Vec::new(); k];
    for (i, &a) in assign.iter().enumerate() {
        m[a as usize].push(i);
    }
    m
}

/// New subspaces of dimension up to `dim` from the current assignment. An empty cluster
/// keeps its previous subspace; a cluster with few points gets at most (points - 1)
/// directions (the rank of its centred points).
pub fn fit(data: &Dataset, assign: &[u32], previous: &[Subspace], dim: usize) -> Vec<Subspace> {
    let groups = members(assign, previous.len());
    groups
        .par_iter()
        .zip(previous)
        .map(|(idx, prev)| {
            if idx.is_empty() {
                return prev.clone();
            }
            let d = data.d;
            let mut mean = vec![0.0f64; d];
            for &i in idx {
                for (m, &v) in mean.iter_mut().zip(data.row(i)) {
                    *m += v as f64;
                }
            }
            let inv = 1.0 / idx.len() as f64;
            mean.iter_mut().for_each(|m| *m *= inv);
            if dim == 0 || idx.len() < 2 {
                return Subspace::point(mean);
            }
            let centred = faer::Mat::<f64>::from_fn(idx.len(), d, |r, c| {
                data.row(idx[r])[c] as f64 - mean[c]
            });
            let Ok(svd) = centred.thin_svd() else {
                return Subspace::point(mean);
            };
            let (s, v) = (svd.S(), svd.V());
            let s_max = s[0].max(0.0);
            let rank = (0..s.dim())
                .take_while(|&i| s[i] > 1e-10 * s_max && s[i] > 0.0)
                .count();
            let basis = (0..dim.min(rank))
                .map(|j| (0..d).map(|r| v[(r, j)]).collect())
                .collect();
            Subspace { mean, basis }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fits_the_principal_direction() {
        // Points on the line (t, 2t, 0) + (1, 1, 1).
        let vals: Vec<f32> = (0..10)
            .flat_map(|t| [1.0 + t as f32, 1.0 + 2.0 * t as f32, 1.0])
            .collect();
        let data = Dataset::new(10, 3, vals).expect("data");
        let prev = vec![Subspace::point(vec![0.0; 3])];
        let s = &fit(&data, &[0; 10], &prev, 2)[0];
        assert_eq!(s.dim(), 1, "rank 1: one direction only");
        let e = &s.basis[0];
        let expect = [1.0 / 5f64.sqrt(), 2.0 / 5f64.sqrt(), 0.0];
        let cos = (e[0] * expect[0] + e[1] * expect[1]).abs();
        assert!((cos - 1.0).abs() < 1e-9);
        assert!((s.mean[0] - 5.5).abs() < 1e-9 && (s.mean[2] - 1.0).abs() < 1e-9);
        let mut scratch = vec![0.0; 3];
        assert!(s.distance(&[3.0, 5.0, 1.0], &mut scratch) < 1e-6);
    }
}
