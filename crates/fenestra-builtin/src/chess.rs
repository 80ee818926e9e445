//! A chess scene after seed 003 Fig. 2.6: white pieces of anisotropic Ward (alpha 0.10 /
//! 0.16), black pieces of Phong (exponent 30), a Phong board (exponent 14) on a table, lit by
//! five spot lights and a sky. Glossy, curved surfaces everywhere: caches reuse records over
//! few pixels, and much of what the pieces reflect is light from each other and the board.

use crate::geometry::{camera, cuboid, sky, Assembler};
use fenestra_core::{Rgb, Vec3};
use fenestra_scene::light::LightDesc;
use fenestra_scene::material;
use fenestra_scene::mesh::{grid, smooth_normals};
use fenestra_scene::{Material, RenderDefaults, SceneDesc, TriangleMesh};
use std::f32::consts::{FRAC_PI_2, PI, TAU};

/// A board square's side (m); the board's centre is the origin, its top at z = 0.
const SQUARE: f32 = 0.05;

/// Pieces, as lathe profiles (and a few boxes for the knight's head and the king's cross).
#[derive(Clone, Copy)]
enum Piece {
    Pawn,
    Rook,
    Knight,
    Bishop,
    Queen,
    King,
}

/// A mid-game position: (piece, file 0-7, rank 0-7) for white, then black.
const WHITE: &[(Piece, u8, u8)] = &[
    (Piece::King, 6, 0),
    (Piece::Queen, 3, 2),
    (Piece::Rook, 0, 0),
    (Piece::Rook, 5, 0),
    (Piece::Bishop, 2, 3),
    (Piece::Bishop, 4, 2),
    (Piece::Knight, 5, 2),
    (Piece::Pawn, 0, 1),
    (Piece::Pawn, 1, 1),
    (Piece::Pawn, 2, 2),
    (Piece::Pawn, 4, 3),
    (Piece::Pawn, 5, 1),
    (Piece::Pawn, 6, 1),
    (Piece::Pawn, 7, 2),
];
const BLACK: &[(Piece, u8, u8)] = &[
    (Piece::King, 6, 7),
    (Piece::Queen, 4, 6),
    (Piece::Rook, 0, 7),
    (Piece::Rook, 5, 7),
    (Piece::Bishop, 2, 4),
    (Piece::Knight, 2, 5),
    (Piece::Knight, 5, 5),
    (Piece::Pawn, 0, 6),
    (Piece::Pawn, 1, 5),
    (Piece::Pawn, 3, 5),
    (Piece::Pawn, 4, 4),
    (Piece::Pawn, 5, 6),
    (Piece::Pawn, 6, 6),
    (Piece::Pawn, 7, 6),
];

/// The chess scene.
pub fn chess() -> SceneDesc {
    let mut a = Assembler::default();
    let ivory = a.material(Material::Ward(material::Ward {
        diffuse: Rgb::new(0.55, 0.52, 0.45),
        specular: Rgb::splat(0.25),
        alpha_x: 0.10,
        alpha_y: 0.16,
    }));
    let ebony = a.material(Material::Phong(material::Phong {
        diffuse: Rgb::splat(0.02),
        specular: Rgb::splat(0.35),
        exponent: 30.0,
    }));
    let light_square = a.material(Material::Phong(material::Phong {
        diffuse: Rgb::new(0.60, 0.52, 0.40),
        specular: Rgb::splat(0.15),
        exponent: 14.0,
    }));
    let dark_square = a.material(Material::Phong(material::Phong {
        diffuse: Rgb::new(0.16, 0.09, 0.05),
        specular: Rgb::splat(0.15),
        exponent: 14.0,
    }));
    let frame = a.material(Material::diffuse(0.12));
    let table = a.material(Material::diffuse(0.45));

    // The board: 8 x 8 squares on a slab with a border, on a large table.
    let (mut light, mut dark) = (TriangleMesh::default(), TriangleMesh::default());
    for file in 0..8u8 {
        for rank in 0..8u8 {
            let quad = TriangleMesh::quad(
                square(file, rank).with_z(0.0),
                Vec3::X * (SQUARE * 0.5),
                Vec3::Y * (SQUARE * 0.5),
            );
            if (file + rank).is_multiple_of(2) {
                dark.append(&quad);
            } else {
                light.append(&quad);
            }
        }
    }
    a.mesh(light, light_square);
    a.mesh(dark, dark_square);
    let half = 4.0 * SQUARE + 0.02;
    a.mesh(
        cuboid(
            Vec3::new(-half, -half, -0.025),
            Vec3::new(half, half, -0.001),
        ),
        frame,
    );
    a.mesh(
        TriangleMesh::quad(Vec3::new(0.0, 0.0, -0.025), Vec3::X * 2.0, Vec3::Y * 2.0),
        table,
    );

    // Each side's knights face the other side.
    for (set, material, facing) in [(WHITE, ivory, 1.0), (BLACK, ebony, -1.0)] {
        let (mut turned, mut boxes) = (TriangleMesh::default(), TriangleMesh::default());
        for &(piece, file, rank) in set {
            let at = square(file, rank);
            turned.append(&lathe(&profile(piece), at));
            boxes.append(&details(piece, at, facing));
        }
        smooth_normals(&mut turned);
        a.mesh(turned, material);
        a.mesh(boxes, material);
    }

    // Five spot lights around the board, aimed at its centre, and a sky.
    for k in 0..5 {
        let phi = FRAC_PI_2 + 0.35 + TAU * k as f32 / 5.0;
        let position = Vec3::new(0.9 * phi.cos(), 0.9 * phi.sin(), 0.85);
        a.lights.push(LightDesc::Spot {
            position,
            direction: (Vec3::new(0.0, 0.0, 0.02) - position).normalize(),
            intensity: Rgb::new(1.0, 0.93, 0.82) * (1.4 + 0.3 * k as f32),
            cone_angle: 22.0,
            falloff_start: 14.0,
        });
    }
    let to_sun = Vec3::new(0.6, 0.5, 0.6).normalize();
    a.lights
        .push(LightDesc::Environment(sky(256, 128, to_sun, 0.35)));
    a.finish(
        "chess",
        camera(
            Vec3::new(0.12, -0.52, 0.27),
            Vec3::new(0.0, 0.02, 0.02),
            42.0,
        ),
        RenderDefaults {
            width: 400,
            height: 300,
            spp: 64,
            max_depth: 6,
            options: Vec::new(),
        },
    )
}

