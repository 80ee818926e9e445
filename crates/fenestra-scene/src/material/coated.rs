//! pbrt-v4's layered materials: a GGX dielectric interface over a Lambertian base or over a
//! GGX conductor.

use super::checks::{albedo, index_of_refraction, non_negative, roughness_ok};
use crate::texture::ImageTexture;
use fenestra_core::Rgb;
use std::sync::Arc;

/// pbrt-v4's coateddiffuse: a Lambertian base under a GGX dielectric interface.
#[derive(Clone, Debug)]
pub struct CoatedDiffuse {
    /// The base's albedo (the texture's mean when it has one).
    pub reflectance: Rgb,
    /// The base's albedo varying over the surface, looked up at each hit.
    pub texture: Option<Arc<ImageTexture>>,
    /// The interface's index of refraction.
    pub eta: f32,
    /// The interface's GGX roughness.
    pub alpha: f32,
}

impl CoatedDiffuse {
    /// Why the parameters make no physical sense, if they do not.
    pub fn validate(&self) -> Option<String> {
        albedo("reflectance", &self.reflectance)
            .or_else(|| index_of_refraction(self.eta))
            .or_else(|| {
                (!roughness_ok(self.alpha))
                    .then(|| format!("roughness {} must be positive", self.alpha))
            })
    }
}

/// pbrt-v4's coatedconductor: a GGX conductor under a GGX dielectric interface.
#[derive(Clone, Debug)]
pub struct CoatedConductor {
    /// The interface's index of refraction.
    pub interface_eta: f32,
    /// The interface's GGX roughness.
    pub interface_alpha: f32,
    /// The conductor's index of refraction.
    pub eta: Rgb,
    /// The conductor's absorption coefficient.
    pub k: Rgb,
    /// The conductor's GGX roughness along the tangent.
    pub alpha_x: f32,
    /// The conductor's GGX roughness along the bitangent.
    pub alpha_y: f32,
}

impl CoatedConductor {
    /// Why the parameters make no physical sense, if they do not.
    pub fn validate(&self) -> Option<String> {
        if !non_negative(&self.eta) || !non_negative(&self.k) {
            return Some("conductor eta and k must be finite and non-negative".into());
        }
        index_of_refraction(self.interface_eta).or_else(|| {
            let alphas = [self.interface_alpha, self.alpha_x, self.alpha_y];
            (!alphas.into_iter().all(roughness_ok)).then(|| "roughness must be positive".into())
        })
    }
}
