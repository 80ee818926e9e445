//! Cut-outs: surfaces that rays pass through where their alpha says (glTF's `alphaMode`
//! MASK, and BLEND as stochastic transparency). Every ray query of a scene with cut-outs
//! honours them, camera, bounce and shadow rays alike, on either backend.

use crate::texture::ImageTexture;
use fenestra_core::sampler::hash_combine;
use fenestra_core::{Vec2, Vec3};
use std::sync::Arc;

/// Where a surface is there: alpha = factor times the texture's first channel.
#[derive(Clone, Debug)]
pub struct Alpha {
    /// Multiplies the texture.
    pub factor: f32,
    /// Per-point alpha in its first channel, if any.
    pub texture: Option<Arc<ImageTexture>>,
    /// How alpha decides.
    pub mode: AlphaMode,
}

/// How alpha makes a surface present or absent.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AlphaMode {
    /// Present where alpha >= the cutoff (foliage, grilles).
    Mask {
        /// The threshold.
        cutoff: f32,
    },
    /// Present with probability alpha, decided by a hash of the point so that every ray
    /// meeting the same point sees the same (and estimators stay consistent).
    Blend,
}

impl Alpha {
    /// Whether the surface is present at texture coordinates `uv`, point `p`.
    pub fn present(&self, uv: Vec2, p: Vec3) -> bool {
        let a = self.factor * self.texture.as_ref().map_or(1.0, |t| t.lookup(uv).r);
        match self.mode {
            AlphaMode::Mask { cutoff } => a >= cutoff,
            AlphaMode::Blend => {
                let h = p
                    .to_array()
                    .iter()
                    .fold(0x616c_7068, |h, c| hash_combine(h, c.to_bits()));
                ((h >> 8) as f32 / (1u32 << 24) as f32) < a
            }
        }
    }

    /// Why the parameters make no sense, if they do not.
    pub fn validate(&self) -> Option<String> {
        match self.mode {
            _ if !(0.0..=1.0).contains(&self.factor) => {
                Some(format!("alpha {} must lie in [0, 1]", self.factor))
            }
            AlphaMode::Mask { cutoff } if !cutoff.is_finite() => {
                Some(format!("alpha cutoff {cutoff} is not finite"))
            }
            _ => None,
        }
    }
}
