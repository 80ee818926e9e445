//! Warps from the unit square to shapes and directions, with their densities.

use crate::trig::sin_cos_quarter;
use crate::{INV_4PI, INV_PI, PI};
use glam::{Vec2, Vec3};

/// Concentric (Shirley-Chiu) map of the square onto the unit disk.
pub fn square_to_disk_concentric(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    if o.x == 0.0 && o.y == 0.0 {
        return Vec2::ZERO;
    }
    // theta = phi when |o.x| > |o.y|, else pi/2 - phi, with |phi| <= pi/4: the two cases
    // differ only in which coordinate is which, chosen without a branch (a coin flip).
    let x_major = o.x.abs() > o.y.abs();
    let (minor, major) = if x_major { (o.y, o.x) } else { (o.x, o.y) };
    let (sin, cos) = sin_cos_quarter(0.25 * PI * (minor / major));
    let d = if x_major {
        Vec2::new(cos, sin)
    } else {
        Vec2::new(sin, cos)
    };
    major * d
}

/// The point of the square that [`square_to_disk_concentric`] maps to `d` (in the unit disk).
pub fn disk_concentric_to_square(d: Vec2) -> Vec2 {
    let r = d.length();
    if r == 0.0 {
        return Vec2::splat(0.5);
    }
    // The inverse of each case: the major coordinate keeps its sign with length r, the minor
    // one is the angle from the major axis over pi/4, times it.
    let o = if d.x.abs() > d.y.abs() {
        let major = r.copysign(d.x);
        Vec2::new(major, (d.y / d.x).atan() * (4.0 / PI) * major)
    } else {
        let major = r.copysign(d.y);
        Vec2::new((d.x / d.y).atan() * (4.0 / PI) * major, major)
    };
    ((o + Vec2::ONE) * 0.5).clamp(Vec2::ZERO, Vec2::ONE)
}

/// Cosine-weighted hemisphere around +z (Malley's method); density cos(theta)/pi.
pub fn square_to_cosine_hemisphere(u: Vec2) -> Vec3 {
    let d = square_to_disk_concentric(u);
    let z = (1.0 - d.length_squared()).max(0.0).sqrt();
    Vec3::new(d.x, d.y, z)
}

/// Density of [`square_to_cosine_hemisphere`] at `v`.
pub fn cosine_hemisphere_pdf(v: Vec3) -> f32 {
    if v.z > 0.0 {
        v.z * INV_PI
    } else {
        0.0
    }
}

/// Uniform directions on the unit sphere.
pub fn square_to_uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Density of [`square_to_uniform_sphere`]: 1 / (4 pi).
pub const UNIFORM_SPHERE_PDF: f32 = INV_4PI;

/// Uniform directions in the cone around +z whose cap on the unit sphere has the height
/// `h` = 1 - cos(theta_max). Taking `h` rather than the cosine keeps tiny cones (small, far
/// lights, where the cosine rounds to 1) exact.
pub fn square_to_uniform_cone(u: Vec2, h: f32) -> Vec3 {
    let one_minus_z = u.x * h;
    let r = (one_minus_z * (2.0 - one_minus_z)).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), 1.0 - one_minus_z)
}

/// Density of [`square_to_uniform_cone`] (per steradian) for the cap height `h`.
pub fn uniform_cone_pdf(h: f32) -> f32 {
    1.0 / (2.0 * PI * h)
}

/// 1 - cos(theta) from sin^2(theta) for theta in [0, pi/2], exact for small angles where
/// 1 - sqrt(1 - s) rounds to zero.
pub fn one_minus_cos_from_sin2(sin2: f32) -> f32 {
    if sin2 < 1e-3 {
        // Taylor: s/2 + s^2/8 (+ s^3/16, below f32's precision here).
        sin2 * 0.5 + sin2 * sin2 * 0.125
    } else {
        1.0 - (1.0 - sin2).max(0.0).sqrt()
    }
}

/// Uniform barycentrics (b1, b2) on a triangle (Heitz 2019, area-preserving, low distortion).
pub fn square_to_triangle(u: Vec2) -> Vec2 {
    let (mut b0, mut b1);
    if u.x < u.y {
        b0 = u.x / 2.0;
        b1 = u.y - b0;
    } else {
        b1 = u.y / 2.0;
        b0 = u.x - b1;
    }
    // Guard against rounding pushing the point outside.
    b0 = b0.clamp(0.0, 1.0);
    b1 = b1.clamp(0.0, 1.0 - b0);
    Vec2::new(b0, b1)
}

