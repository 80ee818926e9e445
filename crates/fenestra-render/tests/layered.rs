//! pbrt-v4's coated materials as fenestra simulates them (bsdf/layered): what `sample` delivers
//! must be what `eval` says, and a smooth coat must give the closed form that holds for it.
//!
//! - For coats smooth and rough, over Lambertian and gold bases, with and without a scattering
//!   slab, and three viewing angles: five moments of f cos over the hemisphere (the albedo,
//!   cos theta, sin theta cos phi, a narrow cone around the mirror direction, and the grazing
//!   band) estimated from `sample`'s weights and from `eval` at cosine-distributed directions
//!   agree within 4.5 standard errors (each error below 0.6% of the albedo, so a 2% bias fails).
//! - Under a 0.3-rough coat over a 0.8 base, the albedos from 8M samples and 8M evaluations
//!   agree within 4.5 standard errors of at most 0.04% (a 0.2% bias fails).
//! - Under a smooth coat with a negligible slab and walks that never stop early, the albedo
//!   is F(cos_o) + (1 - F(cos_o)) rho (1 - Fe) / (eta^2 (1 - rho Fi)) (Fe the cosine-weighted
//!   mean external reflectance, Fi = 1 - (1 - Fe) / eta^2): everything for rho = 1.
//! - `sample`'s density is `pdf`'s value there, and `eval`, `pdf` and `sample` give the same
//!   values for the same arguments.

use fenestra_core::{warp, Rgb, Rng, Vec3};
use fenestra_render::bsdf::{fresnel, Bsdf};
use fenestra_scene::material::{self, Layers};
use fenestra_scene::Material;

const DRAWS: usize = 400_000;
const MOMENTS: usize = 5;

fn at(cos_o: f32) -> Vec3 {
    Vec3::new((1.0 - cos_o * cos_o).sqrt(), 0.0, cos_o)
}

/// The moments' integrands at `wi` for viewer `wo`.
fn moments(wo: Vec3, wi: Vec3) -> [f64; MOMENTS] {
    let mirror = Vec3::new(-wo.x, -wo.y, wo.z);
    [
        1.0,
        f64::from(wi.z),
        f64::from(wi.x),
        f64::from(u8::from(wi.dot(mirror) > 0.95)),
        f64::from(u8::from(wi.z < 0.3)),
    ]
}

/// Mean and standard error of each moment over `draws` draws of `draw`.
fn estimate(
    draws: usize,
    mut draw: impl FnMut(&mut Rng) -> [f64; MOMENTS],
    seed: u64,
) -> [(f64, f64); MOMENTS] {
    let mut rng = Rng::new(seed);
    let (mut sum, mut sq) = ([0.0; MOMENTS], [0.0; MOMENTS]);
    for _ in 0..draws {
        let m = draw(&mut rng);
        for k in 0..MOMENTS {
            sum[k] += m[k];
            sq[k] += m[k] * m[k];
        }
    }
    let n = draws as f64;
    std::array::from_fn(|k| {
        let mean = sum[k] / n;
        (mean, ((sq[k] / n - mean * mean).max(0.0) / n).sqrt())
    })
}

/// The moments of f cos from `draws` samples (Dirac samples left out: `eval` has no Dirac
/// part).
fn from_sampling(bsdf: &Bsdf, wo: Vec3, draws: usize) -> [(f64, f64); MOMENTS] {
    estimate(
        draws,
        |rng| match bsdf.sample(wo, rng.next_f32(), rng.next_2d()) {
            Some(s) if !s.delta => {
                let w = f64::from(s.weight.g);
                moments(wo, s.wi).map(|m| m * w)
            }
            _ => [0.0; MOMENTS],
        },
        1,
    )
}

