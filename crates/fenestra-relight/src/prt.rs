//! Precomputed radiance transfer matrices for the LPCA experiments of seed 003 §3.6.1. For
//! every vertex of a mesh, the transfer vector over a 6 x R x R cubemap of pixel lights:
//! visibility (self-shadowing) x cosine x glossy Phong towards a fixed view, integrated over
//! each cubemap pixel with S x S supersampling. The mesh is a procedural torus knot.

use crate::error::RelightError;
use fenestra_core::{Frame, Ray, Vec3, PI};
use fenestra_render::Progress;
use fenestra_scene::{
    Backend, Camera, Material, RenderDefaults, Scene, SceneDesc, Shape, ShapeKind, TriangleMesh,
};
use rayon::prelude::*;

/// The knot and its transfer's discretisation.
#[derive(Clone, Copy, Debug)]
pub struct PrtOptions {
    /// Segments along the (2,3) torus knot.
    pub segments: usize,
    /// Vertices around the knot's tube (vertices = segments x sides).
    pub sides: usize,
    /// Cubemap face resolution R (columns = 6 R^2).
    pub resolution: usize,
    /// Supersampling S x S per cubemap pixel.
    pub supersample: usize,
    /// Phong lobe exponent of the glossy material.
    pub exponent: f32,
}

/// A transfer matrix: one row per vertex, one column per cubemap pixel, row-major.
#[derive(Clone, Debug)]
pub struct TransferMatrix {
    /// Vertices.
    pub rows: usize,
    /// Cubemap pixels (6 R^2).
    pub columns: usize,
    /// The values.
    pub values: Vec<f32>,
}

impl PrtOptions {
    /// Bytes of the matrix as f32.
    pub fn bytes(&self) -> f64 {
        self.segments as f64 * self.sides as f64 * 6.0 * (self.resolution as f64).powi(2) * 4.0
    }

    fn check(&self) -> Result<(), RelightError> {
        if self.segments < 3 || self.sides < 3 || self.resolution == 0 || self.supersample == 0 {
            return Err(RelightError::Prt(
                "segments and sides must be at least 3, resolution and supersample at least 1"
                    .into(),
            ));
        }
        if !(self.exponent.is_finite() && self.exponent >= 0.0) {
            return Err(RelightError::Prt(format!(
                "exponent (of the Phong lobe) must be a finite non-negative number, got {}",
                self.exponent
            )));
        }
        Ok(())
    }
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

/// The direction of point (u, v) in [-1, 1]^2 of cube face `face` (not normalised).
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

/// The knot's transfer matrix (vertices x cubemap pixels); `progress` counts vertices.
pub fn knot_transfer(
    options: &PrtOptions,
    progress: &dyn Progress,
) -> Result<TransferMatrix, RelightError> {
    options.check()?;
    let mesh = knot_mesh(options.segments, options.sides);
    let vertex_normals = mesh.normals.clone().unwrap_or_default();
    let positions = mesh.positions.clone();
    let camera = Camera::look_at(Vec3::new(0.0, -4.0, 1.0), Vec3::ZERO, Vec3::Z, 45.0)
        .map_err(|e| RelightError::Prt(e.to_string()))?;
    let desc = SceneDesc {
        name: "knot".into(),
        shapes: vec![Shape::new(ShapeKind::Mesh(mesh), 0)],
        materials: vec![Material::diffuse(0.5)],
        lights: vec![],
        camera,
        defaults: RenderDefaults::default(),
        portals: Vec::new(),
    };
    let scene =
        Scene::build(desc, Backend::default()).map_err(|e| RelightError::Prt(e.to_string()))?;
    let (r, s) = (options.resolution, options.supersample);
    let columns = 6 * r * r;
    let view = Vec3::new(0.0, -1.0, 0.3).normalize();
    let (kd, ks, n) = (0.2f32, 0.8f32, options.exponent);
    progress.start(Some(positions.len() as u64));
    let mut values = vec![0.0f32; positions.len() * columns];
    values
        .par_chunks_mut(columns)
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
                                    + ks * (n + 2.0) / (2.0 * PI) * refl.dot(w).max(0.0).powf(n);
                                acc += brdf * cos * domega;
                            }
                        }
                        row[face * r * r + ty * r + tx] = acc;
                    }
                }
            }
            progress.advance(1);
        });
    Ok(TransferMatrix {
        rows: positions.len(),
        columns,
        values,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use fenestra_render::NoProgress;

    #[test]
    fn a_vertex_reflects_at_most_what_arrives_and_shadowed_vertices_less() {
        let options = PrtOptions {
            segments: 24,
            sides: 8,
            resolution: 4,
            supersample: 2,
            exponent: 20.0,
        };
        let m = knot_transfer(&options, &NoProgress).expect("matrix");
        assert_eq!((m.rows, m.columns), (24 * 8, 6 * 16));
        let sums: Vec<f32> = m.values.chunks(m.columns).map(|r| r.iter().sum()).collect();
        assert!(m.values.iter().all(|v| v.is_finite() && *v >= 0.0));
        // kd + ks = 1: a row integrates a BRDF of albedo at most 1 against cosine-weighted
        // unit light from every direction, less where the knot shadows itself.
        let (lo, hi) = sums
            .iter()
            .fold((f32::MAX, 0.0f32), |(l, h), &s| (l.min(s), h.max(s)));
        assert!(hi <= 1.01, "a row sums to {hi}");
        assert!(lo < 0.8 * hi, "no self-shadowing: rows sum to {lo}..{hi}");
        let bad = PrtOptions {
            segments: 2,
            ..options
        };
        let e = knot_transfer(&bad, &NoProgress).expect_err("two segments");
        assert!(
            e.to_string().starts_with("segments and sides must be"),
            "{e}"
        );
    }
}