/// The point of the square that [`square_to_triangle`] maps to the barycentrics `b`.
pub fn triangle_to_square(b: Vec2) -> Vec2 {
    let u = if b.x < b.y {
        Vec2::new(2.0 * b.x, b.y + b.x)
    } else {
        Vec2::new(b.x + b.y, 2.0 * b.y)
    };
    u.clamp(Vec2::ZERO, Vec2::ONE)
}

/// Converts an area density at a point `y` with normal `ny` seen from `x` into a solid-angle
/// density at `x`: p_w = p_A * |x - y|^2 / |cos theta_y| (seed 000 ch. 4, p(Psi)). Returns 0
/// where the conversion would divide by zero (grazing emitters).
pub fn area_to_solid_angle(pdf_area: f32, dist_sq: f32, cos_y: f32) -> f32 {
    let c = cos_y.abs();
    if c <= 1e-7 {
        0.0
    } else {
        pdf_area * dist_sq / c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn warps_stay_on_their_domain() {
        for i in 0..64 {
            for j in 0..64 {
                let u = Vec2::new((i as f32 + 0.5) / 64.0, (j as f32 + 0.5) / 64.0);
                assert!(square_to_disk_concentric(u).length() <= 1.0 + 1e-6);
                let h = square_to_cosine_hemisphere(u);
                assert!((h.length() - 1.0).abs() < 1e-5 && h.z >= 0.0);
                assert!((square_to_uniform_sphere(u).length() - 1.0).abs() < 1e-5);
                let c = square_to_uniform_cone(u, 0.2);
                assert!(c.z >= 0.8 - 1e-6 && (c.length() - 1.0).abs() < 1e-5);
                let b = square_to_triangle(u);
                assert!(b.x >= 0.0 && b.y >= 0.0 && b.x + b.y <= 1.0 + 1e-6);
            }
        }
    }

    #[test]
    fn disk_and_triangle_warps_invert() {
        for i in 0..64 {
            for j in 0..64 {
                let u = Vec2::new((i as f32 + 0.5) / 64.0, (j as f32 + 0.5) / 64.0);
                let back = disk_concentric_to_square(square_to_disk_concentric(u));
                assert!((back - u).length() < 1e-5, "{u} came back as {back}");
                let back = triangle_to_square(square_to_triangle(u));
                assert!((back - u).length() < 1e-5, "{u} came back as {back}");
            }
        }
    }

    #[test]
    fn triangle_warp_is_uniform() {
        // Equal-area split of the triangle into 4 sub-triangles by the edge midpoints: each
        // should get a quarter of a stratified set of points.
        let n = 256;
        let mut counts = [0u32; 4];
        for i in 0..n {
            for j in 0..n {
                let b = square_to_triangle(Vec2::new(
                    (i as f32 + 0.5) / n as f32,
                    (j as f32 + 0.5) / n as f32,
                ));
                let k = if b.x > 0.5 {
                    0
                } else if b.y > 0.5 {
                    1
                } else if b.x + b.y < 0.5 {
                    2
                } else {
                    3
                };
                counts[k] += 1;
            }
        }
        for c in counts {
            assert!(
                (c as f32 / (n * n) as f32 - 0.25).abs() < 0.01,
                "{counts:?}"
            );
        }
    }

    #[test]
    fn one_minus_cos_is_exact_for_tiny_and_large_angles() {
        for theta in [1e-6f64, 1e-4, 0.01, 0.03, 0.1, 1.0, 1.5] {
            let exact = 2.0 * (theta / 2.0).sin().powi(2);
            let got = one_minus_cos_from_sin2(theta.sin().powi(2) as f32) as f64;
            assert!(
                (got / exact - 1.0).abs() < 1e-5,
                "{theta}: {got} vs {exact}"
            );
        }
        // A cone of 1e-6 rad still has its solid angle and its samples inside it.
        let h = one_minus_cos_from_sin2(1e-12);
        assert!((uniform_cone_pdf(h) * 2.0 * PI * 5e-13 - 1.0).abs() < 1e-5);
        let c = square_to_uniform_cone(Vec2::new(0.999, 0.3), h);
        assert!(c.z <= 1.0 && (c.x * c.x + c.y * c.y).sqrt() <= 1.0000001e-6);
    }
}
