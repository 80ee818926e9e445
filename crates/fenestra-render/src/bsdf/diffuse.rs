//! Lambertian reflection.

use super::BsdfSample;
use fenestra_core::{warp, Rgb, Vec2, Vec3, INV_PI};

#[derive(Clone, Debug)]
pub struct Diffuse {
    pub reflectance: Rgb,
}

impl Diffuse {
    pub fn eval(&self, _wo: Vec3, _wi: Vec3) -> Rgb {
        self.reflectance * INV_PI
    }
    pub fn pdf(&self, _wo: Vec3, wi: Vec3) -> f32 {
        warp::cosine_hemisphere_pdf(wi)
    }
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
