//! A building of 1,024 ceiling lights in 64 rooms (issue 64's unseen many-light case): one
//! storey of 8 x 8 rooms of 5 m joined by doorways (a checkerboard of inner walls has one,
//! each at its own place along its wall, so the doorways do not line up), a desk and a
//! cabinet in each room, 16 downlights (disks facing down) per room whose strength differs
//! from room to room (0.3x to 3x), and night outside the windows. Unlike the tower, no light
//! faces a point through a floor: a room's neighbours' lights are near and hidden only by
//! walls, and a light tree ranks them by distance and power alone.

use crate::geometry::{camera, unit, Assembler};
use crate::ponderosa::{floor_plate, Plan};
use fenestra_core::{Rgb, Vec3};
use fenestra_scene::material;
use fenestra_scene::{Material, RenderDefaults, SceneDesc, ShapeKind};

/// Rooms along x and y.
pub const SIDE: usize = 8;
/// Downlights per room, along x and y.
pub const LIGHTS: usize = 4;
const ROOM: f32 = 5.0;
const H: f32 = 3.0;

const PLAN: Plan = Plan {
    cols: SIDE,
    rows: SIDE,
    room: ROOM,
    // Up to 1.5 m either way: the 0.8 m doorway stays 0.6 m from the corners.
    door_offset: |wall, room| 3.0 * (unit(wall as u32, room as u32) - 0.5),
};

/// The building.
pub fn building() -> SceneDesc {
    let mut a = Assembler::default();
    let plaster = a.material(Material::Diffuse(material::Diffuse {
        reflectance: Rgb::new(0.72, 0.72, 0.7),
    }));
    let floor = a.material(Material::Diffuse(material::Diffuse {
        reflectance: Rgb::new(0.36, 0.3, 0.26),
    }));
    let furniture = a.material(Material::Diffuse(material::Diffuse {
        reflectance: Rgb::new(0.5, 0.42, 0.32),
    }));
    let lamp = a.material(Material::diffuse(0.0));
    let plate = floor_plate(&PLAN, 0.0, H, None);
    a.mesh(plate.floor, floor);
    a.mesh(plate.ceiling, plaster);
    a.mesh(plate.walls, plaster);
    a.mesh(plate.props, furniture);
    for i in 0..SIDE {
        for j in 0..SIDE {
            let room = (i * SIDE + j) as u32;
            let strength = 0.3 * 10f32.powf(unit(room, 1000));
            for (p, q) in (0..LIGHTS).flat_map(|p| (0..LIGHTS).map(move |q| (p, q))) {
                let x = (i as f32 + (p as f32 + 0.5) / LIGHTS as f32) * ROOM;
                let y = (j as f32 + (q as f32 + 0.5) / LIGHTS as f32) * ROOM;
                a.emitter(
                    ShapeKind::Disk {
                        center: Vec3::new(x, y, H - 0.02),
                        normal: -Vec3::Z,
                        radius: 0.1,
                    },
                    lamp,
                    Rgb::new(1.0, 0.9, 0.78) * (120.0 * strength),
                );
            }
        }
    }
    let o = Vec3::new(3.0 * ROOM, 3.0 * ROOM, 0.0);
    a.finish(
        "building-1024",
        camera(
            o + Vec3::new(0.4, 0.4, 1.7),
            o + Vec3::new(4.6, 3.0, 0.9),
            75.0,
        ),
        RenderDefaults {
            width: 480,
            height: 270,
            spp: 64,
            max_depth: 6,
            options: Vec::new(),
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::lights_visible;
    use fenestra_scene::{Backend, Scene};

    #[test]
    fn a_room_sees_its_own_lights_and_few_others() {
        let desc = building();
        let centres: Vec<Vec3> = (desc.shapes.iter())
            .filter_map(|s| match (&s.kind, &s.emission) {
                (ShapeKind::Disk { center, .. }, Some(_)) => Some(*center - Vec3::Z * 0.01),
                _ => None,
            })
            .collect();
        assert_eq!(centres.len(), 1024);
        let scene = Scene::build(desc, Backend::Obvhs).expect("build");
        // Desk height anywhere on the plate.
        let side = SIDE as f32 * ROOM;
        let points: Vec<Vec3> = (0..100)
            .map(|k| Vec3::new(unit(k, 0) * side, unit(k, 1) * side, 0.8))
            .collect();
        let per_point = lights_visible(&scene, &points, &centres);
        eprintln!("lights visible per point {per_point:.1} of 1024");
        // Its own room's 16 (fewer behind a desk or cabinet) and a few through doorways.
        assert!(
            (10.0..=40.0).contains(&per_point),
            "{per_point} lights visible"
        );
    }
}
