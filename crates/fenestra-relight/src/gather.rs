//! Gather samples (seed 003 §4.4.1): d points spread uniformly by area over the scene's
//! non-emitting mesh surfaces, each standing for its patch, the part of its shape nearer it
//! than any other sample facing its way (the area measured by [`PATCH_POINTS`] times as many
//! points: equal shares would give a sample with no neighbour near it too little and one in a
//! cluster too much), and two-sided:
//! its radiosity sums the direct light both sides receive and it radiates to both. Scene
//! files face their surfaces either way (the Cornell box of ../shared/scenes has its side
//! walls' normals pointing out of the room); the closed surfaces of interiors are dark on
//! their far side, so this is right for them whichever way they face. A thin panel lit on one
//! side and seen from the other would leak light through. ordered along a balanced kd-tree so that
//! neighbouring indices are neighbouring points (the transfer vectors over them are then
//! smooth, which is what makes their Haar images sparse) and so that every subtree is a range
//! of indices (the N-body traversal of [`crate::transfer`]).

use crate::neighbours::PointTree;
use fenestra_core::distribution::Distribution1D;
use fenestra_core::{warp, Rgb, Sampler, Vec2, Vec3};
use fenestra_render::bsdf::Bsdf;
use fenestra_render::RenderScene;
use fenestra_scene::{ShapeKind, SurfaceInteraction};

/// A gather sample.
#[derive(Clone, Copy, Debug)]
pub struct GatherSample {
    /// Where it is.
    pub p: Vec3,
    /// Its surface's geometric normal (either side: samples are two-sided).
    pub n: Vec3,
    /// The area of its patch.
    pub area: f32,
    /// Its Lambertian albedo (a glossy material's Lambertian lobe; 0 for others).
    pub albedo: Rgb,
    /// Where it is attached: shape, triangle and barycentric coordinates (it moves with its
    /// shape through an animation).
    pub shape: u32,
    pub triangle: u32,
    pub b: Vec2,
    /// Its triangle's area where it was made (areas scale with their triangles').
    pub triangle_area: f32,
}

impl GatherSample {
    /// Moves it with its triangle to where `scene` has it (area scaled with the triangle's).
    fn pose(&mut self, scene: &RenderScene) {
        let (s, t) = (self.shape as usize, self.triangle as usize);
        let shape = &scene.scene.shapes[s];
        let ShapeKind::Mesh(m) = &shape.kind else {
            return;
        };
        let [p0, p1, p2] = m.triangle(t);
        let p = p0 * (1.0 - self.b.x - self.b.y) + p1 * self.b.x + p2 * self.b.y;
        let si = SurfaceInteraction::on_surface(shape, s, t, p, self.b.x, self.b.y);
        let area = m.triangle_area(t);
        self.area *= area / self.triangle_area;
        self.triangle_area = area;
        self.p = si.p;
        self.n = si.ng;
    }
}

/// The non-emitting mesh triangles of a scene, to spread points over by area.
struct Surfaces {
    /// (shape, triangle) of each.
    triangles: Vec<(usize, usize)>,
    pick: Distribution1D,
    total: f32,
}

impl Surfaces {
    fn new(scene: &RenderScene) -> Self {
        let mut triangles = Vec::new();
        let mut areas = Vec::new();
        for (s, shape) in scene.scene.shapes.iter().enumerate() {
            if let (ShapeKind::Mesh(m), None) = (&shape.kind, &shape.emission) {
                triangles.extend((0..m.indices.len()).map(|t| (s, t)));
                areas.extend((0..m.indices.len()).map(|t| m.triangle_area(t)));
            }
        }
        let total = areas.iter().sum();
        let pick = Distribution1D::new(if total > 0.0 { &areas } else { &[1.0] });
        Surfaces {
            triangles,
            pick,
            total,
        }
    }

    /// `count` points uniform by area (random stream `stream`), each an equal share of the
    /// area.
    fn spread(
        &self,
        scene: &RenderScene,
        count: usize,
        seed: u64,
        stream: u64,
    ) -> Vec<GatherSample> {
        if self.total <= 0.0 {
            return Vec::new();
        }
        (0..count as u32)
            .filter_map(|i| {
                let mut sampler = Sampler::new(seed, stream, i);
                let (k, _, _) = self.pick.sample_discrete(sampler.next_1d());
                let (s, t) = self.triangles[k];
                let shape = &scene.scene.shapes[s];
                let ShapeKind::Mesh(m) = &shape.kind else {
                    return None;
                };
                let b = warp::square_to_triangle(sampler.next_2d());
                let [p0, p1, p2] = m.triangle(t);
                let p = p0 * (1.0 - b.x - b.y) + p1 * b.x + p2 * b.y;
                let si = SurfaceInteraction::on_surface(shape, s, t, p, b.x, b.y);
                let albedo = match &*scene.bsdf_at(&si) {
                    Bsdf::Diffuse(d) => d.reflectance,
                    b => b.lambertian_split().map_or(Rgb::ZERO, |(a, _)| a),
                };
                Some(GatherSample {
                    p: si.p,
                    n: si.ng,
                    area: self.total / count as f32,
                    albedo,
                    shape: s as u32,
                    triangle: t as u32,
                    b,
                    triangle_area: m.triangle_area(t),
                })
            })
            .collect()
    }
}