/// The centre of a square on the board's top.
fn square(file: u8, rank: u8) -> Vec3 {
    let c = |i: u8| (i as f32 - 3.5) * SQUARE;
    Vec3::new(c(file), c(rank), 0.0)
}

/// A piece's outline as (radius, height) pairs from the base's centre to the top's, in
/// metres.
fn profile(piece: Piece) -> Vec<(f32, f32)> {
    let mut p = vec![(0.0, 0.0), (0.018, 0.0), (0.018, 0.004), (0.015, 0.007)];
    let ball = |p: &mut Vec<(f32, f32)>, z: f32, r: f32| {
        // The upper part of a ball of radius r centred at height z, from its side up.
        for k in 0..=8 {
            let a = -0.6 + (FRAC_PI_2 + 0.6) * k as f32 / 8.0;
            p.push((r * a.cos(), z + r * a.sin()));
        }
    };
    match piece {
        Piece::Pawn => {
            p.extend([
                (0.011, 0.010),
                (0.006, 0.026),
                (0.010, 0.028),
                (0.006, 0.031),
            ]);
            ball(&mut p, 0.039, 0.009);
        }
        Piece::Rook => p.extend([
            (0.012, 0.010),
            (0.010, 0.034),
            (0.014, 0.036),
            (0.014, 0.048),
            (0.010, 0.048),
            (0.010, 0.044),
            (0.0, 0.044),
        ]),
        Piece::Knight => p.extend([(0.012, 0.010), (0.010, 0.020), (0.012, 0.022), (0.0, 0.022)]),
        Piece::Bishop => {
            p.extend([
                (0.011, 0.010),
                (0.006, 0.036),
                (0.011, 0.038),
                (0.006, 0.041),
            ]);
            // The mitre: a pointed ellipsoid, then a small ball.
            for k in 0..=8 {
                let a = -FRAC_PI_2 + PI * k as f32 / 8.0;
                p.push((0.0085 * a.cos(), 0.051 + 0.011 * a.sin()));
            }
            ball(&mut p, 0.066, 0.003);
        }
        Piece::Queen => {
            p.extend([
                (0.012, 0.010),
                (0.007, 0.048),
                (0.012, 0.050),
                (0.008, 0.053),
                (0.013, 0.064),
                (0.009, 0.064),
                (0.007, 0.062),
            ]);
            ball(&mut p, 0.066, 0.005);
        }
        Piece::King => p.extend([
            (0.012, 0.010),
            (0.008, 0.052),
            (0.013, 0.054),
            (0.009, 0.057),
            (0.012, 0.068),
            (0.0, 0.069),
        ]),
    }
    p
}

/// A closed surface of revolution of `profile` about the vertical through `at`.
fn lathe(profile: &[(f32, f32)], at: Vec3) -> TriangleMesh {
    let rings = profile.len() - 1;
    grid(48, rings, true, |s, t| {
        let (r, z) = profile[(t * rings as f32).round() as usize];
        let phi = TAU * s;
        at + Vec3::new(r * phi.cos(), r * phi.sin(), z)
    })
}

/// The knight's head and the king's cross (boxes); `facing` +-1 turns the head along y.
fn details(piece: Piece, at: Vec3, facing: f32) -> TriangleMesh {
    let b = |lo: Vec3, hi: Vec3| cuboid(at + lo, at + hi);
    match piece {
        Piece::Knight => {
            let mut m = b(
                Vec3::new(-0.006, -0.009, 0.020),
                Vec3::new(0.006, 0.009, 0.046),
            );
            let (y0, y1) = if facing > 0.0 {
                (0.0, 0.017)
            } else {
                (-0.017, 0.0)
            };
            m.append(&b(
                Vec3::new(-0.005, y0, 0.032),
                Vec3::new(0.005, y1, 0.043),
            ));
            m
        }
        Piece::King => {
            let mut m = b(
                Vec3::new(-0.002, -0.002, 0.068),
                Vec3::new(0.002, 0.002, 0.084),
            );
            m.append(&b(
                Vec3::new(-0.006, -0.002, 0.075),
                Vec3::new(0.006, 0.002, 0.079),
            ));
            m
        }
        _ => TriangleMesh::default(),
    }
}
