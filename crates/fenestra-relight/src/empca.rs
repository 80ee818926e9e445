//! Roweis's EM algorithm for PCA (1998) on sparse rows, as Wavelet-LPCA updates a cluster's
//! subspace (seed 003 §4.5.2.2): the l leading principal directions of A = A0 - 1 mu^T,
//! with A0's rows sparse wavelet images and mu dense, never forming A or A^T A. In the
//! expanded form of the seed:
//!
//! - e-step: X = (A0 C^T - 1 (C mu)^T) (C C^T)^-1
//! - m-step: C = (X^T X)^-1 (X^T A0 - (X^T 1) mu^T)
//!
//! with C the l x d matrix of current directions. EM converges to the span of the leading
//! directions; the span is then turned into them, in order, by the eigenvectors of the l x l
//! covariance of the rows' coordinates in it.

use crate::sparse::{interleaved_products, SparseVec};
use faer::linalg::solvers::Solve;
use faer::{Mat, Side};

/// What [`em_pca`] found.
#[derive(Clone, Debug)]
pub struct Principal {
    /// Orthonormal directions, most variance first.
    pub directions: Vec<Vec<f64>>,
    /// The variance (sum of squared coordinates) along each.
    pub variances: Vec<f64>,
    /// EM iterations run.
    pub iterations: usize,
}

/// The leading principal directions of `rows` about `mean`, as many as `start` holds (the
/// previous LPCA iteration's directions, or a few rows): EM until the span moves by less
/// than `tolerance` (largest change of a projection) or for at most `max_iterations`.
/// `None` if the directions become degenerate (fewer independent rows than directions).
pub fn em_pca(
    rows: &[&SparseVec],
    mean: &[f64],
    start: Vec<Vec<f64>>,
    max_iterations: usize,
    tolerance: f64,
) -> Option<Principal> {
    let (l, d) = (start.len(), mean.len());
    let mut c = start;
    let mut previous = orthonormal(&c)?;
    // C and the m-step's X^T A0 with coefficient i of every direction side by side, so that
    // a sparse row meets all l of them in one short run of memory per coefficient.
    let mut interleaved = vec![0.0f64; d * l];
    let mut xa = vec![0.0f64; d * l];
    let mut b = Mat::<f64>::zeros(l, d);
    let (mut products, mut w) = (vec![0.0f64; l], vec![0.0f64; l]);
    let mut iterations = 0;
    while iterations < max_iterations {
        iterations += 1;
        // e-step.
        for (j, cj) in c.iter().enumerate() {
            cj.iter()
                .enumerate()
                .for_each(|(i, &v)| interleaved[i * l + j] = v);
        }
        let cc = Mat::<f64>::from_fn(l, l, |i, j| dot(&c[i], &c[j]));
        let c_mean: Vec<f64> = c.iter().map(|ci| dot(ci, mean)).collect();
        let mut rhs = Mat::<f64>::zeros(l, rows.len());
        for (r, row) in rows.iter().enumerate() {
            interleaved_products(&interleaved, row, &mut products);
            for j in 0..l {
                rhs[(j, r)] = products[j] - c_mean[j];
            }
        }
        let x = solve(&cc, rhs)?; // l x m: column r is row r's X
                                  // m-step.
        xa.iter_mut().for_each(|a| *a = 0.0);
        let mut x_sum = vec![0.0f64; l];
        for (r, row) in rows.iter().enumerate() {
            w.iter_mut().enumerate().for_each(|(j, wj)| *wj = x[(j, r)]);
            x_sum.iter_mut().zip(&w).for_each(|(s, &wj)| *s += wj);
            for (i, v) in row.iter() {
                let acc = &mut xa[i * l..(i + 1) * l];
                acc.iter_mut().zip(&w).for_each(|(a, &wj)| *a += wj * v);
            }
        }
        for i in 0..d {
            for j in 0..l {
                b[(j, i)] = xa[i * l + j] - x_sum[j] * mean[i];
            }
        }
        let xx = &x * x.transpose();
        let llt = xx.llt(Side::Lower).ok()?;
        llt.solve_in_place(b.as_mut());
        for (j, cj) in c.iter_mut().enumerate() {
            cj.iter_mut().enumerate().for_each(|(i, v)| *v = b[(j, i)]);
        }
        let q = orthonormal(&c)?;
        let moved = span_change(&previous, &q);
        previous = q;
        if moved < tolerance {
            break;
        }
    }
    Some(principal(rows, mean, previous, iterations))
}

/// The directions of the span `q` (orthonormal) ordered by variance: eigenvectors of the
/// covariance of the rows' coordinates in it.
fn principal(rows: &[&SparseVec], mean: &[f64], q: Vec<Vec<f64>>, iterations: usize) -> Principal {
    let l = q.len();
    let q_mean: Vec<f64> = q.iter().map(|e| dot(e, mean)).collect();
    let y = Mat::<f64>::from_fn(l, rows.len(), |j, r| rows[r].dot(&q[j]) - q_mean[j]);
    let cov = &y * y.transpose();
    let Ok(evd) = cov.self_adjoint_eigen(Side::Lower) else {
        let variances = vec![0.0; l];
        return Principal {
            directions: q,
            variances,
            iterations,
        };
    };
    let (u, s) = (evd.U(), evd.S());
    // faer orders eigenvalues ascending: the last is the leading direction.
    let order: Vec<usize> = (0..l).rev().collect();
    let directions = order
        .iter()
        .map(|&k| {
            let mut v = vec![0.0; mean.len()];
            for (j, e) in q.iter().enumerate() {
                let w = u[(j, k)];
                v.iter_mut().zip(e).for_each(|(a, b)| *a += w * b);
            }
            v
        })
        .collect();
    Principal {
        directions,
        variances: order.iter().map(|&k| s[k].max(0.0)).collect(),
        iterations,
    }
}