/// The moments of f cos from `eval` at `draws` cosine-distributed directions (f cos / pdf =
/// f pi).
fn from_eval(bsdf: &Bsdf, wo: Vec3, draws: usize) -> [(f64, f64); MOMENTS] {
    estimate(
        draws,
        |rng| {
            let wi = warp::square_to_cosine_hemisphere(rng.next_2d());
            let f = f64::from(bsdf.eval(wo, wi).g) * std::f64::consts::PI;
            moments(wo, wi).map(|m| m * f)
        },
        2,
    )
}

fn coated_diffuse(reflectance: f32, alpha: f32, layers: Layers) -> Bsdf {
    Bsdf::from_material(&Material::CoatedDiffuse(material::CoatedDiffuse {
        reflectance: Rgb::splat(reflectance),
        texture: None,
        eta: 1.5,
        alpha,
        layers,
    }))
}

fn coated_gold(coat_alpha: f32, metal_alpha: f32) -> Bsdf {
    Bsdf::from_material(&Material::CoatedConductor(material::CoatedConductor {
        interface_eta: 1.5,
        interface_alpha: coat_alpha,
        eta: Rgb::new(0.143, 0.374, 1.442),
        k: Rgb::new(3.983, 2.385, 1.603),
        alpha_x: metal_alpha,
        alpha_y: metal_alpha,
        layers: Layers::default(),
    }))
}

#[test]
fn sampling_delivers_what_eval_says() {
    let medium = Layers {
        thickness: 0.5,
        albedo: Rgb::splat(0.8),
        g: 0.4,
        ..Layers::default()
    };
    let cases = [
        (
            "smooth coat, diffuse 0.8",
            coated_diffuse(0.8, 1e-3, Layers::default()),
        ),
        (
            "rough coat 0.3, diffuse 0.8",
            coated_diffuse(0.8, 0.3, Layers::default()),
        ),
        (
            "rough coat 0.6, diffuse 0.3",
            coated_diffuse(0.3, 0.6, Layers::default()),
        ),
        (
            "rough coat 0.3, scattering slab",
            coated_diffuse(0.5, 0.3, medium),
        ),
        (
            "smooth coat, scattering slab",
            coated_diffuse(0.5, 1e-3, medium),
        ),
        ("rough coat 0.3 over gold 0.2", coated_gold(0.3, 0.2)),
        ("smooth coat over gold 0.3", coated_gold(1e-3, 0.3)),
        ("rough coat 0.4 over smooth gold", coated_gold(0.4, 1e-3)),
    ];
    for (name, bsdf) in &cases {
        for cos_o in [0.9f32, 0.5, 0.15] {
            let wo = at(cos_o);
            let (s, e) = (from_sampling(bsdf, wo, DRAWS), from_eval(bsdf, wo, DRAWS));
            let albedo = s[0].0.max(e[0].0);
            for k in 0..MOMENTS {
                let ((ms, es), (me, ee)) = (s[k], e[k]);
                let sigma = (es * es + ee * ee).sqrt();
                println!(
                    "{name}, cos {cos_o}, moment {k}: sampled {ms:.5} +- {es:.5}, eval {me:.5} +- {ee:.5}"
                );
                assert!(
                    sigma < 0.006 * albedo,
                    "{name}, cos {cos_o}, moment {k}: too noisy to judge"
                );
                assert!(
                    (ms - me).abs() < 4.5 * sigma,
                    "{name}, cos {cos_o}, moment {k}: sampled {ms} vs eval {me} (sigma {sigma})"
                );
            }
        }
    }
}

/// Cosine-weighted mean of the dielectric Fresnel reflectance seen from outside.
fn external_reflectance(eta: f32) -> f64 {
    let n = 100_000;
    (0..n)
        .map(|i| {
            f64::from(fresnel::dielectric(
                ((i as f32 + 0.5) / n as f32).sqrt(),
                eta,
            ))
        })
        .sum::<f64>()
        / f64::from(n)
}

