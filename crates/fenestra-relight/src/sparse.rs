//! Sparse wavelet images of transfer vectors and the classification distance of Wavelet-LPCA
//! (seed 003 §4.5.1.2, Alg. 4): for an affine subspace a = (mu, V),
//! d^2(x, a) = |x|^2 - 2 x . mu + |mu|^2 - |V^T x - V^T mu|^2 (eq. 4.3-4.4), where x enters
//! only through products with its few non-zero coefficients, and |mu|^2 and V^T mu are
//! computed once per subspace.

use fenestra_lpca::Subspace;

/// A vector of dimension `len` with `values` at `indices` (ascending) and zeros elsewhere.
#[derive(Clone, Debug, PartialEq)]
pub struct SparseVec {
    /// Dimension.
    pub len: usize,
    /// Where the non-zero coefficients are, ascending.
    pub indices: Vec<u32>,
    /// Their values.
    pub values: Vec<f64>,
    /// |x|^2 (kept: it does not change during LPCA).
    pub norm2: f64,
}

impl SparseVec {
    /// The `keep` coefficients of `dense` largest in magnitude (ties to the lower index).
    pub fn largest(dense: &[f64], keep: usize) -> Self {
        let mut order: Vec<u32> = (0..dense.len() as u32).collect();
        if keep < dense.len() {
            order.select_nth_unstable_by(keep, |&a, &b| {
                dense[b as usize]
                    .abs()
                    .total_cmp(&dense[a as usize].abs())
                    .then(a.cmp(&b))
            });
            order.truncate(keep);
        }
        order.sort_unstable();
        order.retain(|&i| dense[i as usize] != 0.0);
        let values: Vec<f64> = order.iter().map(|&i| dense[i as usize]).collect();
        SparseVec {
            len: dense.len(),
            norm2: values.iter().map(|v| v * v).sum(),
            indices: order,
            values,
        }
    }

    /// Its non-zero coefficients as (index, value).
    pub fn iter(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        (self.indices.iter().map(|&i| i as usize)).zip(self.values.iter().copied())
    }

    /// x . y for a dense y.
    pub fn dot(&self, y: &[f64]) -> f64 {
        self.iter().map(|(i, v)| v * y[i]).sum()
    }

    /// Element `j` of the signal whose Haar transform this is (seed 003 §4.5.3: elements of a
    /// transfer vector from its sparse wavelet image without the full inverse):
    /// its log2(len) + 1 coefficients found by binary search.
    pub fn element(&self, j: usize) -> f64 {
        let levels = self.len.trailing_zeros();
        let find = |index: usize| {
            (self.indices.binary_search(&(index as u32)).ok()).map_or(0.0, |p| {
                self.values[p] * crate::haar::basis_at(index, j, levels)
            })
        };
        find(0)
            + (0..levels)
                .map(|k| find((1 << k) + (j >> (levels - k))))
                .sum::<f64>()
    }

    /// x . y for a sparse y (both index lists ascending).
    pub fn dot_sparse(&self, y: &SparseVec) -> f64 {
        let (mut a, mut b, mut sum) = (0, 0, 0.0);
        while a < self.indices.len() && b < y.indices.len() {
            match self.indices[a].cmp(&y.indices[b]) {
                std::cmp::Ordering::Less => a += 1,
                std::cmp::Ordering::Greater => b += 1,
                std::cmp::Ordering::Equal => {
                    sum += self.values[a] * y.values[b];
                    a += 1;
                    b += 1;
                }
            }
        }
        sum
    }

    /// The dense vector.
    pub fn to_dense(&self) -> Vec<f64> {
        let mut d = vec![0.0; self.len];
        self.iter().for_each(|(i, v)| d[i] = v);
        d
    }
}

/// What Alg. 4 precomputes for a subspace: |mu|^2 and V^T mu.
#[derive(Clone, Debug)]
pub struct Precomputed {
    /// |mu|^2.
    pub mean2: f64,
    /// V^T mu.
    pub basis_mean: Vec<f64>,
}

impl Precomputed {
    /// The terms of `a`.
    pub fn new(a: &Subspace) -> Self {
        let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(p, q)| p * q).sum::<f64>();
        Precomputed {
            mean2: dot(&a.mean, &a.mean),
            basis_mean: a.basis.iter().map(|e| dot(e, &a.mean)).collect(),
        }
    }
}

