//! The GGX microfacet conductor.

use super::checks::{non_negative, roughness_ok};
use crate::texture::RoughnessTexture;
use fenestra_core::Rgb;
use std::sync::Arc;

/// GGX microfacet conductor with complex index eta + i k per channel.
#[derive(Clone, Debug)]
pub struct RoughConductor {
    /// Real part of the index of refraction.
    pub eta: Rgb,
    /// Absorption coefficient (imaginary part).
    pub k: Rgb,
    /// GGX roughness along the tangent.
    pub alpha_x: f32,
    /// GGX roughness along the bitangent.
    pub alpha_y: f32,
    /// Roughness varying over the surface, overriding `alpha_x`/`alpha_y` where given
    /// (those then hold its mean).
    pub roughness: Option<Arc<RoughnessTexture>>,
}

impl RoughConductor {
    /// Why the parameters make no physical sense, if they do not.
    pub fn validate(&self) -> Option<String> {
        if !non_negative(&self.eta) || !non_negative(&self.k) {
            return Some("conductor eta and k must be finite and non-negative".into());
        }
        (!roughness_ok(self.alpha_x) || !roughness_ok(self.alpha_y))
            .then(|| "conductor roughness must be positive".into())
    }
}
