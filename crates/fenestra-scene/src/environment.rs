//! Lighting a scene by an environment map of the user's (an HDRI), whatever environment the
//! scene had: a latitude-longitude image turned to the scene's up axis and about it, scaled.

use crate::light::{EnvironmentDesc, LightDesc};
use crate::scene::SceneDesc;
use fenestra_core::image::Image;
use fenestra_core::{Rgb, Vec3};
use glam::Mat3;
use std::sync::Arc;

/// An environment map placed in a scene.
#[derive(Clone, Debug)]
pub struct EnvironmentMap {
    /// Radiance in latitude-longitude layout (2:1): row 0 at the zenith, the horizon in the
    /// middle, columns going round the up axis.
    pub image: Arc<Image>,
    /// The scene's up direction (a unit vector).
    pub up: Vec3,
    /// Turn about the up axis, in degrees (counter-clockwise seen from above).
    pub rotation_deg: f32,
    /// Multiplies the radiance.
    pub strength: f32,
}

/// The direction through the centre of pixel (`col`, `row`) of a `width` x `height`
/// latitude-longitude map in its frame: row 0 at +z, column 0 at phi = 0 (+x), phi growing
/// towards +y.
pub fn latlong_direction(col: usize, row: usize, width: usize, height: usize) -> Vec3 {
    let theta = std::f32::consts::PI * (row as f32 + 0.5) / height as f32;
    let phi = 2.0 * std::f32::consts::PI * (col as f32 + 0.5) / width as f32;
    Vec3::new(
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        theta.cos(),
    )
}

impl EnvironmentMap {
    /// Why the map cannot light a scene, if it cannot.
    pub fn validate(&self) -> Option<String> {
        let (w, h) = (self.image.width, self.image.height);
        if w != 2 * h || h == 0 {
            return Some(format!(
                "an environment map is a 2:1 latitude-longitude image, this one is {w}x{h}"
            ));
        }
        if !(self.strength.is_finite() && self.strength > 0.0) {
            return Some(format!("strength must be positive, got {}", self.strength));
        }
        let brightest = (self.image.pixels.iter())
            .map(|p| p.max_component())
            .filter(|v| v.is_finite())
            .fold(0.0f32, f32::max);
        if !(brightest * self.strength).is_finite() {
            return Some(format!(
                "strength {} times the map's brightest texel ({brightest}) overflows 32-bit \
                 floats: its light would be infinite",
                self.strength
            ));
        }
        if !self.rotation_deg.is_finite() {
            return Some(format!(
                "rotation must be finite, got {}",
                self.rotation_deg
            ));
        }
        if !(self.up.is_finite() && (self.up.length() - 1.0).abs() < 1e-4) {
            return Some(format!("up must be a unit vector, got {}", self.up));
        }
        None
    }

    /// The map's frame in the world: its pole (z) along `up`, its phi = 0 column (x) along
    /// a horizontal axis turned by the rotation.
    pub fn to_world(&self) -> Mat3 {
        let z = self.up;
        // The world axis least aligned with up, made horizontal.
        let a = z.abs();
        let reference = if a.x <= a.y && a.x <= a.z {
            Vec3::X
        } else if a.y <= a.z {
            Vec3::Y
        } else {
            Vec3::Z
        };
        let x0 = (reference - z * z.dot(reference)).normalize();
        let turn = Mat3::from_axis_angle(z, self.rotation_deg.to_radians());
        let x = turn * x0;
        Mat3::from_cols(x, z.cross(x), z)
    }
}

impl SceneDesc {
    /// The scene lit by `map` instead of the environments it had (its other lights stay).
    pub fn with_environment(mut self, map: &EnvironmentMap) -> SceneDesc {
        self.lights
            .retain(|l| !matches!(l, LightDesc::Environment(_)));
        self.lights
            .push(LightDesc::Environment(EnvironmentDesc::Image {
                image: map.image.clone(),
                scale: Rgb::splat(map.strength),
                to_world: map.to_world(),
            }));
        self
    }

    /// The world axis (+-x, +-y, +-z) nearest the camera's up: the scene's up, as the picture
    /// shows it.
    pub fn camera_up_axis(&self) -> Vec3 {
        let (_, _, up) = self.camera.basis();
        let axes = [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z];
        axes.into_iter()
            .max_by(|a, b| a.dot(up).total_cmp(&b.dot(up)))
            .unwrap_or(Vec3::Z)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_frame_is_a_rotation_with_its_pole_up_and_turns_about_it() {
        let image = Arc::new(Image::new(8, 4));
        for up in [Vec3::Z, Vec3::Y, -Vec3::Y, Vec3::new(0.6, 0.0, 0.8)] {
            let map = |rotation_deg| EnvironmentMap {
                image: image.clone(),
                up,
                rotation_deg,
                strength: 1.0,
            };
            let m = map(0.0).to_world();
            assert!((m.determinant() - 1.0).abs() < 1e-5, "{up}: not a rotation");
            assert!((m * Vec3::Z - up).length() < 1e-6);
            assert!(((m.transpose() * m) - Mat3::IDENTITY).abs_diff_eq(Mat3::ZERO, 1e-5));
            // A quarter turn takes phi = 0 to where phi = 90 degrees was.
            let q = map(90.0).to_world();
            assert!((q * Vec3::X - m * Vec3::Y).length() < 1e-5, "{up}");
            assert!(map(0.0).validate().is_none());
        }
        let bad = EnvironmentMap {
            image: Arc::new(Image::new(8, 8)),
            up: Vec3::Z,
            rotation_deg: 0.0,
            strength: 1.0,
        };
        assert!(bad.validate().is_some_and(|e| e.contains("8x8")));
    }
}
