//! glTF 2.0's metallic-roughness BRDF (the specification's Appendix B):
//!
//!   f = (1 - metallic) * dielectric + metallic * metal,
//!   metal      = F_m(v.h) * S,  F_m = schlick(base colour, 1),
//!   dielectric = (1 - max3 E_d(n.v)) * base colour / pi + F_d(v.h) * S,
//!                F_d = schlick(min(((ior - 1) / (ior + 1))^2 * specular colour, 1) * specular,
//!                              specular)                      (KHR_materials_ior, _specular)
//!   S = D G / (4 |n.l| |n.v|)  (GGX, height-correlated Smith G, alpha = roughness^2),
//!
//! where schlick(f0, f90)(c) = f0 + (f90 - f0) (1 - c)^5. One departure: Appendix B weighs
//! the base by 1 - max3 F_d(v.h), which gains energy (a white dielectric of roughness 0.1
//! reflects 1.48-1.54 of the light arriving at cos 0.1, docs/scenes.md); here the base gets
//! what the specular layer leaves, 1 - its directional albedo E_d at n.v (as Cycles' Principled BSDF
//! scales its albedo), so a white dielectric reflects exactly all the light at every angle.
//! Directions are sampled from the visible normals of D or the cosine, chosen by each lobe's
//! albedo at `wo`.

use super::microfacet::Ggx;
use super::specular_albedo::albedo;
use super::{reflect, specular_probability, BsdfSample};
use fenestra_core::{warp, Rgb, Vec2, Vec3, INV_PI};
use fenestra_scene::material;

/// The glTF metallic-roughness BRDF at one point (textures already looked up).
#[derive(Clone, Debug)]
pub struct MetallicRoughness {
    base_color: Rgb,
    metallic: f32,
    /// The dielectric's F0 and F90 (F90 is the specular weight).
    f0: Rgb,
    f90: f32,
    roughness: f32,
    ggx: Ggx,
}

/// Schlick's Fresnel approximation between `f0` at normal incidence and `f90` at grazing.
fn schlick(f0: Rgb, f90: f32, cos: f32) -> Rgb {
    let m = (1.0 - cos.clamp(0.0, 1.0)).powi(5);
    f0 + (Rgb::splat(f90) - f0) * m
}

impl MetallicRoughness {
    /// The BRDF of base colour, metallic and perceptual roughness in [0, 1] with the
    /// dielectric's ior, specular weight and specular colour.
    pub fn new(
        base_color: Rgb,
        metallic: f32,
        roughness: f32,
        (ior, specular, specular_color): (f32, f32, Rgb),
    ) -> Self {
        let r0 = ((ior - 1.0) / (ior + 1.0)).powi(2);
        let f0 = (specular_color * r0).map(|c| c.min(1.0)) * specular;
        let alpha = roughness * roughness;
        MetallicRoughness {
            base_color,
            metallic,
            f0,
            f90: specular,
            roughness,
            ggx: Ggx::new(alpha, alpha),
        }
    }

    /// The directional albedos of the dielectric's and the metal's specular lobes at `wo`.
    fn specular_albedos(&self, wo: Vec3) -> (Rgb, Rgb) {
        (
            albedo(self.f0, self.f90, wo.z, self.roughness),
            albedo(self.base_color, 1.0, wo.z, self.roughness),
        )
    }

    /// The Lambertian part's albedo at `wo`: what the dielectric's specular layer leaves.
    fn diffuse_albedo(&self, dielectric: Rgb) -> Rgb {
        let left = (1.0 - dielectric.max_component()).max(0.0);
        self.base_color * ((1.0 - self.metallic) * left)
    }

    /// f(wo, wi) in the local frame (both in the upper hemisphere).
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        let h = (wo + wi).normalize_or_zero();
        if h == Vec3::ZERO {
            return Rgb::ZERO;
        }
        let cos = wo.dot(h);
        let m = self.metallic;
        let tint =
            schlick(self.f0, self.f90, cos) * (1.0 - m) + schlick(self.base_color, 1.0, cos) * m;
        let s = self.ggx.d(h) * self.ggx.g(wo, wi) / (4.0 * wo.z * wi.z);
        let diffuse = self.diffuse_albedo(albedo(self.f0, self.f90, wo.z, self.roughness));
        diffuse * INV_PI + tint * s
    }

    /// Probability of sampling the GGX lobe rather than the cosine one for `wo`.
    fn specular_probability(&self, wo: Vec3) -> f32 {
        let (dielectric, metal) = self.specular_albedos(wo);
        let m = self.metallic;
        let specular = dielectric * (1.0 - m) + metal * m;
        specular_probability(self.diffuse_albedo(dielectric), specular)
    }

    /// Solid-angle density with which `sample` gives `wi`.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let h = (wo + wi).normalize_or_zero();
        if h == Vec3::ZERO {
            return 0.0;
        }
        let ps = self.specular_probability(wo);
        let specular = self.ggx.pdf_visible(wo, h) / (4.0 * wo.dot(h).abs());
        ps * specular + (1.0 - ps) * warp::cosine_hemisphere_pdf(wi)
    }

    /// Samples an incident direction for `wo`: `uc` picks the lobe.
    pub fn sample(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample> {
        let wi = if uc < self.specular_probability(wo) {
            reflect(wo, self.ggx.sample_visible(wo, u))
        } else {
            warp::square_to_cosine_hemisphere(u)
        };
        BsdfSample::reflected(wi, |wi| self.eval(wo, wi), |wi| self.pdf(wo, wi))
    }

    /// Material `m`'s BRDF where its base colour, metallic and roughness are `at` (its
    /// factors, or factors times texels).
    pub fn of(
        m: &material::MetallicRoughness,
        (base_color, metallic, roughness): (Rgb, f32, f32),
    ) -> Self {
        Self::new(
            base_color,
            metallic,
            roughness,
            (m.ior, m.specular, m.specular_color),
        )
    }
}

/// The factors alone: texels multiply them where `RenderScene::bsdf_at` looks them up.
impl From<&material::MetallicRoughness> for MetallicRoughness {
    fn from(m: &material::MetallicRoughness) -> Self {
        Self::of(m, (m.base_color, m.metallic, m.roughness))
    }
}
