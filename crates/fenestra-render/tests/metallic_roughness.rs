//! glTF's metallic-roughness BRDF: its directional albedo (a white furnace around one point)
//! computed two ways, by quadrature of f cos and by the mean of sampled weights, agrees and
//! never exceeds one; a white dielectric reflects all the light at every angle and roughness,
//! a smooth white metal almost all; with no specular layer it is exactly its Lambertian base.

use fenestra_core::{Rgb, Rng, Vec3, PI};
use fenestra_render::bsdf::Bsdf;
use fenestra_scene::material::MetallicRoughness;
use fenestra_scene::Material;

fn brdf(base: Rgb, metallic: f32, roughness: f32) -> Bsdf {
    Bsdf::from_material(&Material::MetallicRoughness(MetallicRoughness {
        base_color: base,
        metallic,
        roughness,
        ..MetallicRoughness::new()
    }))
}

/// Directional albedo of `bsdf` lit from `wo`, by the midpoint rule over half vectors h in
/// (theta, phi), which resolves sharp lobes: wi = reflect(wo, h), dwi = 4 |wo.h| dwh.
fn albedo_by_quadrature(bsdf: &Bsdf, wo: Vec3) -> f64 {
    const N: usize = 512;
    let (dtheta, dphi) = (0.5 * PI as f64 / N as f64, PI as f64 / N as f64);
    let mut sum = 0.0f64;
    for i in 0..N {
        let theta = (i as f64 + 0.5) * dtheta;
        for j in 0..2 * N {
            let phi = (j as f64 + 0.5) * dphi;
            let h = Vec3::new(
                (theta.sin() * phi.cos()) as f32,
                (theta.sin() * phi.sin()) as f32,
                theta.cos() as f32,
            );
            let wi = 2.0 * wo.dot(h) * h - wo;
            if wi.z > 0.0 {
                let jacobian = 4.0 * wo.dot(h).abs() as f64 * theta.sin();
                sum += bsdf.eval(wo, wi).g as f64 * wi.z as f64 * jacobian;
            }
        }
    }
    sum * dtheta * dphi
}

/// The same albedo as the mean of sampled weights, with its standard error.
fn albedo_by_sampling(bsdf: &Bsdf, wo: Vec3) -> (f64, f64) {
    const N: usize = 400_000;
    let mut rng = Rng::new(7);
    let (mut s, mut s2) = (0.0f64, 0.0f64);
    for _ in 0..N {
        let uc = rng.next_f32();
        let w = bsdf
            .sample(wo, uc, rng.next_2d())
            .map_or(0.0, |s| s.weight.g as f64);
        s += w;
        s2 += w * w;
    }
    let mean = s / N as f64;
    (mean, ((s2 / N as f64 - mean * mean) / N as f64).sqrt())
}

#[test]
fn white_furnace_albedo_agrees_two_ways_and_stays_below_one() {
    for roughness in [0.15, 0.4, 0.7, 1.0] {
        for metallic in [0.0, 0.5, 1.0] {
            let bsdf = brdf(Rgb::ONE, metallic, roughness);
            for cos in [0.95f32, 0.5, 0.1] {
                let wo = Vec3::new((1.0 - cos * cos).sqrt(), 0.0, cos);
                let q = albedo_by_quadrature(&bsdf, wo);
                let (m, se) = albedo_by_sampling(&bsdf, wo);
                let what = format!("roughness {roughness} metallic {metallic} cos {cos}");
                assert!(
                    (q - m).abs() <= 4.0 * se + 2e-3 * q,
                    "{what}: albedo {q:.5} by quadrature, {m:.5} +- {se:.5} by sampling"
                );
                assert!(q <= 1.0 + 3e-3, "{what}: albedo {q:.5} exceeds one");
                if metallic == 0.0 {
                    // What the specular layer does not reflect, the white base does.
                    assert!(
                        q >= 1.0 - 3e-3,
                        "{what}: a white dielectric reflects {q:.5}"
                    );
                }
            }
        }
    }
    // Single scattering loses little at low roughness: a smooth white metal is a mirror (at
    // roughness 1 it keeps 0.32 at normal incidence, as GGX does without multiple scattering).
    let wo = Vec3::new(0.6, 0.0, 0.8);
    let q = albedo_by_quadrature(&brdf(Rgb::ONE, 1.0, 0.1), wo);
    assert!(q > 0.99, "smooth white metal albedo {q:.5}");
}

#[test]
fn no_specular_layer_is_exactly_the_lambertian_base() {
    let base = Rgb::new(0.7, 0.5, 0.1);
    let bsdf = Bsdf::from_material(&Material::MetallicRoughness(MetallicRoughness {
        base_color: base,
        metallic: 0.0,
        roughness: 0.4,
        specular: 0.0,
        ..MetallicRoughness::new()
    }));
    let wo = Vec3::new(0.3, -0.2, 0.93).normalize();
    for wi in [
        Vec3::new(-0.3, 0.2, 0.93).normalize(),
        Vec3::new(0.5, 0.5, 0.7).normalize(),
        Vec3::new(-0.8, 0.1, 0.2).normalize(),
    ] {
        assert_eq!(bsdf.eval(wo, wi), base * (1.0 / PI));
    }
}
