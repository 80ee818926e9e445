//! Many-light analogue of seed 004's Kitchen (Table 4.1): 72 small ceiling downlights,
//! cabinets, an island, a fridge and a range hood as occluders, a glossy floor. The windows
//! are behind the camera; `kitchen-72-env` adds a sky seen through them (Kitchen 2).

use crate::geometry::{camera, cuboid, room, sky, Assembler, Rect};
use crate::teapot::teapot_mesh;
use fenestra_core::{Rgb, Vec3};
use fenestra_scene::light::LightDesc;
use fenestra_scene::material;
use fenestra_scene::{Material, RenderDefaults, SceneDesc, ShapeKind, TriangleMesh};

/// Room: x in [0, 6], y in [0, 5], z in [0, 2.7]; windows in the y = 0 wall.
const W: f32 = 6.0;
const D: f32 = 5.0;
const H: f32 = 2.7;

pub fn kitchen(with_sky: bool) -> SceneDesc {
    let mut a = Assembler::default();
    let paint = a.material(Material::Diffuse(material::Diffuse {
        reflectance: Rgb::new(0.78, 0.76, 0.72),
    }));
    let floor = a.material(Material::Phong(material::Phong {
        diffuse: Rgb::new(0.32, 0.28, 0.24),
        specular: Rgb::splat(0.2),
        exponent: 300.0,
    }));
    let wood = a.material(Material::Diffuse(material::Diffuse {
        reflectance: Rgb::new(0.55, 0.38, 0.22),
    }));
    let counter = a.material(Material::Phong(material::Phong {
        diffuse: Rgb::splat(0.25),
        specular: Rgb::splat(0.15),
        exponent: 80.0,
    }));
    let enamel = a.material(Material::Phong(material::Phong {
        diffuse: Rgb::splat(0.7),
        specular: Rgb::splat(0.1),
        exponent: 40.0,
    }));
    let metal = a.material(Material::RoughConductor(material::RoughConductor {
        eta: Rgb::new(1.657, 0.880, 0.521),
        k: Rgb::new(9.224, 6.270, 4.837),
        alpha_x: 0.2,
        alpha_y: 0.2,
        roughness: None,
    }));
    let pot = a.material(Material::Phong(material::Phong {
        diffuse: Rgb::new(0.5, 0.08, 0.05),
        specular: Rgb::splat(0.2),
        exponent: 120.0,
    }));
    let lamp = a.material(Material::diffuse(0.8));

    // Shell: floor, ceiling, three plain walls and the window wall (y = 0, facing +y).
    let windows: Vec<Rect> = [1.0f32, 3.0, 5.0]
        .iter()
        .map(|&x| ([x - 0.6, 0.9], [x + 0.6, 2.1]))
        .collect();
    let (floor_mesh, shell) = room(W, D, H, &windows);
    a.mesh(floor_mesh, floor);
    a.mesh(shell, paint);

    // Cabinets: lower run along the back wall and the left wall, upper run on the back wall
    // with a gap for the hood, an island, a fridge, a table.
    let b = |x0: f32, y0: f32, z0: f32, x1: f32, y1: f32, z1: f32| {
        cuboid(Vec3::new(x0, y0, z0), Vec3::new(x1, y1, z1))
    };
    let mut cabinets = b(0.0, 4.4, 0.1, W, D, 0.88);
    cabinets.append(&b(0.0, 1.6, 0.1, 0.6, 4.4, 0.88));
    cabinets.append(&b(0.0, 4.65, 1.5, 2.5, D, 2.3));
    cabinets.append(&b(3.5, 4.65, 1.5, W, D, 2.3));
    cabinets.append(&b(2.0, 2.2, 0.1, 4.0, 3.2, 0.88));
    cabinets.append(&b(0.9, 0.7, 0.72, 2.1, 1.5, 0.76)); // table top
    for (x, y) in [(0.95, 0.75), (2.0, 0.75), (0.95, 1.4), (2.0, 1.4)] {
        cabinets.append(&b(x, y, 0.0, x + 0.05, y + 0.05, 0.72));
    }
    a.mesh(cabinets, wood);
    let mut tops = b(0.0, 4.35, 0.88, W, D, 0.92);
    tops.append(&b(0.0, 1.6, 0.88, 0.65, 4.35, 0.92));
    tops.append(&b(1.95, 2.15, 0.88, 4.05, 3.25, 0.92));
    a.mesh(tops, counter);
    a.mesh(b(5.2, 2.5, 0.0, W, 3.4, 2.0), enamel);
    let mut steel = b(2.6, 4.45, 1.7, 3.4, D, H); // range hood
                                                  // Door handles on every lower and upper cabinet door.
    for k in 0..10 {
        let x = 0.3 + 0.6 * k as f32;
        steel.append(&b(x - 0.06, 4.37, 0.72, x + 0.06, 4.4, 0.74));
        if !(2.5..3.5).contains(&x) {
            steel.append(&b(x - 0.06, 4.62, 1.56, x + 0.06, 4.65, 1.58));
        }
    }
    for k in 0..5 {
        let y = 1.9 + 0.6 * k as f32;
        steel.append(&b(0.6, y - 0.06, 0.72, 0.63, y + 0.06, 0.74));
    }
    a.mesh(steel, metal);
    a.mesh(teapot_mesh(12, 0.07, Vec3::new(3.0, 2.7, 0.92)), pot);

    // 72 downlights: a 12 x 6 grid of 0.15 m squares just below the ceiling, facing down.
    for i in 0..12 {
        for j in 0..6 {
            let c = Vec3::new(0.25 + 0.5 * i as f32, 0.45 + 0.82 * j as f32, H - 0.01);
            let quad = TriangleMesh::quad(c, Vec3::Y * 0.075, Vec3::X * 0.075);
            a.emitter(ShapeKind::Mesh(quad), lamp, Rgb::new(90.0, 80.0, 65.0));
        }
    }
    if with_sky {
        // The sun low behind the windows (outside is -y).
        let sun = Vec3::new(0.3, -1.0, 0.5).normalize();
        a.lights
            .push(LightDesc::Environment(sky(512, 256, sun, 2.0)));
    }
    a.finish(
        if with_sky {
            "kitchen-72-env"
        } else {
            "kitchen-72"
        },
        camera(Vec3::new(3.6, 0.4, 1.65), Vec3::new(2.6, 4.5, 0.9), 70.0),
        RenderDefaults {
            width: 640,
            height: 480,
            spp: 64,
            max_depth: 6,
            options: Vec::new(),
        },
    )
}
