//! `fenestra prt`: precomputed radiance transfer matrices for the LPCA experiments of seed
//! 003 §3.6.1. For every vertex of a mesh, the transfer vector over a 6 x R x R cubemap of
//! pixel lights: visibility (self-shadowing) x cosine x glossy Phong towards a fixed view,
//! integrated over each cubemap pixel with S x S supersampling.

use crate::progress::Bar;
use anyhow::{bail, Context, Result};
use clap::Args;
use fenestra_core::{Frame, Ray, Vec3, PI};
use fenestra_render::Progress;
use fenestra_scene::{
    Backend, Camera, Material, RenderDefaults, Scene, SceneDesc, Shape, ShapeKind, TriangleMesh,
};
use rayon::prelude::*;
use std::path::PathBuf;

#[derive(Args)]
pub struct PrtArgs {
    /// Segments along the (2,3) torus knot of the procedural mesh.
    #[arg(long, default_value_t = 512)]
    segments: usize,
    /// Vertices around the knot's tube (vertices = segments x sides).
    #[arg(long, default_value_t = 64)]
    sides: usize,
    /// Cubemap face resolution R (columns = 6 R^2).
    #[arg(long, default_value_t = 32)]
    resolution: usize,
    /// Supersampling S x S per cubemap pixel.
    #[arg(long, default_value_t = 4)]
    supersample: usize,
    /// Phong lobe exponent of the glossy material.
    #[arg(long, default_value_t = 20.0)]
    exponent: f32,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Output NPY (float32, vertices x 6 R^2).
    #[arg(short, long)]
    output: PathBuf,
}

/// A (2,3) torus knot tube with ridges: self-shadowing everywhere, smooth vertex normals.
pub fn knot_mesh(segments: usize, sides: usize) -> TriangleMesh {
    let curve = |t: f32| {
        let (p, q) = (2.0, 3.0);
        let r = 1.0 + 0.45 * (q * t).cos();
        Vec3::new(r * (p * t).cos(), r * (p * t).sin(), -0.45 * (q * t).sin())
    };
    let ts: Vec<f32> = (0..segments)
        .map(|i| 2.0 * PI * i as f32 / segments as f32)
        .collect();
    let tangents: Vec<Vec3> = ts
        .iter()
        .map(|&t| (curve(t + 1e-3) - curve(t - 1e-3)).normalize())
        .collect();
    // Parallel-transported normal along the curve.
    let mut normals = Vec::with_capacity(segments);
    let mut n = Frame::from_normal(tangents[0]).s;
    for t in &tangents {
        n = (n - *t * n.dot(*t)).normalize();
        normals.push(n);
    }
    let mut mesh = TriangleMesh::default();
    let mut centres: Vec<Vec3> = Vec::with_capacity(segments * sides);
    for (i, &t) in ts.iter().enumerate() {
        let (c, tn, nn) = (curve(t), tangents[i], normals[i]);
        let b = tn.cross(nn);
        for j in 0..sides {
            let v = 2.0 * PI * j as f32 / sides as f32;
            let radius = 0.2 * (1.0 + 0.18 * (17.0 * t).sin() * (3.0 * v).cos());
            mesh.positions
                .push(c + (nn * v.cos() + b * v.sin()) * radius);
            centres.push(c);
        }
    }
    let idx = |i: usize, j: usize| ((i % segments) * sides + j % sides) as u32;
    for i in 0..segments {
        for j in 0..sides {
            mesh.indices
                .push([idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)]);
            mesh.indices
                .push([idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)]);
        }
    }
    // Area-weighted vertex normals, oriented away from the tube's axis.
    let mut vn = vec![Vec3::ZERO; mesh.positions.len()];
    for t in &mesh.indices {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
        let fnrm = (b - a).cross(c - a);
        for &i in t {
            vn[i as usize] += fnrm;
        }
    }
    let outward = |(i, n): (usize, Vec3)| {
        let n = n.normalize_or_zero();
        if n.dot(mesh.positions[i] - centres[i]) < 0.0 {
            -n
        } else {
            n
        }
    };
    mesh.normals = Some(vn.into_iter().enumerate().map(outward).collect());
    mesh
}

