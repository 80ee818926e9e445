//! pbrt-v4's layered materials: a GGX dielectric interface over a Lambertian base or over a
//! GGX conductor, with the slab between them that pbrt-v4's random walk simulates.

use super::checks::{albedo, index_of_refraction, non_negative, roughness_ok};
use crate::texture::ImageTexture;
use fenestra_core::Rgb;
use std::sync::Arc;

/// The slab between a coat and its base, and how pbrt-v4's random walk through it is run
/// (its coated materials' "thickness", "albedo", "g", "maxdepth" and "nsamples").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Layers {
    /// Optical thickness of the slab (its extinction coefficient is 1).
    pub thickness: f32,
    /// Single-scattering albedo of the slab's medium (zero: it only absorbs).
    pub albedo: Rgb,
    /// Henyey-Greenstein asymmetry of the medium's scattering.
    pub g: f32,
    /// Scattering events a walk may take inside the slab.
    pub max_depth: u32,
    /// Walks averaged per evaluation.
    pub samples: u32,
}

impl Default for Layers {
    /// pbrt-v4's defaults.
    fn default() -> Self {
        Layers {
            thickness: 0.01,
            albedo: Rgb::ZERO,
            g: 0.0,
            max_depth: 10,
            samples: 1,
        }
    }
}

impl Layers {
    /// Why the parameters make no physical sense, if they do not.
    pub fn validate(&self) -> Option<String> {
        if !(self.thickness.is_finite() && self.thickness >= 0.0) {
            return Some(format!(
                "thickness {} must be finite and non-negative",
                self.thickness
            ));
        }
        if !(self.g > -1.0 && self.g < 1.0) {
            return Some(format!("g {} must lie in (-1, 1)", self.g));
        }
        if self.samples == 0 {
            return Some("nsamples must be at least 1".into());
        }
        albedo("albedo", &self.albedo)
    }
}

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
    /// The slab between them.
    pub layers: Layers,
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
            .or_else(|| self.layers.validate())
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
    /// The slab between them.
    pub layers: Layers,
}

impl CoatedConductor {
    /// Why the parameters make no physical sense, if they do not.
    pub fn validate(&self) -> Option<String> {
        if !non_negative(&self.eta) || !non_negative(&self.k) {
            return Some("conductor eta and k must be finite and non-negative".into());
        }
        index_of_refraction(self.interface_eta)
            .or_else(|| {
                let alphas = [self.interface_alpha, self.alpha_x, self.alpha_y];
                (!alphas.into_iter().all(roughness_ok)).then(|| "roughness must be positive".into())
            })
            .or_else(|| self.layers.validate())
    }
}