#[test]
fn a_smooth_coat_gives_the_closed_form() {
    let eta = 1.5f32;
    let fe = external_reflectance(eta);
    let fi = 1.0 - (1.0 - fe) / f64::from(eta * eta);
    let layers = Layers {
        thickness: 1e-7,
        max_depth: 1000,
        ..Layers::default()
    };
    for rho in [1.0f32, 0.5] {
        let bsdf = coated_diffuse(rho, 1e-3, layers);
        for cos_o in [0.9f32, 0.4, 0.1] {
            let wo = at(cos_o);
            let fo = f64::from(fresnel::dielectric(cos_o, eta));
            let r = f64::from(rho);
            let diffuse = (1.0 - fo) * r * (1.0 - fe) / (f64::from(eta * eta) * (1.0 - r * fi));
            // eval's diffuse part, and sample's mean weight including the coat's mirror.
            let (e, ee) = from_eval(&bsdf, wo, DRAWS)[0];
            assert!(ee < 0.003 * diffuse, "too noisy: {ee} of {diffuse}");
            assert!(
                (e - diffuse).abs() < 4.5 * ee,
                "rho {rho}, cos {cos_o}: eval's albedo {e} vs {diffuse} (sigma {ee})"
            );
            let (s, es) = estimate(
                DRAWS,
                |rng| match bsdf.sample(wo, rng.next_f32(), rng.next_2d()) {
                    Some(s) => [f64::from(s.weight.g), 0.0, 0.0, 0.0, 0.0],
                    None => [0.0; MOMENTS],
                },
                3,
            )[0];
            assert!(
                (s - (fo + diffuse)).abs() < 4.5 * es.max(1e-6),
                "rho {rho}, cos {cos_o}: sampled albedo {s} vs {} (sigma {es})",
                fo + diffuse
            );
        }
    }
}

/// Where pbrt-v4's weights made f 7.7% brighter than sampling (a 0.3-rough coat over a 0.8
/// base, both rough-coat exits in play): the albedos from sampling and from f agree within
/// 4.5 standard errors of at most 0.04% of the albedo, so a bias of 0.2% fails.
#[test]
fn sampling_and_eval_agree_to_a_fifth_of_a_percent() {
    let bsdf = coated_diffuse(0.8, 0.3, Layers::default());
    let (wo, draws) = (at(0.8), 8_000_000);
    let ((ms, es), (me, ee)) = (
        from_sampling(&bsdf, wo, draws)[0],
        from_eval(&bsdf, wo, draws)[0],
    );
    let sigma = (es * es + ee * ee).sqrt();
    println!("sampled {ms:.5} +- {es:.5}, eval {me:.5} +- {ee:.5}");
    assert!(sigma < 0.0004 * ms, "too noisy to judge ({sigma})");
    assert!(
        (ms - me).abs() < 4.5 * sigma,
        "sampled {ms} vs eval {me} (sigma {sigma})"
    );
}

#[test]
fn estimates_are_functions_of_their_arguments() {
    let bsdf = coated_gold(0.3, 0.2);
    let wo = at(0.6);
    let mut rng = Rng::new(9);
    let mut non_delta = 0;
    for _ in 0..2000 {
        let (uc, u) = (rng.next_f32(), rng.next_2d());
        let Some(s) = bsdf.sample(wo, uc, u) else {
            continue;
        };
        let again = bsdf.sample(wo, uc, u).expect("the same sample");
        assert_eq!((s.wi, s.weight, s.pdf), (again.wi, again.weight, again.pdf));
        if !s.delta {
            non_delta += 1;
            assert_eq!(s.pdf, bsdf.pdf(wo, s.wi), "sample's density is pdf's value");
            assert_eq!(bsdf.eval(wo, s.wi), bsdf.eval(wo, s.wi));
            assert!(bsdf.pdf(wo, s.wi) > 0.0);
        }
    }
    assert!(non_delta > 1000, "{non_delta}");
    // Opposite sides: no transmission through an opaque coated material.
    let below = Vec3::new(0.3, 0.1, -0.9).normalize();
    assert_eq!(bsdf.eval(wo, below), Rgb::ZERO);
    assert_eq!(bsdf.pdf(wo, below), 0.0);
}
