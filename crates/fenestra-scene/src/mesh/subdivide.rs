//! Loop subdivision surfaces (pbrt-v4's `loopsubdiv`; Loop 1987): each level splits every
//! triangle in four, moving the old vertices by their one-ring (weight beta = 3/16 for
//! valence 3, else 3/(8n)) and placing new ones on the edges (3/8 of its ends, 1/8 of the
//! opposite vertices); boundary vertices and edges follow the boundary curve (3/4 and 1/8;
//! 1/2 and 1/2). After the last level the vertices go to their limit positions (weight
//! gamma = 1/(n + 3/(8 beta)) on the ring; 3/5 and 1/5 on a boundary), as pbrt-v4 does.
//!
//! Shading normals are the area-weighted face normals of the limit mesh (pbrt-v4 computes
//! the limit surface's tangents; at the levels scenes use the two agree closely). Edges
//! shared by more than two triangles are treated as boundaries (creases), and vertices on
//! other than two boundary edges (corners, non-manifold fans) stay where they are.

use crate::TriangleMesh;
use fenestra_core::Vec3;
use std::collections::HashMap;

/// Subdivides the triangles `indices` over `positions` `levels` times and moves the result
/// to the limit surface.
pub fn loop_subdivide(positions: &[Vec3], indices: &[[u32; 3]], levels: u32) -> TriangleMesh {
    let mut positions = positions.to_vec();
    let mut faces = indices.to_vec();
    for _ in 0..levels {
        let topology = Topology::new(&positions, &faces);
        let (p, f) = topology.refine(&positions, &faces);
        positions = p;
        faces = f;
    }
    let topology = Topology::new(&positions, &faces);
    let limit: Vec<Vec3> = (0..positions.len())
        .map(|v| topology.limit(&positions, v))
        .collect();
    let normals = area_weighted_normals(&limit, &faces);
    TriangleMesh {
        positions: limit,
        normals: Some(normals),
        uvs: None,
        indices: faces,
    }
}

/// An undirected edge: its ends, how many triangles share it, the vertices opposite it in
/// the first two.
struct Edge {
    ends: [u32; 2],
    faces: u32,
    opposite: [u32; 2],
}

/// Edges in the order the faces meet them (so results do not depend on hashing) and the
/// one-ring sums of every vertex.
struct Topology {
    edges: Vec<Edge>,
    /// For each face, its edges' indices (edge k joins corners k and k + 1).
    face_edges: Vec<[u32; 3]>,
    ring: Vec<Ring>,
}

#[derive(Clone, Copy, Default)]
struct Ring {
    sum: Vec3,
    valence: u32,
    boundary_sum: Vec3,
    boundary_valence: u32,
}

/// Loop's weight of each one-ring neighbour of an interior vertex of valence `n`.
fn beta(n: u32) -> f32 {
    if n == 3 {
        3.0 / 16.0
    } else {
        3.0 / (8.0 * n as f32)
    }
}

impl Topology {
    fn new(positions: &[Vec3], faces: &[[u32; 3]]) -> Self {
        let mut index: HashMap<(u32, u32), u32> = HashMap::with_capacity(faces.len() * 3 / 2);
        let mut edges: Vec<Edge> = Vec::with_capacity(faces.len() * 3 / 2);
        let mut face_edges = Vec::with_capacity(faces.len());
        for f in faces {
            let mut fe = [0; 3];
            for k in 0..3 {
                let (a, b, c) = (f[k], f[(k + 1) % 3], f[(k + 2) % 3]);
                let i = *index.entry((a.min(b), a.max(b))).or_insert_with(|| {
                    edges.push(Edge {
                        ends: [a, b],
                        faces: 0,
                        opposite: [c, c],
                    });
                    edges.len() as u32 - 1
                });
                let e = &mut edges[i as usize];
                if e.faces < 2 {
                    e.opposite[e.faces as usize] = c;
                }
                e.faces += 1;
                fe[k] = i;
            }
            face_edges.push(fe);
        }
        let mut ring = vec![Ring::default(); positions.len()];
        for e in &edges {
            let [a, b] = e.ends.map(|v| v as usize);
            for (v, other) in [(a, b), (b, a)] {
                let r = &mut ring[v];
                r.sum += positions[other];
                r.valence += 1;
                if e.faces != 2 {
                    r.boundary_sum += positions[other];
                    r.boundary_valence += 1;
                }
            }
        }
        Topology {
            edges,
            face_edges,
            ring,
        }
    }

