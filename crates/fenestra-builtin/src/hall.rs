//! A long hall lit through glass windows (seed 000 §5.3, Sibenik-like): 19 windows high on
//! the +y wall with a large area light outside that side only, 7 unlit windows on the -y
//! wall, two rows of pillars. Walls are thin; each window holds a thin glass pane.

use crate::geometry::{camera, cuboid, transposed, wall_with_openings, Assembler, Rect};
use fenestra_core::{Rgb, Vec3};
use fenestra_scene::material;
use fenestra_scene::{Material, RenderDefaults, SceneDesc, ShapeKind, TriangleMesh};

/// The hall's interior: x in [0, LENGTH], y in [-HALF_WIDTH, HALF_WIDTH], z in [0, HEIGHT].
const LENGTH: f32 = 20.0;
const HALF_WIDTH: f32 = 3.0;
const HEIGHT: f32 = 8.0;

/// Window openings in wall coordinates (x, z): `count` windows 0.5 m wide and 1.6 m tall.
pub fn windows(count: usize, z0: f32) -> Vec<Rect> {
    let pitch = LENGTH / count as f32;
    (0..count)
        .map(|k| {
            let x = pitch * (k as f32 + 0.5);
            ([x - 0.25, z0], [x + 0.25, z0 + 1.6])
        })
        .collect()
}

/// builtin:hall-windows.
pub fn hall_windows() -> SceneDesc {
    let mut a = Assembler::default();
    let stone = a.material(Material::Diffuse(material::Diffuse {
        reflectance: Rgb::new(0.62, 0.58, 0.52),
    }));
    let floor = a.material(Material::Diffuse(material::Diffuse {
        reflectance: Rgb::new(0.45, 0.42, 0.38),
    }));
    let glass = a.material(Material::ThinDielectric(material::ThinDielectric {
        eta: 1.5,
    }));
    let lamp = a.material(Material::diffuse(0.0));
    let (lit, unlit) = (windows(19, 5.0), windows(7, 5.6));
    let extent = ([0.0, 0.0], [LENGTH, HEIGHT]);
    // +y wall (facing -y, into the hall) and -y wall (facing +y).
    a.mesh(
        wall_with_openings(
            Vec3::new(0.0, HALF_WIDTH, 0.0),
            Vec3::X,
            Vec3::Z,
            extent,
            &lit,
        ),
        stone,
    );
    a.mesh(
        wall_with_openings(
            Vec3::new(0.0, -HALF_WIDTH, 0.0),
            Vec3::Z,
            Vec3::X,
            ([0.0, 0.0], [HEIGHT, LENGTH]),
            &transposed(&unlit),
        ),
        stone,
    );
    let (w, h) = (HALF_WIDTH, HEIGHT);
    let mut shell = TriangleMesh::quad(
        Vec3::new(LENGTH * 0.5, 0.0, h),
        Vec3::Y * w,
        Vec3::X * LENGTH * 0.5,
    ); // ceiling, -z
    shell.append(&TriangleMesh::quad(
        Vec3::new(0.0, 0.0, h * 0.5),
        Vec3::Y * w,
        Vec3::Z * h * 0.5,
    )); // x = 0, +x
    shell.append(&TriangleMesh::quad(
        Vec3::new(LENGTH, 0.0, h * 0.5),
        Vec3::Z * h * 0.5,
        Vec3::Y * w,
    )); // x = L, -x
    a.mesh(shell, stone);
    a.mesh(
        TriangleMesh::quad(
            Vec3::new(LENGTH * 0.5, 0.0, 0.0),
            Vec3::X * LENGTH * 0.5,
            Vec3::Y * w,
        ),
        floor,
    );
    let mut pillars = TriangleMesh::default();
    for k in 0..5 {
        let x = 2.0 + 4.0 * k as f32;
        for y in [-1.6f32, 1.6] {
            pillars.append(&cuboid(
                Vec3::new(x - 0.3, y - 0.3, 0.0),
                Vec3::new(x + 0.3, y + 0.3, 4.5),
            ));
        }
    }
    // Arcade beams on the pillars along both rows.
    for y in [-1.6f32, 1.6] {
        pillars.append(&cuboid(
            Vec3::new(1.7, y - 0.3, 4.5),
            Vec3::new(18.3, y + 0.3, 5.0),
        ));
    }
    a.mesh(pillars, stone);
    let mut panes = TriangleMesh::default();
    for (lo, hi) in lit.iter().chain(&unlit) {
        let c = Vec3::new((lo[0] + hi[0]) * 0.5, 0.0, (lo[1] + hi[1]) * 0.5);
        let y = if lit.contains(&(*lo, *hi)) {
            HALF_WIDTH
        } else {
            -HALF_WIDTH
        };
        panes.append(&TriangleMesh::quad(
            c + Vec3::Y * y,
            Vec3::X * 0.25,
            Vec3::Z * 0.8,
        ));
    }
    a.mesh(panes, glass);
    // A 24 m x 12 m emitter 4 m outside the lit wall, facing the hall (-y).
    let light = TriangleMesh::quad(
        Vec3::new(LENGTH * 0.5, HALF_WIDTH + 4.0, 6.0),
        Vec3::X * 12.0,
        Vec3::Z * 6.0,
    );
    a.emitter(ShapeKind::Mesh(light), lamp, Rgb::splat(40.0));
    a.finish(
        "hall-windows",
        camera(Vec3::new(0.6, -1.0, 1.7), Vec3::new(LENGTH, 0.8, 4.0), 65.0),
        RenderDefaults {
            width: 640,
            height: 360,
            spp: 64,
            max_depth: 8,
            options: Vec::new(),
        },
    )
}
