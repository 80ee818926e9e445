//! Minimum-volume covering ellipse of planar points by Khachiyan's conditional-gradient
//! method (seed 000 §4.4.2, Alg. 4), with the closed-form line search and the Moore-Penrose
//! pseudo-inverse when (Q U Q^T) is ill-conditioned. It runs on the points' convex hull: the
//! covering ellipse of a set is that of its hull's vertices, and a cluster of photons has
//! hundreds of points but a few dozen on its hull.

use crate::linalg::{condition, outer, pinv_sym, sym_eigen};
use crate::rectangle::convex_hull;
use glam::{DMat2, DMat3, DVec2, DVec3};

/// Above this condition number (in Frobenius norms, [`condition`]) (Q U Q^T) is inverted
/// through its pseudo-inverse.
const ILL_CONDITIONED: f64 = 1e12;

/// An ellipse {x : (x - c)^T E (x - c) <= 1}, as centre and semi-axes.
#[derive(Clone, Debug)]
pub struct Ellipse {
    /// Centre c.
    pub center: DVec2,
    /// Semi-axis vectors (direction times length), major first.
    pub axes: [DVec2; 2],
    /// Conditional-gradient iterations taken.
    pub iterations: usize,
    /// Whether some iteration needed the pseudo-inverse.
    pub used_pseudo_inverse: bool,
}

impl Ellipse {
    /// pi times the semi-axes' lengths.
    pub fn area(&self) -> f64 {
        std::f64::consts::PI * self.axes[0].length() * self.axes[1].length()
    }

    /// (x - c)^T E (x - c): at most 1 inside.
    pub fn level(&self, x: DVec2) -> f64 {
        let d = x - self.center;
        self.axes
            .iter()
            .map(|a| (d.dot(*a) / a.length_squared()).powi(2))
            .sum()
    }
}

/// Alg. 4 for points `p` in the plane, stopping when the weights move less than `eps`
/// (L2) or after `max_iterations`. `None` for fewer than 3 points or all on one line.
pub fn mvce(points: &[DVec2], eps: f64, max_iterations: usize) -> Option<Ellipse> {
    let p = convex_hull(points);
    let m = p.len();
    if m < 3 {
        return None;
    }
    let n = 2.0;
    let q: Vec<DVec3> = p.iter().map(|x| x.extend(1.0)).collect();
    let mut u = vec![1.0 / m as f64; m];
    let mut used_pinv = false;
    let mut iterations = 0;
    while iterations < max_iterations {
        iterations += 1;
        // X = Q U Q^T; the gradient of log det is q_i^T X^-1 q_i.
        let x = q
            .iter()
            .zip(&u)
            .fold(DMat3::ZERO, |acc, (qi, &ui)| acc + outer(*qi, *qi) * ui);
        let x_inv = if condition(&x) > ILL_CONDITIONED {
            used_pinv = true;
            pinv_sym(&x, 1e-12)
        } else {
            x.inverse()
        };
        let (j, g) = q.iter().map(|qi| qi.dot(x_inv * *qi)).enumerate().fold(
            (0, f64::NEG_INFINITY),
            |best, (i, g)| if g > best.1 { (i, g) } else { best },
        );
        // Khachiyan's closed-form step along e_j.
        let alpha = (g - (n + 1.0)) / ((n + 1.0) * (g - 1.0));
        if !(alpha > 0.0 && alpha.is_finite()) {
            break;
        }
        let mut moved = 0.0;
        for (i, ui) in u.iter_mut().enumerate() {
            let new = (1.0 - alpha) * *ui + if i == j { alpha } else { 0.0 };
            moved += (new - *ui) * (new - *ui);
            *ui = new;
        }
        if moved.sqrt() <= eps {
            break;
        }
    }
    // c = P u, E = (P U P^T - c c^T)^-1 / n.
    let c = p.iter().zip(&u).fold(DVec2::ZERO, |a, (x, &w)| a + *x * w);
    let s = p.iter().zip(&u).fold(DMat2::ZERO, |a, (x, &w)| {
        a + DMat2::from_cols(*x * x.x, *x * x.y) * w
    }) - DMat2::from_cols(c * c.x, c * c.y);
    if s.determinant().abs() <= 1e-300 {
        return None;
    }
    let e = s.inverse() * (1.0 / n);
    let e3 = DMat3::from_cols(e.x_axis.extend(0.0), e.y_axis.extend(0.0), DVec3::Z);
    // Semi-axes: 1/sqrt of E's eigenvalues along its eigenvectors (the 3rd is the padding).
    let (vals, vecs) = sym_eigen(&e3);
    let mut axes: Vec<DVec2> = vals
        .iter()
        .zip(vecs)
        .filter(|(_, v)| v.z.abs() < 0.5)
        .map(|(l, v)| v.truncate().normalize() / l.sqrt())
        .collect();
    axes.sort_by(|a, b| b.length().total_cmp(&a.length()));
    if axes.len() != 2 || !axes.iter().all(|a| a.is_finite()) {
        return None;
    }
    let mut ellipse = Ellipse {
        center: c,
        axes: [axes[0], axes[1]],
        iterations,
        used_pseudo_inverse: used_pinv,
    };
    // The iterate covers the points only up to its duality gap: grow it to cover them all.
    let worst = p.iter().map(|&x| ellipse.level(x)).fold(0.0f64, f64::max);
    if worst > 1.0 {
        ellipse.axes = ellipse.axes.map(|a| a * worst.sqrt());
    }
    Some(ellipse)
}

#[cfg(test)]
mod tests {
    use super::*;
    use fenestra_core::Rng;

    #[test]
    fn points_on_an_ellipse_give_that_ellipse() {
        let (c, a, b) = (DVec2::new(1.0, -2.0), 3.0, 1.0);
        let rot = DVec2::from_angle(0.4);
        let pts: Vec<DVec2> = (0..64)
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / 64.0;
                c + rot.rotate(DVec2::new(a * t.cos(), b * t.sin()))
            })
            .collect();
        let e = mvce(&pts, 1e-9, 100_000).expect("ellipse");
        assert!((e.center - c).length() < 1e-3, "{e:?}");
        assert!(
            (e.axes[0].length() - a).abs() < 1e-3 && (e.axes[1].length() - b).abs() < 1e-3,
            "{e:?}"
        );
        assert!(e.axes[0].normalize().dot(rot).abs() > 0.9999, "{e:?}");
    }

    #[test]
    fn covers_every_point_and_is_smaller_than_the_bounding_circle() {
        let mut rng = Rng::new(7);
        let pts: Vec<DVec2> = (0..300)
            .map(|_| {
                DVec2::new(
                    rng.next_f64() * 2.0,
                    rng.next_f64() * 0.5 + rng.next_f64() * 0.2,
                )
            })
            .collect();
        let e = mvce(&pts, 1e-4, 100_000).expect("ellipse");
        let worst = pts.iter().map(|&x| e.level(x)).fold(0.0f64, f64::max);
        assert!(worst <= 1.0 + 1e-9, "worst level {worst}");
        assert!(e.area() < std::f64::consts::PI * 1.1 * 1.1);
        assert!(mvce(&pts[..2], 1e-4, 100).is_none());
        let collinear: Vec<DVec2> = (0..10).map(|i| DVec2::splat(i as f64)).collect();
        assert!(
            mvce(&collinear, 1e-4, 1000).is_none(),
            "a segment has no covering ellipse of positive area"
        );
    }
}
