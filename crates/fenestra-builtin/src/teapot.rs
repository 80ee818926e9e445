//! The Utah teapot from Newell's Bezier patch data (data/teapot.txt), tessellated, in a
//! diffuse box with checker-textured walls lit by an area light: the kettle scene of seed 003
//! (§2.6, Table 2.1) with anisotropic Ward (alpha_x 0.18, alpha_y 0.09).

use crate::geometry::{camera, checker, cuboid, Assembler};
use fenestra_core::{Rgb, Vec3};
use fenestra_scene::material;
use fenestra_scene::mesh::smooth_normals;
use fenestra_scene::texture::ImageTexture;
use fenestra_scene::{Material, RenderDefaults, SceneDesc, ShapeKind, TriangleMesh};
use std::sync::Arc;

const DATA: &str = include_str!("data/teapot.txt");

/// Patches (16 zero-based control point indices each) and control points of the data file.
fn patch_data() -> (Vec<[usize; 16]>, Vec<Vec3>) {
    let mut patches = Vec::new();
    let mut points = Vec::new();
    let mut section = "";
    for line in DATA.lines().filter(|l| !l.starts_with('#')) {
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.as_slice() {
            [s @ ("patches" | "points"), _] => section = s,
            _ if section == "patches" => {
                let idx: Vec<usize> = words
                    .iter()
                    .filter_map(|w| w.parse::<usize>().ok())
                    .collect();
                patches.push(std::array::from_fn(|k| idx[k] - 1));
            }
            _ => {
                let v: Vec<f32> = words.iter().filter_map(|w| w.parse().ok()).collect();
                points.push(Vec3::new(v[0], v[1], v[2]));
            }
        }
    }
    (patches, points)
}

fn bernstein(t: f32) -> [f32; 4] {
    let s = 1.0 - t;
    [s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t]
}

/// The teapot as `n` x `n` quads per patch (2 n^2 triangles each, 32 patches), scaled by
/// `scale` and moved to `base`, with smooth vertex normals (averaged across patch seams and
/// the degenerate corners at the lid and bottom poles).
pub fn teapot_mesh(n: usize, scale: f32, base: Vec3) -> TriangleMesh {
    let (patches, cp) = patch_data();
    let mut mesh = TriangleMesh::default();
    for patch in &patches {
        let first = mesh.positions.len() as u32;
        for i in 0..=n {
            let bu = bernstein(i as f32 / n as f32);
            for j in 0..=n {
                let bv = bernstein(j as f32 / n as f32);
                let mut p = Vec3::ZERO;
                for (r, wu) in bu.iter().enumerate() {
                    for (c, wv) in bv.iter().enumerate() {
                        p += cp[patch[4 * r + c]] * (wu * wv);
                    }
                }
                mesh.positions.push(base + p * scale);
            }
        }
        let at = |i: usize, j: usize| first + (i * (n + 1) + j) as u32;
        for i in 0..n {
            for j in 0..n {
                // Ordered so that the normal points out of the pot.
                for t in [
                    [at(i, j), at(i + 1, j + 1), at(i + 1, j)],
                    [at(i, j), at(i, j + 1), at(i + 1, j + 1)],
                ] {
                    let [a, b, c] = t.map(|k| mesh.positions[k as usize]);
                    if (b - a).cross(c - a).length_squared() > 0.0 {
                        mesh.indices.push(t);
                    }
                }
            }
        }
    }
    smooth_normals(&mut mesh);
    mesh
}

/// The seed's kettle scene: a brushed-metal (anisotropic Ward) teapot in a box.
pub fn teapot_box() -> SceneDesc {
    kettle_box(
        "teapot-box",
        Material::Ward(material::Ward {
            diffuse: Rgb::new(0.05, 0.05, 0.06),
            specular: Rgb::new(0.6, 0.55, 0.45),
            alpha_x: 0.18,
            alpha_y: 0.09,
        }),
    )
}

/// The kettle scene with a Phong kettle of lobe `exponent` (seed 003 Fig. 2.5).
pub fn teapot_box_phong(exponent: f32) -> SceneDesc {
    kettle_box(
        &format!("teapot-box-phong-{exponent}"),
        Material::Phong(material::Phong {
            diffuse: Rgb::new(0.05, 0.05, 0.06),
            specular: Rgb::new(0.6, 0.55, 0.45),
            exponent,
        }),
    )
}

/// The teapot of material `kettle` in the box.
fn kettle_box(name: &str, kettle: Material) -> SceneDesc {
    let mut a = Assembler::default();
    let walls = a.material(Material::TexturedDiffuse(material::TexturedDiffuse {
        texture: Arc::new(ImageTexture::new(
            Arc::new(checker(
                8,
                16,
                Rgb::new(0.7, 0.7, 0.68),
                Rgb::new(0.3, 0.32, 0.35),
            )),
            "checker.exr".into(),
        )),
    }));
    let kettle = a.material(kettle);
    let lamp = a.material(Material::diffuse(0.0));
    // A 2 m box, its floor at z = 0.
    a.mesh(
        cuboid(Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, 1.0, 2.0)),
        walls,
    );
    a.mesh(teapot_mesh(12, 0.22, Vec3::new(0.0, 0.1, 0.0)), kettle);
    let light = TriangleMesh::quad(Vec3::new(0.0, 0.0, 1.99), Vec3::Y * 0.3, Vec3::X * 0.3);
    a.emitter(ShapeKind::Mesh(light), lamp, Rgb::splat(25.0));
    a.finish(
        name,
        camera(Vec3::new(0.0, -0.95, 1.0), Vec3::new(0.0, 0.1, 0.35), 60.0),
        RenderDefaults {
            width: 512,
            height: 512,
            spp: 64,
            max_depth: 8,
            options: Vec::new(),
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn teapot_is_closed_and_upright() {
        let (patches, points) = patch_data();
        assert_eq!((patches.len(), points.len()), (32, 306));
        let m = teapot_mesh(8, 1.0, Vec3::ZERO);
        let top = m.positions.iter().map(|p| p.z).fold(f32::MIN, f32::max);
        assert!((top - 3.15).abs() < 1e-4, "lid knob at 3.15, got {top}");
        // Outward orientation: the signed volume (divergence theorem) is positive.
        let vol: f32 = (0..m.indices.len())
            .map(|t| {
                let [a, b, c] = m.triangle(t);
                a.dot(b.cross(c)) / 6.0
            })
            .sum();
        assert!(vol > 10.0, "volume {vol}");
        // Vertex normals agree with the outward faces around them.
        let normals = m.normals.as_ref().expect("normals");
        let agree = (0..m.indices.len())
            .filter(|&t| {
                let [a, b, c] = m.triangle(t);
                normals[m.indices[t][0] as usize].dot((b - a).cross(c - a)) > 0.0
            })
            .count();
        assert!(
            agree as f64 > 0.99 * m.indices.len() as f64,
            "{agree} of {}",
            m.indices.len()
        );
    }
}
