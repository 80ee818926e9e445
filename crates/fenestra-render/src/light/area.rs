//! Diffuse area emitters: one per emissive triangle, sphere or disk (as pbrt-v4 makes every
//! emissive triangle a light), so that light selection chooses among the parts of an
//! emitting mesh. Spheres are sampled by the cone they subtend, triangles and disks by area.

use super::LightSample;
use fenestra_core::ray::{robust_length, robust_normalize};
use fenestra_core::{warp, Frame, Rgb, Vec2, Vec3, PI};
use fenestra_scene::interaction::MeshPoint;
use fenestra_scene::light::Emission;
use fenestra_scene::{Scene, Shape, ShapeKind, SurfaceInteraction};

/// A diffuse emitter: one triangle of a mesh, or a whole sphere or disk.
#[derive(Clone, Debug)]
pub struct AreaLight {
    shape: usize,
    /// The triangle (0 for spheres and disks).
    prim: usize,
    emission: Emission,
    area: f32,
    /// A triangle of a mesh without vertex normals, kept here: its points are sampled
    /// without reading the mesh, and its normal is the same everywhere.
    flat: Option<FlatTriangle>,
}

/// A triangle's corners and the geometric normal rays see on it (flipped as its shape says).
#[derive(Clone, Copy, Debug)]
struct FlatTriangle {
    corners: [Vec3; 3],
    normal: Vec3,
}

impl AreaLight {
    /// The emitter of primitive `prim` of shape `shape` of `scene` (a triangle's index, 0 for
    /// spheres and disks).
    pub fn new(scene: &Scene, shape: usize, prim: usize, emission: Emission) -> Self {
        let s = &scene.shapes[shape];
        let area = match &s.kind {
            ShapeKind::Mesh(m) => m.triangle_area(prim),
            _ => s.area(),
        };
        let flat = match &s.kind {
            ShapeKind::Mesh(m) if m.normals.is_none() => {
                let normal = MeshPoint::on_shape(s, prim, 0.0, 0.0).map(|p| p.ng);
                normal.map(|normal| FlatTriangle {
                    corners: m.triangle(prim),
                    normal,
                })
            }
            _ => None,
        };
        AreaLight {
            shape,
            prim,
            emission,
            area,
            flat,
        }
    }

    /// The shape it lies on and its primitive there.
    pub fn location(&self) -> (usize, usize) {
        (self.shape, self.prim)
    }

    /// What it emits.
    pub fn emission(&self) -> Emission {
        self.emission
    }

    /// Radiance leaving the emitter point `si` in direction `w` (zero where `si` is not on
    /// this emitter).
    pub fn le(&self, si: &SurfaceInteraction, w: Vec3) -> Rgb {
        if (si.shape, si.prim) != (self.shape, self.prim) {
            return Rgb::ZERO;
        }
        self.emitted(si.ng, w)
    }

    /// Radiance leaving the emitter's surface of geometric normal `ng` towards `w`.
    fn emitted(&self, ng: Vec3, w: Vec3) -> Rgb {
        if self.emission.two_sided || ng.dot(w) > 0.0 {
            self.emission.radiance
        } else {
            Rgb::ZERO
        }
    }

    /// Emitted power (luminance of watts).
    pub fn power(&self) -> f32 {
        let sides = if self.emission.two_sided { 2.0 } else { 1.0 };
        PI * self.area * sides * self.emission.radiance.luminance()
    }

    /// The cone a sphere subtends from a point outside it: sin^2 of its half-angle and its
    /// cap height 1 - cos (exact however small and far the sphere).
    fn sphere_cone(center: Vec3, radius: f32, p: Vec3) -> Option<(f32, f32)> {
        let sin2 = (radius / robust_length(center - p)).powi(2);
        (sin2 < 1.0 / 1.0001).then(|| (sin2, warp::one_minus_cos_from_sin2(sin2)))
    }

    /// A point of the sphere seen from `p` within the cone it subtends, uniform in solid
    /// angle: the direction's angle theta from the axis gives the point's angle alpha at the
    /// centre (law of sines: sin of the angle at the point is sin(theta) / sin(theta_max)),
    /// which stays exact for tiny, far spheres where intersecting the ray loses the point.
    fn sample_sphere(
        center: Vec3,
        radius: f32,
        p: Vec3,
        (sin2_max, cap): (f32, f32),
        u: Vec2,
    ) -> Vec3 {
        let one_minus_cos = u.x * cap;
        let cos_t = 1.0 - one_minus_cos;
        let sin2_t = one_minus_cos * (2.0 - one_minus_cos);
        let ratio = (sin2_t / sin2_max).min(1.0);
        let cos_a = sin2_t / sin2_max.sqrt() + cos_t * (1.0 - ratio).sqrt();
        let sin_a = (1.0 - cos_a * cos_a).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        let axis = robust_normalize(center - p);
        let across = Frame::from_normal(axis).to_world(Vec3::new(phi.cos(), phi.sin(), 0.0));
        center + (across * sin_a - axis * cos_a) * radius
    }

