//! Animated scenes (issue 14): keyframes for objects and the camera, read from JSON, and
//! their interpolation to any frame.
//!
//! ```json
//! {
//!   "frames": 100,
//!   "interpolation": "smooth",
//!   "camera": [
//!     { "frame": 0, "eye": [4, 3, 1.6], "target": [2, 1, 0.5], "fov": 60 },
//!     { "frame": 99, "eye": [3, 3.5, 1.6], "target": [2, 1, 0.5], "fov": 55 }
//!   ],
//!   "objects": {
//!     "ball": [
//!       { "frame": 0, "translate": [0, 0, 0] },
//!       { "frame": 50, "translate": [1, 0, 0], "rotate": [0, 0, 1, 90], "scale": 1.5 }
//!     ]
//!   }
//! }
//! ```
//!
//! `frames` is the sequence's length (frames 0 to frames - 1); each track is a list of keys
//! with strictly increasing `frame`s within it; `rotate` is an axis and an angle in degrees
//! (default none), `scale` uniform (default 1), `translate` default zero; before its first
//! key and after its last a track holds still. `interpolation` is `linear` (positions,
//! scales and the camera piecewise linear, rotations by slerp) or `smooth` (cubic Hermite
//! through the keys with finite-difference tangents, so motion is C1 at the keys;
//! rotations the same on sign-aligned quaternions, normalised).

use glam::{Affine3A, Quat, Vec3, Vec4};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::Path;

/// An animation that does not read or does not make sense: where, and why.
#[derive(Debug, thiserror::Error)]
pub enum AnimationError {
    /// The file could not be read.
    #[error("{path}: {source}")]
    Io {
        path: String,
        source: std::io::Error,
    },
    /// Not JSON of the format, with the line and column.
    #[error("{path}:{line}:{column}: {message}")]
    Syntax {
        path: String,
        line: usize,
        column: usize,
        message: String,
    },
    /// Well-formed but wrong: the JSON path of the offending key.
    #[error("{path}: {at}: {message}")]
    Invalid {
        path: String,
        at: String,
        message: String,
    },
}

/// How keys are joined.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Interpolation {
    /// Piecewise linear (slerp for rotations).
    #[default]
    Linear,
    /// Cubic Hermite through the keys (C1).
    Smooth,
}

/// A key of an object's track.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectKey {
    /// Its frame.
    pub frame: f32,
    /// Translation.
    #[serde(default)]
    pub translate: [f32; 3],
    /// Axis (x, y, z) and angle in degrees.
    #[serde(default)]
    pub rotate: Option<[f32; 4]>,
    /// Uniform scale.
    #[serde(default = "one")]
    pub scale: f32,
}

fn one() -> f32 {
    1.0
}

/// A key of the camera's track.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraKey {
    /// Its frame.
    pub frame: f32,
    /// Where the camera is.
    pub eye: [f32; 3],
    /// What it looks at.
    pub target: [f32; 3],
    /// Vertical field of view, degrees.
    pub fov: f32,
}

/// An animation as read.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Animation {
    /// Frames in the sequence.
    pub frames: u32,
    /// How keys are joined.
    #[serde(default)]
    pub interpolation: Interpolation,
    /// The camera's keys (none: the scene's camera throughout).
    #[serde(default)]
    pub camera: Vec<CameraKey>,
    /// Each animated object's keys, by name.
    #[serde(default)]
    pub objects: BTreeMap<String, Vec<ObjectKey>>,
    /// Where it was read from (for messages).
    #[serde(skip)]
    pub source: String,
}

/// A camera at one frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraPose {
    pub eye: Vec3,
    pub target: Vec3,
    pub fov: f32,
}

