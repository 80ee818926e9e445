//! The paraboloid map (Heidrich and Seidel 1998) from the upper hemisphere (z > 0) to the unit
//! disc, the 2D domain D where an L-tree keeps its directions (seed 003 §2.4.3): low
//! distortion and closed forms both ways.

use fenestra_core::{Vec2, Vec3};

/// The point of D for the unit direction `w` with `w.z > 0`.
pub fn to_disc(w: Vec3) -> Vec2 {
    Vec2::new(w.x, w.y) / (1.0 + w.z)
}

/// The unit direction of the point `q` of D (|q| <= 1).
pub fn from_disc(q: Vec2) -> Vec3 {
    let r2 = q.length_squared();
    let s = 2.0 / (1.0 + r2);
    Vec3::new(q.x * s, q.y * s, (1.0 - r2) / (1.0 + r2))
}

/// Solid angle per unit area of D at `q`: d(omega) = 4 / (1 + |q|^2)^2 dA.
pub fn jacobian(q: Vec2) -> f32 {
    let s = 1.0 + q.length_squared();
    4.0 / (s * s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use fenestra_core::warp;

    #[test]
    fn directions_survive_the_round_trip() {
        for i in 0..1000 {
            let u = Vec2::new(
                (i as f32 + 0.5) / 1000.0,
                ((i * 7919) % 1000) as f32 / 1000.0,
            );
            let w = warp::square_to_cosine_hemisphere(u);
            if w.z <= 1e-4 {
                continue;
            }
            let q = to_disc(w);
            assert!(q.length() <= 1.0 + 1e-6);
            let back = from_disc(q);
            assert!((back - w).length() < 1e-5, "{w} -> {q} -> {back}");
        }
    }

    #[test]
    fn the_jacobian_integrates_to_the_hemisphere() {
        // Midpoint rule over the disc: the solid angle of the hemisphere is 2 pi.
        let n = 600;
        let h = 2.0 / n as f32;
        let mut sum = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let q = Vec2::new(-1.0 + (i as f32 + 0.5) * h, -1.0 + (j as f32 + 0.5) * h);
                if q.length_squared() <= 1.0 {
                    sum += (jacobian(q) * h * h) as f64;
                }
            }
        }
        let two_pi = 2.0 * std::f64::consts::PI;
        assert!((sum - two_pi).abs() < 2e-3 * two_pi, "{sum}");
    }
}
