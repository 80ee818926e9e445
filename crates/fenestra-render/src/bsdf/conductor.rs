//! Rough conductor: GGX microfacets with complex Fresnel, visible-normal sampling.

use super::microfacet::Ggx;
use super::scatter::Scatter;
use super::{fresnel, reflect, BsdfSample};
use fenestra_core::{Rgb, Vec2, Vec3};
use fenestra_scene::material;

/// GGX microfacet conductor with complex Fresnel reflectance.
#[derive(Clone, Debug)]
pub struct RoughConductor {
    eta: Rgb,
    k: Rgb,
    ggx: Ggx,
}

impl RoughConductor {
    /// The conductor of complex index eta + i k and GGX roughness (ax, ay).
    pub fn new(eta: Rgb, k: Rgb, ax: f32, ay: f32) -> Self {
        RoughConductor {
            eta,
            k,
            ggx: Ggx::new(ax, ay),
        }
    }

    /// f(wo, wi) in the local frame.
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        let h = (wo + wi).normalize_or_zero();
        if h == Vec3::ZERO {
            return Rgb::ZERO;
        }
        let f = fresnel::conductor(wo.dot(h), self.eta, self.k);
        f * (self.ggx.d(h) * self.ggx.g(wo, wi) / (4.0 * wo.z * wi.z))
    }

    /// Solid-angle density with which `sample` gives `wi`.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let h = (wo + wi).normalize_or_zero();
        if h == Vec3::ZERO {
            return 0.0;
        }
        self.ggx.pdf_visible(wo, h) / (4.0 * wo.dot(h).abs())
    }

    /// Samples an incident direction for `wo`.
    pub fn sample(&self, wo: Vec3, u: Vec2) -> Option<BsdfSample> {
        let wi = reflect(wo, self.ggx.sample_visible(wo, u));
        BsdfSample::reflected(wi, |wi| self.eval(wo, wi), |wi| self.pdf(wo, wi))
    }

    /// Samples a reflected direction for `wo` through visible normals, with f and density.
    pub(super) fn scatter(&self, wo: Vec3, u: Vec2) -> Option<Scatter> {
        let wi = reflect(wo, self.ggx.sample_visible(wo, u));
        let s = Scatter {
            wi,
            f: self.eval(wo, wi),
            pdf: self.pdf(wo, wi),
            specular: false,
        };
        (wi.z * wo.z > 0.0 && s.pdf > 0.0).then_some(s)
    }
}

/// The roughness texture's mean stands in until a hit point's lookup replaces it
/// (`RenderScene::bsdf_at`).
impl From<&material::RoughConductor> for RoughConductor {
    fn from(m: &material::RoughConductor) -> Self {
        RoughConductor::new(m.eta, m.k, m.alpha_x, m.alpha_y)
    }
}
