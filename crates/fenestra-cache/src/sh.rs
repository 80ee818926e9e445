//! Real spherical harmonics of order 10 (degrees l < 10: 100 functions), the basis of SH
//! radiance caching (Krivanek et al. 2005, seed 003 §2.3): orthonormal over the sphere,
//! Y_l^0 = K_l^0 P_l^0(cos theta), Y_l^m = sqrt 2 K_l^m P_l^m(cos theta) cos(m phi) and
//! Y_l^-m = sqrt 2 K_l^m P_l^m(cos theta) sin(m phi) (m > 0), with the associated Legendre
//! polynomials by their recurrences over l, and cos(m phi) sin^m theta, sin(m phi) sin^m theta
//! as the real and imaginary parts of (x + i y)^m.

use fenestra_core::Vec3;
use std::sync::OnceLock;

/// Order: degrees 0..ORDER.
pub const ORDER: usize = 10;
/// Number of basis functions.
pub const COUNT: usize = ORDER * ORDER;

/// Where Y_l^m lies in a coefficient vector.
pub const fn index(l: usize, m: i32) -> usize {
    ((l * (l + 1)) as i32 + m) as usize
}

/// The normalisations K_l^m = sqrt((2l + 1) / 4 pi (l - m)! / (l + m)!), times sqrt 2 for
/// m > 0, at index(l, m).
fn normalisation() -> &'static [f32; COUNT] {
    static K: OnceLock<[f32; COUNT]> = OnceLock::new();
    K.get_or_init(|| {
        let mut k = [0.0f32; COUNT];
        for l in 0..ORDER {
            for m in 0..=l {
                // (l - m)! / (l + m)! as a product of reciprocals.
                let ratio: f64 = ((l - m + 1)..=(l + m)).map(|i| 1.0 / i as f64).product();
                let v = ((2 * l + 1) as f64 / (4.0 * std::f64::consts::PI) * ratio).sqrt();
                let v = if m == 0 {
                    v
                } else {
                    v * std::f64::consts::SQRT_2
                };
                k[index(l, m as i32)] = v as f32;
            }
        }
        k
    })
}

/// All basis functions at the unit direction `w`.
pub fn eval(w: Vec3, out: &mut [f32; COUNT]) {
    let k = normalisation();
    let (x, y, z) = (w.x, w.y, w.z);
    // P_m^m / sin^m theta = (-1)^m (2m - 1)!!
    let mut pmm = 1.0f32;
    let (mut c, mut s) = (1.0f32, 0.0f32);
    for m in 0..ORDER {
        if m > 0 {
            pmm *= -((2 * m - 1) as f32);
            (c, s) = (c * x - s * y, c * y + s * x);
        }
        let (mut before, mut last) = (0.0f32, 0.0f32);
        for l in m..ORDER {
            let p = if l == m {
                pmm
            } else if l == m + 1 {
                z * (2 * m + 1) as f32 * pmm
            } else {
                ((2 * l - 1) as f32 * z * last - (l + m - 1) as f32 * before) / (l - m) as f32
            };
            (before, last) = (last, p);
            let i = index(l, m as i32);
            if m == 0 {
                out[i] = k[i] * p;
            } else {
                out[i] = k[i] * c * p;
                out[index(l, -(m as i32))] = k[i] * s * p;
            }
        }
    }
}

/// Whether Y_l^m is even under z -> -z (l + |m| even).
pub const fn even(l: usize, m: i32) -> bool {
    (l + m.unsigned_abs() as usize).is_multiple_of(2)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Quadrature over the sphere exact for polynomials of degree < 2 n: Gauss-Legendre
    /// nodes in z (found by Newton's method on P_n), 2 n equal steps in phi; `f` at each
    /// point with its weight.
    fn sphere(n: usize, mut f: impl FnMut(Vec3, f64)) {
        for i in 0..n {
            let mut z = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut derivative = 1.0;
            for _ in 0..50 {
                let (mut p, mut before) = (1.0f64, 0.0f64);
                for k in 1..=n {
                    (p, before) = (
                        ((2 * k - 1) as f64 * z * p - (k - 1) as f64 * before) / k as f64,
                        p,
                    );
                }
                derivative = n as f64 * (z * p - before) / (z * z - 1.0);
                z -= p / derivative;
            }
            let w_z = 2.0 / ((1.0 - z * z) * derivative * derivative);
            let r = (1.0 - z * z).sqrt();
            for j in 0..2 * n {
                let phi = std::f64::consts::TAU * j as f64 / (2 * n) as f64;
                let w = Vec3::new((r * phi.cos()) as f32, (r * phi.sin()) as f32, z as f32);
                f(w, w_z * std::f64::consts::PI / n as f64);
            }
        }
    }

    #[test]
    fn the_basis_is_orthonormal() {
        let mut gram = vec![0.0f64; COUNT * COUNT];
        let mut y = [0.0f32; COUNT];
        sphere(ORDER, |w, weight| {
            eval(w, &mut y);
            for i in 0..COUNT {
                for j in 0..COUNT {
                    gram[i * COUNT + j] += y[i] as f64 * y[j] as f64 * weight;
                }
            }
        });
        for i in 0..COUNT {
            for j in 0..COUNT {
                let want = if i == j { 1.0 } else { 0.0 };
                let got = gram[i * COUNT + j];
                assert!((got - want).abs() < 1e-4, "<Y{i}, Y{j}> = {got}");
            }
        }
    }

    #[test]
    fn low_degree_functions_are_reconstructed_and_parity_holds() {
        // f = 1 + 2x - z^2 + 0.5 x y z has degree 3: its projection reconstructs it.
        let f = |w: Vec3| 1.0 + 2.0 * w.x - w.z * w.z + 0.5 * w.x * w.y * w.z;
        let mut coeffs = [0.0f64; COUNT];
        let mut y = [0.0f32; COUNT];
        sphere(ORDER, |w, weight| {
            eval(w, &mut y);
            for i in 0..COUNT {
                coeffs[i] += f(w) as f64 * y[i] as f64 * weight;
            }
        });
        for w in [
            Vec3::new(0.3, -0.5, 0.81).normalize(),
            Vec3::new(-0.9, 0.1, -0.2).normalize(),
            Vec3::Z,
        ] {
            eval(w, &mut y);
            let back: f64 = (0..COUNT).map(|i| coeffs[i] * y[i] as f64).sum();
            assert!((back - f(w) as f64).abs() < 1e-4, "{back} vs {}", f(w));
            // Mirroring z changes the sign of exactly the odd functions.
            let mut mirrored = [0.0f32; COUNT];
            eval(Vec3::new(w.x, w.y, -w.z), &mut mirrored);
            for l in 0..ORDER {
                for m in -(l as i32)..=(l as i32) {
                    let (i, sign) = (index(l, m), if even(l, m) { 1.0 } else { -1.0 });
                    assert!((mirrored[i] - sign * y[i]).abs() < 1e-4, "Y_{l}^{m}");
                }
            }
        }
    }
}
