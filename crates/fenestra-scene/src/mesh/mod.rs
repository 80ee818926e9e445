//! Mesh files: PLY (ply-rs-bw) and OBJ with MTL (tobj); Loop subdivision surfaces; meshes
//! built from functions.

mod build;
pub mod obj;
pub mod ply;
pub mod subdivide;

pub use build::{grid, smooth_normals};

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

/// A scene file's format from its name, lower case, looking through a `.gz` suffix:
/// "pbrt" for `Scene.PBRT.gz`, "ply" for `m.ply`.
pub fn format_of(path: &Path) -> Option<String> {
    let name = path.file_name()?.to_string_lossy().to_ascii_lowercase();
    let name = name.strip_suffix(".gz").unwrap_or(&name);
    Path::new(name)
        .extension()
        .map(|e| e.to_string_lossy().into_owned())
}

/// A mesh file made a scene ([`viewer_scene`]).
pub struct MeshScene {
    /// The scene.
    pub desc: SceneDesc,
    /// Problems that did not stop loading.
    pub warnings: Vec<String>,
    /// The files it was read from: the mesh file and the MTL files an OBJ names.
    pub files: Vec<PathBuf>,
}

/// A mesh file (OBJ or PLY, the PLY perhaps gzip-compressed) staged for viewing: Y up as most such files are, a camera in
/// front of its bounding sphere, lit by its emissive materials or, without any, as in a
/// studio: a grey floor under it, a key light from above front left that casts its shadow
/// there, and a dim sky as fill.
pub fn viewer_scene(path: &Path) -> Result<MeshScene, MeshError> {
    let mut files = vec![path.to_path_buf()];
    let (mut shapes, mut materials, warnings) = match format_of(path).as_deref() {
        Some("obj")
            if path
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("gz")) =>
        {
            return Err(MeshError {
                path: path.to_path_buf(),
                reason: "gzip-compressed OBJ files are not read: decompress it first".into(),
            })
        }
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
            files.extend(model.material_files);
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
        // A floor far wider than the mesh, just under it.
        shapes.push(Shape::new(
            ShapeKind::Disk {
                center: Vec3::new(centre.x, lo.y, centre.z),
                normal: Vec3::Y,
                radius: 20.0 * radius,
            },
            materials.len(),
        ));
        materials.push(Material::diffuse(0.5));
        lights.push(LightDesc::Distant {
            direction: -Vec3::new(-0.5, 1.0, 0.6).normalize(),
            irradiance: Rgb::splat(3.0),
        });
        lights.push(LightDesc::Environment(EnvironmentDesc::Constant(
            Rgb::splat(0.25),
        )));
    }
    let name = path
        .file_stem()
        .map_or_else(|| "mesh".into(), |s| s.to_string_lossy().into_owned());
    Ok(MeshScene {
        desc: SceneDesc {
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
                options: Vec::new(),
            },
            portals: Vec::new(),
        },
        warnings,
        files,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bare_mesh_gets_a_floor_a_key_light_and_a_sky_and_a_lit_one_keeps_its_lights() {
        let dir = std::env::temp_dir().join(format!("fenestra-viewer-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let bare = dir.join("bare.obj");
        std::fs::write(&bare, "v 0 1 0\nv 1 1 0\nv 0 2 0\nf 1 2 3\n").expect("obj");
        let desc = viewer_scene(&bare).expect("bare").desc;
        assert_eq!(desc.shapes.len(), 2);
        let ShapeKind::Disk { center, normal, .. } = desc.shapes[1].kind else {
            panic!("a floor disk")
        };
        // Under the mesh (its lowest point is at y = 1), facing up.
        assert_eq!((center.y, normal), (1.0, Vec3::Y));
        assert!(matches!(
            desc.lights[..],
            [LightDesc::Distant { direction, .. }, LightDesc::Environment(_)] if direction.y < 0.0
        ));
        std::fs::write(dir.join("lamp.mtl"), "newmtl lamp\nKe 4 4 4\n").expect("mtl");
        let lit = dir.join("lit.obj");
        std::fs::write(
            &lit,
            "mtllib lamp.mtl\nv 0 1 0\nv 1 1 0\nv 0 2 0\nusemtl lamp\nf 1 2 3\n",
        )
        .expect("obj");
        let desc = viewer_scene(&lit).expect("lit").desc;
        assert_eq!(desc.shapes.len(), 1);
        assert!(desc.lights.is_empty());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
