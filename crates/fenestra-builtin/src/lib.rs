//! Built-in procedural scenes, so every experiment runs with no files: `builtin:NAME`.
//! docs/scenes.md shows each with a thumbnail.

mod box_hole;
mod building;
mod chess;
mod cornell;
mod geometry;
pub mod glazed;
mod glossy_room;
pub mod hall;
mod kitchen;
mod ponderosa;
mod relight_room;
mod teapot;
mod terminal;
mod tower;
mod tunnel;

use fenestra_scene::material;
use fenestra_scene::{Material, SceneDesc, Shape, ShapeKind, TriangleMesh};

/// (name, description) of every built-in scene.
pub const SCENES: &[(&str, &str)] = &[
    (
        "box-hole",
        "1 m white box lit through one ceiling hole by a 25 W panel above it (seed 000 §5.2)",
    ),
    (
        "box-4holes",
        "the same box with four small ceiling holes near the corners (seed 000 §5.2)",
    ),
    (
        "box-hole-sky",
        "the one-hole box lit by a uniform sky instead of the panel",
    ),
    (
        "box-blob",
        "the one-hole box with a bumpy 1M-triangle ball inside (ray throughput)",
    ),
    (
        "hall-windows",
        "long hall lit through 19 glass windows on one side (seed 000 §5.3, Sibenik-like)",
    ),
    (
        "tunnel",
        "room lit only through a tunnel from a closed lamp chamber (seed 000 Fig. 5.13)",
    ),
    (
        "cornell-box",
        "the Cornell box with its published geometry and ceiling light",
    ),
    (
        "teapot-box",
        "brushed-metal Utah teapot (anisotropic Ward) in a box with a checkered wall (seed 003 §2.6)",
    ),
    (
        "teapot-box-phong-16",
        "the teapot box with a Phong kettle of lobe exponent 16 (teapot-box-phong-N: exponent N; seed 003 Fig. 2.5)",
    ),
    (
        "chess",
        "ivory (anisotropic Ward) and ebony (Phong) chess pieces on a glossy board, 5 spots and a sky (seed 003 Fig. 2.6)",
    ),
    (
        "glossy-room",
        "polished floor and metal furniture in a room lit by the sun through a window (seed 003 ch. 2)",
    ),
    (
        "kitchen-72",
        "kitchen with 72 ceiling downlights, cabinets and a glossy floor (seed 004 Table 4.1)",
    ),
    (
        "kitchen-72-env",
        "the kitchen with daylight through windows behind the camera (seed 004 Kitchen 2)",
    ),
    (
        "ponderosa-138",
        "24-room house with 138 lamps, most hidden behind walls, and a sky (seed 004 Table 4.1)",
    ),
    (
        "tower",
        "8-storey office tower, 192 rooms, 4,608 ceiling-panel lights (few visible from anywhere) and a sky (issue 12)",
    ),
    (
        "building-1024",
        "one storey of 64 rooms joined by doorways, 16 downlights of its own strength in each: 1,024 lights, a few dozen visible from a point (issue 64)",
    ),
    (
        "terminal-832",
        "Grand Central-like concourse, 832 lights, 1.1M triangles (seed 004 Table 4.1)",
    ),
    (
        "room-glazed-sky",
        "room lit by the sky through a window glazed with a refracting 8 mm pane, a mullion and a transom, in a 20 cm wall (issue 64)",
    ),
    (
        "room-glazed-blind",
        "the glazed room with a blind behind the glass, lit by an area light outside facing the window (issue 64)",
    ),
    (
        "rooms-door-ajar",
        "a room lit from the next one through a door 8 degrees ajar, a ceiling panel there the only light (issue 64)",
    ),
    (
        "relight-room",
        "diffuse room with a crate and a screen that move over 100 frames, two point lights and a spot (issue 14; its animation: `fenestra relight`)",
    ),
];

/// The animation (JSON, docs/relight.md's format) that goes with built-in scene `name`, if
/// it is animated.
pub fn animation(name: &str) -> Option<&'static str> {
    match name {
        "relight-room" => Some(relight_room::ANIMATION),
        _ => None,
    }
}

/// A name that is not one of the built-in scenes.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown built-in scene '{0}' (available: {names})", names = SCENES.iter().map(|s| s.0).collect::<Vec<_>>().join(", "))]
pub struct UnknownScene(pub String);

