//! The animated room of the relighting system (issue 14, seed 003 ch. 4): a closed 6 x 4 x 3 m
//! room of diffuse surfaces (a warm floor, white walls, a red and a blue end wall) with a
//! table, and two objects that move through it over 100 frames, an orange crate that slides
//! and turns across the floor and a green screen that glides along the back wall, while the
//! camera dollies; two point lights under the ceiling and a spot on the back wall, which a
//! lighting artist moves and recolours at run time. Every surface is Lambertian, so that
//! direct light plus one diffuse bounce, what relighting computes, is the whole of a
//! path-traced image of path length 2 (`--max-depth 3`), its ground truth.

use crate::geometry::{camera, cuboid, Assembler};
use fenestra_core::{Rgb, Vec3};
use fenestra_scene::light::LightDesc;
use fenestra_scene::material;
use fenestra_scene::{Material, RenderDefaults, SceneDesc, Shape, ShapeKind, TriangleMesh};

/// Room size (m).
const W: f32 = 6.0;
const D: f32 = 4.0;
const H: f32 = 3.0;

/// The room at rest (frame 0 of [`ANIMATION`]).
pub fn relight_room() -> SceneDesc {
    let mut a = Assembler::default();
    let white = a.material(Material::diffuse(0.75));
    let floor = a.material(Material::Diffuse(material::Diffuse {
        reflectance: Rgb::new(0.55, 0.40, 0.25),
    }));
    let red = a.material(Material::Diffuse(material::Diffuse {
        reflectance: Rgb::new(0.70, 0.12, 0.08),
    }));
    let blue = a.material(Material::Diffuse(material::Diffuse {
        reflectance: Rgb::new(0.10, 0.22, 0.65),
    }));
    let orange = a.material(Material::Diffuse(material::Diffuse {
        reflectance: Rgb::new(0.85, 0.45, 0.08),
    }));
    let green = a.material(Material::Diffuse(material::Diffuse {
        reflectance: Rgb::new(0.15, 0.60, 0.20),
    }));

    // Floor, ceiling, the white long walls and the coloured end walls, every face inwards
    // (one surface per wall: gather samples on a wall hidden behind another would stand in
    // the dark next to lit ones, and transfer mixes neighbours).
    let quad = TriangleMesh::quad;
    let half = |v: Vec3| v * 0.5;
    a.mesh(
        quad(
            Vec3::new(W / 2.0, D / 2.0, 0.0),
            half(Vec3::X * W),
            half(Vec3::Y * D),
        ),
        floor,
    );
    let mut white_walls = quad(
        Vec3::new(W / 2.0, D / 2.0, H),
        half(Vec3::Y * D),
        half(Vec3::X * W),
    );
    white_walls.append(&quad(
        Vec3::new(W / 2.0, 0.0, H / 2.0),
        half(Vec3::Z * H),
        half(Vec3::X * W),
    ));
    white_walls.append(&quad(
        Vec3::new(W / 2.0, D, H / 2.0),
        half(Vec3::X * W),
        half(Vec3::Z * H),
    ));
    a.mesh(white_walls, white);
    a.mesh(
        quad(
            Vec3::new(0.0, D / 2.0, H / 2.0),
            half(Vec3::Y * D),
            half(Vec3::Z * H),
        ),
        red,
    );
    a.mesh(
        quad(
            Vec3::new(W, D / 2.0, H / 2.0),
            half(Vec3::Z * H),
            half(Vec3::Y * D),
        ),
        blue,
    );
    // A table: top and four legs.
    let mut table = cuboid(Vec3::new(3.6, 2.2, 0.72), Vec3::new(5.0, 3.2, 0.78));
    for (x, y) in [(3.65, 2.25), (4.9, 2.25), (3.65, 3.1), (4.9, 3.1)] {
        table.append(&cuboid(
            Vec3::new(x, y, 0.0),
            Vec3::new(x + 0.05, y + 0.05, 0.72),
        ));
    }
    a.mesh(table, white);
    // The moving objects, named for the animation's tracks.
    a.shapes.push(
        Shape::new(
            ShapeKind::Mesh(cuboid(Vec3::new(1.0, 2.0, 0.0), Vec3::new(1.8, 2.8, 0.8))),
            orange,
        )
        .named("crate"),
    );
    a.shapes.push(
        Shape::new(
            ShapeKind::Mesh(cuboid(Vec3::new(0.6, 3.55, 0.3), Vec3::new(2.2, 3.7, 2.1))),
            green,
        )
        .named("screen"),
    );
    a.lights = vec![
        LightDesc::Point {
            position: Vec3::new(1.8, 1.4, 2.6),
            intensity: Rgb::new(9.0, 8.0, 6.5),
        },
        LightDesc::Point {
            position: Vec3::new(4.4, 1.2, 2.5),
            intensity: Rgb::new(5.0, 6.0, 8.0),
        },
        LightDesc::Spot {
            position: Vec3::new(3.0, 0.6, 2.7),
            direction: Vec3::new(0.0, 1.0, -0.55).normalize(),
            intensity: Rgb::splat(30.0),
            cone_angle: 28.0,
            falloff_start: 20.0,
        },
    ];
    a.finish(
        "relight-room",
        camera(Vec3::new(3.0, 0.15, 1.5), Vec3::new(3.0, 4.0, 1.0), 75.0),
        RenderDefaults {
            width: 320,
            height: 240,
            spp: 64,
            max_depth: 3,
            options: Vec::new(),
        },
    )
}

/// The room's animation (docs/relight.md's format): 100 frames; the crate slides 3.3 m across
/// the floor turning half a turn, the screen glides 2.8 m along the back wall, the camera
/// dollies sideways and back.
pub const ANIMATION: &str = r#"{
  "frames": 100,
  "interpolation": "smooth",
  "camera": [
    { "frame": 0, "eye": [2.6, 0.15, 1.5], "target": [3.0, 4.0, 1.0], "fov": 75 },
    { "frame": 99, "eye": [3.4, 0.3, 1.6], "target": [3.0, 4.0, 1.0], "fov": 75 }
  ],
  "objects": {
    "crate": [
      { "frame": 0 },
      { "frame": 50, "translate": [1.6, 0.2, 0], "rotate": [0, 0, 1, 90] },
      { "frame": 99, "translate": [3.2, -0.9, 0], "rotate": [0, 0, 1, 180] }
    ],
    "screen": [
      { "frame": 10 },
      { "frame": 90, "translate": [2.8, 0, 0] }
    ]
  }
}"#;
