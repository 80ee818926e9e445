//! Mesh files: PLY (ply-rs-bw) and OBJ with MTL (tobj); Loop subdivision surfaces.

pub mod obj;
pub mod ply;
pub mod subdivide;

use crate::light::{Emission, EnvironmentDesc, LightDesc};
use crate::{Camera, Material, RenderDefaults, SceneDesc, Shape, ShapeKind};
use fenestra_core::{Rgb, Vec3};
use std::path::Path;
use std::path::PathBuf;

/// A mesh file that cannot be read.
#[derive(Debug, thiserror::Error)]
#[error("{path}: {reason}")]
pub struct MeshError {
    /// The file.
    pub path: PathBuf,
    /// What is wrong with it.
    pub reason: String,
}

/// Fan triangulation of a polygon's vertex indices (PLY faces may be quads or n-gons).
fn fan(poly: &[u32], out: &mut Vec<[u32; 3]>) {
    for i in 1..poly.len().saturating_sub(1) {
        out.push([poly[0], poly[i], poly[i + 1]]);
    }
}

/// A mesh file (OBJ or PLY) staged for viewing: Y up as most such files are, a camera in
/// front of its bounding sphere, lit by its emissive materials or, without any, by a white
/// sky. Returns the scene and loading warnings.
pub fn viewer_scene(path: &Path) -> Result<(SceneDesc, Vec<String>), MeshError> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    let (shapes, materials, warnings) = match ext.as_deref() {
        Some("obj") => {
            let model = obj::read(path)?;
            let shapes: Vec<Shape> = model
                .meshes
                .into_iter()
                .map(|(mesh, m)| {
                    let shape = Shape::new(ShapeKind::Mesh(mesh), m);
                    match model.materials[m].1 {
                        Some(ke) => shape.emitting(Emission {
                            radiance: ke,
                            two_sided: false,
                        }),
                        None => shape,
                    }
                })
                .collect();
            let materials = model.materials.into_iter().map(|m| m.0).collect();
            (shapes, materials, model.warnings)
        }
        Some("ply") => (
            vec![Shape::new(ShapeKind::Mesh(ply::read(path)?), 0)],
            vec![Material::diffuse(0.7)],
            Vec::new(),
        ),
        _ => {
            return Err(MeshError {
                path: path.to_path_buf(),
                reason: "not a mesh file (.obj or .ply)".into(),
            })
        }
    };
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for s in &shapes {
        if let ShapeKind::Mesh(m) = &s.kind {
            for p in &m.positions {
                lo = lo.min(*p);
                hi = hi.max(*p);
            }
        }
    }
    let centre = (lo + hi) * 0.5;
    let radius = fenestra_core::ray::robust_length(hi - lo) * 0.5;
    let radius = if radius > 0.0 { radius } else { 1.0 };
    let fov = 40.0f32;
    let distance = radius / (0.5 * fov.to_radians()).sin();
    let eye = centre + Vec3::new(0.35, 0.3, 1.0).normalize() * distance;
    let camera = Camera::look_at(eye, centre, Vec3::Y, fov).map_err(|e| MeshError {
        path: path.to_path_buf(),
        reason: e.to_string(),
    })?;
    let mut lights = Vec::new();
    if shapes.iter().all(|s| s.emission.is_none()) {
        lights.push(LightDesc::Environment(EnvironmentDesc::Constant(Rgb::ONE)));
    }
    let name = path
        .file_stem()
        .map_or_else(|| "mesh".into(), |s| s.to_string_lossy().into_owned());
    Ok((
        SceneDesc {
            name,
            shapes,
            materials,
            lights,
            camera,
            defaults: RenderDefaults {
                width: 512,
                height: 512,
                spp: 64,
                max_depth: 8,
            },
            portals: Vec::new(),
        },
        warnings,
    ))
}
