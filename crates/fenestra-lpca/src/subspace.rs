//! Affine subspaces (a mean and an orthonormal basis) and the point-subspace distance of
//! eqs. 3.1-3.2; the distance between two subspaces through the Gram matrix and a Cholesky
//! solve (§3.4.3, eq. 3.5).

use crate::kernels::{dot, dot_f32_f64};

/// An affine subspace: a mean and orthonormal directions.
#[derive(Clone, Debug, PartialEq)]
pub struct Subspace {
    /// Its origin.
    pub mean: Vec<f64>,
    /// Orthonormal directions, each of length d.
    pub basis: Vec<Vec<f64>>,
}

impl Subspace {
    /// The 0-dimensional subspace at `mean`.
    pub fn point(mean: Vec<f64>) -> Self {
        Subspace {
            mean,
            basis: Vec::new(),
        }
    }

    /// Its dimension.
    pub fn dim(&self) -> usize {
        self.basis.len()
    }

    /// Eq. 3.1: |(x - mu) - x_s| with x_s the projection of x - mu on the basis (eq. 3.2).
    /// `scratch` (length d) holds x - mu and then the residual. The residual is formed
    /// explicitly rather than as |x - mu|^2 - sum c^2, which would cancel catastrophically for
    /// points close to the subspace.
    pub fn distance(&self, x: &[f32], scratch: &mut [f64]) -> f64 {
        for ((s, &xi), &mi) in scratch.iter_mut().zip(x).zip(&self.mean) {
            *s = xi as f64 - mi;
        }
        for e in &self.basis {
            let c = dot(scratch, e);
            for (s, &ei) in scratch.iter_mut().zip(e) {
                *s -= c * ei;
            }
        }
        dot(scratch, scratch).sqrt()
    }

    /// Coefficients of x in the basis (for the compressed representation).
    pub fn coefficients(&self, x: &[f32], scratch: &mut [f64]) -> Vec<f64> {
        for ((s, &xi), &mi) in scratch.iter_mut().zip(x).zip(&self.mean) {
            *s = xi as f64 - mi;
        }
        self.basis.iter().map(|e| dot(scratch, e)).collect()
    }

    /// |x - mu|, used for the pruning margin.
    pub fn distance_to_mean(&self, x: &[f32]) -> f64 {
        let xx: f64 = x.iter().map(|&v| v as f64 * v as f64).sum();
        (xx - 2.0 * dot_f32_f64(x, &self.mean) + dot(&self.mean, &self.mean))
            .max(0.0)
            .sqrt()
    }
}

/// The blocks of the Gram matrix of all subspaces' bases, from one matrix product.
pub struct GramBlocks {
    /// Column offset of each subspace's basis in the stacked basis matrix.
    offsets: Vec<usize>,
    /// B^T B for the stacked bases B (d x sum of dimensions).
    gram: faer::Mat<f64>,
}

impl GramBlocks {
    /// The Gram blocks of `models`.
    pub fn new(models: &[Subspace]) -> Self {
        let mut offsets = Vec::with_capacity(models.len() + 1);
        let mut columns: Vec<&Vec<f64>> = Vec::new();
        for m in models {
            offsets.push(columns.len());
            columns.extend(&m.basis);
        }
        offsets.push(columns.len());
        let d = models.first().map_or(0, |m| m.mean.len());
        let b = faer::Mat::<f64>::from_fn(d, columns.len(), |r, c| columns[c][r]);
        GramBlocks {
            offsets,
            gram: b.transpose() * &b,
        }
    }

    /// <dir_i(a), dir_j(b)>.
    fn get(&self, a: usize, i: usize, b: usize, j: usize) -> f64 {
        self.gram[(self.offsets[a] + i, self.offsets[b] + j)]
    }
}

