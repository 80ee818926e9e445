//! Lambertian materials: reflecting (of an albedo, or of an image texture) and reflecting
//! on one side while transmitting to the other.

use super::checks::albedo;
use crate::texture::ImageTexture;
use fenestra_core::Rgb;
use std::sync::Arc;

/// Lambertian reflector.
#[derive(Clone, Debug)]
pub struct Diffuse {
    /// Albedo.
    pub reflectance: Rgb,
}

impl Diffuse {
    /// Why the parameters make no physical sense, if they do not.
    pub fn validate(&self) -> Option<String> {
        albedo("reflectance", &self.reflectance)
    }
}

/// Lambertian reflector whose reflectance comes from an image texture.
#[derive(Clone, Debug)]
pub struct TexturedDiffuse {
    /// The albedo texture, looked up at the surface's uv.
    pub texture: Arc<ImageTexture>,
}

impl TexturedDiffuse {
    /// Nothing to refuse: texels are clamped to [0, 1] where they are looked up.
    pub fn validate(&self) -> Option<String> {
        None
    }
}

/// pbrt-v4's diffusetransmission: Lambertian reflection on the side light comes from and
/// Lambertian transmission to the other (leaves, lampshades, paper).
#[derive(Clone, Debug)]
pub struct DiffuseTransmission {
    /// Albedo of the reflection.
    pub reflectance: Rgb,
    /// Albedo of the transmission.
    pub transmittance: Rgb,
}

impl DiffuseTransmission {
    /// Why the parameters make no physical sense, if they do not.
    pub fn validate(&self) -> Option<String> {
        albedo("reflectance", &self.reflectance)
            .or_else(|| albedo("transmittance", &self.transmittance))
    }
}
