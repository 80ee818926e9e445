//! Affine subspaces (a mean and an orthonormal basis) and the point-subspace distance of
//! eqs. 3.1-3.2; the distance between two subspaces through the Gram matrix and a Cholesky
//! solve (§3.4.3, eq. 3.5).

use crate::kernels::{dot, dot_f32_f64};

#[derive(Clone, Debug, PartialEq)]
pub struct Subspace {
    pub mean: Vec<f64>,
    /// Orthonormal directions, each of length d.
    pub basis: Vec<Vec<f64>>,
}

impl Subspace {
    pub fn point(mean: Vec<f64>) -> Self {
        Subspace {
            mean,
            basis: Vec::new(),
        }
    }

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

/// Distance between two affine subspaces (eq. 3.5 by §3.4.3): with K = [dir(a), dir(b)],
/// solve G(K) z = K^T (mu_a - mu_b) by Cholesky and return |mu_a - mu_b - K z|. When G is
/// singular (the subspaces share a direction) the Cholesky factorisation fails and the
/// system is solved by the pseudo-inverse of G's eigendecomposition instead.
pub fn subspace_distance(a: &Subspace, b: &Subspace) -> f64 {
    let delta: Vec<f64> = a.mean.iter().zip(&b.mean).map(|(x, y)| x - y).collect();
    let k: Vec<&Vec<f64>> = a.basis.iter().chain(&b.basis).collect();
    let m = k.len();
    if m == 0 {
        return dot(&delta, &delta).sqrt();
    }
    // Gram matrix; each basis is orthonormal, so only the cross block needs dot products.
    let (ma, _) = (a.basis.len(), b.basis.len());
    let g = faer::Mat::<f64>::from_fn(m, m, |i, j| {
        if i == j {
            1.0
        } else if (i < ma) == (j < ma) {
            0.0
        } else {
            dot(k[i], k[j])
        }
    });
    let mut rhs = faer::Mat::<f64>::from_fn(m, 1, |i, _| dot(k[i], &delta));
    let z = match g.llt(faer::Side::Lower) {
        Ok(llt) => {
            faer::linalg::solvers::Solve::solve_in_place(&llt, rhs.as_mut());
            rhs
        }
        Err(_) => match g.self_adjoint_eigen(faer::Side::Lower) {
            Ok(evd) => evd.pseudoinverse() * &rhs,
            Err(_) => return 0.0, // a lower bound that never prunes
        },
    };
    let mut r = delta;
    for (i, e) in k.iter().enumerate() {
        let c = z[(i, 0)];
        for (ri, &ei) in r.iter_mut().zip(e.iter()) {
            *ri -= c * ei;
        }
    }
    dot(&r, &r).sqrt()
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

    #[test]
    fn skew_lines_parallel_lines_and_points() {
        // Skew lines x-axis at z=0 and y-axis at z=2: distance 2.
        let a = line([0.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
        let b = line([3.0, -1.0, 2.0], [0.0, 1.0, 0.0]);
        assert!((subspace_distance(&a, &b) - 2.0).abs() < 1e-12);
        // Parallel lines (singular Gram matrix): distance between them.
        let c = line([7.0, 3.0, 4.0], [1.0, 0.0, 0.0]);
        assert!((subspace_distance(&a, &c) - 5.0).abs() < 1e-9);
        // Intersecting lines: 0.
        let d = line([2.0, -1.0, 0.0], [0.0, 1.0, 0.0]);
        assert!(subspace_distance(&a, &d).abs() < 1e-12);
        let (p, q) = (
            Subspace::point(vec![0.0, 0.0, 0.0]),
            Subspace::point(vec![3.0, 4.0, 0.0]),
        );
        assert!((subspace_distance(&p, &q) - 5.0).abs() < 1e-12);
    }

    #[test]
    fn generalised_triangle_inequality_holds() {
        // eq. 3.4 on random subspaces and points.
        let mut rng = crate::rng::Rng::new(3);
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
            assert!(
                subspace_distance(&a, &b)
                    <= a.distance(&x, &mut s) + b.distance(&x, &mut s) + 1e-12
            );
        }
    }
}