/// The scene called `name` (without the `builtin:` prefix).
pub fn load(name: &str) -> Result<SceneDesc, UnknownScene> {
    match name {
        "box-hole" => Ok(box_hole::box_scene(box_hole::Variant::OneHole)),
        "box-4holes" => Ok(box_hole::box_scene(box_hole::Variant::FourHoles)),
        "box-hole-sky" => Ok(box_hole::box_scene(box_hole::Variant::Sky)),
        "box-blob" => Ok(box_hole::box_blob()),
        "hall-windows" => Ok(hall::hall_windows()),
        "tunnel" => Ok(tunnel::tunnel()),
        "cornell-box" => Ok(cornell::cornell_box()),
        "teapot-box" => Ok(teapot::teapot_box()),
        "chess" => Ok(chess::chess()),
        "glossy-room" => Ok(glossy_room::glossy_room()),
        "kitchen-72" => Ok(kitchen::kitchen(false)),
        "kitchen-72-env" => Ok(kitchen::kitchen(true)),
        "ponderosa-138" => Ok(ponderosa::ponderosa()),
        "terminal-832" => Ok(terminal::terminal()),
        "tower" => Ok(tower::tower()),
        "building-1024" => Ok(building::building()),
        "relight-room" => Ok(relight_room::relight_room()),
        "room-glazed-sky" => Ok(glazed::glazed_room(glazed::Lit::Sky)),
        "room-glazed-blind" => Ok(glazed::glazed_room(glazed::Lit::LampBlind)),
        "rooms-door-ajar" => Ok(glazed::door_ajar()),
        _ => match name
            .strip_prefix("teapot-box-phong-")
            .map(str::parse::<f32>)
        {
            Some(Ok(exponent)) if exponent.is_finite() && exponent >= 0.0 => {
                Ok(teapot::teapot_box_phong(exponent))
            }
            _ => Err(UnknownScene(name.to_string())),
        },
    }
}

/// `desc` with a thin glass pane (eta 1.5, pbrt's "thindielectric") filling each of its
/// openings, the quads listed as its portals: the box scenes with glazed holes.
pub fn glazed(mut desc: SceneDesc) -> SceneDesc {
    let glass = desc.materials.len();
    desc.materials
        .push(Material::ThinDielectric(material::ThinDielectric {
            eta: 1.5,
        }));
    for q in desc.portals.clone() {
        let c = (q[0] + q[1] + q[2] + q[3]) / 4.0;
        let pane = TriangleMesh::quad(c, (q[1] - q[0]) * 0.5, (q[3] - q[0]) * 0.5);
        desc.shapes.push(Shape::new(ShapeKind::Mesh(pane), glass));
    }
    desc
}

#[cfg(test)]
mod tests {
    use super::*;
    use fenestra_scene::{Backend, Scene};

    #[test]
    fn every_scene_builds_and_matches_its_description() {
        for (name, _) in SCENES {
            let desc = load(name).expect(name);
            let lights =
                desc.lights.len() + desc.shapes.iter().filter(|s| s.emission.is_some()).count();
            let tris: usize = desc
                .shapes
                .iter()
                .filter(|s| matches!(s.kind, fenestra_scene::ShapeKind::Mesh(_)))
                .map(|s| s.primitive_count())
                .sum();
            match *name {
                "kitchen-72" => assert_eq!(lights, 72),
                "kitchen-72-env" => assert_eq!(lights, 73),
                "ponderosa-138" => assert_eq!(lights, 139),
                "tower" => {
                    // Every emissive triangle is a light: 12 panels of 2 in each room.
                    let panels: usize = (desc.shapes.iter())
                        .filter(|s| s.emission.is_some())
                        .map(|s| s.primitive_count())
                        .sum();
                    let rooms = tower::STOREYS * ponderosa::COLS * ponderosa::ROWS;
                    assert_eq!(panels, rooms * 24);
                    assert!(panels >= 4096);
                }
                "building-1024" => assert_eq!(lights, 1024),
                "terminal-832" => {
                    assert_eq!(desc.lights.len(), 613);
                    assert_eq!(lights, 832);
                    assert!(tris >= 1_000_000, "{tris} triangles");
                }
                _ => assert!(lights >= 1, "{name} has no light"),
            }
            Scene::build(desc, Backend::Obvhs).expect(name);
        }
    }

    #[test]
    fn hall_has_19_lit_windows() {
        assert_eq!(hall::windows(19, 5.0).len(), 19);
    }
}