impl Animation {
    /// Reads and checks the animation in `path`.
    pub fn read(path: &Path) -> Result<Self, AnimationError> {
        let name = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|source| AnimationError::Io {
            path: name.clone(),
            source,
        })?;
        Self::parse(&text, &name)
    }

    /// Parses and checks `text` (`name` for messages).
    pub fn parse(text: &str, name: &str) -> Result<Self, AnimationError> {
        let mut a: Animation = serde_json::from_str(text).map_err(|e| AnimationError::Syntax {
            path: name.to_string(),
            line: e.line(),
            column: e.column(),
            message: e.to_string(),
        })?;
        a.check().map_err(|(at, message)| AnimationError::Invalid {
            path: name.to_string(),
            at,
            message,
        })?;
        a.source = name.to_string();
        Ok(a)
    }

    /// The first thing wrong, as (JSON path, message).
    fn check(&self) -> Result<(), (String, String)> {
        if self.frames == 0 {
            return Err(("frames".into(), "must be at least 1".into()));
        }
        let last = (self.frames - 1) as f32;
        let frames = |track: &str, keys: &mut dyn Iterator<Item = f32>| {
            let mut previous = f32::NEG_INFINITY;
            for (k, f) in keys.enumerate() {
                let at = format!("{track}[{k}].frame");
                if !(0.0..=last).contains(&f) {
                    return Err((
                        at,
                        format!("{f} is outside the sequence's frames 0..={last}"),
                    ));
                }
                if f <= previous {
                    return Err((
                        at,
                        format!("{f} does not come after the previous key's {previous}"),
                    ));
                }
                previous = f;
            }
            Ok(())
        };
        frames("camera", &mut self.camera.iter().map(|k| k.frame))?;
        for (k, key) in self.camera.iter().enumerate() {
            let finite = key.eye.iter().chain(&key.target).all(|v| v.is_finite());
            if !finite {
                return Err((
                    format!("camera[{k}]"),
                    "eye and target must be finite".into(),
                ));
            }
            if Vec3::from(key.eye).distance(Vec3::from(key.target)) < 1e-6 {
                return Err((format!("camera[{k}]"), "eye and target coincide".into()));
            }
            if !(key.fov > 0.0 && key.fov < 180.0) {
                return Err((
                    format!("camera[{k}].fov"),
                    format!("{} is not in (0, 180) degrees", key.fov),
                ));
            }
            // What the camera itself refuses (an eye beyond what f32 ray tracing resolves)
            // would otherwise leave the scene's camera in place of the whole track.
            let (eye, target) = (Vec3::from(key.eye), Vec3::from(key.target));
            if let Err(e) = fenestra_scene::Camera::look_at(eye, target, Vec3::Z, key.fov) {
                return Err((format!("camera[{k}]"), e.to_string()));
            }
        }
        for (name, keys) in &self.objects {
            let track = format!("objects.{name}");
            if keys.is_empty() {
                return Err((track, "has no keys".into()));
            }
            frames(&track, &mut keys.iter().map(|k| k.frame))?;
            for (k, key) in keys.iter().enumerate() {
                if !key.translate.iter().all(|v| v.is_finite()) {
                    return Err((format!("{track}[{k}].translate"), "must be finite".into()));
                }
                if let Some(r) = key.rotate {
                    if !r.iter().all(|v| v.is_finite())
                        || Vec3::new(r[0], r[1], r[2]).length() < 1e-6
                    {
                        return Err((
                            format!("{track}[{k}].rotate"),
                            "needs a finite non-zero axis and angle".into(),
                        ));
                    }
                }
                if !(key.scale > 0.0 && key.scale.is_finite()) {
                    return Err((
                        format!("{track}[{k}].scale"),
                        format!("{} must be positive", key.scale),
                    ));
                }
            }
        }
        Ok(())
    }

    /// Object `name`'s transform at `frame` (any real frame), if it is animated.
    pub fn object(&self, name: &str, frame: f32) -> Option<Affine3A> {
        let keys = self.objects.get(name)?;
        let (t, r, s) = sample(keys, frame, self.interpolation, true, |k| {
            let rotate = k.rotate.map_or(Quat::IDENTITY, |r| {
                Quat::from_axis_angle(Vec3::new(r[0], r[1], r[2]).normalize(), r[3].to_radians())
            });
            (Vec3::from(k.translate), rotate, k.scale)
        });
        Some(Affine3A::from_scale_rotation_translation(
            Vec3::splat(s),
            r,
            t,
        ))
    }

    /// The camera at `frame`, if the animation moves it.
    pub fn camera(&self, frame: f32) -> Option<CameraPose> {
        if self.camera.is_empty() {
            return None;
        }
        let (eye, target_fov, _) = sample(&self.camera, frame, self.interpolation, false, |k| {
            let t = Vec3::from(k.target);
            (
                Vec3::from(k.eye),
                Quat::from_xyzw(t.x, t.y, t.z, k.fov),
                0.0,
            )
        });
        Some(CameraPose {
            eye,
            target: Vec3::new(target_fov.x, target_fov.y, target_fov.z),
            fov: target_fov.w,
        })
    }
}

