//! The local geometry at a ray hit.

use crate::shape::{Shape, ShapeKind, TriangleMesh};
use crate::Hit;
use fenestra_core::ray::{offset_distance, offset_origin, robust_normalize};
use fenestra_core::{Frame, Ray, Vec2, Vec3, INV_2PI, INV_PI};

/// A point on a surface where a ray hit it, with its frame and parametrisation.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceInteraction {
    /// The point.
    pub p: Vec3,
    /// Geometric normal; its side is the shape's "outside" (emitting side).
    pub ng: Vec3,
    /// Shading normal, in the same hemisphere as `ng`.
    pub ns: Vec3,
    /// Tangent along increasing u (for anisotropic materials).
    pub dpdu: Vec3,
    /// Texture coordinates.
    pub uv: Vec2,
    /// Index of the shape in the scene.
    pub shape: usize,
    /// Primitive (triangle) index within the shape.
    pub prim: usize,
    /// Distance along the ray that found it.
    pub t: f32,
    /// How far `p` may lie off the surface through rounding (relative to the magnitudes it
    /// was computed from): rays leaving the point start this far off it.
    pub offset: f32,
}

impl SurfaceInteraction {
    /// The origin of a ray leaving the point towards `w`: `p` moved off the surface, to the
    /// side of `w`, by `offset`.
    pub fn spawn(&self, w: Vec3) -> Vec3 {
        offset_origin(self.p, self.ng, w, self.offset)
    }

    /// A shadow ray leaving the point towards `w` and its length: to just short of `target`
    /// (a point on a light) when there is one, aimed at it from the moved origin (as pbrt-v4's
    /// `SpawnRayTo`), since a ray parallel to `w` from there passes beside it and, leaving
    /// at a grazing angle, meets the light's own surface short of it; without end otherwise.
    pub fn shadow_ray(&self, w: Vec3, target: Option<Vec3>) -> (Ray, f32) {
        let origin = self.spawn(w);
        let to = target.map(|q| q - origin);
        match to.map(|d| (d, d.length())) {
            Some((d, length)) if length > 0.0 => {
                (Ray::new(origin, d / length), length * (1.0 - 1e-4))
            }
            _ => (Ray::new(origin, w), f32::INFINITY),
        }
    }

    /// The shading frame: `ns` as +z, `dpdu` as the first tangent.
    pub fn shading_frame(&self) -> Frame {
        Frame::from_normal_tangent(self.ns, self.dpdu)
    }

    /// The interaction at point `p` of primitive `prim` with barycentrics (b1, b2) (meshes),
    /// as if a ray had hit it there: used by light sampling to see the same normals as rays.
    pub fn on_surface(
        shape: &Shape,
        shape_index: usize,
        prim: usize,
        p: Vec3,
        b1: f32,
        b2: f32,
    ) -> Self {
        let hit = Hit {
            t: 0.0,
            shape: shape_index as u32,
            prim: prim as u32,
            u: b1,
            v: b2,
        };
        Self::from_hit(shape, &Ray::new(p, Vec3::Z), &hit)
    }

