//! An office tower with thousands of lights, few of them visible from anywhere (issue 12's
//! occlusion-heavy scene, the case light trees handle worst): 8 storeys of 24 rooms (the
//! ponderosa floor plate: a 6 x 4 grid of 4 m rooms with doorways between neighbours and
//! windows outside), each room lit by 12 ceiling panels of two emitting triangles: 4,608
//! lights, and a sky through the windows. From a point in a room only its own panels and a
//! few through doorways are visible; the panels of the storeys above face down towards it
//! through their floors, which a light tree's bounds cannot see.

use crate::geometry::{camera, sky, Assembler};
use crate::ponderosa::{floor_plate, COLS, PLAN, ROOM, ROWS};
use fenestra_core::{Rgb, Vec3};
use fenestra_scene::light::LightDesc;
use fenestra_scene::material;
use fenestra_scene::{Material, RenderDefaults, SceneDesc, ShapeKind, TriangleMesh};

/// Storeys.
pub const STOREYS: usize = 8;
/// Floor-to-floor height (m); a room is `ROOM_H` high, the slab between is the rest.
const STOREY_H: f32 = 3.2;
const ROOM_H: f32 = 2.8;
/// Ceiling panels per room, along x and y.
const PANELS: (usize, usize) = (4, 3);

/// The tower.
pub fn tower() -> SceneDesc {
    let mut a = Assembler::default();
    let plaster = a.material(Material::Diffuse(material::Diffuse {
        reflectance: Rgb::new(0.75, 0.74, 0.72),
    }));
    let carpet = a.material(Material::Diffuse(material::Diffuse {
        reflectance: Rgb::new(0.3, 0.32, 0.36),
    }));
    let furniture = a.material(Material::Diffuse(material::Diffuse {
        reflectance: Rgb::new(0.55, 0.45, 0.3),
    }));
    let lamp = a.material(Material::diffuse(0.0));
    let (wx, wy) = (COLS as f32 * ROOM, ROWS as f32 * ROOM);
    let mut panels = TriangleMesh::default();
    for storey in 0..STOREYS {
        let z0 = storey as f32 * STOREY_H;
        let plate = floor_plate(&PLAN, z0, ROOM_H, None);
        a.mesh(plate.floor, carpet);
        a.mesh(plate.ceiling, plaster);
        a.mesh(plate.walls, plaster);
        a.mesh(plate.props, furniture);
        for i in 0..COLS {
            for j in 0..ROWS {
                for (pi, pj) in (0..PANELS.0).flat_map(|p| (0..PANELS.1).map(move |q| (p, q))) {
                    let x = (i as f32 + (pi as f32 + 0.5) / PANELS.0 as f32) * ROOM;
                    let y = (j as f32 + (pj as f32 + 0.5) / PANELS.1 as f32) * ROOM;
                    // Facing down: its normal (Y x X) is -z.
                    panels.append(&TriangleMesh::quad(
                        Vec3::new(x, y, z0 + ROOM_H - 0.01),
                        Vec3::Y * 0.25,
                        Vec3::X * 0.3,
                    ));
                }
            }
        }
    }
    a.emitter(
        ShapeKind::Mesh(panels),
        lamp,
        Rgb::new(1.0, 0.95, 0.88) * 6.0,
    );
    // The ground around the tower.
    a.mesh(
        TriangleMesh::quad(
            Vec3::new(wx / 2.0, wy / 2.0, -0.01),
            Vec3::X * (wx * 2.0),
            Vec3::Y * (wy * 2.0),
        ),
        carpet,
    );
    let sun = Vec3::new(-0.4, -0.6, 0.7).normalize();
    a.lights
        .push(LightDesc::Environment(sky(512, 256, sun, 1.0)));
    let z = 3.0 * STOREY_H;
    a.finish(
        "tower",
        camera(
            Vec3::new(0.4, 0.4, z + 1.7),
            Vec3::new(4.5, 2.3, z + 0.9),
            75.0,
        ),
        RenderDefaults {
            width: 480,
            height: 360,
            spp: 64,
            max_depth: 6,
            options: Vec::new(),
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{lights_visible, unit};
    use fenestra_scene::{Backend, Scene};

    #[test]
    fn a_few_dozen_of_thousands_of_lights_are_visible_from_a_point() {
        let desc = tower();
        // Panel centres: the mean of each emitting quad's corners, a little below it.
        let centres: Vec<Vec3> = (desc.shapes.iter())
            .filter(|s| s.emission.is_some())
            .flat_map(|s| match &s.kind {
                ShapeKind::Mesh(m) => m
                    .positions
                    .chunks(4)
                    .map(|q| q.iter().copied().sum::<Vec3>() / 4.0 - Vec3::Z * 0.01)
                    .collect::<Vec<_>>(),
                _ => Vec::new(),
            })
            .collect();
        assert_eq!(centres.len() * 2, STOREYS * COLS * ROWS * 24);
        let scene = Scene::build(desc, Backend::Obvhs).expect("build");
        // Desk height on a random storey, anywhere on the plate.
        let points: Vec<Vec3> = (0..60)
            .map(|k| {
                let storey = (unit(k, 2) * STOREYS as f32) as usize % STOREYS;
                Vec3::new(
                    unit(k, 0) * COLS as f32 * ROOM,
                    unit(k, 1) * ROWS as f32 * ROOM,
                    storey as f32 * STOREY_H + 0.8,
                )
            })
            .collect();
        let per_point = lights_visible(&scene, &points, &centres);
        eprintln!(
            "panels visible per point {per_point:.1} of {}",
            centres.len()
        );
        assert!(
            (4.0..=60.0).contains(&per_point),
            "{per_point} panels visible"
        );
    }
}
