//! Built-in procedural scenes, so every experiment runs with no files: `builtin:NAME`.

mod box_hole;

use crate::SceneDesc;

/// (name, description) of every built-in scene.
pub const SCENES: &[(&str, &str)] = &[
    (
        "box-hole",
        "seed 000 §5.2: 1 m diffuse box, 0.25 m ceiling hole, 25 W emitter above",
    ),
    (
        "box-4holes",
        "seed 000 §5.2: the box with four 0.125 m ceiling holes near the corners",
    ),
    (
        "box-hole-sky",
        "the box-hole box lit by a constant sky of radiance 1 instead of the emitter",
    ),
    (
        "box-blob",
        "box-hole with a bumpy tessellated sphere of about 1M triangles (ray throughput)",
    ),
];

/// The scene called `name` (without the `builtin:` prefix).
pub fn load(name: &str) -> Result<SceneDesc, String> {
    match name {
        "box-hole" => Ok(box_hole::box_scene(box_hole::Variant::OneHole)),
        "box-4holes" => Ok(box_hole::box_scene(box_hole::Variant::FourHoles)),
        "box-hole-sky" => Ok(box_hole::box_scene(box_hole::Variant::Sky)),
        "box-blob" => Ok(box_hole::box_blob()),
        _ => {
            let names: Vec<&str> = SCENES.iter().map(|s| s.0).collect();
            Err(format!(
                "unknown built-in scene '{name}' (available: {})",
                names.join(", ")
            ))
        }
    }
}