    /// One level: the old vertices moved (even), one new vertex per edge (odd), four
    /// triangles per triangle with the winding kept.
    fn refine(&self, positions: &[Vec3], faces: &[[u32; 3]]) -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let n = positions.len();
        let mut out = Vec::with_capacity(n + self.edges.len());
        out.extend((0..n).map(|v| {
            let r = &self.ring[v];
            let p = positions[v];
            match (r.boundary_valence, r.valence) {
                (0, 0) => p,
                (0, valence) => {
                    let b = beta(valence);
                    p * (1.0 - valence as f32 * b) + r.sum * b
                }
                (2, _) => p * 0.75 + r.boundary_sum * 0.125,
                _ => p,
            }
        }));
        out.extend(self.edges.iter().map(|e| {
            let [a, b] = e.ends.map(|v| positions[v as usize]);
            if e.faces == 2 {
                let [c, d] = e.opposite.map(|v| positions[v as usize]);
                (a + b) * 0.375 + (c + d) * 0.125
            } else {
                (a + b) * 0.5
            }
        }));
        let mut refined = Vec::with_capacity(faces.len() * 4);
        for (f, fe) in faces.iter().zip(&self.face_edges) {
            let [e01, e12, e20] = fe.map(|e| n as u32 + e);
            refined.push([f[0], e01, e20]);
            refined.push([f[1], e12, e01]);
            refined.push([f[2], e20, e12]);
            refined.push([e01, e12, e20]);
        }
        (out, refined)
    }

    /// The limit position of vertex `v`.
    fn limit(&self, positions: &[Vec3], v: usize) -> Vec3 {
        let r = &self.ring[v];
        let p = positions[v];
        match (r.boundary_valence, r.valence) {
            (0, 0) => p,
            (0, valence) => {
                let n = valence as f32;
                let gamma = 1.0 / (n + 3.0 / (8.0 * beta(valence)));
                p * (1.0 - n * gamma) + r.sum * gamma
            }
            (2, _) => p * 0.6 + r.boundary_sum * 0.2,
            _ => p,
        }
    }
}

