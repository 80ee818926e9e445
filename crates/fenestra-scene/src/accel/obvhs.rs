//! Pure-Rust backend: obvhs' CWBVH over all primitives, intersected by our exact routines.
//!
//! obvhs culls nodes nearer than an absolute 1e-4 along a ray, which loses every hit in a
//! scene measured in micrometres. The geometry is therefore kept scaled by a power of two
//! that brings it to about unit size, and rays are scaled to match: exact in floating point,
//! so hits are the same at every scale.

use super::{Hit, RayQuery};
use crate::shape::{intersect_disk, intersect_sphere, intersect_triangle, Shape, ShapeKind};
use fenestra_core::{Ray, Vec3};
use obvhs::{aabb::Aabb, cwbvh::CwBvh, BvhBuildParams};
use std::time::Duration;

/// A primitive copied out of its shape, so traversal touches one array.
#[derive(Clone, Copy)]
enum Prim {
    Triangle([Vec3; 3]),
    Sphere {
        center: Vec3,
        radius: f32,
    },
    Disk {
        center: Vec3,
        normal: Vec3,
        radius: f32,
    },
}

struct Item {
    prim: Prim,
    shape: u32,
    index: u32,
    bounds: Aabb,
}

impl obvhs::Boundable for Item {
    fn aabb(&self) -> Aabb {
        self.bounds
    }
}

pub struct ObvhsScene {
    bvh: Option<CwBvh>,
    items: Vec<Item>,
    /// The power of two the geometry is multiplied by.
    scale: f32,
}

impl ObvhsScene {
    pub fn new(shapes: &[Shape]) -> Self {
        let extent = shapes
            .iter()
            .flat_map(|s| (0..s.primitive_count()).map(|p| s.primitive_bounds(p)))
            .fold(0.0f32, |m, (lo, hi)| {
                m.max(lo.abs().max_element()).max(hi.abs().max_element())
            });
        let scale = if extent > 0.0 && extent.is_finite() {
            2f32.powi(-extent.log2().round() as i32)
        } else {
            1.0
        };
        let mut items = Vec::new();
        for (s, shape) in shapes.iter().enumerate() {
            for p in 0..shape.primitive_count() {
                let prim = match &shape.kind {
                    ShapeKind::Mesh(m) => Prim::Triangle(m.triangle(p).map(|v| v * scale)),
                    ShapeKind::Sphere { center, radius } => Prim::Sphere {
                        center: *center * scale,
                        radius: *radius * scale,
                    },
                    ShapeKind::Disk {
                        center,
                        normal,
                        radius,
                    } => Prim::Disk {
                        center: *center * scale,
                        normal: *normal,
                        radius: *radius * scale,
                    },
                };
                let (lo, hi) = shape.primitive_bounds(p);
                let (lo, hi) = (lo * scale, hi * scale);
                items.push(Item {
                    prim,
                    shape: s as u32,
                    index: p as u32,
                    bounds: Aabb::new(lo.into(), hi.into()),
                });
            }
        }
        let bvh = (!items.is_empty()).then(|| {
            let mut t = Duration::ZERO;
            obvhs::cwbvh::builder::build_cwbvh(&items, BvhBuildParams::medium_build(), &mut t)
        });
        ObvhsScene { bvh, items, scale }
    }

    /// `ray` and `tmax` in the scaled geometry's units.
    fn local(&self, ray: &Ray, tmax: f32) -> (Ray, f32) {
        (Ray::new(ray.o * self.scale, ray.d), tmax * self.scale)
    }

    fn item(&self, bvh: &CwBvh, id: usize) -> &Item {
        &self.items[bvh.primitive_indices[id] as usize]
    }
}

fn intersect_prim(prim: &Prim, ray: &Ray, tmax: f32) -> Option<(f32, f32, f32)> {
    match *prim {
        Prim::Triangle(t) => intersect_triangle(t, ray, 0.0, tmax),
        Prim::Sphere { center, radius } => {
            intersect_sphere(center, radius, ray, 0.0, tmax).map(|t| (t, 0.0, 0.0))
        }
        Prim::Disk {
            center,
            normal,
            radius,
        } => intersect_disk(center, normal, radius, ray, 0.0, tmax).map(|t| (t, 0.0, 0.0)),
    }
}

impl RayQuery for ObvhsScene {
    fn intersect(&self, ray: &Ray, tmax: f32) -> Option<Hit> {
        let bvh = self.bvh.as_ref()?;
        let (ray, tmax) = self.local(ray, tmax);
        let oray = obvhs::ray::Ray::new(ray.o.into(), ray.d.into(), 0.0, tmax);
        let mut hit = obvhs::ray::RayHit::none();
        let mut best: Option<Hit> = None;
        bvh.ray_traverse(oray, &mut hit, |r, id| {
            let item = self.item(bvh, id);
            match intersect_prim(&item.prim, &ray, r.tmax) {
                Some((t, u, v)) => {
                    best = Some(Hit {
                        t: t / self.scale,
                        shape: item.shape,
                        prim: item.index,
                        u,
                        v,
                    });
                    t
                }
                None => f32::INFINITY,
            }
        });
        best
    }

    fn occluded(&self, ray: &Ray, tmax: f32) -> bool {
        let Some(bvh) = self.bvh.as_ref() else {
            return false;
        };
        let (ray, tmax) = self.local(ray, tmax);
        let oray = obvhs::ray::Ray::new(ray.o.into(), ray.d.into(), 0.0, tmax);
        !bvh.ray_traverse_miss(oray, |_, id| {
            intersect_prim(&self.item(bvh, id).prim, &ray, tmax).map_or(f32::INFINITY, |h| h.0)
        })
    }
}