/// Direction and solid angle of sub-pixel (x, y) of an R x R face, S x S supersampled.
fn cube_direction(face: usize, u: f32, v: f32) -> Vec3 {
    match face {
        0 => Vec3::new(1.0, -v, -u),
        1 => Vec3::new(-1.0, -v, u),
        2 => Vec3::new(u, 1.0, v),
        3 => Vec3::new(u, -1.0, -v),
        4 => Vec3::new(u, -v, 1.0),
        _ => Vec3::new(-u, -v, -1.0),
    }
}

pub fn run(args: PrtArgs) -> Result<()> {
    if args.segments < 3 || args.sides < 3 || args.resolution == 0 || args.supersample == 0 {
        bail!("--segments and --sides must be at least 3, --resolution and --supersample positive");
    }
    if !(args.exponent.is_finite() && args.exponent >= 0.0) {
        bail!(
            "--exponent must be a finite non-negative number, got {}",
            args.exponent
        );
    }
    let bytes =
        args.segments as f64 * args.sides as f64 * 6.0 * (args.resolution as f64).powi(2) * 4.0;
    if bytes > 8.0 * (1u64 << 30) as f64 {
        bail!(
            "the matrix would take {:.1} GiB; lower --segments, --sides or --resolution",
            bytes / (1u64 << 30) as f64
        );
    }
    let mesh = knot_mesh(args.segments, args.sides);
    let vertex_normals = mesh.normals.clone().context("knot mesh has normals")?;
    let positions = mesh.positions.clone();
    let desc = SceneDesc {
        name: "knot".into(),
        shapes: vec![Shape::new(ShapeKind::Mesh(mesh), 0)],
        materials: vec![Material::diffuse(0.5)],
        lights: vec![],
        camera: Camera::look_at(Vec3::new(0.0, -4.0, 1.0), Vec3::ZERO, Vec3::Z, 45.0)
            .map_err(anyhow::Error::msg)?,
        defaults: RenderDefaults::default(),
        portals: Vec::new(),
    };
    let scene = Scene::build(desc, Backend::default())?;
    let (r, s) = (args.resolution, args.supersample);
    let columns = 6 * r * r;
    let view = Vec3::new(0.0, -1.0, 0.3).normalize();
    let (kd, ks, n) = (0.2f32, 0.8f32, args.exponent);
    let pool = crate::thread_pool(args.threads)?;
    let bar = Bar::new(false);
    bar.start(Some(positions.len() as u64));
    let mut out = vec![0.0f32; positions.len() * columns];
    pool.install(|| {
        out.par_chunks_mut(columns)
            .enumerate()
            .for_each(|(vi, row)| {
                let (p, nrm) = (positions[vi], vertex_normals[vi]);
                let refl = 2.0 * view.dot(nrm) * nrm - view;
                let origin = p + nrm * 1e-4;
                let texel = 2.0 / r as f32;
                let sub = texel / s as f32;
                for face in 0..6 {
                    for ty in 0..r {
                        for tx in 0..r {
                            let mut acc = 0.0f32;
                            for sy in 0..s {
                                for sx in 0..s {
                                    let u = -1.0 + tx as f32 * texel + (sx as f32 + 0.5) * sub;
                                    let v = -1.0 + ty as f32 * texel + (sy as f32 + 0.5) * sub;
                                    let d = cube_direction(face, u, v);
                                    let len2 = d.length_squared();
                                    let w = d / len2.sqrt();
                                    let cos = w.dot(nrm);
                                    if cos <= 0.0 {
                                        continue;
                                    }
                                    // Solid angle of the sub-pixel: dA / (1 + u^2 + v^2)^(3/2).
                                    let domega = sub * sub / (len2 * len2.sqrt());
                                    if scene.occluded(&Ray::new(origin, w), f32::INFINITY) {
                                        continue;
                                    }
                                    let brdf = kd / PI
                                        + ks * (n + 2.0) / (2.0 * PI)
                                            * refl.dot(w).max(0.0).powf(n);
                                    acc += brdf * cos * domega;
                                }
                            }
                            row[face * r * r + ty * r + tx] = acc;
                        }
                    }
                }
                bar.advance(1);
            })
    });
    bar.finish();
    fenestra_lpca::io::write_npy(&args.output, &[positions.len() as u64, columns as u64], out)?;
    println!(
        "wrote {} ({} vertices x {} cubemap pixels)",
        args.output.display(),
        positions.len(),
        columns
    );
    Ok(())
}
