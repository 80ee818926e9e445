//! RANSAC plane fitting (seed 000 §4.4.1, Alg. 3): a cluster of photons gets a plane robust
//! to outliers; its inliers are then covered in that plane.

use crate::linalg::{outer, sym_eigen};
use fenestra_core::Rng;
use glam::{DMat3, DVec2, DVec3};

/// A plane through `point` with unit `normal`.
#[derive(Clone, Copy, Debug)]
pub struct Plane {
    /// A point on it.
    pub point: DVec3,
    /// Unit normal.
    pub normal: DVec3,
}

impl Plane {
    /// Distance of `x` from the plane.
    pub fn distance(&self, x: DVec3) -> f64 {
        (x - self.point).dot(self.normal).abs()
    }

    /// An orthonormal basis (u, v) of the plane.
    pub fn basis(&self) -> (DVec3, DVec3) {
        let f = fenestra_core::Frame::from_normal(self.normal.as_vec3());
        let u = (f.s.as_dvec3() - self.normal * self.normal.dot(f.s.as_dvec3())).normalize();
        (u, self.normal.cross(u))
    }

    /// In-plane coordinates of `x` (projected onto the plane).
    pub fn to_plane(&self, x: DVec3) -> DVec2 {
        let (u, v) = self.basis();
        DVec2::new((x - self.point).dot(u), (x - self.point).dot(v))
    }

    /// The point of in-plane coordinates `p`.
    pub fn from_plane(&self, p: DVec2) -> DVec3 {
        let (u, v) = self.basis();
        self.point + u * p.x + v * p.y
    }
}

/// Least-squares plane through points: their mean and the direction of least variance.
pub fn fit_plane(points: &[DVec3]) -> Option<Plane> {
    if points.len() < 3 {
        return None;
    }
    let mean = points.iter().fold(DVec3::ZERO, |a, p| a + *p) / points.len() as f64;
    let cov = points
        .iter()
        .fold(DMat3::ZERO, |a, p| a + outer(*p - mean, *p - mean));
    let (vals, vecs) = sym_eigen(&cov);
    // A line (two vanishing eigenvalues) has no plane.
    (vals[1] > 1e-12 * vals[2].max(1e-300)).then(|| Plane {
        point: mean,
        normal: vecs[0].normalize(),
    })
}

/// RANSAC parameters, as named in the seed: inlier tolerance eps, inlier fraction tau that
/// ends the search, at most N trials.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct Ransac {
    /// Inlier distance to the plane (m).
    pub eps: f64,
    /// Inlier fraction that ends the search.
    pub tau: f64,
    /// Maximum trials N.
    pub trials: usize,
    /// Seed of the random point choices.
    pub seed: u64,
}

impl Default for Ransac {
    /// Seed 000 §5.2: RANSAC(Plane, eps = 0.07, tau = 0.07, N = 1024).
    fn default() -> Self {
        Ransac {
            eps: 0.07,
            tau: 0.07,
            trials: 1024,
            seed: 0,
        }
    }
}

/// The fitted plane and the indices of its inliers.
#[derive(Clone, Debug)]
pub struct PlaneFit {
    /// The least-squares plane of the inliers.
    pub plane: Plane,
    /// Indices of the points within eps of the plane.
    pub inliers: Vec<usize>,
    /// Trials made.
    pub trials: usize,
}

/// Alg. 3: planes through 3 random points until one has more than tau of the points within
/// eps; then the least-squares plane of its inliers. Without such a plane the best one found
/// is refined instead (the seed leaves this case open).
pub fn ransac_plane(points: &[DVec3], params: &Ransac) -> Option<PlaneFit> {
    let n = points.len();
    if n < 3 {
        return None;
    }
    let mut rng = Rng::new(params.seed);
    let inliers_of = |plane: &Plane| -> Vec<usize> {
        (0..n)
            .filter(|&i| plane.distance(points[i]) <= params.eps)
            .collect()
    };
    let mut best: Option<(Plane, usize)> = None;
    let mut trials = 0;
    while trials < params.trials {
        trials += 1;
        let (a, b, c) = (
            points[rng.below(n)],
            points[rng.below(n)],
            points[rng.below(n)],
        );
        let normal = (b - a).cross(c - a);
        if normal.length_squared() < 1e-24 {
            continue;
        }
        let plane = Plane {
            point: a,
            normal: normal.normalize(),
        };
        let count = (0..n)
            .filter(|&i| plane.distance(points[i]) <= params.eps)
            .count();
        if best.is_none_or(|(_, k)| count > k) {
            best = Some((plane, count));
        }
        if count as f64 / n as f64 > params.tau && count >= 3 {
            break;
        }
    }
    let (plane, _) = best?;
    let inliers = inliers_of(&plane);
    let chosen: Vec<DVec3> = inliers.iter().map(|&i| points[i]).collect();
    let refined = fit_plane(&chosen).unwrap_or(plane);
    Some(PlaneFit {
        inliers: inliers_of(&refined),
        plane: refined,
        trials,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_a_plane_despite_40_percent_outliers() {
        let mut rng = Rng::new(3);
        let truth = Plane {
            point: DVec3::new(0.0, 0.0, 0.5),
            normal: DVec3::new(0.1, -0.2, 1.0).normalize(),
        };
        let mut pts = Vec::new();
        for i in 0..1000 {
            let (x, y) = (rng.next_f64() * 2.0 - 1.0, rng.next_f64() * 2.0 - 1.0);
            if i % 5 < 2 {
                // 40% outliers anywhere in the unit cube around the plane.
                pts.push(DVec3::new(x, y, rng.next_f64() * 2.0 - 0.5));
            } else {
                let on = truth.from_plane(DVec2::new(x, y));
                pts.push(on + truth.normal * ((rng.next_f64() - 0.5) * 0.01));
            }
        }
        let fit = ransac_plane(
            &pts,
            &Ransac {
                eps: 0.02,
                tau: 0.5,
                trials: 1024,
                seed: 1,
            },
        )
        .expect("plane");
        assert!(
            fit.plane.normal.dot(truth.normal).abs() > 0.9999,
            "{:?}",
            fit.plane
        );
        assert!(truth.distance(fit.plane.point) < 1e-3);
        assert!(fit.inliers.len() >= 600, "{} inliers", fit.inliers.len());
        assert!(
            fit.inliers.len() < 700,
            "outliers were taken in: {}",
            fit.inliers.len()
        );
    }
}
