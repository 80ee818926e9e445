//! pbrt-v4's coated materials as analytic layers. coateddiffuse, energy-conserving: a GGX dielectric
//! interface of index eta over a Lambertian base of albedo rho (the "rough plastic" model of
//! Weidlich and Wilkie 2007 and Mitsuba's roughplastic). The interface reflects
//! F(wo.h) D G / (4 cos_o cos_i); light it lets through reaches the base, and what the base
//! sends back is trapped by the interface with the hemispherical internal reflectance Fi,
//! so the diffuse part is
//!
//!   (1 - F(cos_i)) (1 - F(cos_o)) rho / (pi eta^2 (1 - rho Fi)),
//!
//! Fi = 1 - (1 - Fe) / eta^2 with Fe the cosine-weighted mean external reflectance. With a
//! smooth interface and rho = 1 the two parts add up to exactly 1 (tested). pbrt-v4 simulates
//! the layers stochastically instead; its thickness, medium albedo and sample counts have no
//! counterpart here.

use super::microfacet::Ggx;
use super::{fresnel, reflect, BsdfSample, RoughConductor};
use fenestra_core::{warp, Rgb, Vec2, Vec3, INV_PI};
use fenestra_scene::material;

/// A GGX-coated Lambertian.
#[derive(Clone, Debug)]
pub struct CoatedDiffuse {
    reflectance: Rgb,
    eta: f32,
    ggx: Ggx,
    /// rho / (pi eta^2 (1 - rho Fi)): the diffuse part without its two transmittances.
    diffuse: Rgb,
    /// Fi, the interface's reflectance for the base's light.
    internal: f32,
}

/// Cosine-weighted mean of the dielectric Fresnel reflectance over the hemisphere seen from
/// outside: 2 int F(mu) mu dmu, by 64-point midpoint rule in mu^2 (exact weights).
fn external_reflectance(eta: f32) -> f32 {
    const N: usize = 64;
    (0..N)
        .map(|i| fresnel::dielectric(((i as f32 + 0.5) / N as f32).sqrt(), eta))
        .sum::<f32>()
        / N as f32
}

impl CoatedDiffuse {
    /// The base of albedo `reflectance` under an interface of index `eta` and GGX `alpha`.
    pub fn new(reflectance: Rgb, eta: f32, alpha: f32) -> Self {
        let internal = 1.0 - (1.0 - external_reflectance(eta)) / (eta * eta);
        CoatedDiffuse {
            reflectance,
            eta,
            ggx: Ggx::new(alpha, alpha),
            diffuse: Self::base_term(reflectance, eta, internal),
            internal,
        }
    }

    fn base_term(reflectance: Rgb, eta: f32, internal: f32) -> Rgb {
        reflectance.map(|r| r * INV_PI / (eta * eta * (1.0 - r * internal)))
    }

    /// The same coat over a base of another albedo (a texture's value at a hit), clamped to
    /// [0, 1] as pbrt-v4 clamps reflectances (above 1/Fi the trapped light would diverge).
    pub fn with_reflectance(&self, reflectance: Rgb) -> Self {
        let reflectance = reflectance.map(|c| c.clamp(0.0, 1.0));
        CoatedDiffuse {
            reflectance,
            diffuse: Self::base_term(reflectance, self.eta, self.internal),
            ..self.clone()
        }
    }

    /// Probability of sampling the interface's lobe for `wo`: its Fresnel reflectance against
    /// what the base sends back, kept away from 0 and 1.
    fn p_specular(&self, wo: Vec3) -> f32 {
        let f = fresnel::dielectric(wo.z, self.eta);
        let d = (1.0 - f) * self.reflectance.average();
        (f / (f + d).max(1e-6)).clamp(0.1, 0.9)
    }

