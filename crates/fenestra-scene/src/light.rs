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
    /// One-sided emission of radiance `l`.
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

/// Light arriving from infinitely far away in every direction.
#[derive(Clone, Debug)]
pub enum EnvironmentDesc {
    /// The same radiance from every direction.
    Constant(Rgb),
    /// A latitude-longitude image: column 0 at phi = 0 (the +x axis), row 0 at the +z pole
    /// after `to_world`, which maps the map's frame (z up) to the world.
    Image {
        /// Radiance per pixel.
        image: Arc<Image>,
        /// Multiplies the image.
        scale: Rgb,
        /// The map's frame in the world.
        to_world: glam::Mat3,
    },
    /// The sun: a disk of uniform radiance seen from everywhere in the same direction.
    Sun {
        /// Unit vector towards the sun's centre.
        direction: Vec3,
        /// Radiance over the disk (W/(m^2 sr)).
        radiance: Rgb,
        /// Angular radius of the disk (radians, in (0, pi/2)).
        half_angle: f32,
    },
}

impl LightDesc {
    /// What makes the light unusable, if anything: positions beyond what f32 resolves,
    /// non-finite or negative power, zero directions, impossible cone angles.
    pub fn problem(&self) -> Option<String> {
        if let Some(what) = crate::extent::extent_error(self.extent()) {
            return Some(what);
        }
        let finite_rgb = |c: &Rgb| c.is_finite() && c.r >= 0.0 && c.g >= 0.0 && c.b >= 0.0;
        let problem = match self {
            LightDesc::Point {
                position,
                intensity,
            }
            | LightDesc::Spot {
                position,
                intensity,
                ..
            } if !(position.is_finite() && finite_rgb(intensity)) => {
                "position or intensity is not finite, or intensity is negative"
            }
            LightDesc::Distant { irradiance, .. } if !finite_rgb(irradiance) => {
                "irradiance is not finite or negative"
            }
            LightDesc::Spot { direction, .. } | LightDesc::Distant { direction, .. }
                if !(direction.length() >= 1e-6) =>
            {
                "light direction is zero"
            }
            LightDesc::Spot {
                cone_angle,
                falloff_start,
                ..
            } if !(*cone_angle > 0.0
                && *cone_angle <= 180.0
                && *falloff_start >= 0.0
                && *falloff_start <= *cone_angle) =>
            {
                "spot light cone angles must satisfy 0 <= falloff start <= cone angle <= 180"
            }
            LightDesc::Environment(EnvironmentDesc::Constant(l)) if !finite_rgb(l) => {
                "environment radiance is not finite or negative"
            }
            LightDesc::Environment(EnvironmentDesc::Image { image, scale, .. })
                if !finite_rgb(scale) || image.pixels.iter().any(|p| !finite_rgb(p)) =>
            {
                "environment image or scale is not finite or negative"
            }
            LightDesc::Environment(EnvironmentDesc::Sun {
                direction,
                radiance,
                half_angle,
            }) if !((direction.length() - 1.0).abs() < 1e-4
                && finite_rgb(radiance)
                && *half_angle > 0.0
                && *half_angle < 0.5 * fenestra_core::PI) =>
            {
                "the sun needs a unit direction, a finite radiance and an angular radius in (0, 90) degrees"
            }
            _ => return None,
        };
        Some(problem.to_string())
    }

    /// The largest coordinate magnitude of the light's position (0 for lights at infinity).
    pub fn extent(&self) -> f32 {
        match self {
            LightDesc::Point { position, .. } | LightDesc::Spot { position, .. } => {
                position.abs().max_element()
            }
            LightDesc::Distant { .. } | LightDesc::Environment(_) => 0.0,
        }
    }
}

/// A light that is not an emissive shape.
#[derive(Clone, Debug)]
pub enum LightDesc {
    /// Isotropic point light.
    Point {
        /// Where it is.
        position: Vec3,
        /// Intensity (W/sr).
        intensity: Rgb,
    },
    /// Spot light with pbrt's smooth falloff between the two cone angles (degrees).
    Spot {
        /// Where it is.
        position: Vec3,
        /// The cone's axis.
        direction: Vec3,
        /// Intensity on the axis (W/sr).
        intensity: Rgb,
        /// Half-angle of the cone, beyond which nothing is emitted.
        cone_angle: f32,
        /// Half-angle where the falloff starts.
        falloff_start: f32,
    },
    /// Directional light.
    Distant {
        /// The direction light travels (unit).
        direction: Vec3,
        /// Irradiance (W/m^2) on a surface facing it.
        irradiance: Rgb,
    },
    /// Light from infinitely far away.
    Environment(EnvironmentDesc),
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spot(cone_angle: f32, falloff_start: f32) -> LightDesc {
        LightDesc::Spot {
            position: Vec3::ZERO,
            direction: -Vec3::Z,
            intensity: Rgb::new(1.0, 1.0, 1.0),
            cone_angle,
            falloff_start,
        }
    }

    #[test]
    fn spot_cones_are_checked_at_both_ends() {
        assert_eq!(spot(30.0, 0.0).problem(), None);
        assert_eq!(spot(30.0, 30.0).problem(), None);
        // A negative falloff start (a glTF innerConeAngle below 0) lit everything outside
        // the cone and nothing inside.
        for (cone, start) in [
            (30.0, -5.0),
            (30.0, 31.0),
            (0.0, 0.0),
            (181.0, 10.0),
            (30.0, f32::NAN),
        ] {
            let problem = spot(cone, start).problem().expect("refused");
            assert!(problem.contains("0 <= falloff start"), "{problem}");
        }
    }
}
