//! Rough dielectric: GGX microfacet reflection and refraction (Walter et al. 2007), sampled
//! through visible normals with Fresnel lobe selection.

use super::microfacet::Ggx;
use super::scatter::{Lobes, Mode, Scatter};
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
    /// Interior index over exterior index.
    pub fn eta(&self) -> f32 {
        self.eta
    }

    /// The interface of relative index `eta` and GGX roughness `alpha`.
    pub fn new(eta: f32, alpha: f32) -> Self {
        RoughDielectric {
            eta,
            ggx: Ggx::new(alpha, alpha),
        }
    }

    /// f(wo, wi) in the local frame.
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        Rgb::splat(self.f(wo, wi, Mode::Radiance))
    }

    /// f(wo, wi) for light carrying `mode`: refraction divides radiance by the relative
    /// index squared, not importance.
    pub(super) fn f(&self, wo: Vec3, wi: Vec3, mode: Mode) -> f32 {
        let Some((wm, etap, reflection)) = half_vector(wo, wi, self.eta) else {
            return 0.0;
        };
        let f = fresnel::dielectric(wo.dot(wm), self.eta);
        let dg = self.ggx.d(wm) * self.ggx.g(wo, wi);
        if reflection {
            dg * f / (4.0 * wi.z * wo.z).abs()
        } else {
            let denom = (wi.dot(wm) + wo.dot(wm) / etap).powi(2) * wi.z * wo.z;
            let ft = dg * (1.0 - f) * (wi.dot(wm) * wo.dot(wm) / denom).abs();
            match mode {
                Mode::Radiance => ft / (etap * etap),
                Mode::Importance => ft,
            }
        }
    }

    /// Solid-angle density with which `sample` gives `wi`.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.pdf_of(wo, wi, Lobes::All)
    }

    /// The density of `wi` when sampling only `lobes`.
    pub(super) fn pdf_of(&self, wo: Vec3, wi: Vec3, lobes: Lobes) -> f32 {
        let Some((wm, etap, reflection)) = half_vector(wo, wi, self.eta) else {
            return 0.0;
        };
        let Some((pr, pt)) = lobes.shares(fresnel::dielectric(wo.dot(wm), self.eta)) else {
            return 0.0;
        };
        let pv = self.ggx.pdf_visible(wo, wm);
        if reflection {
            pv / (4.0 * wo.dot(wm).abs()) * pr
        } else {
            let dwm_dwi = wi.dot(wm).abs() / (wi.dot(wm) + wo.dot(wm) / etap).powi(2);
            pv * dwm_dwi * pt
        }
    }

    /// Samples an incident direction for `wo`.
    pub fn sample(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample> {
        let s = self.scatter(wo, uc, u, Mode::Radiance, Lobes::All)?;
        Some(BsdfSample {
            wi: s.wi,
            weight: s.weight(),
            pdf: s.pdf,
            delta: false,
        })
    }

    /// Samples one of `lobes` for `wo` through visible normals, the lobe chosen in proportion
    /// to the microfacet's Fresnel reflectance.
    pub(super) fn scatter(
        &self,
        wo: Vec3,
        uc: f32,
        u: Vec2,
        mode: Mode,
        lobes: Lobes,
    ) -> Option<Scatter> {
        let wm = self.ggx.sample_visible(wo, u);
        let (pr, _) = lobes.shares(fresnel::dielectric(wo.dot(wm), self.eta))?;
        let wi = if uc < pr {
            let wi = reflect(wo, wm);
            if wi.z * wo.z <= 0.0 {
                return None;
            }
            wi
        } else {
            let (wi, _) = fresnel::refract(wo, wm, self.eta)?;
            if wi.z * wo.z >= 0.0 || wi.z == 0.0 {
                return None;
            }
            wi
        };
        let s = Scatter {
            wi,
            f: Rgb::splat(self.f(wo, wi, mode)),
            pdf: self.pdf_of(wo, wi, lobes),
            specular: false,
        };
        (s.pdf > 0.0 && s.weight().is_finite()).then_some(s)
    }
}

impl From<&material::RoughDielectric> for RoughDielectric {
    fn from(m: &material::RoughDielectric) -> Self {
        RoughDielectric::new(m.eta, m.alpha)
    }
}
