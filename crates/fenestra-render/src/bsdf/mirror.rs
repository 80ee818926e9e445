//! Perfect specular reflection.

use super::{reflect_z, BsdfSample};
use fenestra_core::{Rgb, Vec3};

#[derive(Clone, Debug)]
pub struct Mirror {
    pub reflectance: Rgb,
}

impl Mirror {
    pub fn sample(&self, wo: Vec3) -> Option<BsdfSample> {
        Some(BsdfSample {
            wi: reflect_z(wo),
            weight: self.reflectance,
            pdf: 1.0,
            delta: true,
        })
    }
}
