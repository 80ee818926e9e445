//! Lights as scene data; the render crate turns them into samplable lights.

use fenestra_core::image::Image;
use fenestra_core::{Rgb, Vec3};
use std::sync::Arc;

/// Emission of a diffuse area emitter.
#[derive(Clone, Copy, Debug)]
pub struct Emission {
    /// Emitted radiance (W/(m^2 sr)); uniform over the surface.
    pub radiance: Rgb,
    /// Emits on both sides (one-sided, along the normal, by default).
    pub two_sided: bool,
}

impl Emission {
    pub fn radiance(l: Rgb) -> Self {
        Emission {
            radiance: l,
            two_sided: false,
        }
    }

    /// The radiance a Lambertian emitter of `area` needs to emit `power` watts (per channel):
    /// Phi = L * pi * A per emitting side.
    pub fn from_power(power: Rgb, area: f32, two_sided: bool) -> Self {
        let sides = if two_sided { 2.0 } else { 1.0 };
        Emission {
            radiance: power / (fenestra_core::PI * area * sides),
            two_sided,
        }
    }
}

#[derive(Clone, Debug)]
pub enum EnvironmentDesc {
    Constant(Rgb),
    /// A latitude-longitude image: column 0 at phi = 0 (the +x axis), row 0 at the +z pole
    /// after `to_world`, which maps the map's frame (z up) to the world.
    Image {
        image: Arc<Image>,
        scale: Rgb,
        to_world: glam::Mat3,
    },
}

#[derive(Clone, Debug)]
pub enum LightDesc {
    /// Isotropic point light of intensity `intensity` (W/sr).
    Point {
        position: Vec3,
        intensity: Rgb,
    },
    /// Spot light with pbrt's smooth falloff between the two cone angles (degrees).
    Spot {
        position: Vec3,
        direction: Vec3,
        intensity: Rgb,
        cone_angle: f32,
        falloff_start: f32,
    },
    /// Directional light arriving along `direction` (unit, the direction light travels),
    /// with irradiance `irradiance` (W/m^2) on a surface facing it.
    Distant {
        direction: Vec3,
        irradiance: Rgb,
    },
    Environment(EnvironmentDesc),
}
