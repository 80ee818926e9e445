//! Pure-Rust backend: obvhs' CWBVH over all primitives, intersected by our exact routines.

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
}

impl ObvhsScene {
    pub fn new(shapes: &[Shape]) -> Self {
        let mut items = Vec::new();
        for (s, shape) in shapes.iter().enumerate() {
            for p in 0..shape.primitive_count() {
                let prim = match &shape.kind {
                    ShapeKind::Mesh(m) => Prim::Triangle(m.triangle(p)),
                    ShapeKind::Sphere { center, radius } => Prim::Sphere {
                        center: *center,
                        radius: *radius,
                    },
                    ShapeKind::Disk {
                        center,
                        normal,
                        radius,
                    } => Prim::Disk {
                        center: *center,
                        normal: *normal,
                        radius: *radius,
                    },
                };
                let (lo, hi) = shape.primitive_bounds(p);
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
        ObvhsScene { bvh, items }
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
        let oray = obvhs::ray::Ray::new(ray.o.into(), ray.d.into(), 0.0, tmax);
        let mut hit = obvhs::ray::RayHit::none();
        let mut best: Option<Hit> = None;
        bvh.ray_traverse(oray, &mut hit, |r, id| {
            let item = self.item(bvh, id);
            match intersect_prim(&item.prim, ray, r.tmax) {
                Some((t, u, v)) => {
                    best = Some(Hit {
                        t,
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
        let oray = obvhs::ray::Ray::new(ray.o.into(), ray.d.into(), 0.0, tmax);
        !bvh.ray_traverse_miss(oray, |_, id| {
            intersect_prim(&self.item(bvh, id).prim, ray, tmax).map_or(f32::INFINITY, |h| h.0)
        })
    }
}