/// Keys that carry a frame.
trait Keyed {
    fn frame(&self) -> f32;
}

impl Keyed for ObjectKey {
    fn frame(&self) -> f32 {
        self.frame
    }
}

impl Keyed for CameraKey {
    fn frame(&self) -> f32 {
        self.frame
    }
}

/// A track's (vector, quaternion, scalar) at `frame`. `unit`: the quaternion is a rotation
/// (slerp, normalised); else a plain 4-vector (the camera's target and field of view).
fn sample<K: Keyed>(
    keys: &[K],
    frame: f32,
    how: Interpolation,
    unit: bool,
    value: impl Fn(&K) -> (Vec3, Quat, f32),
) -> (Vec3, Quat, f32) {
    let last = keys.len() - 1;
    if frame <= keys[0].frame() {
        return value(&keys[0]);
    }
    if frame >= keys[last].frame() {
        return value(&keys[last]);
    }
    let i = keys.partition_point(|k| k.frame() <= frame) - 1;
    let (f0, f1) = (keys[i].frame(), keys[i + 1].frame());
    let u = (frame - f0) / (f1 - f0);
    let (a, b) = (value(&keys[i]), value(&keys[i + 1]));
    // Quaternions of a rotation track on the same side as the previous key's.
    let aligned = |q: Quat, to: Quat| if unit && q.dot(to) < 0.0 { -q } else { q };
    let b1 = aligned(b.1, a.1);
    match how {
        Interpolation::Linear => {
            let q = if unit {
                a.1.slerp(b1, u)
            } else {
                // Quat::lerp normalises; the camera's 4-vector must not be.
                Quat::from_vec4(Vec4::from(a.1).lerp(Vec4::from(b1), u))
            };
            (a.0.lerp(b.0, u), q, a.2 + (b.2 - a.2) * u)
        }
        Interpolation::Smooth => {
            // Finite-difference tangents (per frame) at both ends of the span.
            let tangent = |k: usize| {
                let (lo, hi) = (k.saturating_sub(1), (k + 1).min(last));
                let (vl, vh) = (value(&keys[lo]), value(&keys[hi]));
                let dt = keys[hi].frame() - keys[lo].frame();
                let q_hi = aligned(vh.1, value(&keys[k]).1);
                let q_lo = aligned(vl.1, value(&keys[k]).1);
                (
                    (vh.0 - vl.0) / dt,
                    (Vec4::from(q_hi) - Vec4::from(q_lo)) / dt,
                    (vh.2 - vl.2) / dt,
                )
            };
            let (m0, m1) = (tangent(i), tangent(i + 1));
            let span = f1 - f0;
            let (h00, h10, h01, h11) = hermite(u);
            let v = a.0 * h00 + m0.0 * (h10 * span) + b.0 * h01 + m1.0 * (h11 * span);
            let q = Vec4::from(a.1) * h00
                + m0.1 * (h10 * span)
                + Vec4::from(b1) * h01
                + m1.1 * (h11 * span);
            let q = Quat::from_vec4(q);
            let q = if unit { q.normalize() } else { q };
            let s = a.2 * h00 + m0.2 * (h10 * span) + b.2 * h01 + m1.2 * (h11 * span);
            (v, q, s)
        }
    }
}

