//! Lambertian reflection.

use super::BsdfSample;
use fenestra_core::{warp, Rgb, Vec2, Vec3, INV_PI};

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