fn area_weighted_normals(positions: &[Vec3], faces: &[[u32; 3]]) -> Vec<Vec3> {
    let mut normals = vec![Vec3::ZERO; positions.len()];
    for f in faces {
        let [a, b, c] = f.map(|v| positions[v as usize]);
        // Twice the area times the unit normal.
        let n = (b - a).cross(c - a);
        for &v in f {
            normals[v as usize] += n;
        }
    }
    normals.iter().map(|n| n.normalize_or_zero()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tetrahedron() -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let p = vec![
            Vec3::new(1.0, 1.0, 1.0),
            Vec3::new(1.0, -1.0, -1.0),
            Vec3::new(-1.0, 1.0, -1.0),
            Vec3::new(-1.0, -1.0, 1.0),
        ];
        // Outward winding.
        let f = vec![[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]];
        (p, f)
    }

    #[test]
    fn each_level_quadruples_the_triangles_and_keeps_a_closed_surface_closed() {
        let (p, f) = tetrahedron();
        // Loop's weights on one level: a valence-3 vertex keeps 1 - 3 beta = 7/16 of itself
        // and takes 3/16 of each neighbour; the vertex on edge (0, 1) is 3/8 of its ends and
        // 1/8 of the two opposite vertices.
        let (q, _) = Topology::new(&p, &f).refine(&p, &f);
        assert_eq!(q[0], Vec3::splat(0.25));
        assert!(q[4..].contains(&Vec3::new(0.5, 0.0, 0.0)), "{q:?}");
        for levels in 0..4 {
            let m = loop_subdivide(&p, &f, levels);
            assert_eq!(m.indices.len(), 4 * 4usize.pow(levels));
            // A closed surface: V - E + F = 2, and every edge in exactly two triangles.
            let t = Topology::new(&m.positions, &m.indices);
            assert!(t.edges.iter().all(|e| e.faces == 2));
            let euler = m.positions.len() as i64 - t.edges.len() as i64 + m.indices.len() as i64;
            assert_eq!(euler, 2, "level {levels}");
        }
    }

    #[test]
    fn the_limit_surface_is_smooth_symmetric_and_inside_the_control_hull() {
        let (p, f) = tetrahedron();
        let m = loop_subdivide(&p, &f, 4);
        // The tetrahedron's symmetry keeps the centre at the origin; the limit surface
        // shrinks inside the hull (|x| = sqrt(3) at the corners) but stays round.
        let centre = m.positions.iter().copied().sum::<Vec3>() / m.positions.len() as f32;
        assert!(centre.length() < 1e-4, "{centre}");
        let radii: Vec<f32> = m.positions.iter().map(|q| q.length()).collect();
        let (lo, hi) = radii
            .iter()
            .fold((f32::MAX, 0.0f32), |(l, h), &r| (l.min(r), h.max(r)));
        assert!(hi < 3f32.sqrt() && lo > 0.2 && hi / lo < 2.0, "{lo} {hi}");
        // Normals point outward, and neighbouring faces differ little (smooth).
        for (q, n) in m.positions.iter().zip(m.normals.as_ref().expect("normals")) {
            assert!(q.dot(*n) > 0.0);
        }
        let face_normal = |f: &[u32; 3]| {
            let [a, b, c] = f.map(|v| m.positions[v as usize]);
            (b - a).cross(c - a).normalize()
        };
        let t = Topology::new(&m.positions, &m.indices);
        let mut faces_of_edge: HashMap<u32, Vec<usize>> = HashMap::new();
        for (i, fe) in t.face_edges.iter().enumerate() {
            for &e in fe {
                faces_of_edge.entry(e).or_default().push(i);
            }
        }
        let sharpest = faces_of_edge
            .values()
            .map(|fs| face_normal(&m.indices[fs[0]]).dot(face_normal(&m.indices[fs[1]])))
            .fold(1.0f32, f32::min);
        assert!(sharpest > 0.9, "adjacent faces at acos({sharpest})");
    }

    #[test]
    fn a_flat_patch_stays_flat_and_its_boundary_follows_the_boundary_rule() {
        // Two triangles forming the unit square in z = 0: every vertex is on the boundary.
        let p = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ];
        let f = vec![[0, 1, 2], [0, 2, 3]];
        let m = loop_subdivide(&p, &f, 2);
        assert_eq!(m.indices.len(), 32);
        assert!(m.positions.iter().all(|q| q.z == 0.0));
        assert!(m
            .normals
            .as_ref()
            .expect("normals")
            .iter()
            .all(|n| (*n - Vec3::Z).length() < 1e-6));
        // Corner 0 has boundary neighbours 1 and 3: after one level 3/4 (0,0) + 1/8 ((1,0) +
        // (0,1)) = (1/8, 1/8), and so on toward its limit; it stays on the diagonal.
        // Level 2 gives 3/4 (1/8, 1/8) + 1/8 ((1/2, 0) + (0, 1/2)) = (5/32, 5/32), its boundary
        // neighbours (5/16, 1/16) and (1/16, 5/16); the limit is 3/5 and 1/5 of those.
        let q = m.positions[0];
        assert!(
            (q - Vec3::new(0.16875, 0.16875, 0.0)).length() < 1e-6,
            "{q}"
        );
    }
}