    /// A direction from `p` towards a point of the emitter: triangles by area, spheres by the cone they subtend, disks by area.
    pub fn sample_li(&self, scene: &Scene, p: Vec3, u: Vec2) -> Option<LightSample> {
        // A degenerate triangle of an emitting mesh is a light that emits nothing.
        if self.area <= 0.0 {
            return None;
        }
        let shape = &scene.shapes[self.shape];
        let cone = match &shape.kind {
            ShapeKind::Sphere { center, radius } => {
                Self::sphere_cone(*center, *radius, p).map(|cone| (*center, *radius, cone))
            }
            _ => None,
        };
        let (q, ng) = match cone {
            Some((center, radius, cone)) => {
                let q = Self::sample_sphere(center, radius, p, cone, u);
                let si = SurfaceInteraction::on_surface(shape, self.shape, 0, q, 0.0, 0.0);
                (si.p, si.ng)
            }
            None => self.sample_point(shape, u),
        };
        let d = q - p;
        let dist_sq = d.length_squared();
        let dist = dist_sq.sqrt();
        if dist == 0.0 {
            return None;
        }
        let wi = d / dist;
        let pdf = match cone {
            Some((_, _, (_, cap))) => warp::uniform_cone_pdf(cap),
            None => warp::area_to_solid_angle(1.0 / self.area, dist_sq, ng.dot(wi)),
        };
        if pdf <= 0.0 {
            return None;
        }
        let li = self.emitted(ng, -wi);
        (!li.is_black()).then_some(LightSample {
            wi,
            li,
            pdf,
            point: Some(q),
            delta: false,
        })
    }

    /// A point uniform by area on the emitter and its geometric normal, as a ray hitting it
    /// there would see them.
    fn sample_point(&self, shape: &Shape, u: Vec2) -> (Vec3, Vec3) {
        if let Some(t) = &self.flat {
            // What MeshPoint computes, without the mesh.
            let b = warp::square_to_triangle(u);
            let [p0, p1, p2] = t.corners;
            return (p0 * (1.0 - b.x - b.y) + p1 * b.x + p2 * b.y, t.normal);
        }
        let (prim, point, b) = self.sample_area(&shape.kind, u);
        match MeshPoint::on_shape(shape, prim, b.x, b.y) {
            Some(m) => (m.p, m.ng),
            None => {
                let si = SurfaceInteraction::on_surface(shape, self.shape, prim, point, b.x, b.y);
                (si.p, si.ng)
            }
        }
    }

    /// A ray leaving the emitter: a point uniform by area, a cosine-weighted direction on its
    /// emitting side (either side, chosen by `u_dir.x`, when it emits on both).
    pub fn sample_ray(
        &self,
        scene: &Scene,
        u_pos: Vec2,
        mut u_dir: Vec2,
    ) -> Option<super::EmittedRay> {
        let shape = &scene.shapes[self.shape];
        let (origin, mut n) = self.sample_point(shape, u_pos);
        if self.emission.two_sided {
            u_dir.x *= 2.0;
            if u_dir.x >= 1.0 {
                u_dir.x -= 1.0;
                n = -n;
            }
        }
        let dir = Frame::from_normal(n).to_world(warp::square_to_cosine_hemisphere(u_dir));
        // L cos over the densities 1 / area, cos / pi and 1 / sides.
        let sides = if self.emission.two_sided { 2.0 } else { 1.0 };
        let power = self.emission.radiance * (PI * self.area * sides);
        (n != Vec3::ZERO).then_some(super::EmittedRay { origin, dir, power })
    }

    /// Uniform point on the emitter by area: (primitive, point, barycentrics).
    fn sample_area(&self, kind: &ShapeKind, u: Vec2) -> (usize, Vec3, Vec2) {
        match kind {
            ShapeKind::Mesh(m) => {
                let b = warp::square_to_triangle(u);
                let [p0, p1, p2] = m.triangle(self.prim);
                (self.prim, p0 * (1.0 - b.x - b.y) + p1 * b.x + p2 * b.y, b)
            }
            ShapeKind::Sphere { center, radius } => (
                0,
                *center + warp::square_to_uniform_sphere(u) * *radius,
                Vec2::ZERO,
            ),
            ShapeKind::Disk {
                center,
                normal,
                radius,
            } => {
                let d = warp::square_to_disk_concentric(u) * *radius;
                (
                    0,
                    *center + Frame::from_normal(*normal).to_world(Vec3::new(d.x, d.y, 0.0)),
                    Vec2::ZERO,
                )
            }
        }
    }

    /// Solid-angle density at `p` of sampling the emitter point `si` (hit by a ray from `p`).
    pub fn pdf_li(&self, scene: &Scene, p: Vec3, si: &SurfaceInteraction) -> f32 {
        if let ShapeKind::Sphere { center, radius } = scene.shapes[self.shape].kind {
            if let Some((_, cap)) = Self::sphere_cone(center, radius, p) {
                return warp::uniform_cone_pdf(cap);
            }
        }
        let d = si.p - p;
        if self.area <= 0.0 || (si.shape, si.prim) != (self.shape, self.prim) {
            return 0.0;
        }
        warp::area_to_solid_angle(
            1.0 / self.area,
            d.length_squared(),
            si.ng.dot(d.normalize_or_zero()),
        )
    }
}
