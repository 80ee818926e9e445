//! Pure-Rust backend: obvhs' CWBVH over all primitives, intersected by our exact routines.
//!
//! obvhs skips every node a ray leaves within an absolute 1e-4 of its origin, which loses
//! every hit in a scene measured in micrometres, and small geometry near a ray's origin in a
//! large scene. The geometry is therefore kept scaled by a power of two that brings it to
//! about unit size (rays are scaled to match: exact in floating point, so hits are the same
//! at every scale), and nodes are tested from a little behind the ray's origin, primitives
//! from the origin itself.
//!
//! obvhs' own traversal keeps a fixed stack of 32 node groups and overwrites its top when a
//! tree needs more, silently losing hits. Its builder makes deep trees from primitives that
//! share a centre (copies of one mesh, nested shells: 600 of them kept 51 groups pending and
//! lost the hit of one ray in six from their centre). We therefore traverse with obvhs'
//! `traverse!` and a stack sized to the tree's depth: slow on such trees, never wrong.

use super::{Hit, RayQuery};
use crate::shape::{intersect_disk, intersect_sphere, intersect_triangle, Shape, ShapeKind};
use fenestra_core::{Ray, Vec3};
use glam::UVec2;
use obvhs::{
    aabb::Aabb,
    bvh2::reinsertion::ReinsertionOptimizer,
    cwbvh::{bvh2_to_cwbvh::bvh2_to_cwbvh, CwBvh},
    faststack::{FastStack, HeapStack, StackStack},
    ploc::PlocBuilder,
    traverse, BvhBuildParams,
};

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
    /// The most node groups a traversal keeps pending: the tree's depth plus one.
    stack_size: usize,
}

/// obvhs skips every node a ray leaves within 1e-4 of its origin (in the scaled units):
/// nodes are therefore tested from this far behind the origin.
const BACK_OFF: f32 = 2e-4;

/// Traversal stack of obvhs' own size, enough for every tree of sane geometry.
const SHALLOW: usize = 32;

/// The state obvhs' `traverse!` macro walks with, over any stack.
struct Walk<S> {
    stack: S,
    current_group: UVec2,
    primitive_group: UVec2,
    oct_inv4: u32,
    primitive_id: u32,
    hitmask: u32,
}

impl<S: FastStack<UVec2>> Walk<S> {
    fn new(bvh: &CwBvh, stack: S, direction: Vec3) -> Self {
        let start = bvh.new_traversal(direction.into());
        Walk {
            stack,
            current_group: start.current_group,
            primitive_group: start.primitive_group,
            oct_inv4: start.oct_inv4,
            primitive_id: 0,
            hitmask: 0,
        }
    }
}

/// obvhs' `build_cwbvh` with its medium settings, less the debug-build validation that
/// asserts the depth its own traversal stack holds.
fn build(items: &[Item]) -> CwBvh {
    let params = BvhBuildParams::medium_build();
    let indices = (0..items.len() as u32).collect();
    let mut bvh2 = PlocBuilder::with_capacity(items.len()).build(
        params.ploc_search_distance,
        items,
        indices,
        params.sort_precision,
        params.search_depth_threshold,
    );
    ReinsertionOptimizer::default().run(&mut bvh2, params.reinsertion_batch_ratio, None);
    bvh2_to_cwbvh(&bvh2, params.max_prims_per_leaf.clamp(1, 3), true, false)
}

/// Deepest level below the root of a CWBVH.
fn depth(bvh: &CwBvh) -> usize {
    let parents = bvh.compute_parents();
    let mut depth = vec![usize::MAX; parents.len()];
    if let Some(root) = depth.first_mut() {
        *root = 0;
    }
    let mut chain = Vec::new();
    for node in 0..parents.len() {
        let mut up = node;
        while depth[up] == usize::MAX {
            chain.push(up);
            up = parents[up] as usize;
        }
        let mut d = depth[up];
        for &n in chain.iter().rev() {
            d += 1;
            depth[n] = d;
        }
        chain.clear();
    }
    depth.into_iter().max().unwrap_or(0)
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
        let bvh = (!items.is_empty()).then(|| build(&items));
        let stack_size = bvh.as_ref().map_or(1, |b| depth(b) + 1);
        ObvhsScene {
            bvh,
            items,
            scale,
            stack_size,
        }
    }

    /// Calls `prim(id, tmax)` for the primitives `ray` may hit nearer than `tmax`; `prim`
    /// returns the new `tmax` (shorter to find the nearest hit, 0 to stop).
    fn walk(&self, bvh: &CwBvh, ray: &Ray, tmax: f32, prim: impl FnMut(usize, f32) -> f32) {
        if self.stack_size <= SHALLOW {
            self.walk_with(
                bvh,
                StackStack::<UVec2, SHALLOW>::default(),
                ray,
                tmax,
                prim,
            )
        } else {
            let stack = HeapStack::new_with_capacity(self.stack_size);
            self.walk_with(bvh, stack, ray, tmax, prim)
        }
    }

    fn walk_with(
        &self,
        bvh: &CwBvh,
        stack: impl FastStack<UVec2>,
        ray: &Ray,
        tmax: f32,
        mut prim: impl FnMut(usize, f32) -> f32,
    ) {
        // Nodes see the ray from BACK_OFF behind its origin, primitives from the origin.
        let o = ray.o - BACK_OFF * ray.d;
        // obvhs takes a component's octant from `d < 0` but its slab from 1/d: for -0 they
        // disagree (positive octant, -inf) and every node is missed. Adding +0 makes -0 +0.
        let d = ray.d + Vec3::ZERO;
        let mut oray = obvhs::ray::Ray::new(o.into(), d.into(), 0.0, tmax + BACK_OFF);
        let mut state = Walk::new(bvh, stack, d);
        let mut node;
        'walk: {
            traverse!(
                bvh,
                node,
                state,
                node.intersect_ray(&oray, state.oct_inv4),
                {
                    let t = prim(state.primitive_id as usize, oray.tmax - BACK_OFF);
                    if t <= 0.0 {
                        break 'walk;
                    }
                    oray.tmax = t + BACK_OFF;
                }
            );
        }
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
        let mut best: Option<Hit> = None;
        self.walk(bvh, &ray, tmax, |id, tmax| {
            let item = self.item(bvh, id);
            match intersect_prim(&item.prim, &ray, tmax) {
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
                None => tmax,
            }
        });
        best
    }

    fn occluded(&self, ray: &Ray, tmax: f32) -> bool {
        let Some(bvh) = self.bvh.as_ref() else {
            return false;
        };
        let (ray, tmax) = self.local(ray, tmax);
        let mut hit = false;
        self.walk(bvh, &ray, tmax, |id, tmax| {
            hit = intersect_prim(&self.item(bvh, id).prim, &ray, tmax).is_some();
            if hit {
                0.0
            } else {
                tmax
            }
        });
        hit
    }
}
