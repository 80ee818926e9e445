//! Rough dielectric: GGX microfacet reflection and refraction (Walter et al. 2007), sampled
//! through visible normals with Fresnel lobe selection.

use super::microfacet::Ggx;
use super::{fresnel, reflect, BsdfSample};
use fenestra_core::{Rgb, Vec2, Vec3};
use fenestra_scene::material;

/// GGX microfacet dielectric (Walter et al. 2007): rough reflection and refraction.
#[derive(Clone, Debug)]
pub struct RoughDielectric {
    eta: f32,
    ggx: Ggx,
}

/// The microfacet normal that takes wo to wi, with the relative index crossed, or `None`
/// when the configuration is impossible (back-facing microfacet, grazing).
fn half_vector(wo: Vec3, wi: Vec3, eta: f32) -> Option<(Vec3, f32, bool)> {
    let reflection = wo.z * wi.z > 0.0;
    let etap = if reflection {
        1.0
    } else if wo.z > 0.0 {
        eta
    } else {
        1.0 / eta
    };
    let wm = wi * etap + wo;
    if wi.z == 0.0 || wo.z == 0.0 || wm.length_squared() == 0.0 {
        return None;
    }
    let mut wm = wm.normalize();
    if wm.z < 0.0 {
        wm = -wm;
    }
    // Both directions must see the front of the microfacet on their side of the surface.
    if wm.dot(wi) * wi.z < 0.0 || wm.dot(wo) * wo.z < 0.0 {
        return None;
    }
    Some((wm, etap, reflection))
}

impl RoughDielectric {
    /// The interface of relative index `eta` and GGX roughness `alpha`.
    pub fn new(eta: f32, alpha: f32) -> Self {
        RoughDielectric {
            eta,
            ggx: Ggx::new(alpha, alpha),
        }
    }

    /// f(wo, wi) in the local frame.
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        let Some((wm, etap, reflection)) = half_vector(wo, wi, self.eta) else {
            return Rgb::ZERO;
        };
        let f = fresnel::dielectric(wo.dot(wm), self.eta);
        let dg = self.ggx.d(wm) * self.ggx.g(wo, wi);
        if reflection {
            Rgb::splat(dg * f / (4.0 * wi.z * wo.z).abs())
        } else {
            let denom = (wi.dot(wm) + wo.dot(wm) / etap).powi(2) * wi.z * wo.z;
            let ft = dg * (1.0 - f) * (wi.dot(wm) * wo.dot(wm) / denom).abs();
            // Radiance transport: divide by etap^2 (see dielectric.rs).
            Rgb::splat(ft / (etap * etap))
        }
    }

    /// Solid-angle density with which `sample` gives `wi`.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let Some((wm, etap, reflection)) = half_vector(wo, wi, self.eta) else {
            return 0.0;
        };
        let f = fresnel::dielectric(wo.dot(wm), self.eta);
        let pv = self.ggx.pdf_visible(wo, wm);
        if reflection {
            pv / (4.0 * wo.dot(wm).abs()) * f
        } else {
            let dwm_dwi = wi.dot(wm).abs() / (wi.dot(wm) + wo.dot(wm) / etap).powi(2);
            pv * dwm_dwi * (1.0 - f)
        }
    }

    /// Samples an incident direction for `wo`.
    pub fn sample(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample> {
        let wm = self.ggx.sample_visible(wo, u);
        let f = fresnel::dielectric(wo.dot(wm), self.eta);
        let wi = if uc < f {
            let wi = reflect(wo, wm);
            if wi.z * wo.z <= 0.0 {
                return None;
            }
            wi
        } else {
            // Refract about the microfacet normal, oriented to the side of wo.
            let (wi, _) = fresnel::refract(wo, wm, self.eta)?;
            if wi.z * wo.z >= 0.0 || wi.z == 0.0 {
                return None;
            }
            wi
        };
        let pdf = self.pdf(wo, wi);
        if pdf <= 0.0 {
            return None;
        }
        let weight = self.eval(wo, wi) * (wi.z.abs() / pdf);
        weight.is_finite().then_some(BsdfSample {
            wi,
            weight,
            pdf,
            delta: false,
        })
    }
}

impl From<&material::RoughDielectric> for RoughDielectric {
    fn from(m: &material::RoughDielectric) -> Self {
        RoughDielectric::new(m.eta, m.alpha)
    }
}
