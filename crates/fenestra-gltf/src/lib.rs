//! glTF 2.0 scenes (`.gltf` with external or embedded buffers, `.glb`) as fenestra scene
//! descriptions: the node hierarchy, meshes, perspective cameras, metallic-roughness
//! materials and KHR_lights_punctual. What fenestra does not support is reported, each thing
//! once with where it occurs, as pbrt-v4 input is; errors name the file and the JSON path.

mod accessor;
mod camera;
mod error;
mod geometry;
mod graph;
mod images;
mod lights;
mod materials;
mod report;
mod source;

pub use error::GltfError;
pub use lights::LUMENS_PER_WATT;

use fenestra_scene::{RenderDefaults, SceneDesc, Shape, ShapeKind, TriangleMesh};
use images::Images;
use report::Report;
use source::Source;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Extensions whose content the loader reads (others are reported when used, and when
/// required too).
const SUPPORTED: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_materials_emissive_strength",
    "KHR_materials_ior",
    "KHR_materials_specular",
    "KHR_materials_transmission",
    "KHR_materials_volume",
    "KHR_texture_transform",
    "KHR_mesh_quantization",
    "AMD_split_roughnessMetallic",
];

/// A loaded glTF scene.
pub struct Loaded {
    /// The scene.
    pub desc: SceneDesc,
    /// What the file asks for that is not supported or is approximated, one line each.
    pub warnings: Vec<String>,
    /// Every file read: the scene file, buffers and images.
    pub files: Vec<PathBuf>,
    /// The names of the file's perspective cameras, in the order `camera` indices count.
    pub cameras: Vec<String>,
}

/// Reads the glTF scene at `path`, seen from the camera named or numbered `camera` (the
/// first by default; a framing camera in a file without one).
pub fn load(path: &Path, camera: Option<&str>) -> Result<Loaded, GltfError> {
    let mut src = Source::open(path)?;
    let mut report = Report::default();
    for ext in src.document.extensions_used() {
        if !SUPPORTED.contains(&ext) {
            let required = src.document.extensions_required().any(|r| r == ext);
            let what = match required {
                true => format!(
                    "extension {ext} is required but not supported (the scene may look wrong)"
                ),
                false => format!("extension {ext} is not supported (ignored)"),
            };
            report.say("/extensionsUsed", what);
        }
    }
    // The spec asks a required extension to be listed as used too; one that is not would
    // go unsaid above.
    for ext in src.document.extensions_required() {
        let used = src.document.extensions_used().any(|u| u == ext);
        if !used && !SUPPORTED.contains(&ext) {
            report.say(
                "/extensionsRequired",
                format!("extension {ext} is required but not supported (the scene may look wrong)"),
            );
        }
    }
    if src.document.animations().next().is_some() {
        report.say(
            "/animations",
            "animations are not played (the scene is rendered as posed)",
        );
    }
    let wanted = materials::wanted_images(&src.document);
    let images = Images::decode(&mut src, &wanted)?;
    let materials = materials::build(&src, &images, &mut report)?;
    let placed = graph::walk(&src)?;

    let mut shapes = Vec::new();
    let mut lights = Vec::new();
    let mut local: HashMap<usize, Vec<geometry::LocalMesh>> = HashMap::new();
    for p in &placed {
        if p.node.skin().is_some() {
            report.say(
                format!("/nodes/{}", p.node.index()),
                "skins are not applied (meshes are rendered in their bind pose)",
            );
        }
        if let Some(light) = p.node.light() {
            lights.push(lights::light(&light, &p.world, &mut report));
        }
        let Some(mesh) = p.node.mesh() else { continue };
        if let std::collections::hash_map::Entry::Vacant(e) = local.entry(mesh.index()) {
            let mut prims = Vec::new();
            for prim in mesh.primitives() {
                prims.extend(geometry::primitive(&src, mesh.index(), &prim, &mut report)?);
            }
            e.insert(prims);
        }
        for prim in &local[&mesh.index()] {
            if prim.mesh.indices.is_empty() {
                continue;
            }
            let (material, emission) = match prim.material {
                Some(m) => materials.of_gltf[m],
                None => (materials.default, None),
            };
            let mut shape = Shape::new(
                ShapeKind::Mesh(geometry::placed(&prim.mesh, &p.world)),
                material,
            );
            shape.emission = emission;
            shape.name = p.node.name().map(str::to_string);
            shapes.push(shape);
        }
    }

    let cameras = camera::cameras(&placed);
    let (camera, aspect) = match camera::pick(&src, &cameras, camera)? {
        Some(c) => (c.camera(&src)?, c.aspect),
        None => {
            let orthographic = (src.document.cameras())
                .filter(|c| matches!(c.projection(), gltf::camera::Projection::Orthographic(_)))
                .count();
            if orthographic > 0 {
                report.say(
                    "/cameras",
                    format!(
                        "{orthographic} orthographic camera(s), which fenestra does not render \
                         (perspective only): a camera that frames the scene stands in"
                    ),
                );
            }
            let meshes: Vec<&TriangleMesh> = shapes
                .iter()
                .filter_map(|s| match &s.kind {
                    ShapeKind::Mesh(m) => Some(m),
                    _ => None,
                })
                .collect();
            (camera::framing(&src, &meshes)?, None)
        }
    };
    // An aspect ratio beyond 10:1 either way is not a picture anyone frames (and would ask
    // for an image of millions of rows): the default stands in.
    if let Some(a) = aspect.filter(|a| !(0.1..=10.0).contains(a)) {
        report.say(
            "/cameras",
            format!("the camera's aspectRatio {a} lies beyond 10:1; the image is 16:9"),
        );
    }
    let aspect = aspect
        .filter(|a| (0.1..=10.0).contains(a))
        .unwrap_or(16.0 / 9.0);
    let width = 960u32;
    let desc = SceneDesc {
        name: path
            .file_stem()
            .map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned()),
        shapes,
        materials: materials.materials,
        lights,
        camera,
        defaults: RenderDefaults {
            width,
            height: ((width as f32 / aspect).round() as u32).max(1),
            ..RenderDefaults::default()
        },
        portals: Vec::new(),
    };
    Ok(Loaded {
        desc,
        warnings: report.lines(),
        files: src.files,
        cameras: cameras.into_iter().map(|c| c.name).collect(),
    })
}
