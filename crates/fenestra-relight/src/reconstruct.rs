//! Transfer vectors at view samples the exploration did not evaluate (seed 003 §4.5.3,
//! eq. 4.5): a combination sum alpha_r x_r of the sparse wavelet images of nearby explored
//! samples, the weights alpha fitted by least squares to the new sample's transfer at a few
//! element indices I (|I| >= k), which are cheap to evaluate (eq. 4.1 for single gather
//! samples); the neighbours' elements at I come from their sparse images without a full
//! inverse transform ([`SparseVec::element`]).

use crate::sparse::SparseVec;

/// The sparse wavelet image of the vector whose elements at `indices` are `values`, as a
/// least-squares combination of `neighbours` (sparse wavelet images, all of length `n`, a
/// power of two), or their average where the elements at `indices` say nothing about the
/// weights; `None` when there are fewer indices than neighbours.
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
    // The |I| x k system, row-major: column r holds neighbour r's elements at I.
    let a: Vec<f64> = (0..indices.len() * k)
        .map(|e| neighbours[e % k].element(indices[e / k]))
        .collect();
    // (A^T A + lambda I) alpha = A^T b + lambda / k by Cholesky: k is a handful, and the
    // ridge (at least 1e-12 of the columns' scale, so that dependent neighbours share their
    // weight instead of failing) keeps the system positive definite.
    let norm2 = (0..k)
        .map(|r| {
            (0..indices.len())
                .map(|i| a[i * k + r].powi(2))
                .sum::<f64>()
        })
        .sum::<f64>()
        / k as f64;
    let average = vec![1.0 / k as f64; k];
    let lambda = ridge.max(1e-12) * norm2;
    let mut m = vec![0.0; k * k];
    let mut rhs = vec![lambda / k as f64; k];
    for i in 0..indices.len() {
        let row = &a[i * k..(i + 1) * k];
        for r in 0..k {
            rhs[r] += row[r] * values[i];
            for c in 0..=r {
                m[r * k + c] += row[r] * row[c];
            }
        }
    }
    for r in 0..k {
        m[r * k + r] += lambda;
    }
    // Neighbours that are all zero at I (a pixel in shadow where they are lit) say nothing
    // about the weights: their average then.
    let alpha = if norm2 > 0.0 {
        non_negative(&m, &rhs, k).unwrap_or(average)
    } else {
        average
    };
    // Eq. 4.5 on the sparse images.
    let mut terms: Vec<(u32, f64)> = (neighbours.iter().zip(&alpha))
        .flat_map(|(x, &w)| {
            x.indices
                .iter()
                .zip(&x.values)
                .map(move |(&i, &v)| (i, w * v))
        })
        .collect();
    terms.sort_unstable_by_key(|t| t.0);
    let (mut indices, mut values): (Vec<u32>, Vec<f64>) = (Vec::new(), Vec::new());
    for (i, v) in terms {
        if indices.last() == Some(&i) {
            *values.last_mut().expect("paired") += v;
        } else {
            indices.push(i);
            values.push(v);
        }
    }
    Some(SparseVec {
        len: n,
        norm2: values.iter().map(|v| v * v).sum(),
        indices,
        values,
    })
}

/// The normal equations `m` alpha = `rhs` (lower triangle of m, row-major) solved with the
/// weights kept non-negative: transfer vectors are, and so must be a combination standing
/// for one. A fit to a near-field spike at a few elements buys weights of opposite signs that
/// make negative light elsewhere; the most negative weight is dropped and the rest solved
/// again (Lawson and Hanson's active set, only ever dropping) until none is negative.
fn non_negative(m: &[f64], rhs: &[f64], k: usize) -> Option<Vec<f64>> {
    let mut free: Vec<usize> = (0..k).collect();
    while !free.is_empty() {
        let j = free.len();
        let mut sub = vec![0.0; j * j];
        for (a, &r) in free.iter().enumerate() {
            for (b, &c) in free.iter().enumerate().take(a + 1) {
                sub[a * j + b] = m[r * k + c];
            }
        }
        let x = cholesky_solve(&mut sub, free.iter().map(|&r| rhs[r]).collect(), j)?;
        match (0..j)
            .filter(|&a| x[a] < 0.0)
            .min_by(|&a, &b| x[a].total_cmp(&x[b]))
        {
            Some(a) => {
                free.remove(a);
            }
            None => {
                let mut alpha = vec![0.0; k];
                free.iter().zip(&x).for_each(|(&r, &w)| alpha[r] = w);
                return Some(alpha);
            }
        }
    }
    None
}

/// Solves m x = b for the symmetric positive definite k x k `m` (lower triangle, row-major,
/// overwritten by its Cholesky factor); `None` if it is not positive definite.
fn cholesky_solve(m: &mut [f64], mut b: Vec<f64>, k: usize) -> Option<Vec<f64>> {
    for j in 0..k {
        let d = m[j * k + j] - (0..j).map(|p| m[j * k + p].powi(2)).sum::<f64>();
        if d.is_nan() || d <= 0.0 {
            return None;
        }
        let d = d.sqrt();
        m[j * k + j] = d;
        for i in j + 1..k {
            let s = m[i * k + j] - (0..j).map(|p| m[i * k + p] * m[j * k + p]).sum::<f64>();
            m[i * k + j] = s / d;
        }
    }
    for i in 0..k {
        b[i] = (b[i] - (0..i).map(|p| m[i * k + p] * b[p]).sum::<f64>()) / m[i * k + i];
    }
    for i in (0..k).rev() {
        b[i] = (b[i] - (i + 1..k).map(|p| m[p * k + i] * b[p]).sum::<f64>()) / m[i * k + i];
    }
    Some(b)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::haar;
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
        // The new sample's transfer: 0.5 x0 + 2 x1 + 0.25 x2 (in the signal domain).
        let weights = [0.5, 2.0, 0.25];
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
        // Values no non-negative combination reaches (a spike at one element): the weights
        // stay non-negative, where least squares alone would subtract neighbours.
        // (Whole images: truncated ones may dip below zero themselves.)
        let whole: Vec<SparseVec> = (0..3)
            .map(|_| {
                let mut x: Vec<f64> = (0..n).map(|_| s.next_1d() as f64).collect();
                haar::forward(&mut x, &mut scratch);
                SparseVec::largest(&x, n)
            })
            .collect();
        let whole: Vec<&SparseVec> = whole.iter().collect();
        let mut spiky = values.clone();
        spiky[0] *= 50.0;
        let got = reconstruct(&whole, &indices, &spiky, n, 0.0).expect("fit");
        let mut back = got.to_dense();
        haar::inverse(&mut back, &mut scratch);
        assert!(back.iter().all(|&v| v >= -1e-9), "negative light: {back:?}");
        // A neighbour twice: the two copies share its weight, the fit is the same.
        let twice = [refs[0], refs[0], refs[1], refs[2]];
        let got = reconstruct(&twice, &indices, &values, n, 0.0).expect("fit");
        let mut back = got.to_dense();
        haar::inverse(&mut back, &mut scratch);
        for (j, (a, b)) in back.iter().zip(&truth).enumerate() {
            assert!((a - b).abs() < 1e-6, "twice, element {j}: {a} vs {b}");
        }
    }
}
