//! The directional albedo of an isotropic GGX lobe with Schlick's Fresnel, split as
//! E(mu) = f0 A(mu, r) + f90 B(mu, r): A weighs 1 - (1 - v.h)^5, B weighs (1 - v.h)^5, for
//! the cosine mu of the outgoing direction and the perceptual roughness r (alpha = r^2).
//! Tabulated once by stratified visible-normal sampling (the estimator of f cos / pdf is
//! F G2 / G1), looked up bilinearly.

use super::microfacet::Ggx;
use super::reflect;
use fenestra_core::{Rgb, Vec2, Vec3};
use std::sync::OnceLock;

/// Table points along mu and along r.
const N: usize = 32;
/// Stratified samples per table point (a STRATA x STRATA grid).
const STRATA: usize = 48;

/// A(mu, r) and B(mu, r) at mu = i / (N - 1) (from 0.02 up), r = j / (N - 1).
struct Table {
    ab: Vec<[f32; 2]>,
}

fn table() -> &'static Table {
    static TABLE: OnceLock<Table> = OnceLock::new();
    TABLE.get_or_init(|| Table {
        ab: (0..N * N)
            .map(|k| integrate(mu_at(k / N), (k % N) as f32 / (N - 1) as f32))
            .collect(),
    })
}

fn mu_at(i: usize) -> f32 {
    (i as f32 / (N - 1) as f32).max(0.02)
}

/// A and B at one point by a stratified grid of visible normals.
fn integrate(mu: f32, r: f32) -> [f32; 2] {
    let ggx = Ggx::new(r * r, r * r);
    let wo = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
    let (mut a, mut b) = (0.0f64, 0.0f64);
    for i in 0..STRATA {
        for j in 0..STRATA {
            let u = Vec2::new(
                (i as f32 + 0.5) / STRATA as f32,
                (j as f32 + 0.5) / STRATA as f32,
            );
            let h = ggx.sample_visible(wo, u);
            let wi = reflect(wo, h);
            if wi.z <= 0.0 {
                continue;
            }
            let w = (ggx.g(wo, wi) / ggx.g1(wo)) as f64;
            let m = (1.0 - wo.dot(h).clamp(0.0, 1.0)).powi(5) as f64;
            a += w * (1.0 - m);
            b += w * m;
        }
    }
    let n = (STRATA * STRATA) as f64;
    [(a / n) as f32, (b / n) as f32]
}

/// The albedo of the lobe with Fresnel from `f0` to `f90`, seen at cosine `mu`, of
/// perceptual roughness `r`.
pub fn albedo(f0: Rgb, f90: f32, mu: f32, r: f32) -> Rgb {
    let t = table();
    let x = mu.clamp(0.0, 1.0) * (N - 1) as f32;
    let y = r.clamp(0.0, 1.0) * (N - 1) as f32;
    let (i, j) = ((x as usize).min(N - 2), (y as usize).min(N - 2));
    let (fx, fy) = (x - i as f32, y - j as f32);
    let at = |i: usize, j: usize| t.ab[i * N + j];
    let mut ab = [0.0f32; 2];
    for (k, v) in ab.iter_mut().enumerate() {
        *v = (1.0 - fx) * ((1.0 - fy) * at(i, j)[k] + fy * at(i, j + 1)[k])
            + fx * ((1.0 - fy) * at(i + 1, j)[k] + fy * at(i + 1, j + 1)[k]);
    }
    f0 * ab[0] + Rgb::splat(f90 * ab[1])
}
