//! The lights a relit sequence is lit by (`lights.json`): the scene's point, spot and
//! distant lights replaced by these (area emitters and environments stay, their transfer is
//! part of the scene). `fenestra relight precompute` writes the scene's own lights in this
//! form beside the precomputation, as a starting point:
//!
//! ```json
//! { "lights": [
//!   { "type": "point", "position": [1.8, 1.4, 2.6], "intensity": [9, 8, 6.5] },
//!   { "type": "spot", "position": [3, 0.6, 2.7], "direction": [0, 1, -0.55],
//!     "intensity": [30, 30, 30], "cone_angle": 28, "falloff_start": 20 },
//!   { "type": "distant", "direction": [0, 0, -1], "irradiance": [2, 2, 2] }
//! ] }
//! ```
//!
//! Intensities are W/sr, irradiance W/m^2, angles degrees, directions need not be unit.

use crate::error::RelightError;
use fenestra_core::{Rgb, Vec3};
use fenestra_scene::light::LightDesc;
use serde::{Deserialize, Serialize};

/// A light of the file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub enum LightSpec {
    Point {
        position: [f32; 3],
        intensity: [f32; 3],
    },
    Spot {
        position: [f32; 3],
        direction: [f32; 3],
        intensity: [f32; 3],
        cone_angle: f32,
        falloff_start: f32,
    },
    Distant {
        direction: [f32; 3],
        irradiance: [f32; 3],
    },
}

/// The file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LightsFile {
    pub lights: Vec<LightSpec>,
}

impl LightsFile {
    /// Parses `text` (`name` for messages: `name:LINE:COLUMN: what`, or the light at fault).
    pub fn parse(text: &str, name: &str) -> Result<Self, RelightError> {
        let file: LightsFile = serde_json::from_str(text).map_err(|e| {
            RelightError::Lights(format!("{name}:{}:{}: {e}", e.line(), e.column()))
        })?;
        for (i, l) in file.lights.iter().enumerate() {
            let bad = |what: &str| RelightError::Lights(format!("{name}: lights[{i}]: {what}"));
            let finite = |v: &[f32]| v.iter().all(|x| x.is_finite());
            // A direction to normalise: finite and not zero.
            let usable = |d: &[f32; 3]| finite(d) && Vec3::from(*d).length() > 0.0;
            if let LightSpec::Point {
                position,
                intensity,
            }
            | LightSpec::Spot {
                position,
                intensity,
                ..
            } = l
            {
                if !finite(position) || !finite(intensity) {
                    return Err(bad("values must be finite"));
                }
            }
            match l {
                LightSpec::Spot {
                    direction,
                    cone_angle,
                    falloff_start,
                    ..
                } => {
                    if !usable(direction) {
                        return Err(bad("direction must not be zero"));
                    }
                    let angles = (0.0..=180.0).contains(cone_angle) && *cone_angle > 0.0;
                    if !angles || !(0.0..=*cone_angle).contains(falloff_start) {
                        return Err(bad(
                            "angles must satisfy 0 <= falloff_start <= cone_angle <= 180",
                        ));
                    }
                }
                LightSpec::Distant {
                    direction,
                    irradiance,
                } => {
                    if !finite(irradiance) || !usable(direction) {
                        return Err(bad("direction must not be zero, irradiance finite"));
                    }
                }
                LightSpec::Point { .. } => {}
            }
            if [l.colour()]
                .iter()
                .any(|c| c.r < 0.0 || c.g < 0.0 || c.b < 0.0)
            {
                return Err(bad("intensities must not be negative"));
            }
        }
        Ok(file)
    }

    /// The scene's point, spot and distant lights.
    pub fn of(lights: &[LightDesc]) -> Self {
        let a = |v: Vec3| v.to_array();
        let c = |c: Rgb| [c.r, c.g, c.b];
        LightsFile {
            lights: (lights.iter())
                .filter_map(|l| match l {
                    LightDesc::Point {
                        position,
                        intensity,
                    } => Some(LightSpec::Point {
                        position: a(*position),
                        intensity: c(*intensity),
                    }),
                    LightDesc::Spot {
                        position,
                        direction,
                        intensity,
                        cone_angle,
                        falloff_start,
                    } => Some(LightSpec::Spot {
                        position: a(*position),
                        direction: a(*direction),
                        intensity: c(*intensity),
                        cone_angle: *cone_angle,
                        falloff_start: *falloff_start,
                    }),
                    LightDesc::Distant {
                        direction,
                        irradiance,
                    } => Some(LightSpec::Distant {
                        direction: a(*direction),
                        irradiance: c(*irradiance),
                    }),
                    LightDesc::Environment(_) => None,
                })
                .collect(),
        }
    }

    /// `lights` with their point, spot and distant lights replaced by the file's.
    pub fn apply(&self, lights: &[LightDesc]) -> Vec<LightDesc> {
        let rgb = |v: [f32; 3]| Rgb::new(v[0], v[1], v[2]);
        let kept = lights
            .iter()
            .filter(|l| matches!(l, LightDesc::Environment(_)))
            .cloned();
        kept.chain(self.lights.iter().map(|l| match l {
            LightSpec::Point {
                position,
                intensity,
            } => LightDesc::Point {
                position: Vec3::from(*position),
                intensity: rgb(*intensity),
            },
            LightSpec::Spot {
                position,
                direction,
                intensity,
                cone_angle,
                falloff_start,
            } => LightDesc::Spot {
                position: Vec3::from(*position),
                direction: Vec3::from(*direction).normalize(),
                intensity: rgb(*intensity),
                cone_angle: *cone_angle,
                falloff_start: *falloff_start,
            },
            LightSpec::Distant {
                direction,
                irradiance,
            } => LightDesc::Distant {
                direction: Vec3::from(*direction).normalize(),
                irradiance: rgb(*irradiance),
            },
        }))
        .collect()
    }
}

impl LightSpec {
    fn colour(&self) -> Rgb {
        let (LightSpec::Point { intensity: c, .. }
        | LightSpec::Spot { intensity: c, .. }
        | LightSpec::Distant { irradiance: c, .. }) = self;
        Rgb::new(c[0], c[1], c[2])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_scenes_lights_round_trip_and_bad_files_say_where() {
        let scene = fenestra_builtin::load("relight-room").expect("scene");
        let file = LightsFile::of(&scene.lights);
        assert_eq!(file.lights.len(), 3);
        let text = serde_json::to_string_pretty(&file).expect("json");
        let back = LightsFile::parse(&text, "l.json").expect("parses");
        assert_eq!(back, file);
        assert_eq!(back.apply(&scene.lights).len(), 3);
        let err = LightsFile::parse(
            r#"{ "lights": [ { "type": "point", "position": [0, 0] } ] }"#,
            "l.json",
        )
        .expect_err("short position")
        .to_string();
        assert!(err.starts_with("l.json:1:"), "{err}");
        let err = LightsFile::parse(
            r#"{ "lights": [ { "type": "spot", "position": [0,0,0], "direction": [0,0,0],
                 "intensity": [1,1,1], "cone_angle": 30, "falloff_start": 10 } ] }"#,
            "l.json",
        )
        .expect_err("zero direction");
        assert_eq!(
            err.to_string(),
            "l.json: lights[0]: direction must not be zero"
        );
        let err = LightsFile::parse(
            r#"{ "lights": [ { "type": "point", "position": [0,0,0], "intensity": [-1,1,1] } ] }"#,
            "l.json",
        )
        .expect_err("negative");
        assert_eq!(
            err.to_string(),
            "l.json: lights[0]: intensities must not be negative"
        );
    }
}
