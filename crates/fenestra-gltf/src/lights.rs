//! KHR_lights_punctual in fenestra's radiometric units. glTF gives point and spot lights in
//! candela and directional lights in lux; fenestra's intensities are W/sr and irradiances
//! W/m^2, per RGB channel. One factor converts them: 683 lm/W, the luminous efficacy at
//! 555 nm that defines the candela, which Blender's glTF exporter uses too (checked with
//! Blender 5.0.1: a 100 W point light is written as 100 / (4 pi) x 683 cd), so a Blender
//! scene comes back with its watts.

use crate::report::Report;
use fenestra_core::{Rgb, Vec3};
use fenestra_scene::LightDesc;
use glam::Mat4;
use gltf::khr_lights_punctual::Kind;

/// Lumens per watt: photometric glTF values divided by this are radiometric.
pub const LUMENS_PER_WATT: f32 = 683.0;

/// The light `light` placed by a node's world matrix.
pub fn light(
    light: &gltf::khr_lights_punctual::Light,
    world: &Mat4,
    report: &mut Report,
) -> LightDesc {
    let at = format!("/extensions/KHR_lights_punctual/lights/{}", light.index());
    if light.range().is_some() {
        report.say(
            &at,
            "a light's range is not applied (light falls off with the square of distance)",
        );
    }
    let power = Rgb::from(light.color()) * (light.intensity() / LUMENS_PER_WATT);
    let position = world.transform_point3(Vec3::ZERO);
    let direction = world.transform_vector3(-Vec3::Z).normalize_or_zero();
    match light.kind() {
        Kind::Point => LightDesc::Point {
            position,
            intensity: power,
        },
        Kind::Directional => LightDesc::Distant {
            direction,
            irradiance: power,
        },
        Kind::Spot {
            inner_cone_angle,
            outer_cone_angle,
        } => {
            report.say(&at, "spot lights fall off between their cones as pbrt-v4's smoothstep, not glTF's squared linear ramp");
            LightDesc::Spot {
                position,
                direction,
                intensity: power,
                cone_angle: outer_cone_angle.to_degrees(),
                falloff_start: inner_cone_angle.min(outer_cone_angle).to_degrees(),
            }
        }
    }
}
