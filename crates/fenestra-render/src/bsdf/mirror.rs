//! Perfect specular reflection.

use super::{reflect_z, BsdfSample};
use fenestra_core::{Rgb, Vec3};
use fenestra_scene::material;

/// A perfect mirror.
#[derive(Clone, Debug)]
pub struct Mirror {
    /// Albedo.
    pub reflectance: Rgb,
}

impl Mirror {
    /// Samples an incident direction for `wo`.
    pub fn sample(&self, wo: Vec3) -> Option<BsdfSample> {
        Some(BsdfSample {
            wi: reflect_z(wo),
            weight: self.reflectance,
            pdf: 1.0,
            delta: true,
        })
    }
}

impl From<&material::Mirror> for Mirror {
    fn from(m: &material::Mirror) -> Self {
        Mirror {
            reflectance: m.reflectance,
        }
    }
}
