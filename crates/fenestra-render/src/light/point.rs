//! Isotropic point light.

use super::LightSample;
use fenestra_core::{Rgb, Vec3, PI};

#[derive(Clone, Debug)]
pub struct PointLight {
    position: Vec3,
    intensity: Rgb,
}

impl PointLight {
    pub fn new(position: Vec3, intensity: Rgb) -> Self {
        PointLight {
            position,
            intensity,
        }
    }

    pub fn position(&self) -> Vec3 {
        self.position
    }

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

    pub fn power(&self) -> f32 {
        4.0 * PI * self.intensity.luminance()
    }
}
