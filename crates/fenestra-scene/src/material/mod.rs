//! Materials as parameters, one kind to a module (its parameters and their checks); the
//! render crate's bsdf module evaluates and samples them. A new kind is a module here and a
//! line in [`kinds!`]'s list (then a BSDF in the render crate, and its pbrt-v4 reading and
//! writing).

mod alpha;
mod checks;
mod coated;
mod conductor;
mod dielectric;
mod diffuse;
mod metallic_roughness;
mod mirror;
mod mix;
mod normal_map;
mod phong;
mod relief;
mod ward;

pub use alpha::{Alpha, AlphaMode};
pub use coated::{CoatedConductor, CoatedDiffuse, Layers};
pub use conductor::RoughConductor;
pub use dielectric::{Dielectric, RoughDielectric, ThinDielectric};
pub use diffuse::{Diffuse, DiffuseTransmission, TexturedDiffuse};
pub use metallic_roughness::MetallicRoughness;
pub use mirror::Mirror;
pub use mix::Mix;
pub use normal_map::NormalMap;
pub use phong::Phong;
pub use relief::{BumpMap, Relief};
pub use ward::Ward;

use crate::texture::ImageTexture;

/// The GGX roughness at or below which pbrt-v4 takes a microfacet distribution as perfectly
/// smooth (its `EffectivelySmooth`): readers clamp smaller roughnesses to it, and BSDFs that
/// treat smooth interfaces apart (the layered coats) test against it.
pub const SMOOTH_ALPHA: f32 = 1e-3;
use fenestra_core::sampler::hash_combine;
use fenestra_core::{Rgb, Vec3};
use std::sync::Arc;

/// Declares [`Material`], one variant per kind (each a type of the same name), and what
/// dispatches to every kind.
macro_rules! kinds {
    ($($kind:ident,)*) => {
        /// A surface's scattering: a kind of material with its parameters.
        #[derive(Clone, Debug)]
        pub enum Material {
            $(
                #[allow(missing_docs)]
                $kind($kind),
            )*
        }

        impl Material {
            /// A parameter that makes no physical sense, as a message; `None` when valid.
            pub fn validate(&self) -> Option<String> {
                match self {
                    $(Material::$kind(m) => m.validate(),)*
                }
            }
        }
    };
}

kinds! {
    Diffuse,
    TexturedDiffuse,
    Mirror,
    Dielectric,
    ThinDielectric,
    Phong,
    Ward,
    RoughConductor,
    RoughDielectric,
    CoatedConductor,
    DiffuseTransmission,
    Mix,
    CoatedDiffuse,
    MetallicRoughness,
}

impl Material {
    /// A grey Lambertian material of albedo `r`.
    pub fn diffuse(r: f32) -> Self {
        Material::Diffuse(Diffuse {
            reflectance: Rgb::splat(r),
        })
    }

    /// The image texture of the material's reflectance (its base colour), if any.
    pub fn texture(&self) -> Option<&Arc<ImageTexture>> {
        match self {
            Material::TexturedDiffuse(m) => Some(&m.texture),
            Material::CoatedDiffuse(m) => m.texture.as_ref(),
            Material::MetallicRoughness(m) => m.base_color_texture.as_ref(),
            _ => None,
        }
    }

    /// Which material a [`Material::Mix`] is at the point `p` (any other material is itself):
    /// the second with probability `amount`, by a hash of `p`'s coordinates, followed through
    /// mixes of mixes. `materials[index]` must have passed [`Scene`](crate::Scene)'s checks.
    pub fn resolve(materials: &[Material], mut index: usize, p: Vec3) -> usize {
        let h = p
            .to_array()
            .iter()
            .fold(0x6d69_7865, |h, c| hash_combine(h, c.to_bits()));
        while let Material::Mix(Mix {
            materials: pair,
            amount,
        }) = materials[index]
        {
            // 24 bits of the hash as a uniform number in [0, 1); a fresh hash per level.
            let u = (hash_combine(h, index as u32) >> 8) as f32 / (1u32 << 24) as f32;
            index = pair[usize::from(u < amount)];
        }
        index
    }
}
