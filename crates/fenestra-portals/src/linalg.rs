//! Symmetric 3x3 eigendecomposition (through faer) and what is built on it: the
//! pseudo-inverse that Alg. 4's fallback needs, its condition test, and principal axes.

use glam::{DMat3, DVec3};

/// Eigenvalues (ascending) and unit eigenvectors (columns) of the symmetric matrix `m`.
pub fn sym_eigen(m: &DMat3) -> ([f64; 3], [DVec3; 3]) {
    let a = faer::Mat::<f64>::from_fn(3, 3, |r, c| m.col(c)[r]);
    match a.self_adjoint_eigen(faer::Side::Lower) {
        Ok(evd) => {
            let (s, u) = (evd.S(), evd.U());
            let vals = [s[0], s[1], s[2]];
            let vecs = [0, 1, 2].map(|j| DVec3::new(u[(0, j)], u[(1, j)], u[(2, j)]));
            (vals, vecs)
        }
        // faer reports no convergence only for non-finite input.
        Err(_) => ([f64::NAN; 3], [DVec3::X, DVec3::Y, DVec3::Z]),
    }
}

/// The condition number in Frobenius norms, ||M||_F ||M^-1||_F: between the 2-norm one and
/// three times it for 3x3 matrices, at the cost of an inverse rather than an
/// eigendecomposition (infinite when singular).
pub fn condition(m: &DMat3) -> f64 {
    let frobenius = |a: &DMat3| a.to_cols_array().iter().map(|x| x * x).sum::<f64>().sqrt();
    let det = m.determinant();
    let kappa = if det != 0.0 {
        frobenius(m) * frobenius(&m.inverse())
    } else {
        f64::INFINITY
    };
    if kappa.is_finite() {
        kappa
    } else {
        f64::INFINITY
    }
}

/// Moore-Penrose pseudo-inverse of a symmetric matrix: eigenvalues below `rel_tol` times the
/// largest are treated as zero.
pub fn pinv_sym(m: &DMat3, rel_tol: f64) -> DMat3 {
    let (vals, vecs) = sym_eigen(m);
    let max = vals.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let mut out = DMat3::ZERO;
    for (l, v) in vals.iter().zip(vecs) {
        if l.abs() > rel_tol * max {
            out += outer(v, v) * (1.0 / l);
        }
    }
    out
}

/// The outer product a b^T.
pub fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eigen_and_pseudo_inverse() {
        let m = DMat3::from_cols(
            DVec3::new(4.0, 1.0, 0.0),
            DVec3::new(1.0, 3.0, 0.0),
            DVec3::new(0.0, 0.0, 2.0),
        );
        let (vals, vecs) = sym_eigen(&m);
        for (l, v) in vals.iter().zip(vecs) {
            assert!((m * v - v * *l).length() < 1e-12);
        }
        assert!((pinv_sym(&m, 1e-12) - m.inverse())
            .to_cols_array()
            .iter()
            .all(|x| x.abs() < 1e-12));
        // Rank one: the pseudo-inverse inverts the range and zeroes the rest.
        let r = outer(DVec3::new(1.0, 2.0, 2.0), DVec3::new(1.0, 2.0, 2.0));
        let p = pinv_sym(&r, 1e-9);
        assert!(((r * p * r) - r)
            .to_cols_array()
            .iter()
            .all(|x| x.abs() < 1e-9));
        assert!(condition(&r) > 1e12);
    }

    #[test]
    fn condition_is_within_three_times_the_eigenvalue_ratio() {
        let mut rng = fenestra_core::Rng::new(3);
        for scale in [1.0, 1e-3, 1e-6] {
            let q = [0; 3].map(|_| DVec3::new(rng.next_f64(), rng.next_f64(), 1.0));
            let m = q.iter().fold(DMat3::ZERO, |acc, v| acc + outer(*v, *v))
                + outer(DVec3::X, DVec3::X) * scale;
            let (vals, _) = sym_eigen(&m);
            let ratio = vals[2].abs() / vals[0].abs();
            let kappa = condition(&m);
            assert!(
                kappa >= ratio * (1.0 - 1e-9) && kappa <= 3.0 * ratio * (1.0 + 1e-9),
                "{kappa} against {ratio}"
            );
        }
    }
}
