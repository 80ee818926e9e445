//! Transfer vectors at view samples the exploration did not evaluate (seed 003 §4.5.3,
//! eq. 4.5): a combination sum alpha_r x_r of the sparse wavelet images of nearby explored
//! samples, the weights alpha fitted by least squares to the new sample's transfer at a few
//! element indices I (|I| >= k), which are cheap to evaluate (eq. 4.1 for single gather
//! samples); the neighbours' elements at I come from their sparse images without a full
//! inverse transform ([`haar::element`]).

use crate::haar;
use crate::sparse::SparseVec;
use faer::Mat;
use std::collections::BTreeMap;

/// The sparse wavelet image of the vector whose elements at `indices` are `values`, as a
/// least-squares combination of `neighbours` (sparse wavelet images, all of length `n`, a
/// power of two); `None` when there are fewer indices than neighbours or the fit fails.
/// `ridge` > 0 pulls the weights towards the neighbours' average (1 / k each) with that
/// weight relative to the system's mean squared column norm: a few elements of spiky
/// transfer vectors otherwise buy a fit with large weights of opposite signs that is wrong
/// everywhere else.
pub fn reconstruct(
    neighbours: &[&SparseVec],
    indices: &[usize],
    values: &[f64],
    n: usize,
    ridge: f64,
) -> Option<SparseVec> {
    let k = neighbours.len();
    if k == 0 || indices.len() < k || indices.len() != values.len() {
        return None;
    }
    // The |I| x k system: column r holds neighbour r's elements at I.
    let a = Mat::<f64>::from_fn(indices.len(), k, |i, r| {
        haar::element(neighbours[r].iter(), indices[i], n)
    });
    let b = Mat::<f64>::from_fn(indices.len(), 1, |i, _| values[i]);
    // (A^T A + lambda I) alpha = A^T b + lambda / k, through the SVD of the stacked system
    // [A; sqrt(lambda) I] alpha = [b; sqrt(lambda) / k] (rank-deficient neighbours share
    // their weight).
    let norm2 = (0..k)
        .map(|r| {
            (0..indices.len())
                .map(|i| a[(i, r)] * a[(i, r)])
                .sum::<f64>()
        })
        .sum::<f64>()
        / k as f64;
    let lambda = ridge * norm2;
    let rows = indices.len() + if lambda > 0.0 { k } else { 0 };
    let m = Mat::<f64>::from_fn(rows, k, |i, r| {
        if i < indices.len() {
            a[(i, r)]
        } else if i - indices.len() == r {
            lambda.sqrt()
        } else {
            0.0
        }
    });
    let rhs = |i: usize| {
        if i < indices.len() {
            b[(i, 0)]
        } else {
            lambda.sqrt() / k as f64
        }
    };
    let svd = m.thin_svd().ok()?;
    let (u, s, v) = (svd.U(), svd.S(), svd.V());
    let s_max = (0..s.dim()).map(|i| s[i]).fold(0.0, f64::max);
    let mut alpha = vec![0.0; k];
    for j in 0..s.dim() {
        if s[j] <= 1e-10 * s_max || s[j] <= 0.0 {
            continue;
        }
        let c: f64 = (0..rows).map(|i| u[(i, j)] * rhs(i)).sum::<f64>() / s[j];
        for (r, a) in alpha.iter_mut().enumerate() {
            *a += v[(r, j)] * c;
        }
    }
    // Eq. 4.5 on the sparse images.
    let mut sum: BTreeMap<usize, f64> = BTreeMap::new();
    for (x, &w) in neighbours.iter().zip(&alpha) {
        for (i, v) in x.iter() {
            *sum.entry(i).or_insert(0.0) += w * v;
        }
    }
    let (indices, values): (Vec<u32>, Vec<f64>) =
        sum.into_iter().map(|(i, v)| (i as u32, v)).unzip();
    Some(SparseVec {
        len: n,
        norm2: values.iter().map(|v| v * v).sum(),
        indices,
        values,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use fenestra_core::Sampler;

    #[test]
    fn a_combination_of_the_neighbours_is_recovered_from_a_few_elements() {
        let n = 64;
        let mut s = Sampler::new(31, 0, 0);
        let mut scratch = vec![0.0; n];
        let images: Vec<SparseVec> = (0..3)
            .map(|_| {
                let mut x: Vec<f64> = (0..n).map(|_| s.next_1d() as f64).collect();
                haar::forward(&mut x, &mut scratch);
                SparseVec::largest(&x, 20)
            })
            .collect();
        // The new sample's transfer: 0.5 x0 - 2 x1 + 0.25 x2 (in the signal domain).
        let weights = [0.5, -2.0, 0.25];
        let mut truth = vec![0.0; n];
        for (img, w) in images.iter().zip(weights) {
            let mut x = img.to_dense();
            haar::inverse(&mut x, &mut scratch);
            truth.iter_mut().zip(&x).for_each(|(t, v)| *t += w * v);
        }
        let indices = [3, 17, 30, 41, 60];
        let values: Vec<f64> = indices.iter().map(|&j| truth[j]).collect();
        let refs: Vec<&SparseVec> = images.iter().collect();
        let got = reconstruct(&refs, &indices, &values, n, 0.0).expect("fit");
        let mut back = got.to_dense();
        haar::inverse(&mut back, &mut scratch);
        for (j, (a, b)) in back.iter().zip(&truth).enumerate() {
            assert!((a - b).abs() < 1e-9, "element {j}: {a} vs {b}");
        }
        assert!(reconstruct(&refs, &indices[..2], &values[..2], n, 0.0).is_none());
    }
}
