//! Fresnel reflectance for dielectrics (seed 000 §2.4) and conductors.

use fenestra_core::{Rgb, Vec3};

/// Unpolarised Fresnel reflectance at a dielectric interface. `cos_i` is measured against the
/// normal on the exterior side (negative when arriving from inside); `eta` = interior/exterior.
pub fn dielectric(cos_i: f32, eta: f32) -> f32 {
    let (cos_i, eta) = if cos_i < 0.0 {
        (-cos_i, 1.0 / eta)
    } else {
        (cos_i, eta)
    };
    let cos_i = cos_i.min(1.0);
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0; // total internal reflection
    }
    let cos_t = (1.0 - sin2_t).max(0.0).sqrt();
    let r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    0.5 * (r_parl * r_parl + r_perp * r_perp)
}

/// Refracts `wi` through the interface with normal `n` (exterior side) and relative index
/// `eta`; returns (transmitted direction, relative index actually crossed), or `None` on total
/// internal reflection.
pub fn refract(wi: Vec3, n: Vec3, eta: f32) -> Option<(Vec3, f32)> {
    let mut cos_i = n.dot(wi);
    let (mut eta, mut n) = (eta, n);
    if cos_i < 0.0 {
        eta = 1.0 / eta;
        cos_i = -cos_i;
        n = -n;
    }
    let sin2_t = (1.0 - cos_i * cos_i).max(0.0) / (eta * eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some((-wi / eta + (cos_i / eta - cos_t) * n, eta))
}

/// Fresnel reflectance of a conductor with complex index eta + i k, per channel.
pub fn conductor(cos_i: f32, eta: Rgb, k: Rgb) -> Rgb {
    let c = cos_i.abs().min(1.0);
    let f = |eta: f32, k: f32| -> f32 {
        // |r_s|^2 and |r_p|^2 for n = eta + i k (pbrt's FrComplex written out in reals).
        let sin2 = 1.0 - c * c;
        // n^2 - sin^2 as a complex number, then its square root.
        let (a_re, a_im) = (eta * eta - k * k - sin2, 2.0 * eta * k);
        let m = (a_re * a_re + a_im * a_im).sqrt();
        let t_re = ((m + a_re) * 0.5).max(0.0).sqrt();
        let t_im = ((m - a_re) * 0.5).max(0.0).sqrt().copysign(a_im);
        let abs2 = |re: f32, im: f32| re * re + im * im;
        // r_s = (c - t) / (c + t)
        let rs = abs2(c - t_re, -t_im) / abs2(c + t_re, t_im).max(1e-20);
        // r_p = (n^2 c - t) / (n^2 c + t), n^2 = (eta^2 - k^2) + i 2 eta k
        let (n2_re, n2_im) = (eta * eta - k * k, 2.0 * eta * k);
        let rp = abs2(n2_re * c - t_re, n2_im * c - t_im)
            / abs2(n2_re * c + t_re, n2_im * c + t_im).max(1e-20);
        (0.5 * (rs + rp)).clamp(0.0, 1.0)
    };
    Rgb::new(f(eta.r, k.r), f(eta.g, k.g), f(eta.b, k.b))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dielectric_known_values() {
        // Normal incidence: ((eta - 1) / (eta + 1))^2 = 0.04 for eta = 1.5.
        assert!((dielectric(1.0, 1.5) - 0.04).abs() < 1e-6);
        assert!((dielectric(-1.0, 1.5) - 0.04).abs() < 1e-6);
        // Brewster's angle: parallel polarisation vanishes, so F = r_perp^2 / 2.
        let tb = 1.5f32.atan();
        let f = dielectric(tb.cos(), 1.5);
        assert!((f - 0.0739).abs() < 1e-3, "{f}");
        // Beyond the critical angle from inside: total internal reflection.
        assert_eq!(dielectric(-0.5, 1.5), 1.0);
        assert_eq!(dielectric(0.0, 1.5), 1.0);
    }

    #[test]
    fn conductor_reduces_to_dielectric_when_k_is_zero() {
        for c in [0.1, 0.5, 0.9, 1.0] {
            let a = conductor(c, Rgb::splat(1.5), Rgb::ZERO).r;
            assert!((a - dielectric(c, 1.5)).abs() < 1e-5, "{c}: {a}");
        }
        // Gold-like values reflect strongly at normal incidence: ((n-1)^2 + k^2) / ((n+1)^2 + k^2).
        let r = conductor(1.0, Rgb::splat(0.2), Rgb::splat(3.0)).r;
        let expect = (0.64 + 9.0) / (1.44 + 9.0);
        assert!((r - expect).abs() < 1e-4);
    }

    #[test]
    fn refraction_obeys_snell() {
        let wi = Vec3::new(0.6, 0.0, 0.8);
        let (wt, etap) = refract(wi, Vec3::Z, 1.5).expect("refracts");
        assert_eq!(etap, 1.5);
        assert!((wt.length() - 1.0).abs() < 1e-5 && wt.z < 0.0);
        assert!((wi.x - 1.5 * -wt.x).abs() < 1e-5, "sin_i = eta sin_t");
        assert!(refract(Vec3::new(0.9, 0.0, -0.435_889_9), Vec3::Z, 1.5).is_none());
    }
}
