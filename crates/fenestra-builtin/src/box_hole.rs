//! The box scenes of seed 000 §5.2: a 1 m cube centred at the origin (Z up) with thin
//! diffuse walls of albedo 0.75, light entering through square holes in the ceiling.

use crate::geometry::{transposed, wall_with_openings, Rect};
use fenestra_core::{Rgb, Vec3, PI};
use fenestra_scene::light::{Emission, EnvironmentDesc, LightDesc};
use fenestra_scene::mesh::grid;
use fenestra_scene::{Camera, Material, RenderDefaults, SceneDesc, Shape, ShapeKind, TriangleMesh};

pub enum Variant {
    /// One 0.25 m hole in the ceiling centre, 25 W emitter above.
    OneHole,
    /// Four 0.125 m holes, each with a corner 0.125 m from a ceiling corner along x and y.
    FourHoles,
    /// One hole, no emitter, a constant sky of radiance 1.
    Sky,
}

const WALL: usize = 0;
const EMITTER: usize = 1;

fn holes(v: &Variant) -> Vec<Rect> {
    match v {
        Variant::OneHole | Variant::Sky => vec![([-0.125, -0.125], [0.125, 0.125])],
        Variant::FourHoles => [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
            .iter()
            .map(|&(sx, sy): &(f32, f32)| {
                // Near corner 0.375 from the centre (0.125 from the wall), far one 0.25.
                let (x0, x1) = ((0.25 * sx).min(0.375 * sx), (0.25 * sx).max(0.375 * sx));
                let (y0, y1) = ((0.25 * sy).min(0.375 * sy), (0.25 * sy).max(0.375 * sy));
                ([x0, y0], [x1, y1])
            })
            .collect(),
    }
}

/// The ceiling (z = 0.5) minus the holes, facing into the box (-z).
fn ceiling(holes: &[Rect]) -> TriangleMesh {
    // Wall coordinates (s, t) = (y, x): the normal u x v = y x x = -z.
    wall_with_openings(
        Vec3::new(0.0, 0.0, 0.5),
        Vec3::Y,
        Vec3::X,
        ([-0.5, -0.5], [0.5, 0.5]),
        &transposed(holes),
    )
}

/// Floor and the four side walls, normals facing into the box.
fn walls() -> TriangleMesh {
    let h = 0.5;
    let mut m = TriangleMesh::quad(Vec3::new(0.0, 0.0, -h), Vec3::X * h, Vec3::Y * h); // floor, +z
    m.append(&TriangleMesh::quad(
        Vec3::new(-h, 0.0, 0.0),
        Vec3::Y * h,
        Vec3::Z * h,
    )); // x = -0.5, +x
    m.append(&TriangleMesh::quad(
        Vec3::new(h, 0.0, 0.0),
        Vec3::Z * h,
        Vec3::Y * h,
    )); // x = +0.5, -x
    m.append(&TriangleMesh::quad(
        Vec3::new(0.0, -h, 0.0),
        Vec3::Z * h,
        Vec3::X * h,
    )); // y = -0.5, +y
    m.append(&TriangleMesh::quad(
        Vec3::new(0.0, h, 0.0),
        Vec3::X * h,
        Vec3::Z * h,
    )); // y = +0.5, -y
    m
}

pub fn box_scene(variant: Variant) -> SceneDesc {
    let name = match variant {
        Variant::OneHole => "box-hole",
        Variant::FourHoles => "box-4holes",
        Variant::Sky => "box-hole-sky",
    };
    let mut shapes = vec![
        Shape::new(ShapeKind::Mesh(walls()), WALL),
        Shape::new(ShapeKind::Mesh(ceiling(&holes(&variant))), WALL),
    ];
    let mut lights = Vec::new();
    match variant {
        Variant::Sky => lights.push(LightDesc::Environment(EnvironmentDesc::Constant(Rgb::ONE))),
        _ => {
            // 0.95 m square, centred 0.05 m above the ceiling, facing down, 25 W.
            let h = 0.95 * 0.5;
            let quad = TriangleMesh::quad(Vec3::new(0.0, 0.0, 0.55), Vec3::Y * h, Vec3::X * h);
            let emission = Emission::from_power(Rgb::splat(25.0), 0.95 * 0.95, false);
            shapes.push(Shape::new(ShapeKind::Mesh(quad), EMITTER).emitting(emission));
        }
    }
    // The holes themselves are the manual portals (seed 000's mLP_HF).
    let portals = holes(&variant)
        .iter()
        .map(|(lo, hi)| {
            [
                Vec3::new(lo[0], lo[1], 0.5),
                Vec3::new(hi[0], lo[1], 0.5),
                Vec3::new(hi[0], hi[1], 0.5),
                Vec3::new(lo[0], hi[1], 0.5),
            ]
        })
        .collect();
    SceneDesc {
        name: name.into(),
        shapes,
        materials: vec![Material::diffuse(0.75), Material::diffuse(0.0)],
        lights,
        camera: box_camera(),
        defaults: RenderDefaults {
            width: 256,
            height: 256,
            spp: 64,
            max_depth: 6,
            options: Vec::new(),
        },
        portals,
    }
}

fn box_camera() -> Camera {
    // Fixed valid parameters: look_at cannot fail here.
    Camera::look_at(
        Vec3::new(0.0, -0.45, 0.0),
        Vec3::new(0.0, 0.5, 0.0),
        Vec3::Z,
        60.0,
    )
    .unwrap_or_else(|e| unreachable!("{e}"))
}

/// box-hole with a bumpy sphere of 2 x 512 x 1024 = 1,048,576 triangles standing on the floor.
pub fn box_blob() -> SceneDesc {
    let mut desc = box_scene(Variant::OneHole);
    desc.name = "box-blob".into();
    let (nt, np) = (512usize, 1024usize);
    let centre = Vec3::new(0.0, 0.15, -0.28);
    let radius = 0.2;
    let mesh = grid(np, nt, true, |s, t| {
        let (theta, phi) = (PI * t, 2.0 * PI * s);
        let r = radius * (1.0 + 0.06 * (12.0 * theta).sin() * (9.0 * phi).sin());
        let d = Vec3::new(
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        );
        centre + d * r
    });
    desc.shapes.push(Shape::new(ShapeKind::Mesh(mesh), WALL));
    desc
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(m: &TriangleMesh) -> f32 {
        (0..m.indices.len()).map(|i| m.triangle_area(i)).sum()
    }

    #[test]
    fn ceilings_have_the_seed_holes() {
        assert!((area(&ceiling(&holes(&Variant::OneHole))) - (1.0 - 0.25 * 0.25)).abs() < 1e-5);
        let four = holes(&Variant::FourHoles);
        assert!((area(&ceiling(&four)) - (1.0 - 4.0 * 0.125 * 0.125)).abs() < 1e-5);
        // One hole's near corner 0.125 m from the ceiling corner (0.5, 0.5).
        assert!(four
            .iter()
            .any(|(_, hi)| (hi[0] - 0.375).abs() < 1e-6 && (hi[1] - 0.375).abs() < 1e-6));
        // The ceiling faces into the box.
        let c = ceiling(&four);
        let [a, b, d] = c.triangle(0);
        assert!((b - a).cross(d - a).z < 0.0);
    }

    #[test]
    fn emitter_radiates_25_watts_downwards() {
        let s = box_scene(Variant::OneHole);
        let e = s
            .shapes
            .iter()
            .find(|s| s.emission.is_some())
            .expect("emitter");
        let ShapeKind::Mesh(m) = &e.kind else {
            panic!("emitter is a mesh")
        };
        let [a, b, c] = m.triangle(0);
        assert!((b - a).cross(c - a).z < 0.0, "faces down");
        let power = e.emission.expect("emission").radiance.r * PI * e.area();
        assert!((power - 25.0).abs() < 1e-3);
        assert!((e.area() - 0.9025).abs() < 1e-5);
    }
}
