//! Many-light analogue of seed 004's Ponderosa (Table 4.1): a single-storey house of 24 rooms
//! in a 6 x 4 grid with doorways between neighbours and windows outside, 138 point lights (6
//! in each of 23 rooms; the 24th is an open courtyard), and a sky. From a typical point only
//! its own room's lights are visible: 94% of the lights are occluded from a random point at
//! table height (measured by the test below; 95.9% if no light leaked through doorways).

use crate::geometry::{camera, cuboid, sky, wall_with_openings, Assembler, Rect};
use fenestra_core::{Rgb, Vec3};
use fenestra_scene::light::LightDesc;
use fenestra_scene::material;
use fenestra_scene::{Material, RenderDefaults, SceneDesc, TriangleMesh};

pub const ROOM: f32 = 4.0;
pub const COLS: usize = 6;
pub const ROWS: usize = 4;
const H: f32 = 2.8;
/// The room left open to the sky.
pub const COURTYARD: (usize, usize) = (3, 2);

pub fn ponderosa() -> SceneDesc {
    let mut a = Assembler::default();
    let plaster = a.material(Material::Diffuse(material::Diffuse {
        reflectance: Rgb::new(0.75, 0.7, 0.62),
    }));
    let floor = a.material(Material::Diffuse(material::Diffuse {
        reflectance: Rgb::new(0.4, 0.3, 0.22),
    }));
    let furniture = a.material(Material::Diffuse(material::Diffuse {
        reflectance: Rgb::new(0.35, 0.3, 0.5),
    }));
    let plate = floor_plate(&PLAN, 0.0, H, Some(COURTYARD));
    a.mesh(plate.floor, floor);
    a.mesh(plate.ceiling, plaster);
    a.mesh(plate.walls, plaster);
    for i in 0..COLS {
        for j in 0..ROWS {
            if (i, j) == COURTYARD {
                continue;
            }
            let o = Vec3::new(i as f32 * ROOM, j as f32 * ROOM, 0.0);
            for (lx, ly) in [
                (1.0, 1.2),
                (2.0, 1.2),
                (3.0, 1.2),
                (1.0, 2.8),
                (2.0, 2.8),
                (3.0, 2.8),
            ] {
                let warm = Rgb::new(1.0, 0.78, 0.55) * 2.5;
                a.lights.push(LightDesc::Point {
                    position: o + Vec3::new(lx, ly, 2.7),
                    intensity: warm,
                });
            }
        }
    }
    a.mesh(plate.props, furniture);
    let sun = Vec3::new(0.5, 0.4, 0.75).normalize();
    a.lights
        .push(LightDesc::Environment(sky(512, 256, sun, 1.0)));
    a.finish(
        "ponderosa-138",
        camera(Vec3::new(0.3, 0.3, 2.0), Vec3::new(4.5, 2.3, 0.9), 75.0),
        RenderDefaults {
            width: 640,
            height: 480,
            spp: 64,
            max_depth: 6,
            options: Vec::new(),
        },
    )
}

/// The house's plan: doorways on the centre lines of the walls.
pub const PLAN: Plan = Plan {
    cols: COLS,
    rows: ROWS,
    room: ROOM,
    door_offset: |_, _| 0.0,
};

/// A floor plan: a grid of `cols` x `rows` square rooms of side `room`, a doorway in every
/// other inner wall (a checkerboard), `door_offset(wall, room)` from the middle of its wall
/// (walls of constant x numbered 0..=cols, then those of constant y), and a window in the
/// middle of every outer wall.
pub struct Plan {
    pub cols: usize,
    pub rows: usize,
    pub room: f32,
    pub door_offset: fn(usize, usize) -> f32,
}

/// One storey of a plan: its floor, its ceiling (open above the courtyard, if any), its
/// walls (doorways between neighbouring rooms in a checkerboard pattern, windows outside) and
/// two pieces of furniture per room, at height `z0`, rooms `h` high.
pub struct Plate {
    pub floor: TriangleMesh,
    pub ceiling: TriangleMesh,
    pub walls: TriangleMesh,
    pub props: TriangleMesh,
}