    /// f(wo, wi) in the local frame (both above the surface).
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        self.base(wo, wi) + Rgb::splat(self.interface(wo, wi))
    }

    /// What the base sends back through the interface.
    fn base(&self, wo: Vec3, wi: Vec3) -> Rgb {
        let transmitted = (1.0 - fresnel::dielectric(wi.z, self.eta))
            * (1.0 - fresnel::dielectric(wo.z, self.eta));
        self.diffuse * transmitted
    }

    /// The interface's GGX reflection.
    fn interface(&self, wo: Vec3, wi: Vec3) -> f32 {
        interface_reflection(&self.ggx, self.eta, wo, wi)
    }

    /// Solid-angle density with which `sample` gives `wi`.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let p = self.p_specular(wo);
        p * ggx_reflection_pdf(&self.ggx, wo, wi) + (1.0 - p) * warp::cosine_hemisphere_pdf(wi)
    }

    /// Samples an incident direction for `wo`: the interface's visible normals or the base's
    /// cosine lobe.
    pub fn sample(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample> {
        let wi = if uc < self.p_specular(wo) {
            reflect(wo, self.ggx.sample_visible(wo, u))
        } else {
            warp::square_to_cosine_hemisphere(u)
        };
        BsdfSample::reflected(wi, |wi| self.eval(wo, wi), |wi| self.pdf(wo, wi))
    }
}

/// pbrt-v4's coatedconductor, analytically: the interface's GGX reflection plus the
/// conductor's lobe seen through it, weighted by the two transmittances
/// (1 - F(cos_i)) (1 - F(cos_o)). Refraction's narrowing of the conductor's lobe and light
/// bouncing between the layers are left out: never more energy than arrives, somewhat less
/// than the stochastic layers give for a rough interface.
#[derive(Clone, Debug)]
pub struct CoatedConductor {
    eta: f32,
    interface: Ggx,
    conductor: RoughConductor,
}

impl CoatedConductor {
    /// `conductor` under an interface of index `eta` and GGX roughness `alpha`.
    pub fn new(eta: f32, alpha: f32, conductor: RoughConductor) -> Self {
        CoatedConductor {
            eta,
            interface: Ggx::new(alpha, alpha),
            conductor,
        }
    }

    /// Probability of sampling the interface's lobe for `wo`.
    fn p_interface(&self, wo: Vec3) -> f32 {
        let f = fresnel::dielectric(wo.z, self.eta);
        (f / (f + (1.0 - f) * (1.0 - f)).max(1e-6)).clamp(0.1, 0.9)
    }

    /// f(wo, wi) in the local frame (both above the surface).
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        let transmitted = (1.0 - fresnel::dielectric(wi.z, self.eta))
            * (1.0 - fresnel::dielectric(wo.z, self.eta));
        self.conductor.eval(wo, wi) * transmitted
            + Rgb::splat(interface_reflection(&self.interface, self.eta, wo, wi))
    }

    /// Solid-angle density with which `sample` gives `wi`.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let p = self.p_interface(wo);
        p * ggx_reflection_pdf(&self.interface, wo, wi) + (1.0 - p) * self.conductor.pdf(wo, wi)
    }

    /// Samples an incident direction for `wo`: the interface's or the conductor's visible
    /// normals.
    pub fn sample(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample> {
        let wi = if uc < self.p_interface(wo) {
            reflect(wo, self.interface.sample_visible(wo, u))
        } else {
            self.conductor.sample(wo, u)?.wi
        };
        BsdfSample::reflected(wi, |wi| self.eval(wo, wi), |wi| self.pdf(wo, wi))
    }
}

/// A dielectric interface's GGX reflection F(wo.h) D G / (4 cos_o cos_i).
fn interface_reflection(ggx: &Ggx, eta: f32, wo: Vec3, wi: Vec3) -> f32 {
    let h = (wo + wi).normalize_or_zero();
    if h == Vec3::ZERO {
        return 0.0;
    }
    fresnel::dielectric(wo.dot(h), eta) * ggx.d(h) * ggx.g(wo, wi) / (4.0 * wo.z * wi.z)
}

/// Density of reflecting about visible normals of `ggx`.
fn ggx_reflection_pdf(ggx: &Ggx, wo: Vec3, wi: Vec3) -> f32 {
    let h = (wo + wi).normalize_or_zero();
    if h == Vec3::ZERO {
        0.0
    } else {
        ggx.pdf_visible(wo, h) / (4.0 * wo.dot(h).abs())
    }
}

/// The base texture's mean stands in until a hit point's lookup replaces it
/// (`RenderScene::bsdf_at`).
impl From<&material::CoatedDiffuse> for CoatedDiffuse {
    fn from(m: &material::CoatedDiffuse) -> Self {
        CoatedDiffuse::new(m.reflectance, m.eta, m.alpha)
    }
}