/// A lower bound on the distance between subspaces `a` and `b` (eq. 3.5 by §3.4.3), equal
/// to the distance up to rounding when the bases are not nearly parallel. With
/// K = [dir(a), dir(b)] and G = K^T K, solve G z = K^T (mu_a - mu_b) by Cholesky (by the
/// pseudo-inverse when G is singular); r = mu_a - mu_b - K z is then at least as far from
/// span(K) as the true residual, and |r| overestimates the distance by at most
/// |K^T r| / sqrt(lambda_min(G)). Subtracting that keeps the pruning of SortCluster-LPCA
/// exact even when G is ill-conditioned, where a plain Cholesky solve could make D too large.
pub fn subspace_distance(models: &[Subspace], gram: &GramBlocks, a: usize, b: usize) -> f64 {
    let (sa, sb) = (&models[a], &models[b]);
    let delta: Vec<f64> = sa.mean.iter().zip(&sb.mean).map(|(x, y)| x - y).collect();
    let k: Vec<&Vec<f64>> = sa.basis.iter().chain(&sb.basis).collect();
    let m = k.len();
    let delta_norm = dot(&delta, &delta).sqrt();
    if m == 0 {
        return delta_norm;
    }
    let ma = sa.basis.len();
    let index = |i: usize| if i < ma { (a, i) } else { (b, i - ma) };
    let g = faer::Mat::<f64>::from_fn(m, m, |i, j| {
        let ((x, xi), (y, yj)) = (index(i), index(j));
        gram.get(x, xi, y, yj)
    });
    let rhs = faer::Mat::<f64>::from_fn(m, 1, |i, _| dot(k[i], &delta));
    let Ok(eigenvalues) = g.self_adjoint_eigenvalues(faer::Side::Lower) else {
        return 0.0;
    };
    let lambda_max = eigenvalues.last().copied().unwrap_or(0.0);
    let z = match g.llt(faer::Side::Lower) {
        Ok(llt) => {
            let mut z = rhs.clone();
            faer::linalg::solvers::Solve::solve_in_place(&llt, z.as_mut());
            z
        }
        Err(_) => match g.self_adjoint_eigen(faer::Side::Lower) {
            Ok(evd) => evd.pseudoinverse() * &rhs,
            Err(_) => return 0.0,
        },
    };
    let mut r = delta;
    for (i, e) in k.iter().enumerate() {
        let c = z[(i, 0)];
        for (ri, &ei) in r.iter_mut().zip(e.iter()) {
            *ri -= c * ei;
        }
    }
    let upper = dot(&r, &r).sqrt();
    // |P r| <= |K^T r| / sqrt(lambda_min) on span(K); directions with eigenvalues below the
    // rounding level are shared by both subspaces and r has no component along them.
    let lambda_min = eigenvalues
        .iter()
        .copied()
        .find(|&l| l > 1e-10 * lambda_max)
        .unwrap_or(0.0);
    if lambda_min <= 0.0 {
        return 0.0;
    }
    let s2: f64 = k.iter().map(|e| dot(e, &r).powi(2)).sum();
    (upper - s2.sqrt() / lambda_min.sqrt() - 1e-12 * (delta_norm + upper)).max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(p: [f64; 3], dir: [f64; 3]) -> Subspace {
        let n = (dir.iter().map(|x| x * x).sum::<f64>()).sqrt();
        Subspace {
            mean: p.to_vec(),
            basis: vec![dir.iter().map(|x| x / n).collect()],
        }
    }

    #[test]
    fn point_line_and_plane_distances() {
        let l = line([0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
        let mut s = vec![0.0; 3];
        assert!((l.distance(&[5.0, 3.0, 1.0], &mut s) - 3.0).abs() < 1e-12);
        let p = Subspace::point(vec![1.0, 1.0, 1.0]);
        assert!((p.distance(&[1.0, 4.0, 5.0], &mut s) - 5.0).abs() < 1e-12);
        assert!((p.distance_to_mean(&[1.0, 4.0, 5.0]) - 5.0).abs() < 1e-12);
    }

    fn dist(a: &Subspace, b: &Subspace) -> f64 {
        let models = [a.clone(), b.clone()];
        subspace_distance(&models, &GramBlocks::new(&models), 0, 1)
    }

    #[test]
    fn skew_lines_parallel_lines_and_points() {
        // Skew lines x-axis at z=0 and y-axis at z=2: distance 2.
        let a = line([0.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
        let b = line([3.0, -1.0, 2.0], [0.0, 1.0, 0.0]);
        assert!((dist(&a, &b) - 2.0).abs() < 1e-9);
        // Parallel lines (singular Gram matrix): the distance, 5, through the pseudo-inverse.
        let c = line([7.0, 3.0, 4.0], [1.0, 0.0, 0.0]);
        let dc = dist(&a, &c);
        assert!((dc - 5.0).abs() < 1e-9, "{dc}");
        // Intersecting lines: 0.
        let d = line([2.0, -1.0, 0.0], [0.0, 1.0, 0.0]);
        assert!(dist(&a, &d).abs() < 1e-12);
        let (p, q) = (
            Subspace::point(vec![0.0, 0.0, 0.0]),
            Subspace::point(vec![3.0, 4.0, 0.0]),
        );
        assert!((dist(&p, &q) - 5.0).abs() < 1e-12);
        // A line and a point: distance from the point to the line.
        assert!((dist(&a, &q) - 4.0).abs() < 1e-9);
    }

    #[test]
    fn nearly_parallel_bases_give_a_lower_bound() {
        // Lines 1e-7 radians apart, 3 apart: the bound may be loose but never exceeds 3.
        let a = line([0.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
        let b = line([0.0, 3.0, 0.0], [1.0, 1e-7, 0.0]);
        let dab = dist(&a, &b);
        assert!((0.0..=3.0 + 1e-9).contains(&dab), "{dab}");
    }

    #[test]
    fn generalised_triangle_inequality_holds() {
        // eq. 3.4 on random subspaces and points.
        let mut rng = fenestra_core::Rng::new(3);
        let mut s = vec![0.0; 6];
        for _ in 0..200 {
            let mut sub = |dim: usize| {
                let mean: Vec<f64> = (0..6).map(|_| rng.next_f64() * 4.0 - 2.0).collect();
                let mut basis: Vec<Vec<f64>> = Vec::new();
                while basis.len() < dim {
                    let mut v: Vec<f64> = (0..6).map(|_| rng.next_f64() - 0.5).collect();
                    for e in &basis {
                        let c = dot(&v, e);
                        v.iter_mut().zip(e).for_each(|(x, y)| *x -= c * y);
                    }
                    let n = dot(&v, &v).sqrt();
                    basis.push(v.iter().map(|x| x / n).collect());
                }
                Subspace { mean, basis }
            };
            let (a, b) = (sub(2), sub(1));
            let x: Vec<f32> = (0..6)
                .map(|_| (rng.next_f64() * 4.0 - 2.0) as f32)
                .collect();
            assert!(dist(&a, &b) <= a.distance(&x, &mut s) + b.distance(&x, &mut s) + 1e-12);
        }
    }
}