/// The storey of `plan` at `z0` with rooms `h` high and the room `courtyard` left open to
/// the sky.
pub fn floor_plate(plan: &Plan, z0: f32, h: f32, courtyard: Option<(usize, usize)>) -> Plate {
    let &Plan {
        cols,
        rows,
        room,
        door_offset,
    } = plan;
    let (wx, wy) = (cols as f32 * room, rows as f32 * room);
    let floor = TriangleMesh::quad(
        Vec3::new(wx / 2.0, wy / 2.0, z0),
        Vec3::X * (wx / 2.0),
        Vec3::Y * (wy / 2.0),
    );
    let open: Vec<Rect> = courtyard
        .map(|(i, j)| {
            let (cx, cy) = (i as f32 * room, j as f32 * room);
            ([cy, cx], [cy + room, cx + room])
        })
        .into_iter()
        .collect();
    let ceiling = wall_with_openings(
        Vec3::new(0.0, 0.0, z0 + h),
        Vec3::Y,
        Vec3::X,
        ([0.0, 0.0], [wy, wx]),
        &open,
    );
    let door = |s: f32| -> Rect { ([s - 0.4, 0.0], [s + 0.4, 1.9]) };
    let window = |s: f32| -> Rect { ([s - 0.6, 1.0], [s + 0.6, 2.0]) };
    let mut walls = TriangleMesh::default();
    // Walls of constant x (spanned by y, z) and of constant y (spanned by x, z).
    for i in 0..=cols {
        let x = i as f32 * room;
        let openings: Vec<Rect> = (0..rows)
            .filter(|j| i == 0 || i == cols || (i + j) % 2 == 1)
            .map(|j| {
                let s = (j as f32 + 0.5) * room;
                if i == 0 || i == cols {
                    window(s)
                } else {
                    door(s + door_offset(i, j))
                }
            })
            .collect();
        walls.append(&wall_with_openings(
            Vec3::new(x, 0.0, z0),
            Vec3::Y,
            Vec3::Z,
            ([0.0, 0.0], [wy, h]),
            &openings,
        ));
    }
    for j in 0..=rows {
        let y = j as f32 * room;
        let openings: Vec<Rect> = (0..cols)
            .filter(|i| j == 0 || j == rows || (i + j) % 2 == 0)
            .map(|i| {
                let s = (i as f32 + 0.5) * room;
                if j == 0 || j == rows {
                    window(s)
                } else {
                    door(s + door_offset(cols + 1 + j, i))
                }
            })
            .collect();
        walls.append(&wall_with_openings(
            Vec3::new(0.0, y, z0),
            Vec3::X,
            Vec3::Z,
            ([0.0, 0.0], [wx, h]),
            &openings,
        ));
    }
    let mut props = TriangleMesh::default();
    for i in 0..cols {
        for j in 0..rows {
            if Some((i, j)) == courtyard {
                continue;
            }
            let o = Vec3::new(i as f32 * room, j as f32 * room, z0);
            props.append(&cuboid(
                o + Vec3::new(1.2, 1.4, 0.0),
                o + Vec3::new(2.4, 2.2, 0.75),
            ));
            props.append(&cuboid(
                o + Vec3::new(2.9, 0.3, 0.0),
                o + Vec3::new(3.7, 2.3, 0.5),
            ));
        }
    }
    Plate {
        floor,
        ceiling,
        walls,
        props,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{lights_visible, unit};
    use fenestra_scene::{Backend, Scene};

    #[test]
    fn about_96_percent_of_lights_are_occluded() {
        let scene = Scene::build(ponderosa(), Backend::Obvhs).expect("build");
        let lights: Vec<Vec3> = scene
            .lights
            .iter()
            .filter_map(|l| match l {
                LightDesc::Point { position, .. } => Some(*position),
                _ => None,
            })
            .collect();
        assert_eq!(lights.len(), 138);
        // Points at table height anywhere in the house.
        let points: Vec<Vec3> = (0..400)
            .map(|k| {
                Vec3::new(
                    unit(k, 0) * COLS as f32 * ROOM,
                    unit(k, 1) * ROWS as f32 * ROOM,
                    0.8,
                )
            })
            .collect();
        let occluded = 1.0 - lights_visible(&scene, &points, &lights) / lights.len() as f64;
        eprintln!("occluded fraction {occluded:.4}");
        assert!((0.93..0.96).contains(&occluded), "{occluded}");
    }
}
