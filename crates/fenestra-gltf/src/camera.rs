//! The camera: one of the file's perspective cameras, picked by name or index (the first
//! met in the scene by default), or, in a file without cameras, one that frames the scene.

use crate::error::GltfError;
use crate::graph::Placed;
use crate::source::Source;
use fenestra_core::Vec3;
use fenestra_scene::camera::FieldOfView;
use fenestra_scene::{Camera, TriangleMesh};
use glam::Mat4;

/// A camera of the file: its name (or "camera N"), world matrix, vertical field of view in
/// radians and aspect ratio.
pub struct FileCamera {
    /// Its name.
    pub name: String,
    world: Mat4,
    yfov: f32,
    /// Width over height, if the file says.
    pub aspect: Option<f32>,
}

/// Every perspective camera placed in the scene, in the order the walk met them.
pub fn cameras(placed: &[Placed]) -> Vec<FileCamera> {
    placed
        .iter()
        .filter_map(|p| {
            let c = p.node.camera()?;
            match c.projection() {
                gltf::camera::Projection::Perspective(q) => Some(FileCamera {
                    name: c
                        .name()
                        .map_or_else(|| format!("camera {}", c.index()), str::to_string),
                    world: p.world,
                    yfov: q.yfov(),
                    aspect: q.aspect_ratio(),
                }),
                gltf::camera::Projection::Orthographic(_) => None,
            }
        })
        .collect()
}

/// The camera `choice` names (a name, or an index into `cameras`), or the first.
pub fn pick<'c>(
    src: &Source,
    cameras: &'c [FileCamera],
    choice: Option<&str>,
) -> Result<Option<&'c FileCamera>, GltfError> {
    let Some(choice) = choice else {
        return Ok(cameras.first());
    };
    let found = cameras
        .iter()
        .find(|c| c.name == choice)
        .or_else(|| choice.parse::<usize>().ok().and_then(|i| cameras.get(i)));
    match found {
        Some(c) => Ok(Some(c)),
        None => {
            let names: Vec<String> = cameras
                .iter()
                .enumerate()
                .map(|(i, c)| format!("{i}: {}", c.name))
                .collect();
            Err(GltfError::file(
                &src.path,
                format!(
                    "no camera \"{choice}\" (the file has {})",
                    if names.is_empty() {
                        "none".to_string()
                    } else {
                        names.join(", ")
                    }
                ),
            ))
        }
    }
}

impl FileCamera {
    /// As a fenestra camera: glTF cameras look down their -z with +y up.
    pub fn camera(&self, src: &Source) -> Result<Camera, GltfError> {
        let w = &self.world;
        Camera::from_basis(
            w.transform_point3(Vec3::ZERO),
            w.transform_vector3(-Vec3::Z).normalize_or_zero(),
            w.transform_vector3(Vec3::X).normalize_or_zero(),
            w.transform_vector3(Vec3::Y).normalize_or_zero(),
            FieldOfView::Vertical(self.yfov.to_degrees()),
            None,
        )
        .map_err(|e| GltfError::file(&src.path, format!("camera \"{}\": {e}", self.name)))
    }
}

/// A camera that sees all of `meshes` from the front, slightly above (+y up), with a
/// 45-degree vertical field of view.
pub fn framing(src: &Source, meshes: &[&TriangleMesh]) -> Result<Camera, GltfError> {
    let (lo, hi) = meshes.iter().flat_map(|m| m.positions.iter()).fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    if lo.x > hi.x {
        return Err(GltfError::file(
            &src.path,
            "the scene has no triangles and no camera",
        ));
    }
    let (center, radius) = ((lo + hi) * 0.5, ((hi - lo) * 0.5).length().max(1e-3));
    let fov = 45.0f32;
    let distance = radius / (fov.to_radians() * 0.5).sin();
    let eye = center + Vec3::new(0.0, 0.35, 1.0).normalize() * distance;
    Camera::look_at(eye, center, Vec3::Y, fov)
        .map_err(|e| GltfError::file(&src.path, format!("framing camera: {e}")))
}
