//! Many-light analogue of seed 004's Grand Central Terminal (Table 4.1): a 90 m x 36 m
//! concourse under a barrel vault with fluted columns along both long walls, two levels of
//! balconies with balustrades, an information booth with its clock; 613 point lights (300
//! along the cornice, 313 "stars" under the vault) and 219 spherical area lights (216 lamps on
//! the balcony edges, the clock and two lanterns). Over 1M triangles.

use crate::geometry::{camera, column, cuboid, Assembler};
use fenestra_core::sampler::{hash_combine, hash_u32};
use fenestra_core::{Rgb, Vec3, PI};
use fenestra_scene::light::{Emission, LightDesc};
use fenestra_scene::material;
use fenestra_scene::mesh::grid;
use fenestra_scene::{Material, RenderDefaults, SceneDesc, Shape, ShapeKind, TriangleMesh};

const HALF_L: f32 = 45.0;
const HALF_W: f32 = 18.0;
/// Height of the walls where the vault springs.
const SPRING: f32 = 22.0;

pub fn terminal() -> SceneDesc {
    let mut a = Assembler::default();
    let stone = a.material(Material::Diffuse(material::Diffuse {
        reflectance: Rgb::new(0.68, 0.62, 0.52),
    }));
    let marble = a.material(Material::Phong(material::Phong {
        diffuse: Rgb::new(0.5, 0.46, 0.4),
        specular: Rgb::splat(0.08),
        exponent: 500.0,
    }));
    let vault_paint = a.material(Material::Diffuse(material::Diffuse {
        reflectance: Rgb::new(0.25, 0.42, 0.42),
    }));
    let brass = a.material(Material::RoughConductor(material::RoughConductor {
        eta: Rgb::new(0.444, 0.527, 1.094),
        k: Rgb::new(3.695, 2.765, 1.829),
        alpha_x: 0.25,
        alpha_y: 0.25,
        roughness: None,
    }));
    let glow = a.material(Material::diffuse(0.8));

    a.mesh(
        TriangleMesh::quad(Vec3::ZERO, Vec3::X * HALF_L, Vec3::Y * HALF_W),
        marble,
    );
    let mut walls = TriangleMesh::default();
    for (c, u, v) in [
        (Vec3::new(0.0, -HALF_W, SPRING / 2.0), Vec3::Z, Vec3::X),
        (Vec3::new(0.0, HALF_W, SPRING / 2.0), Vec3::X, Vec3::Z),
        (Vec3::new(-HALF_L, 0.0, SPRING / 2.0), Vec3::Y, Vec3::Z),
        (Vec3::new(HALF_L, 0.0, SPRING / 2.0), Vec3::Z, Vec3::Y),
    ] {
        let hu = u * if u == Vec3::Z {
            SPRING / 2.0
        } else if u == Vec3::X {
            HALF_L
        } else {
            HALF_W
        };
        let hv = v * if v == Vec3::Z {
            SPRING / 2.0
        } else if v == Vec3::X {
            HALF_L
        } else {
            HALF_W
        };
        walls.append(&TriangleMesh::quad(c, hu, hv));
    }
    // Lunettes closing the vault at both ends.
    for x in [-HALF_L, HALF_L] {
        walls.append(&grid(64, 1, false, |s, t| {
            let phi = PI * s;
            Vec3::new(x, -HALF_W * phi.cos() * t, SPRING + HALF_W * phi.sin() * t)
        }));
    }
    a.mesh(walls, stone);
    // Barrel vault: 512 x 256 quads (262,144 triangles).
    a.mesh(
        grid(512, 256, false, |s, t| {
            let phi = PI * t;
            Vec3::new(
                -HALF_L + 2.0 * HALF_L * s,
                HALF_W * phi.cos(),
                SPRING + HALF_W * phi.sin(),
            )
        }),
        vault_paint,
    );
    // 34 fluted columns of 24,576 triangles each.
    let mut columns = TriangleMesh::default();
    for k in 0..17 {
        let x = -40.0 + 5.0 * k as f32;
        for y in [-HALF_W + 1.6, HALF_W - 1.6] {
            columns.append(&column(
                Vec3::new(x, y, 0.0),
                0.8,
                SPRING,
                128,
                96,
                24.0,
                0.06,
            ));
        }
    }
    a.mesh(columns, stone);
    // Balconies at 8 m and 14 m along both long walls, with balustrades.
    let mut balconies = TriangleMesh::default();
    let mut rails = TriangleMesh::default();
    for z in [8.0f32, 14.0] {
        for side in [-1.0f32, 1.0] {
            let (y_in, y_out) = (side * (HALF_W - 3.2), side * HALF_W);
            balconies.append(&cuboid(
                Vec3::new(-HALF_L, y_in.min(y_out), z - 0.4),
                Vec3::new(HALF_L, y_in.max(y_out), z),
            ));
            rails.append(&cuboid(
                Vec3::new(-HALF_L, y_in - 0.1, z + 1.0),
                Vec3::new(HALF_L, y_in + 0.1, z + 1.1),
            ));
            for b in 0..180 {
                let x = -HALF_L + 0.25 + 0.5 * b as f32;
                rails.append(&cuboid(
                    Vec3::new(x - 0.05, y_in - 0.05, z),
                    Vec3::new(x + 0.05, y_in + 0.05, z + 1.0),
                ));
            }
        }
    }
    a.mesh(balconies, stone);
    // The information booth.
    rails.append(&column(Vec3::ZERO, 3.0, 3.0, 96, 8, 16.0, 0.03));
    rails.append(&grid(96, 8, true, |s, t| {
        let phi = 2.0 * PI * s;
        Vec3::new(
            3.0 * (1.0 - t) * phi.cos(),
            3.0 * (1.0 - t) * phi.sin(),
            3.0,
        )
    }));
    a.mesh(rails, brass);

    // 219 spherical area lights.
    let warm = Rgb::new(1.0, 0.82, 0.6);
    let mut spheres = Vec::new();
    for z in [8.0f32, 14.0] {
        for side in [-1.0f32, 1.0] {
            for k in 0..54 {
                let x = -HALF_L + 1.0 + (2.0 * HALF_L - 2.0) * k as f32 / 53.0;
                spheres.push((
                    Vec3::new(x, side * (HALF_W - 3.2), z + 1.5),
                    0.22,
                    warm * 30.0,
                ));
            }
        }
    }
    spheres.push((Vec3::new(0.0, 0.0, 4.0), 0.6, warm * 12.0)); // the clock
    spheres.push((Vec3::new(-20.0, 0.0, 6.0), 0.5, warm * 20.0));
    spheres.push((Vec3::new(20.0, 0.0, 6.0), 0.5, warm * 20.0));
    for (center, radius, radiance) in spheres {
        a.shapes.push(
            Shape::new(ShapeKind::Sphere { center, radius }, glow)
                .emitting(Emission::radiance(radiance)),
        );
    }
    // 613 point lights: 300 along the cornice, 313 stars scattered under the vault.
    for side in [-1.0f32, 1.0] {
        for k in 0..150 {
            let x = -HALF_L + 0.3 + (2.0 * HALF_L - 0.6) * k as f32 / 149.0;
            a.lights.push(LightDesc::Point {
                position: Vec3::new(x, side * (HALF_W - 0.4), SPRING - 0.5),
                intensity: warm * 25.0,
            });
        }
    }
    for k in 0..313u32 {
        let r = |d: u32| hash_u32(hash_combine(k, d)) as f32 / u32::MAX as f32;
        let (s, t) = (r(0), 0.1 + 0.8 * r(1));
        let phi = PI * t;
        let inset = HALF_W - 0.3;
        a.lights.push(LightDesc::Point {
            position: Vec3::new(
                -HALF_L + 1.0 + (2.0 * HALF_L - 2.0) * s,
                inset * phi.cos(),
                SPRING + inset * phi.sin(),
            ),
            intensity: Rgb::new(0.9, 0.95, 1.0) * 6.0,
        });
    }
    a.finish(
        "terminal-832",
        camera(
            Vec3::new(42.0, -9.0, 9.5),
            Vec3::new(-20.0, 3.0, 11.0),
            70.0,
        ),
        RenderDefaults {
            width: 960,
            height: 540,
            spp: 64,
            max_depth: 6,
            options: Vec::new(),
        },
    )
}