    /// The interaction where `ray` hit `shape` (`hit` from a ray query).
    pub fn from_hit(shape: &Shape, ray: &Ray, hit: &Hit) -> Self {
        let prim = hit.prim as usize;
        let (p, mut ng, mut ns, dpdu, uv, offset) = match &shape.kind {
            ShapeKind::Mesh(m) => {
                let (b1, b2) = (hit.u, hit.v);
                let MeshPoint { p, ng, ns, offset } = MeshPoint::new(m, prim, b1, b2);
                let [i0, i1, i2] = m.indices[prim].map(|i| i as usize);
                let [p0, p1, p2] = [m.positions[i0], m.positions[i1], m.positions[i2]];
                let (uv, dpdu) = match &m.uvs {
                    Some(uv) => {
                        let [t0, t1, t2] = [uv[i0], uv[i1], uv[i2]];
                        let (du1, du2, dv1, dv2) =
                            (t1.x - t0.x, t2.x - t0.x, t1.y - t0.y, t2.y - t0.y);
                        let det = du1 * dv2 - dv1 * du2;
                        let dpdu = if det.abs() > 1e-12 {
                            ((p1 - p0) * dv2 - (p2 - p0) * dv1) / det
                        } else {
                            p1 - p0
                        };
                        let b0 = 1.0 - b1 - b2;
                        (t0 * b0 + t1 * b1 + t2 * b2, dpdu)
                    }
                    None => (Vec2::new(b1, b2), p1 - p0),
                };
                (p, ng, ns, dpdu, uv, offset)
            }
            ShapeKind::Sphere { center, radius } => {
                // Projected onto the sphere: its error is that of the centre and radius.
                let dir = robust_normalize(ray.at(hit.t) - *center);
                let p = *center + dir * *radius;
                let offset = offset_distance(center.abs().max_element() + radius);
                // pbrt-v4's parametrisation, in the sphere's object space: v = 1 at the pole
                // along its +z.
                let local = shape.orientation.map_or(dir, |o| o.transpose() * dir);
                let phi = local.y.atan2(local.x);
                let uv = Vec2::new(
                    (phi * INV_2PI).rem_euclid(1.0),
                    1.0 - local.z.clamp(-1.0, 1.0).acos() * INV_PI,
                );
                let dpdu = Vec3::new(-local.y, local.x, 0.0);
                let dpdu = shape.orientation.map_or(dpdu, |o| o * dpdu);
                (p, dir, dir, dpdu, uv, offset)
            }
            ShapeKind::Disk {
                center,
                normal,
                radius,
            } => {
                // Projected onto the disk's plane: its error is that of the centre and radius,
                // not of the ray's origin.
                let f = Frame::from_normal(*normal);
                let local = f.to_local(ray.at(hit.t) - *center);
                let p = *center + f.s * local.x + f.t * local.y;
                let offset = offset_distance(center.abs().max_element() + radius);
                let uv = Vec2::new(local.x / radius * 0.5 + 0.5, local.y / radius * 0.5 + 0.5);
                (p, *normal, *normal, f.s, uv, offset)
            }
        };
        if shape.flip_normals {
            ng = -ng;
            ns = -ns;
        }
        SurfaceInteraction {
            p,
            ng,
            ns,
            dpdu,
            uv,
            shape: hit.shape as usize,
            prim,
            t: hit.t,
            offset,
        }
    }
}

/// A point of a triangle given by barycentrics: what a ray hit there would see of its
/// position and normals, without the parametrisation (light sampling needs no more).
pub struct MeshPoint {
    /// The point.
    pub p: Vec3,
    /// Geometric normal, on the side the vertex normals call outside (not yet flipped by
    /// the shape's `flip_normals`).
    pub ng: Vec3,
    /// Shading normal (`ng` without vertex normals).
    pub ns: Vec3,
    /// Rounding bound of `p` (see [`SurfaceInteraction::offset`]).
    pub offset: f32,
}

impl MeshPoint {
    /// Triangle `prim` of `m` at barycentrics (b1, b2) of its 2nd and 3rd vertex.
    pub fn new(m: &TriangleMesh, prim: usize, b1: f32, b2: f32) -> Self {
        let [i0, i1, i2] = m.indices[prim].map(|i| i as usize);
        let [p0, p1, p2] = [m.positions[i0], m.positions[i1], m.positions[i2]];
        let b0 = 1.0 - b1 - b2;
        let p = p0 * b0 + p1 * b1 + p2 * b2;
        // Rounding of the interpolation (pbrt's bound, as a scalar): it moves p off the
        // triangle's plane by at most a few ulps of the terms summed.
        let scale = (p0 * b0).abs() + (p1 * b1).abs() + (p2 * b2).abs();
        let offset = offset_distance(scale.max_element());
        let mut ng = robust_normalize((p1 - p0).cross(p2 - p0));
        let ns = match &m.normals {
            Some(n) => {
                let ns = robust_normalize(n[i0] * b0 + n[i1] * b1 + n[i2] * b2);
                if ns == Vec3::ZERO {
                    ng
                } else {
                    // pbrt's convention: vertex normals say which side is outside.
                    if ng.dot(ns) < 0.0 {
                        ng = -ng;
                    }
                    ns
                }
            }
            None => ng,
        };
        MeshPoint { p, ng, ns, offset }
    }

    /// The point of the mesh shape `shape` (`None` for analytic shapes), its normals on the
    /// side a ray hit there would report.
    pub fn on_shape(shape: &Shape, prim: usize, b1: f32, b2: f32) -> Option<Self> {
        let ShapeKind::Mesh(m) = &shape.kind else {
            return None;
        };
        let mut point = Self::new(m, prim, b1, b2);
        if shape.flip_normals {
            point.ng = -point.ng;
            point.ns = -point.ns;
        }
        Some(point)
    }
}
