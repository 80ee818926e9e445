//! glTF 2.0's metallic-roughness material (the core specification's Appendix B), with the
//! dielectric's index of refraction and specular weight of `KHR_materials_ior` and
//! `KHR_materials_specular`.

use super::checks::{albedo, index_of_refraction, non_negative};
use super::{Alpha, NormalMap};
use crate::texture::ImageTexture;
use fenestra_core::{Rgb, Vec2};
use std::sync::Arc;

/// A mix of a metal and a dielectric over a Lambertian base, both GGX of alpha =
/// roughness^2; each parameter a factor times an optional texture, as glTF defines them.
#[derive(Clone, Debug)]
pub struct MetallicRoughness {
    /// The base colour factor: the diffuse albedo of the dielectric, the metal's F0.
    pub base_color: Rgb,
    /// Multiplies `base_color` at each point (texels decoded from sRGB).
    pub base_color_texture: Option<Arc<ImageTexture>>,
    /// The metal's share, in [0, 1].
    pub metallic: f32,
    /// Perceptual roughness in [0, 1]: GGX alpha = roughness^2.
    pub roughness: f32,
    /// Linear texels: green multiplies `roughness`, blue `metallic`.
    pub metallic_roughness_texture: Option<Arc<ImageTexture>>,
    /// The dielectric's index of refraction (1.5 unless `KHR_materials_ior` says otherwise).
    pub ior: f32,
    /// `KHR_materials_specular`'s weight of the dielectric's specular layer.
    pub specular: f32,
    /// `KHR_materials_specular`'s tint of the dielectric's F0 (F0 is clamped to 1).
    pub specular_color: Rgb,
    /// A tangent-space normal map, if any.
    pub normal_map: Option<NormalMap>,
    /// Where the surface is a cut-out, if anywhere.
    pub alpha: Option<Alpha>,
}

impl MetallicRoughness {
    /// glTF's defaults: white, fully metallic and fully rough (as the specification has them),
    /// ior 1.5, full specular weight, no textures.
    pub fn new() -> Self {
        MetallicRoughness {
            base_color: Rgb::ONE,
            base_color_texture: None,
            metallic: 1.0,
            roughness: 1.0,
            metallic_roughness_texture: None,
            ior: 1.5,
            specular: 1.0,
            specular_color: Rgb::ONE,
            normal_map: None,
            alpha: None,
        }
    }

    /// Why the parameters make no physical sense, if they do not.
    pub fn validate(&self) -> Option<String> {
        let unit = |what: &str, v: f32| {
            (!(0.0..=1.0).contains(&v)).then(|| format!("{what} {v} must lie in [0, 1]"))
        };
        albedo("base colour", &self.base_color)
            .or_else(|| unit("metallic", self.metallic))
            .or_else(|| unit("roughness", self.roughness))
            .or_else(|| unit("specular", self.specular))
            .or_else(|| {
                let c = self.specular_color;
                (!non_negative(&c)).then(|| format!("specular colour {c:?} must be non-negative"))
            })
            .or_else(|| index_of_refraction(self.ior))
            .or_else(|| self.alpha.as_ref().and_then(Alpha::validate))
            .or_else(|| {
                let scale = self.normal_map.as_ref().map_or(1.0, |n| n.scale);
                (!scale.is_finite()).then(|| format!("normal map scale {scale} is not finite"))
            })
    }

    /// Base colour, metallic and roughness at texture coordinates `uv`: the factors times
    /// the texels (clamped to [0, 1]).
    pub fn at(&self, uv: Vec2) -> (Rgb, f32, f32) {
        let texel = |t: &Option<Arc<ImageTexture>>| {
            t.as_ref()
                .map_or(Rgb::ONE, |t| t.lookup(uv).map(|c| c.clamp(0.0, 1.0)))
        };
        let mr = texel(&self.metallic_roughness_texture);
        (
            self.base_color * texel(&self.base_color_texture),
            self.metallic * mr.b,
            self.roughness * mr.g,
        )
    }

    /// Whether any parameter varies over the surface (a normal map aside).
    pub fn is_textured(&self) -> bool {
        self.base_color_texture.is_some() || self.metallic_roughness_texture.is_some()
    }

    /// The textures it looks up, for the memory report and export.
    pub fn textures(&self) -> impl Iterator<Item = &Arc<ImageTexture>> {
        [
            self.base_color_texture.as_ref(),
            self.metallic_roughness_texture.as_ref(),
            self.normal_map.as_ref().map(|n| &n.texture),
        ]
        .into_iter()
        .flatten()
    }
}

impl Default for MetallicRoughness {
    fn default() -> Self {
        Self::new()
    }
}
