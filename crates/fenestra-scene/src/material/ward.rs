//! Anisotropic Ward (seed 003 §2.5).

use super::checks::{non_negative, roughness_ok};
use fenestra_core::Rgb;

/// Anisotropic Ward with Walter's (2005) normalisation (seed 003 §2.5).
#[derive(Clone, Debug)]
pub struct Ward {
    /// Diffuse albedo.
    pub diffuse: Rgb,
    /// Specular albedo.
    pub specular: Rgb,
    /// Roughness along the tangent.
    pub alpha_x: f32,
    /// Roughness along the bitangent.
    pub alpha_y: f32,
}

impl Ward {
    /// Why the parameters make no physical sense, if they do not.
    pub fn validate(&self) -> Option<String> {
        if !non_negative(&self.diffuse) || !non_negative(&self.specular) {
            return Some("Ward reflectances must be finite and non-negative".into());
        }
        (!roughness_ok(self.alpha_x) || !roughness_ok(self.alpha_y))
            .then(|| "Ward roughness must be positive".into())
    }
}
