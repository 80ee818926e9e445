//! Directional light (sun-like), at infinity.

use super::LightSample;
use fenestra_core::{Rgb, Vec3, PI};
use fenestra_scene::Scene;

/// A directional light.
#[derive(Clone, Debug)]
pub struct DistantLight {
    /// Direction light travels.
    direction: Vec3,
    irradiance: Rgb,
}

impl DistantLight {
    /// Light travelling along `direction` with `irradiance` on a surface facing it.
    pub fn new(direction: Vec3, irradiance: Rgb) -> Self {
        DistantLight {
            direction: direction.normalize(),
            irradiance,
        }
    }

    /// The direction light travels.
    pub fn direction(&self) -> Vec3 {
        self.direction
    }

    /// Irradiance on a surface facing it.
    pub fn irradiance(&self) -> Rgb {
        self.irradiance
    }

    /// The light's only direction.
    pub fn sample_li(&self) -> Option<LightSample> {
        Some(LightSample {
            wi: -self.direction,
            li: self.irradiance,
            pdf: 1.0,
            point: None,
            delta: true,
        })
    }

    /// Power through the scene's bounding disk (pbrt-v4's convention).
    pub fn power(&self, scene: &Scene) -> f32 {
        let r = scene.bounding_sphere().1;
        PI * r * r * self.irradiance.luminance()
    }
}