/// A node of the balanced tree: the samples `lo..hi`, their bounds and area.
#[derive(Clone, Copy, Debug)]
pub struct Node {
    pub lo: u32,
    pub hi: u32,
    pub min: Vec3,
    pub max: Vec3,
    pub area: f32,
    /// Its children (0: a leaf; the root is never a child).
    pub children: [u32; 2],
}

/// The gather samples in tree order, and the tree.
#[derive(Clone, Debug)]
pub struct Gather {
    pub samples: Vec<GatherSample>,
    pub nodes: Vec<Node>,
}

/// Points a gather sample's patch is measured with, on average.
pub const PATCH_POINTS: usize = 16;

impl Gather {
    /// `count` gather samples on the non-emitting meshes of `scene` (none if it has none).
    pub fn new(scene: &RenderScene, count: usize, seed: u64) -> Self {
        let surfaces = Surfaces::new(scene);
        let mut gather = Gather {
            samples: surfaces.spread(scene, count, seed, 0),
            nodes: Vec::new(),
        };
        if !gather.samples.is_empty() {
            gather.build(0, gather.samples.len());
            // Each sample's area its patch's: the share of `PATCH_POINTS` points a sample
            // that fall in it.
            let mut area = vec![0.0; gather.samples.len()];
            for (j, point) in gather.patch_points(scene, &surfaces, seed) {
                area[j as usize] += point.area;
            }
            for (g, a) in gather.samples.iter_mut().zip(area) {
                g.area = a;
            }
            gather.refit();
        }
        gather
    }

    /// `PATCH_POINTS` points a sample spread over the surfaces by area, each with the sample
    /// whose patch it lies in ([`Gather::owner`]; points no sample on their shape faces are
    /// left out).
    fn patch_points(
        &self,
        scene: &RenderScene,
        surfaces: &Surfaces,
        seed: u64,
    ) -> Vec<(u32, GatherSample)> {
        let tree = self.points();
        let mut found = Vec::new();
        let count = self.samples.len() * PATCH_POINTS;
        (surfaces.spread(scene, count, seed, 1).into_iter())
            .filter_map(|c| Some((self.owner(&tree, c.p, c.n, c.shape, &mut found)?, c)))
            .collect()
    }

    /// The samples' positions, for [`Gather::owner`].
    pub fn points(&self) -> PointTree {
        let points: Vec<[f32; 4]> = (self.samples.iter())
            .map(|g| [g.p.x, g.p.y, g.p.z, 0.0])
            .collect();
        PointTree::new(&points)
    }

    /// The sample whose patch the point `p` of shape `shape` (geometric normal `n`) lies in:
    /// the nearest of the samples on its shape that face its way (`tree` from
    /// [`Gather::points`], `found` reused); none if no such sample is among the nearest 16.
    pub fn owner(
        &self,
        tree: &PointTree,
        p: Vec3,
        n: Vec3,
        shape: u32,
        found: &mut Vec<(f32, u32)>,
    ) -> Option<u32> {
        tree.nearest(&[p.x, p.y, p.z, 0.0], 16, found);
        found.iter().map(|&(_, j)| j).find(|&j| {
            let g = &self.samples[j as usize];
            g.shape == shape && g.n.dot(n).abs() > 0.5
        })
    }

    /// The same samples (same order and tree) on `scene`, the scene they were made on with
    /// its shapes moved (an animation's frame): positions, normals and areas follow their
    /// triangles, and the tree's bounds are refitted.
    pub fn posed(&self, scene: &RenderScene) -> Gather {
        let mut out = self.clone();
        for g in &mut out.samples {
            g.pose(scene);
        }
        out.refit();
        out
    }

    /// The nodes' bounds and areas from their samples'.
    fn refit(&mut self) {
        // Children come after their parent: refit from the last node back.
        for i in (0..self.nodes.len()).rev() {
            let node = self.nodes[i];
            let (min, max, area) = if node.children == [0, 0] {
                bounds(&self.samples[node.lo as usize..node.hi as usize])
            } else {
                let [l, r] = node.children.map(|c| self.nodes[c as usize]);
                (l.min.min(r.min), l.max.max(r.max), l.area + r.area)
            };
            self.nodes[i] = Node {
                min,
                max,
                area,
                ..node
            };
        }
    }

