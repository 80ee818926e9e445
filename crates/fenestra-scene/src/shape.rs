//! Shapes and their exact ray intersection routines, shared by both ray-query backends.

use crate::light::Emission;
use crate::material::Relief;
use fenestra_core::hash::fingerprint;
use fenestra_core::{Ray, Vec2, Vec3};
use std::sync::Arc;

/// An indexed triangle mesh in world space.
#[derive(Clone, Default)]
pub struct TriangleMesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Per-vertex shading normals (optional).
    pub normals: Option<Vec<Vec3>>,
    /// Per-vertex texture coordinates (optional).
    pub uvs: Option<Vec<Vec2>>,
    /// Vertex indices of each triangle.
    pub indices: Vec<[u32; 3]>,
}

/// Its sizes and fingerprints of its arrays (printed in full, a large mesh made keying a
/// scene by its `Debug` form take seconds).
impl std::fmt::Debug for TriangleMesh {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let indices = fingerprint(self.indices.iter().flatten().copied());
        f.debug_struct("TriangleMesh")
            .field("positions", &summary(&self.positions))
            .field("normals", &self.normals.as_deref().map(summary))
            .field("uvs", &self.uvs.as_deref().map(summary))
            .field(
                "indices",
                &format!("{} ({indices:016x})", self.indices.len()),
            )
            .finish()
    }
}

/// An array of vectors as its length and a fingerprint of its floats.
fn summary<T: Copy + Into<[f32; N]>, const N: usize>(v: &[T]) -> String {
    let words = v.iter().flat_map(|&p| p.into().map(f32::to_bits));
    format!("{} ({:016x})", v.len(), fingerprint(words))
}

impl TriangleMesh {
    /// A planar parallelogram centred at `center` spanned by half-edges `hu` and `hv`; its
    /// normal is `hu x hv` normalised.
    pub fn quad(center: Vec3, hu: Vec3, hv: Vec3) -> Self {
        let positions = vec![
            center - hu - hv,
            center + hu - hv,
            center + hu + hv,
            center - hu + hv,
        ];
        let uvs = Some(vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(0.0, 1.0),
        ]);
        TriangleMesh {
            positions,
            normals: None,
            uvs,
            indices: vec![[0, 1, 2], [0, 2, 3]],
        }
    }

    /// The corners of triangle `i`.
    pub fn triangle(&self, i: usize) -> [Vec3; 3] {
        let [a, b, c] = self.indices[i];
        [
            self.positions[a as usize],
            self.positions[b as usize],
            self.positions[c as usize],
        ]
    }

    /// The area of triangle `i`.
    pub fn triangle_area(&self, i: usize) -> f32 {
        let [a, b, c] = self.triangle(i);
        0.5 * fenestra_core::ray::robust_length((b - a).cross(c - a))
    }

    /// Triangle `i` alone, with its normals and uvs.
    pub fn triangle_mesh(&self, i: usize) -> TriangleMesh {
        let corners = self.indices[i].map(|v| v as usize);
        TriangleMesh {
            positions: corners.iter().map(|&v| self.positions[v]).collect(),
            normals: self
                .normals
                .as_ref()
                .map(|n| corners.iter().map(|&v| n[v]).collect()),
            uvs: self
                .uvs
                .as_ref()
                .map(|uv| corners.iter().map(|&v| uv[v]).collect()),
            indices: vec![[0, 1, 2]],
        }
    }

    /// Appends another mesh (used to merge quads into one shape).
    pub fn append(&mut self, other: &TriangleMesh) {
        let base = self.positions.len() as u32;
        self.positions.extend_from_slice(&other.positions);
        self.indices
            .extend(other.indices.iter().map(|t| t.map(|i| i + base)));
        match (&mut self.uvs, &other.uvs) {
            (Some(a), Some(b)) => a.extend_from_slice(b),
            _ => self.uvs = None,
        }
        match (&mut self.normals, &other.normals) {
            (Some(a), Some(b)) => a.extend_from_slice(b),
            _ => self.normals = None,
        }
    }

    /// Bytes of its indices and vertex data.
    pub fn bytes(&self) -> usize {
        use std::mem::size_of_val;
        size_of_val(self.indices.as_slice())
            + size_of_val(self.positions.as_slice())
            + self
                .normals
                .as_ref()
                .map_or(0, |n| size_of_val(n.as_slice()))
            + self.uvs.as_ref().map_or(0, |uv| size_of_val(uv.as_slice()))
    }

    /// Asks the CPU to bring triangle `prim`'s vertex indices into the cache.
    pub fn prefetch_indices(&self, prim: usize) {
        prefetch(&self.indices[prim]);
    }

    /// Asks the CPU to bring triangle `prim`'s vertex data into the cache (reads its
    /// indices: prefetch those first).
    pub fn prefetch_vertices(&self, prim: usize) {
        for i in self.indices[prim].map(|i| i as usize) {
            prefetch(&self.positions[i]);
            if let Some(n) = &self.normals {
                prefetch(&n[i]);
            }
            if let Some(uv) = &self.uvs {
                prefetch(&uv[i]);
            }
        }
    }
}