/// The cubic Hermite basis at `u`.
fn hermite(u: f32) -> (f32, f32, f32, f32) {
    let (u2, u3) = (u * u, u * u * u);
    (
        2.0 * u3 - 3.0 * u2 + 1.0,
        u3 - 2.0 * u2 + u,
        -2.0 * u3 + 3.0 * u2,
        u3 - u2,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = r#"{
        "frames": 100,
        "interpolation": "INTERP",
        "camera": [
            { "frame": 0, "eye": [4, 3, 1.6], "target": [2, 1, 0.5], "fov": 60 },
            { "frame": 99, "eye": [2, 5, 1.6], "target": [2, 1, 0.5], "fov": 40 }
        ],
        "objects": {
            "ball": [
                { "frame": 10, "translate": [0, 0, 0] },
                { "frame": 20, "translate": [1, 0, 0], "rotate": [0, 0, 1, 90], "scale": 2 },
                { "frame": 40, "translate": [1, 2, 0], "rotate": [0, 0, 1, 180] }
            ]
        }
    }"#;

    fn read(how: &str) -> Animation {
        Animation::parse(&TEXT.replace("INTERP", how), "a.json").expect("valid")
    }

    #[test]
    fn keys_are_met_and_linear_spans_are_linear() {
        let a = read("linear");
        for how in ["linear", "smooth"] {
            let a = read(how);
            let at = |f: f32| a.object("ball", f).expect("ball").transform_point3(Vec3::X);
            // Key 20: scale 2, 90 degrees about z, then (1, 0, 0): x -> (1, 2, 0).
            assert!(at(20.0).distance(Vec3::new(1.0, 2.0, 0.0)) < 1e-5, "{how}");
            // Before the first key and after the last the track holds still.
            assert!(at(0.0).distance(Vec3::X) < 1e-6 && at(10.0).distance(Vec3::X) < 1e-6);
            assert!(
                at(99.0).distance(Vec3::new(0.0, 2.0, 0.0)) < 1e-5,
                "{how}: {}",
                at(99.0)
            );
            let c = a.camera(99.0).expect("camera");
            assert!(c.eye.distance(Vec3::new(2.0, 5.0, 1.6)) < 1e-6 && (c.fov - 40.0).abs() < 1e-5);
        }
        // Halfway between keys 10 and 20: translation (0.5, 0, 0), 45 degrees, scale 1.5.
        let m = a.object("ball", 15.0).expect("ball");
        let (s, r, t) = m.to_scale_rotation_translation();
        assert!(t.distance(Vec3::new(0.5, 0.0, 0.0)) < 1e-6);
        assert!((s.x - 1.5).abs() < 1e-6);
        assert!((r.angle_between(Quat::IDENTITY) - 45f32.to_radians()).abs() < 1e-4);
        let c = a.camera(49.5).expect("camera");
        assert!((c.fov - 50.0).abs() < 1e-4 && c.eye.distance(Vec3::new(3.0, 4.0, 1.6)) < 1e-5);
    }

    #[test]
    fn smooth_motion_has_no_kink_at_a_key() {
        let a = read("smooth");
        let p = |f: f32| a.object("ball", f).expect("ball").translation;
        let h = 1e-2;
        let left = (p(20.0) - p(20.0 - h)) / h;
        let right = (p(20.0 + h) - p(20.0)) / h;
        assert!(left.distance(right) < 2e-3, "velocity {left} then {right}");
        // The linear track turns a corner there.
        let b = read("linear");
        let q = |f: f32| b.object("ball", f).expect("ball").translation;
        let (l, r) = ((q(20.0) - q(20.0 - h)) / h, (q(20.0 + h) - q(20.0)) / h);
        assert!(l.distance(r) > 0.05);
    }

    #[test]
    fn bad_animations_are_refused_with_where_and_why() {
        let bad = |text: &str| {
            Animation::parse(text, "a.json")
                .expect_err("refused")
                .to_string()
        };
        let e = bad(r#"{"frames": 10, "objects": {"box": [{"frame": 5}, {"frame": 3}]}}"#);
        assert!(
            e.contains("a.json: objects.box[1].frame: 3 does not come after"),
            "{e}"
        );
        let e = bad(
            r#"{"frames": 10, "camera": [{"frame": 12, "eye": [0,0,0], "target": [1,0,0], "fov": 50}]}"#,
        );
        assert!(e.contains("camera[0].frame: 12 is outside"), "{e}");
        // An eye too far for f32 ray tracing replaced the whole track by the scene's camera.
        let far = bad(
            r#"{"frames": 10, "camera": [{"frame": 0, "eye": [2e12,0,0], "target": [1,0,0], "fov": 50}]}"#,
        );
        assert!(
            far.contains("a.json: camera[0]: ") && far.contains("2e12"),
            "{far}"
        );
        let e = bad(r#"{"frames": 10, "objects": {"box": [{"frame": 0, "scale": -1}]}}"#);
        assert!(e.contains("objects.box[0].scale"), "{e}");
        let e = bad("{\"frames\": 10,\n \"objects\": [}");
        assert!(e.starts_with("a.json:2:"), "{e}");
        let e = bad(r#"{"frames": 10, "speed": 2}"#);
        assert!(e.contains("unknown field `speed`"), "{e}");
    }
}