/// Eq. 4.3-4.4: the squared distance of `x` to the affine subspace `a` (`pre` its terms).
pub fn distance2(x: &SparseVec, a: &Subspace, pre: &Precomputed) -> f64 {
    let y = x.norm2 - 2.0 * x.dot(&a.mean) + pre.mean2;
    let z: f64 = (a.basis.iter().zip(&pre.basis_mean))
        .map(|(e, &em)| {
            let c = x.dot(e) - em;
            c * c
        })
        .sum();
    (y - z).max(0.0)
}

/// Alg. 4: the nearest of the subspaces `a` (with their terms `pre`) to `x`, and the squared
/// distance.
pub fn nearest(x: &SparseVec, a: &[Subspace], pre: &[Precomputed]) -> (usize, f64) {
    let mut best = (0, f64::INFINITY);
    for (i, (s, p)) in a.iter().zip(pre).enumerate() {
        let d = distance2(x, s, p);
        if d < best.1 {
            best = (i, d);
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::haar;
    use fenestra_core::Sampler;

    /// A random affine subspace of dimension `l` in `d` dimensions (orthonormal basis).
    fn subspace(d: usize, l: usize, seed: u64) -> Subspace {
        let mut s = Sampler::new(seed, 1, 0);
        let mut r = || s.next_1d() as f64 - 0.5;
        let mean: Vec<f64> = (0..d).map(|_| r()).collect();
        let mut basis: Vec<Vec<f64>> = Vec::new();
        while basis.len() < l {
            let mut v: Vec<f64> = (0..d).map(|_| r()).collect();
            for e in &basis {
                let c: f64 = v.iter().zip(e).map(|(a, b)| a * b).sum();
                v.iter_mut().zip(e).for_each(|(a, b)| *a -= c * b);
            }
            let n = v.iter().map(|a| a * a).sum::<f64>().sqrt();
            basis.push(v.into_iter().map(|a| a / n).collect());
        }
        Subspace { mean, basis }
    }

    #[test]
    fn the_sparse_distance_equals_the_dense_one_and_survives_the_transform() {
        let (d, l) = (128, 4);
        let a = subspace(d, l, 5);
        let pre = Precomputed::new(&a);
        let mut s = Sampler::new(6, 2, 0);
        let mut scratch = vec![0.0; d];
        let mut dense_scratch = vec![0.0f64; d];
        for keep in [1, 9, 40, 128] {
            let x: Vec<f64> = (0..d).map(|_| s.next_1d() as f64 * 2.0 - 1.0).collect();
            let sparse = SparseVec::largest(&x, keep);
            let dense: Vec<f32> = sparse.to_dense().iter().map(|&v| v as f32).collect();
            let want = a.distance(&dense, &mut dense_scratch).powi(2);
            let got = distance2(&sparse, &a, &pre);
            assert!(
                (got - want).abs() < 1e-5 * want.max(1.0),
                "keep {keep}: {got} vs {want}"
            );
            // In wavelets: x and a transformed by W are as far apart (eq. 4.3's invariance).
            let mut wx = x.clone();
            haar::forward(&mut wx, &mut scratch);
            let mut wa = a.clone();
            haar::forward(&mut wa.mean, &mut scratch);
            wa.basis
                .iter_mut()
                .for_each(|e| haar::forward(e, &mut scratch));
            let full = SparseVec::largest(&wx, d);
            let plain: Vec<f32> = x.iter().map(|&v| v as f32).collect();
            let original = a.distance(&plain, &mut dense_scratch).powi(2);
            let transformed = distance2(&full, &wa, &Precomputed::new(&wa));
            assert!((original - transformed).abs() < 1e-5 * original.max(1.0));
        }
    }

    #[test]
    fn the_largest_coefficients_are_kept() {
        let x = [0.5, -3.0, 0.0, 2.0, -0.1, 2.0];
        let s = SparseVec::largest(&x, 3);
        assert_eq!(s.indices, vec![1, 3, 5]);
        assert_eq!(s.values, vec![-3.0, 2.0, 2.0]);
        assert!((s.norm2 - 17.0).abs() < 1e-12);
        assert_eq!(SparseVec::largest(&x, 10).indices, vec![0, 1, 3, 4, 5]);
    }
}
