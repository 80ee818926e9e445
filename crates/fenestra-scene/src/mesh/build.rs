//! Meshes built from functions: parametric grids, and vertex normals for faceted meshes.

use crate::TriangleMesh;
use fenestra_core::{Vec2, Vec3};

/// A parametric surface `f(s, t)` over [0,1]^2 sampled on an (nu+1) x (nv+1) grid; with
/// `wrap_u` the last column is the first (closed surfaces). Triangles are ordered so the
/// normal is df/ds x df/dt.
pub fn grid(nu: usize, nv: usize, wrap_u: bool, f: impl Fn(f32, f32) -> Vec3) -> TriangleMesh {
    let cols = if wrap_u { nu } else { nu + 1 };
    let mut mesh = TriangleMesh {
        uvs: Some(Vec::with_capacity(cols * (nv + 1))),
        ..TriangleMesh::default()
    };
    for j in 0..=nv {
        for i in 0..cols {
            let (s, t) = (i as f32 / nu as f32, j as f32 / nv as f32);
            mesh.positions.push(f(s, t));
            if let Some(uv) = mesh.uvs.as_mut() {
                uv.push(Vec2::new(s, t));
            }
        }
    }
    let at = |i: usize, j: usize| (j * cols + i % cols) as u32;
    for j in 0..nv {
        for i in 0..nu {
            mesh.indices
                .push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            mesh.indices
                .push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    mesh
}

/// Vertex normals from the area-weighted normals of the faces around each position
/// (vertices at the same position, as on patch seams, share one normal).
pub fn smooth_normals(mesh: &mut TriangleMesh) {
    let key = |p: Vec3| p.to_array().map(f32::to_bits);
    let mut sums: std::collections::HashMap<[u32; 3], Vec3> = std::collections::HashMap::new();
    for t in 0..mesh.indices.len() {
        let [a, b, c] = mesh.triangle(t);
        let n = (b - a).cross(c - a);
        for p in [a, b, c] {
            *sums.entry(key(p)).or_insert(Vec3::ZERO) += n;
        }
    }
    mesh.normals = Some(
        mesh.positions
            .iter()
            .map(|&p| {
                sums.get(&key(p))
                    .copied()
                    .unwrap_or(Vec3::Z)
                    .normalize_or(Vec3::Z)
            })
            .collect(),
    );
}
