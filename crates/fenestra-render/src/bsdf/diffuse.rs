//! Lambertian reflection, and Lambertian reflection with Lambertian transmission.

use super::BsdfSample;
use fenestra_core::{warp, Rgb, Vec2, Vec3, INV_PI};
use fenestra_scene::material;

/// Lambertian reflection.
#[derive(Clone, Debug)]
pub struct Diffuse {
    /// Albedo.
    pub reflectance: Rgb,
}

impl Diffuse {
    /// f(wo, wi) in the local frame.
    pub fn eval(&self, _wo: Vec3, _wi: Vec3) -> Rgb {
        self.reflectance * INV_PI
    }
    /// Solid-angle density with which `sample` gives `wi`.
    pub fn pdf(&self, _wo: Vec3, wi: Vec3) -> f32 {
        warp::cosine_hemisphere_pdf(wi)
    }
    /// Samples an incident direction for `wo`.
    pub fn sample(&self, _wo: Vec3, u: Vec2) -> Option<BsdfSample> {
        let wi = warp::square_to_cosine_hemisphere(u);
        let pdf = warp::cosine_hemisphere_pdf(wi);
        Some(BsdfSample {
            wi,
            weight: self.reflectance,
            pdf,
            delta: false,
        })
    }
}

/// Lambertian reflection on `wo`'s side and Lambertian transmission to the other side
/// (pbrt-v4's diffusetransmission). The side is chosen in proportion to the two albedos.
#[derive(Clone, Debug)]
pub struct DiffuseTransmission {
    /// Albedo of the reflection.
    pub reflectance: Rgb,
    /// Albedo of the transmission.
    pub transmittance: Rgb,
}

impl DiffuseTransmission {
    /// Probability of sampling the reflection.
    fn reflect_probability(&self) -> f32 {
        let (r, t) = (self.reflectance.average(), self.transmittance.average());
        if r + t > 0.0 {
            r / (r + t)
        } else {
            0.5
        }
    }

    /// f(wo, wi) in the local frame, for `wi` on either side.
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        if wo.z * wi.z > 0.0 {
            self.reflectance * INV_PI
        } else {
            self.transmittance * INV_PI
        }
    }

    /// Solid-angle density with which `sample` gives `wi`.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let pr = self.reflect_probability();
        let side = if wo.z * wi.z > 0.0 { pr } else { 1.0 - pr };
        side * wi.z.abs() * INV_PI
    }

    /// Samples an incident direction for `wo`; `uc` picks reflection or transmission.
    pub fn sample(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample> {
        let pr = self.reflect_probability();
        let (albedo, side, chosen) = if uc < pr {
            (self.reflectance, wo.z.signum(), pr)
        } else {
            (self.transmittance, -wo.z.signum(), 1.0 - pr)
        };
        let mut wi = warp::square_to_cosine_hemisphere(u);
        wi.z *= side;
        let pdf = chosen * wi.z.abs() * INV_PI;
        (pdf > 0.0).then(|| BsdfSample {
            wi,
            weight: albedo / chosen,
            pdf,
            delta: false,
        })
    }
}

impl From<&material::Diffuse> for Diffuse {
    fn from(m: &material::Diffuse) -> Self {
        Diffuse {
            reflectance: m.reflectance,
        }
    }
}

/// The texture's mean stands in until a hit point's lookup replaces it
/// (`RenderScene::bsdf_at`).
impl From<&material::TexturedDiffuse> for Diffuse {
    fn from(m: &material::TexturedDiffuse) -> Self {
        Diffuse {
            reflectance: m.texture.average(),
        }
    }
}

impl From<&material::DiffuseTransmission> for DiffuseTransmission {
    fn from(m: &material::DiffuseTransmission) -> Self {
        DiffuseTransmission {
            reflectance: m.reflectance,
            transmittance: m.transmittance,
        }
    }
}