/// A hint that `x` will be read soon: in a large mesh, each hit's vertex data is a cache
/// miss, and the misses of several hits asked for together overlap.
fn prefetch<T>(x: &T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch only hints the cache; it reads no value and cannot fault.
    unsafe {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        _mm_prefetch::<_MM_HINT_T0>((x as *const T).cast());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = x;
}

/// The geometry of a shape.
#[derive(Clone, Debug)]
pub enum ShapeKind {
    /// Triangles.
    Mesh(TriangleMesh),
    /// A sphere, its normal pointing outwards.
    Sphere {
        /// Its centre.
        center: Vec3,
        /// Its radius.
        radius: f32,
    },
    /// A disk of `radius` around `center`, facing `normal` (unit).
    Disk {
        /// Its centre.
        center: Vec3,
        /// The side it faces (unit).
        normal: Vec3,
        /// Its radius.
        radius: f32,
    },
}

/// A shape with its material and, if it emits, its area emission.
#[derive(Clone, Debug)]
pub struct Shape {
    /// Its geometry.
    pub kind: ShapeKind,
    /// Index of its material in the scene.
    pub material: usize,
    /// Its emission, if it is an area light.
    pub emission: Option<Emission>,
    /// Flips the geometric and shading normals (pbrt's ReverseOrientation): emission and
    /// "outside" follow the flipped normal.
    pub flip_normals: bool,
    /// Its name, for what refers to it (animation tracks), if it has one.
    pub name: Option<String>,
    /// Its material's bump or normal map, which tilts its shading normals.
    pub relief: Option<Arc<Relief>>,
    /// A sphere's turn: the rotation (orthogonal, world from object) of the object space its
    /// uv parametrisation lives in, as pbrt-v4 parametrises a sphere in its own space (u
    /// about the object's z axis, v from pole to pole); `None` is the world's axes.
    pub orientation: Option<glam::Mat3>,
}

impl Shape {
    /// A shape of `material` that does not emit.
    pub fn new(kind: ShapeKind, material: usize) -> Self {
        Shape {
            kind,
            material,
            emission: None,
            flip_normals: false,
            name: None,
            relief: None,
            orientation: None,
        }
    }
    /// The shape named `name`.
    pub fn named(mut self, name: &str) -> Self {
        self.name = Some(name.to_string());
        self
    }
    /// The shape emitting `e`.
    pub fn emitting(mut self, e: Emission) -> Self {
        self.emission = Some(e);
        self
    }
    /// The shape with its normals flipped.
    pub fn flipped(mut self) -> Self {
        self.flip_normals = !self.flip_normals;
        self
    }

    /// The largest coordinate magnitude the shape reaches.
    pub fn extent(&self) -> f32 {
        match &self.kind {
            ShapeKind::Mesh(m) => m
                .positions
                .iter()
                .fold(0.0f32, |e, p| e.max(p.abs().max_element())),
            ShapeKind::Sphere { center, radius } | ShapeKind::Disk { center, radius, .. } => {
                center.abs().max_element() + radius
            }
        }
    }

    /// Number of primitives the ray-query backends see.
    pub fn primitive_count(&self) -> usize {
        match &self.kind {
            ShapeKind::Mesh(m) => m.indices.len(),
            _ => 1,
        }
    }

    /// Surface area (m^2).
    pub fn area(&self) -> f32 {
        match &self.kind {
            ShapeKind::Mesh(m) => (0..m.indices.len()).map(|i| m.triangle_area(i)).sum(),
            ShapeKind::Sphere { radius, .. } => 4.0 * fenestra_core::PI * radius * radius,
            ShapeKind::Disk { radius, .. } => fenestra_core::PI * radius * radius,
        }
    }

    /// Axis-aligned bounds of primitive `prim`.
    pub fn primitive_bounds(&self, prim: usize) -> (Vec3, Vec3) {
        match &self.kind {
            ShapeKind::Mesh(m) => {
                let [a, b, c] = m.triangle(prim);
                (a.min(b).min(c), a.max(b).max(c))
            }
            ShapeKind::Sphere { center, radius } => (
                *center - Vec3::splat(*radius),
                *center + Vec3::splat(*radius),
            ),
            ShapeKind::Disk {
                center,
                normal,
                radius,
            } => {
                // Extent of a disk along axis i is r * sqrt(1 - n_i^2).
                let e = (Vec3::ONE - *normal * *normal).max(Vec3::ZERO).sqrt() * *radius;
                (*center - e, *center + e)
            }
        }
    }

    /// Exact intersection with primitive `prim` in (tmin, tmax): (t, u, v) where (u, v) are
    /// the barycentrics of the 2nd and 3rd vertex for triangles and unused otherwise.
    pub fn intersect(
        &self,
        prim: usize,
        ray: &Ray,
        tmin: f32,
        tmax: f32,
    ) -> Option<(f32, f32, f32)> {
        match &self.kind {
            ShapeKind::Mesh(m) => intersect_triangle(m.triangle(prim), ray, tmin, tmax),
            ShapeKind::Sphere { center, radius } => {
                intersect_sphere(*center, *radius, ray, tmin, tmax).map(|t| (t, 0.0, 0.0))
            }
            ShapeKind::Disk {
                center,
                normal,
                radius,
            } => intersect_disk(*center, *normal, *radius, ray, tmin, tmax).map(|t| (t, 0.0, 0.0)),
        }
    }
}

/// Möller-Trumbore ray/triangle test.
pub fn intersect_triangle(
    [p0, p1, p2]: [Vec3; 3],
    ray: &Ray,
    tmin: f32,
    tmax: f32,
) -> Option<(f32, f32, f32)> {
    let e1 = p1 - p0;
    let e2 = p2 - p0;
    let pv = ray.d.cross(e2);
    let det = e1.dot(pv);
    // Parallel rays only: det scales with the triangle's area, so any threshold would
    // lose small triangles.
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let inv = 1.0 / det;
    let tv = ray.o - p0;
    let u = tv.dot(pv) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let qv = tv.cross(e1);
    let v = ray.d.dot(qv) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(qv) * inv;
    (t > tmin && t < tmax).then_some((t, u, v))
}

/// Nearest root of |o + t d - c| = r in (tmin, tmax); rays starting inside find the far wall.
pub fn intersect_sphere(center: Vec3, radius: f32, ray: &Ray, tmin: f32, tmax: f32) -> Option<f32> {
    // Numerically stable form (Haines et al., Ray Tracing Gems ch. 7).
    let f = ray.o - center;
    let b = -f.dot(ray.d);
    let l = f + b * ray.d;
    let disc = radius * radius - l.length_squared();
    if disc < 0.0 {
        return None;
    }
    let q = b + b.signum() * disc.sqrt();
    let c = f.length_squared() - radius * radius;
    let (mut t0, mut t1) = if q == 0.0 { (0.0, 0.0) } else { (c / q, q) };
    if t0 > t1 {
        std::mem::swap(&mut t0, &mut t1);
    }
    if t0 > tmin && t0 < tmax {
        Some(t0)
    } else if t1 > tmin && t1 < tmax {
        Some(t1)
    } else {
        None
    }
}

/// Distance along `ray` in (tmin, tmax) to the disk of `radius` around `center` facing
/// `normal`, if it hits.
pub fn intersect_disk(
    center: Vec3,
    normal: Vec3,
    radius: f32,
    ray: &Ray,
    tmin: f32,
    tmax: f32,
) -> Option<f32> {
    let denom = normal.dot(ray.d);
    if denom.abs() < 1e-12 {
        return None;
    }
    let t = normal.dot(center - ray.o) / denom;
    if !(t > tmin && t < tmax) {
        return None;
    }
    ((ray.at(t) - center).length_squared() <= radius * radius).then_some(t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_mesh_prints_its_sizes_and_fingerprints_that_any_change_changes() {
        let mut mesh = TriangleMesh::quad(Vec3::ZERO, Vec3::X, Vec3::Y);
        let before = format!("{mesh:?}");
        assert!(before.contains("positions: \"4 (") && before.contains("indices: \"2 ("));
        mesh.positions[3].z = 1e-7;
        let moved = format!("{mesh:?}");
        assert_ne!(moved, before);
        mesh.indices[1].swap(1, 2);
        assert_ne!(format!("{mesh:?}"), moved);
    }

    #[test]
    fn sphere_hits_from_outside_and_inside() {
        let r = Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z);
        assert!(
            (intersect_sphere(Vec3::ZERO, 1.0, &r, 0.0, f32::INFINITY).expect("hit") - 4.0).abs()
                < 1e-5
        );
        let inside = Ray::new(Vec3::ZERO, Vec3::X);
        assert!(
            (intersect_sphere(Vec3::ZERO, 2.0, &inside, 0.0, f32::INFINITY).expect("hit") - 2.0)
                .abs()
                < 1e-5
        );
        assert!(intersect_sphere(Vec3::ZERO, 1.0, &r, 0.0, 3.9).is_none());
    }

    #[test]
    fn triangle_and_disk_hits() {
        let tri = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let r = Ray::new(Vec3::new(0.25, 0.25, 1.0), -Vec3::Z);
        let (t, u, v) = intersect_triangle(tri, &r, 0.0, 10.0).expect("hit");
        assert!((t - 1.0).abs() < 1e-6 && (u - 0.25).abs() < 1e-6 && (v - 0.25).abs() < 1e-6);
        assert!(intersect_triangle(
            tri,
            &Ray::new(Vec3::new(0.8, 0.8, 1.0), -Vec3::Z),
            0.0,
            10.0
        )
        .is_none());
        assert!(intersect_disk(Vec3::ZERO, Vec3::Z, 1.0, &r, 0.0, 10.0).is_some());
        assert!(intersect_disk(Vec3::ZERO, Vec3::Z, 0.3, &r, 0.0, 10.0).is_none());
    }

    #[test]
    fn disk_bounds_are_tight_and_conservative() {
        let n = Vec3::new(1.0, 1.0, 0.0).normalize();
        let s = Shape::new(
            ShapeKind::Disk {
                center: Vec3::ZERO,
                normal: n,
                radius: 2.0,
            },
            0,
        );
        let (lo, hi) = s.primitive_bounds(0);
        assert!((hi.z - 2.0).abs() < 1e-5 && (hi.x - 2.0 * 0.5f32.sqrt()).abs() < 1e-5);
        assert_eq!(lo, -hi);
    }
}
