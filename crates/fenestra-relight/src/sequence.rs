//! An animated scene: a scene at rest and an [`Animation`] whose tracks move its shapes and
//! camera; the scene posed at any frame. A track names the shapes it moves by their name (a
//! built-in scene names its movable objects) or as `shape:N`, the N-th shape of the scene (as
//! `fenestra scene info` counts them). An object's keys scale, rotate and translate it about
//! the centre of its bounds at rest, in that order.

use crate::animation::{Animation, AnimationError};
use fenestra_core::Vec3;
use fenestra_scene::transform::transformed;
use fenestra_scene::{Camera, SceneDesc, ShapeKind};
use glam::{Affine3A, DMat4};

/// A track and the shapes it moves.
#[derive(Clone, Debug)]
struct Track {
    name: String,
    shapes: Vec<usize>,
    /// The centre of their bounds at rest.
    pivot: Vec3,
}

/// A scene and its animation.
#[derive(Clone, Debug)]
pub struct AnimatedScene {
    /// The scene at rest.
    pub rest: SceneDesc,
    pub animation: Animation,
    tracks: Vec<Track>,
}

impl AnimatedScene {
    /// `rest` animated by `animation`; every track must name shapes of the scene.
    pub fn new(rest: SceneDesc, animation: Animation) -> Result<Self, AnimationError> {
        let mut tracks = Vec::new();
        for name in animation.objects.keys() {
            let shapes: Vec<usize> = match name.strip_prefix("shape:") {
                Some(n) => n
                    .parse::<usize>()
                    .ok()
                    .filter(|&i| i < rest.shapes.len())
                    .into_iter()
                    .collect(),
                None => (0..rest.shapes.len())
                    .filter(|&i| rest.shapes[i].name.as_deref() == Some(name))
                    .collect(),
            };
            if shapes.is_empty() {
                let named: Vec<&str> = rest
                    .shapes
                    .iter()
                    .filter_map(|s| s.name.as_deref())
                    .collect();
                return Err(AnimationError::Invalid {
                    path: animation.source.clone(),
                    at: format!("objects.{name}"),
                    message: format!(
                        "scene '{}' has no such object (named objects: {}; or shape:0 to shape:{})",
                        rest.name,
                        if named.is_empty() {
                            "none".to_string()
                        } else {
                            named.join(", ")
                        },
                        rest.shapes.len().saturating_sub(1)
                    ),
                });
            }
            let (lo, hi) = shapes.iter().fold(
                (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
                |(lo, hi), &s| {
                    let (a, b) = bounds(&rest.shapes[s].kind);
                    (lo.min(a), hi.max(b))
                },
            );
            tracks.push(Track {
                name: name.clone(),
                shapes,
                pivot: (lo + hi) * 0.5,
            });
        }
        Ok(AnimatedScene {
            rest,
            animation,
            tracks,
        })
    }

    /// Frames in the sequence.
    pub fn frames(&self) -> u32 {
        self.animation.frames
    }

    /// The scene at `frame`: moved shapes (same indices, same triangles) and the camera.
    pub fn at(&self, frame: u32) -> SceneDesc {
        let mut desc = self.rest.clone();
        let f = frame as f32;
        for track in &self.tracks {
            let Some(a) = self.animation.object(&track.name, f) else {
                continue;
            };
            let m = Affine3A::from_translation(track.pivot)
                * a
                * Affine3A::from_translation(-track.pivot);
            let m: DMat4 = glam::Mat4::from(m).as_dmat4();
            for &s in &track.shapes {
                // Keys are checked (positive scales, unit axes): the transform is regular.
                if let Ok(moved) = transformed(&self.rest.shapes[s], &m) {
                    desc.shapes[s] = moved;
                }
            }
        }
        if let Some(pose) = self.animation.camera(f) {
            if let Ok(mut camera) = Camera::look_at(pose.eye, pose.target, Vec3::Z, pose.fov) {
                camera.filter = self.rest.camera.filter.clone();
                desc.camera = camera;
            }
        }
        desc
    }
}

/// A shape's bounds.
fn bounds(kind: &ShapeKind) -> (Vec3, Vec3) {
    match kind {
        ShapeKind::Mesh(m) => m.positions.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), &p| (lo.min(p), hi.max(p)),
        ),
        ShapeKind::Sphere { center, radius } | ShapeKind::Disk { center, radius, .. } => (
            *center - Vec3::splat(*radius),
            *center + Vec3::splat(*radius),
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn room() -> AnimatedScene {
        let rest = fenestra_builtin::load("relight-room").expect("scene");
        let text = fenestra_builtin::animation("relight-room").expect("animated");
        AnimatedScene::new(
            rest,
            Animation::parse(text, "relight-room").expect("animation"),
        )
        .expect("tracks")
    }

    #[test]
    fn objects_move_about_their_centres_and_the_rest_stays() {
        let scene = room();
        let crate_index = (scene.rest.shapes.iter())
            .position(|s| s.name.as_deref() == Some("crate"))
            .expect("crate");
        let (lo0, hi0) = bounds(&scene.rest.shapes[crate_index].kind);
        let start = bounds(&scene.at(0).shapes[crate_index].kind);
        assert!(
            (start.0 - lo0).abs().max_element() < 1e-6
                && (start.1 - hi0).abs().max_element() < 1e-6
        );
        // Half a turn about its centre, then (3.2, -0.9, 0): the same box, moved.
        let end = scene.at(99);
        let (lo, hi) = bounds(&end.shapes[crate_index].kind);
        let shift = Vec3::new(3.2, -0.9, 0.0);
        assert!(
            (lo - (lo0 + shift)).abs().max_element() < 1e-4,
            "{lo} vs {}",
            lo0 + shift
        );
        assert!(
            (hi - (hi0 + shift)).abs().max_element() < 1e-4,
            "{hi} vs {}",
            hi0 + shift
        );
        for (s, shape) in end.shapes.iter().enumerate() {
            if shape.name.is_none() {
                assert_eq!(
                    bounds(&shape.kind),
                    bounds(&scene.rest.shapes[s].kind),
                    "shape {s} moved"
                );
            }
        }
        assert_ne!(end.camera.position, scene.rest.camera.position);
    }

    #[test]
    fn tracks_must_name_objects_of_the_scene() {
        let rest = fenestra_builtin::load("relight-room").expect("scene");
        let bad = r#"{ "frames": 10, "objects": { "sofa": [ { "frame": 0 } ] } }"#;
        let err = AnimatedScene::new(
            rest.clone(),
            Animation::parse(bad, "a.json").expect("parses"),
        )
        .expect_err("no sofa");
        let text = err.to_string();
        assert!(
            text.starts_with("a.json: objects.sofa: scene 'relight-room' has no such object")
                && text.contains("crate, screen"),
            "{text}"
        );
        let by_index = r#"{ "frames": 10, "objects": { "shape:1": [ { "frame": 0 } ] } }"#;
        assert!(
            AnimatedScene::new(rest, Animation::parse(by_index, "b.json").expect("parses")).is_ok()
        );
    }
}
