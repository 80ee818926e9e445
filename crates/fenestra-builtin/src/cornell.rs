//! The Cornell box with its published geometry (Cornell Program of Computer Graphics,
//! "Cornell Box Data", in mm) and a quad light; reflectances and emission as commonly used
//! (Mitsuba's cbox). The data's y-up frame is turned to fenestra's z-up by the rotation
//! (x, y, z) -> (-x, z, y), in metres, which keeps the red wall on the left.

use crate::geometry::{camera, Assembler};
use fenestra_core::{Rgb, Vec3};
use fenestra_scene::material;
use fenestra_scene::{Material, RenderDefaults, SceneDesc, ShapeKind, TriangleMesh};

fn p(x: f32, y: f32, z: f32) -> Vec3 {
    Vec3::new(-x, z, y) * 0.001
}

/// Quads as listed in the data (four corners in order).
fn quads(corners: &[[f32; 12]]) -> TriangleMesh {
    let mut m = TriangleMesh::default();
    for c in corners {
        let base = m.positions.len() as u32;
        for k in 0..4 {
            m.positions.push(p(c[3 * k], c[3 * k + 1], c[3 * k + 2]));
        }
        m.indices.push([base, base + 1, base + 2]);
        m.indices.push([base, base + 2, base + 3]);
    }
    m
}

pub fn cornell_box() -> SceneDesc {
    let mut a = Assembler::default();
    let white = a.material(Material::Diffuse(material::Diffuse {
        reflectance: Rgb::new(0.725, 0.71, 0.68),
    }));
    let red = a.material(Material::Diffuse(material::Diffuse {
        reflectance: Rgb::new(0.63, 0.065, 0.05),
    }));
    let green = a.material(Material::Diffuse(material::Diffuse {
        reflectance: Rgb::new(0.14, 0.45, 0.091),
    }));
    let lamp = a.material(Material::diffuse(0.78));
    a.mesh(
        quads(&[
            // floor, ceiling, back wall
            [
                552.8, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 559.2, 549.6, 0.0, 559.2,
            ],
            [
                556.0, 548.8, 0.0, 556.0, 548.8, 559.2, 0.0, 548.8, 559.2, 0.0, 548.8, 0.0,
            ],
            [
                549.6, 0.0, 559.2, 0.0, 0.0, 559.2, 0.0, 548.8, 559.2, 556.0, 548.8, 559.2,
            ],
            // short block
            [
                130.0, 165.0, 65.0, 82.0, 165.0, 225.0, 240.0, 165.0, 272.0, 290.0, 165.0, 114.0,
            ],
            [
                290.0, 0.0, 114.0, 290.0, 165.0, 114.0, 240.0, 165.0, 272.0, 240.0, 0.0, 272.0,
            ],
            [
                130.0, 0.0, 65.0, 130.0, 165.0, 65.0, 290.0, 165.0, 114.0, 290.0, 0.0, 114.0,
            ],
            [
                82.0, 0.0, 225.0, 82.0, 165.0, 225.0, 130.0, 165.0, 65.0, 130.0, 0.0, 65.0,
            ],
            [
                240.0, 0.0, 272.0, 240.0, 165.0, 272.0, 82.0, 165.0, 225.0, 82.0, 0.0, 225.0,
            ],
            // tall block
            [
                423.0, 330.0, 247.0, 265.0, 330.0, 296.0, 314.0, 330.0, 456.0, 472.0, 330.0, 406.0,
            ],
            [
                423.0, 0.0, 247.0, 423.0, 330.0, 247.0, 472.0, 330.0, 406.0, 472.0, 0.0, 406.0,
            ],
            [
                472.0, 0.0, 406.0, 472.0, 330.0, 406.0, 314.0, 330.0, 456.0, 314.0, 0.0, 456.0,
            ],
            [
                314.0, 0.0, 456.0, 314.0, 330.0, 456.0, 265.0, 330.0, 296.0, 265.0, 0.0, 296.0,
            ],
            [
                265.0, 0.0, 296.0, 265.0, 330.0, 296.0, 423.0, 330.0, 247.0, 423.0, 0.0, 247.0,
            ],
        ]),
        white,
    );
    a.mesh(
        quads(&[[
            552.8, 0.0, 0.0, 549.6, 0.0, 559.2, 556.0, 548.8, 559.2, 556.0, 548.8, 0.0,
        ]]),
        red,
    );
    a.mesh(
        quads(&[[
            0.0, 0.0, 559.2, 0.0, 0.0, 0.0, 0.0, 548.8, 0.0, 0.0, 548.8, 559.2,
        ]]),
        green,
    );
    // The light, 0.1 mm below the ceiling, facing down.
    a.emitter(
        ShapeKind::Mesh(quads(&[[
            343.0, 548.7, 227.0, 343.0, 548.7, 332.0, 213.0, 548.7, 332.0, 213.0, 548.7, 227.0,
        ]])),
        lamp,
        Rgb::new(17.0, 12.0, 4.0),
    );
    // 35 mm lens on a 25 mm film: a 39.3 degree field of view.
    let fov = 2.0 * (12.5f32 / 35.0).atan().to_degrees();
    let cam = camera(p(278.0, 273.0, -800.0), p(278.0, 273.0, 0.0), fov);
    a.finish(
        "cornell-box",
        cam,
        RenderDefaults {
            width: 512,
            height: 512,
            spp: 64,
            max_depth: 8,
            options: Vec::new(),
        },
    )
}