/// Solves `m z = rhs` for symmetric positive definite `m` (Cholesky).
fn solve(m: &Mat<f64>, mut rhs: Mat<f64>) -> Option<Mat<f64>> {
    let llt = m.llt(Side::Lower).ok()?;
    llt.solve_in_place(rhs.as_mut());
    Some(rhs)
}

/// An orthonormal basis of the rows of `c` (Gram-Schmidt, twice for accuracy); `None` if
/// they are dependent.
fn orthonormal(c: &[Vec<f64>]) -> Option<Vec<Vec<f64>>> {
    let mut q: Vec<Vec<f64>> = Vec::with_capacity(c.len());
    let scale = c.iter().map(|r| dot(r, r)).fold(0.0, f64::max).sqrt();
    for v in c {
        let mut v = v.clone();
        for _ in 0..2 {
            for e in &q {
                let k = dot(&v, e);
                v.iter_mut().zip(e).for_each(|(a, b)| *a -= k * b);
            }
        }
        let n = dot(&v, &v).sqrt();
        if n.is_nan() || n <= 1e-12 * scale.max(f64::MIN_POSITIVE) {
            return None;
        }
        q.push(v.into_iter().map(|a| a / n).collect());
    }
    Some(q)
}

/// How far span(`b`) is from span(`a`) (both orthonormal): the largest distance of a `b`
/// direction from its projection on span(`a`) (the sine of the largest principal angle).
pub fn span_change(a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    b.iter()
        .map(|v| {
            let inside: f64 = a.iter().map(|e| dot(v, e).powi(2)).sum();
            (1.0 - inside).max(0.0).sqrt()
        })
        .fold(0.0, f64::max)
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use fenestra_core::Sampler;

    #[test]
    fn em_converges_to_the_svd_subspace_on_sparse_rows() {
        // 300 rows in 64 dimensions: a mean, three strong directions, a little noise, then
        // sparsified (the 24 largest coefficients kept), as wavelet images are.
        let (m, d, l) = (300, 64, 3);
        let mut s = Sampler::new(11, 0, 0);
        let mut r = || s.next_1d() as f64 * 2.0 - 1.0;
        let mean: Vec<f64> = (0..d).map(|i| if i % 5 == 0 { 1.0 } else { 0.0 }).collect();
        let dirs: Vec<Vec<f64>> = (0..l).map(|_| (0..d).map(|_| r()).collect()).collect();
        let rows: Vec<SparseVec> = (0..m)
            .map(|_| {
                let w = [3.0 * r(), 2.0 * r(), 1.0 * r()];
                let x: Vec<f64> = (0..d)
                    .map(|i| mean[i] + (0..l).map(|j| w[j] * dirs[j][i]).sum::<f64>() + 0.01 * r())
                    .collect();
                SparseVec::largest(&x, 24)
            })
            .collect();
        // The truth: the thin SVD of the centred dense rows (their own mean).
        let mut mu = vec![0.0; d];
        for row in &rows {
            row.iter().for_each(|(i, v)| mu[i] += v / m as f64);
        }
        let a = Mat::<f64>::from_fn(m, d, |i, j| rows[i].to_dense()[j] - mu[j]);
        let svd = a.thin_svd().expect("svd");
        let truth: Vec<Vec<f64>> = (0..l)
            .map(|k| (0..d).map(|i| svd.V()[(i, k)]).collect())
            .collect();
        // Start from three rows, as the seed does.
        let start: Vec<Vec<f64>> = (0..l).map(|k| rows[k * 7].to_dense()).collect();
        let refs: Vec<&SparseVec> = rows.iter().collect();
        let p = em_pca(&refs, &mu, start, 500, 1e-10).expect("directions");
        assert!(
            span_change(&truth, &p.directions) < 1e-6,
            "span off by {} after {} iterations",
            span_change(&truth, &p.directions),
            p.iterations
        );
        // And each direction is the SVD's, in order (up to sign), with its variance.
        for (k, t) in truth.iter().enumerate() {
            let cos = dot(t, &p.directions[k]).abs();
            assert!((cos - 1.0).abs() < 1e-6, "direction {k}: cos {cos}");
            let sigma2 = svd.S()[k] * svd.S()[k];
            assert!((p.variances[k] - sigma2).abs() < 1e-6 * sigma2);
        }
    }

    #[test]
    fn dependent_starting_directions_are_refused() {
        let rows = [SparseVec::largest(&[1.0, 2.0, 3.0], 3)];
        let start = vec![vec![1.0, 0.0, 0.0], vec![2.0, 0.0, 0.0]];
        assert!(em_pca(&[&rows[0]], &[0.0; 3], start, 10, 1e-9).is_none());
    }
}