impl From<&material::CoatedConductor> for CoatedConductor {
    fn from(m: &material::CoatedConductor) -> Self {
        let conductor = RoughConductor::new(m.eta, m.k, m.alpha_x, m.alpha_y);
        CoatedConductor::new(m.interface_eta, m.interface_alpha, conductor)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The hemispherical integral of `f` cos for `wo`, by stratified cosine sampling
    /// (f cos / pdf = f pi).
    fn albedo(f: impl Fn(Vec3) -> Rgb) -> Rgb {
        let n = 256;
        let mut sum = Rgb::ZERO;
        for i in 0..n {
            for j in 0..n {
                let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                sum += f(warp::square_to_cosine_hemisphere(u)) * std::f32::consts::PI;
            }
        }
        sum / (n * n) as f32
    }

    fn at(cos_o: f32) -> Vec3 {
        Vec3::new((1.0 - cos_o * cos_o).sqrt(), 0.0, cos_o)
    }

    #[test]
    fn a_textured_base_is_the_same_coat_over_another_albedo() {
        let coat = CoatedDiffuse::new(Rgb::splat(0.5), 1.4, 0.2);
        let other = CoatedDiffuse::new(Rgb::new(0.9, 0.2, 0.0), 1.4, 0.2);
        let textured = coat.with_reflectance(Rgb::new(0.9, 0.2, 0.0));
        let (wo, wi) = (at(0.7), Vec3::new(-0.3, 0.2, 0.93).normalize());
        assert_eq!(textured.eval(wo, wi), other.eval(wo, wi));
        assert_eq!(textured.pdf(wo, wi), other.pdf(wo, wi));
        // A texel above 1 (a scaled texture) is clamped, never a negative or infinite value.
        let bright = coat.with_reflectance(Rgb::splat(5.0));
        assert_eq!(
            bright.eval(wo, wi),
            CoatedDiffuse::new(Rgb::ONE, 1.4, 0.2).eval(wo, wi)
        );
    }

    #[test]
    fn a_coated_conductor_reflects_no_more_than_arrives() {
        // Silver reflects about 97%; the coat's own 4% on top must not push the sum past 1.
        let silver = |a| RoughConductor::new(Rgb::splat(0.155), Rgb::splat(4.83), a, a);
        for (coat, metal) in [(0.05, 0.1), (0.3, 0.3), (0.6, 0.05)] {
            let coated = CoatedConductor::new(1.5, coat, silver(metal));
            for cos_o in [1.0f32, 0.5, 0.15] {
                let a = albedo(|wi| coated.eval(at(cos_o), wi)).r;
                assert!(a <= 1.01, "coat {coat}, cos {cos_o}: {a}");
            }
        }
    }

    #[test]
    fn a_white_base_under_a_smooth_coat_reflects_everything() {
        // With rho = 1 the internal bounces give back all that entered: the base sends
        // 1 - F(cos_o), the (smooth) interface reflects F(cos_o).
        let b = CoatedDiffuse::new(Rgb::ONE, 1.5, 1e-3);
        for cos_o in [0.95f32, 0.6, 0.2] {
            let wo = at(cos_o);
            let total = albedo(|wi| b.base(wo, wi)).r + fresnel::dielectric(cos_o, 1.5);
            assert!((total - 1.0).abs() < 0.005, "cos {cos_o}: {total}");
        }
    }

    #[test]
    fn a_coat_darkens_the_base_as_internal_reflection_predicts() {
        // rho = 0.5 under eta = 1.5 at normal incidence: the base sends back
        // (1 - F0)(1 - Fe) rho / (eta^2 (1 - rho Fi)) = 0.276, the interface about F0 = 0.04:
        // well below the uncoated 0.5 and the 0.48 of the Phong stand-in used before.
        let b = CoatedDiffuse::new(Rgb::splat(0.5), 1.5, 0.3);
        let a = albedo(|wi| b.eval(Vec3::Z, wi)).r;
        assert!(a > 0.29 && a < 0.33, "{a}");
        // Never more than what arrives, however rough.
        for alpha in [0.05, 0.3, 0.8] {
            let b = CoatedDiffuse::new(Rgb::ONE, 1.5, alpha);
            for cos_o in [1.0f32, 0.5, 0.1] {
                let a = albedo(|wi| b.eval(at(cos_o), wi)).r;
                assert!(a <= 1.01, "alpha {alpha}, cos {cos_o}: {a}");
            }
        }
    }
}