    /// Orders `samples[lo..hi]` by median splits along the longest extent, pushing the
    /// nodes; returns the subtree's node.
    fn build(&mut self, lo: usize, hi: usize) -> u32 {
        let index = self.nodes.len() as u32;
        let (min, max, area) = bounds(&self.samples[lo..hi]);
        self.nodes.push(Node {
            lo: lo as u32,
            hi: hi as u32,
            min,
            max,
            area,
            children: [0, 0],
        });
        if hi - lo > 1 {
            let extent = max - min;
            let axis = if extent.x >= extent.y && extent.x >= extent.z {
                0
            } else if extent.y >= extent.z {
                1
            } else {
                2
            };
            let mid = (lo + hi) / 2;
            self.samples[lo..hi]
                .select_nth_unstable_by(mid - lo, |a, b| a.p[axis].total_cmp(&b.p[axis]));
            let left = self.build(lo, mid);
            let right = self.build(mid, hi);
            self.nodes[index as usize].children = [left, right];
        }
        index
    }
}

/// The bounds and area of `samples`.
fn bounds(samples: &[GatherSample]) -> (Vec3, Vec3, f32) {
    samples.iter().fold(
        (
            Vec3::splat(f32::INFINITY),
            Vec3::splat(f32::NEG_INFINITY),
            0.0,
        ),
        |(a, b, s), g| (a.min(g.p), b.max(g.p), s + g.area),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::animation::Animation;
    use crate::sequence::AnimatedScene;
    use fenestra_scene::{Backend, Scene};

    #[test]
    fn a_sample_s_area_is_its_patch_s_the_points_nearest_it_on_its_shape_facing_its_way() {
        let scene = RenderScene::new(
            Scene::build(
                fenestra_builtin::load("cornell-box").expect("scene"),
                Backend::Obvhs,
            )
            .expect("build"),
        );
        let gather = Gather::new(&scene, 500, 2);
        let points = gather.patch_points(&scene, &Surfaces::new(&scene), 2);
        // Every point kept (the box's samples face every side of it), each an equal share.
        assert_eq!(points.len(), 500 * PATCH_POINTS);
        let mut area = vec![0.0f32; 500];
        for (j, c) in &points {
            let g = &gather.samples[*j as usize];
            area[*j as usize] += c.area;
            assert_eq!(c.shape, g.shape);
            assert!(c.n.dot(g.n).abs() > 0.5);
            // No sample of its shape facing its way is nearer.
            let d = c.p.distance_squared(g.p);
            assert!(!gather.samples.iter().any(|h| {
                h.shape == c.shape && h.n.dot(c.n).abs() > 0.5 && h.p.distance_squared(c.p) < d
            }));
        }
        for (g, a) in gather.samples.iter().zip(area) {
            assert_eq!(g.area, a);
        }
        // Patches differ in size (equal shares would not), and the areas still sum to the
        // surfaces' (the tree's root included).
        let (min, max) = (gather.samples.iter()).fold((f32::INFINITY, 0.0f32), |(a, b), g| {
            (a.min(g.area), b.max(g.area))
        });
        assert!(max > 2.0 * min, "{min} to {max}");
        let total: f32 = (scene.scene.shapes.iter())
            .filter(|s| s.emission.is_none())
            .map(|s| s.area())
            .sum();
        assert!((gather.nodes[0].area - total).abs() < 1e-3 * total);
    }

    #[test]
    fn posed_samples_move_with_their_shapes_and_the_tree_follows() {
        let rest = fenestra_builtin::load("relight-room").expect("scene");
        let text = fenestra_builtin::animation("relight-room").expect("animated");
        let animated =
            AnimatedScene::new(rest, Animation::parse(text, "a").expect("parses")).expect("tracks");
        let build =
            |f: u32| RenderScene::new(Scene::build(animated.at(f), Backend::Obvhs).expect("build"));
        let gather = Gather::new(&build(0), 2000, 4);
        let end = gather.posed(&build(99));
        let moving = |g: &GatherSample| animated.rest.shapes[g.shape as usize].name.is_some();
        let (before, after): (Vec<&GatherSample>, Vec<&GatherSample>) =
            (gather.samples.iter().zip(&end.samples))
                .filter(|(g, _)| moving(g))
                .unzip();
        assert!(before.len() > 20);
        for (g, h) in gather.samples.iter().zip(&end.samples) {
            if !moving(g) {
                assert_eq!((g.p, g.n, g.area), (h.p, h.n, h.area));
            }
        }
        // Rigid motion: distances between samples of one object kept, normals turned with it.
        for k in 1..before.len() {
            let (a, b, c, d) = (before[k - 1], before[k], after[k - 1], after[k]);
            if a.shape == b.shape {
                assert!((a.p.distance(b.p) - c.p.distance(d.p)).abs() < 1e-4);
                assert!((a.n.dot(b.n) - c.n.dot(d.n)).abs() < 1e-4);
            }
            assert!(a.p.distance(c.p) > 0.1, "{} stayed at {}", a.p, c.p);
        }
        for node in &end.nodes {
            for g in &end.samples[node.lo as usize..node.hi as usize] {
                assert!(g.p.cmpge(node.min).all() && g.p.cmple(node.max).all());
            }
        }
        let area = |g: &Gather| g.samples.iter().map(|s| s.area).sum::<f32>();
        assert!((area(&gather) - area(&end)).abs() < 1e-3 * area(&gather));
    }
}
