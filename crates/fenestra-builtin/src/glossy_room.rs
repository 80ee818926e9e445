//! A glossy interior lit through a window (seed 003 ch. 2's hardest case for path tracing,
//! the third scene): a 5 x 4 m room with a polished wooden floor (Ward, alpha 0.08),
//! a brushed-metal table (anisotropic Ward 0.25/0.05), an aluminium cabinet and a gold ball
//! (GGX conductors), white walls; the sun shines through a window in the -y wall onto the
//! floor, a sky fills the window. Most light the glossy surfaces reflect comes from the sunlit
//! patch and the walls it lights: indirect light.

use crate::geometry::{camera, cuboid, room, sky, Assembler};
use fenestra_core::{Rgb, Vec3};
use fenestra_scene::light::LightDesc;
use fenestra_scene::material;
use fenestra_scene::{Material, RenderDefaults, SceneDesc, TriangleMesh};

/// Room size (m).
const W: f32 = 5.0;
const D: f32 = 4.0;
const H: f32 = 2.7;

/// The glossy room.
pub fn glossy_room() -> SceneDesc {
    let mut a = Assembler::default();
    let white = a.material(Material::diffuse(0.7));
    let floor = a.material(Material::Ward(material::Ward {
        diffuse: Rgb::new(0.30, 0.19, 0.10),
        specular: Rgb::splat(0.12),
        alpha_x: 0.08,
        alpha_y: 0.08,
    }));
    let brushed = a.material(Material::Ward(material::Ward {
        diffuse: Rgb::splat(0.03),
        specular: Rgb::splat(0.75),
        alpha_x: 0.25,
        alpha_y: 0.05,
    }));
    let aluminium = a.material(Material::RoughConductor(material::RoughConductor {
        eta: Rgb::new(1.66, 0.88, 0.52),
        k: Rgb::new(9.22, 6.27, 4.84),
        alpha_x: 0.15,
        alpha_y: 0.15,
        roughness: None,
    }));
    let gold = a.material(Material::RoughConductor(material::RoughConductor {
        eta: Rgb::new(0.143, 0.375, 1.442),
        k: Rgb::new(3.983, 2.386, 1.603),
        alpha_x: 0.1,
        alpha_y: 0.1,
        roughness: None,
    }));

    // The window (2 x 1.4 m) is in the wall at y = 0.
    let (floor_mesh, walls) = room(W, D, H, &[([1.5, 0.8], [3.5, 2.2])]);
    a.mesh(floor_mesh, floor);
    a.mesh(walls, white);

    // A brushed-metal table (top and four legs), a cabinet beside the window, a ball.
    let mut table = cuboid(Vec3::new(1.6, 1.7, 0.72), Vec3::new(3.2, 2.6, 0.76));
    for (x, y) in [(1.7, 1.8), (3.06, 1.8), (1.7, 2.46), (3.06, 2.46)] {
        table.append(&cuboid(
            Vec3::new(x, y, 0.0),
            Vec3::new(x + 0.04, y + 0.04, 0.72),
        ));
    }
    a.mesh(table, brushed);
    a.mesh(
        cuboid(Vec3::new(3.7, 0.05, 0.0), Vec3::new(4.7, 0.55, 0.9)),
        aluminium,
    );
    a.mesh(sphere_mesh(Vec3::new(2.4, 2.15, 0.96), 0.2, 48, 24), gold);

    // The sun, low in the south (outside is -y), through the window onto the floor; the sky.
    let to_sun = Vec3::new(-0.25, -1.0, 0.75).normalize();
    a.lights.push(LightDesc::Distant {
        direction: -to_sun,
        irradiance: Rgb::new(9.0, 8.3, 7.2),
    });
    a.lights
        .push(LightDesc::Environment(sky(512, 256, to_sun, 1.0)));
    a.finish(
        "glossy-room",
        camera(Vec3::new(4.3, 3.7, 1.6), Vec3::new(2.2, 0.9, 0.5), 62.0),
        RenderDefaults {
            width: 320,
            height: 240,
            spp: 64,
            max_depth: 6,
            options: Vec::new(),
        },
    )
}

/// A UV sphere with smooth normals (the ball is a mesh so that it has a tangent frame like
/// the other metals).
fn sphere_mesh(center: Vec3, radius: f32, segments: usize, rings: usize) -> TriangleMesh {
    let mut m = fenestra_scene::mesh::grid(segments, rings, true, |s, t| {
        let (phi, theta) = (std::f32::consts::TAU * s, std::f32::consts::PI * t);
        center
            + radius
                * Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    -theta.cos(),
                )
    });
    m.normals = Some(m.positions.iter().map(|p| (*p - center) / radius).collect());
    m
}
