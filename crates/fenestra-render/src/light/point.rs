//! Isotropic point light.

use super::LightSample;
use fenestra_core::{Rgb, Vec3, PI};

/// An isotropic point light.
#[derive(Clone, Debug)]
pub struct PointLight {
    position: Vec3,
    intensity: Rgb,
}

impl PointLight {
    /// A light at `position` of `intensity` (W/sr).
    pub fn new(position: Vec3, intensity: Rgb) -> Self {
        PointLight {
            position,
            intensity,
        }
    }

    /// Where it is.
    pub fn position(&self) -> Vec3 {
        self.position
    }

    /// Radiant intensity.
    pub fn intensity(&self) -> Rgb {
        self.intensity
    }

    /// The direction from `p` to the light and the radiance-like I/d^2.
    pub fn sample_li(&self, p: Vec3) -> Option<LightSample> {
        let (wi, d2) = super::toward(self.position, p)?;
        Some(LightSample {
            wi,
            li: self.intensity / d2,
            pdf: 1.0,
            point: Some(self.position),
            delta: true,
        })
    }

    /// Emitted power, 4 pi I (luminance of watts).
    pub fn power(&self) -> f32 {
        4.0 * PI * self.intensity.luminance()
    }
}
