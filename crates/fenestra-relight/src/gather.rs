//! Gather samples (seed 003 §4.4.1): d points spread uniformly by area over the scene's
//! non-emitting mesh surfaces, each standing for an equal share of the area and two-sided:
//! its radiosity sums the direct light both sides receive and it radiates to both. Scene
//! files face their surfaces either way (the Cornell box of ../shared/scenes has its side
//! walls' normals pointing out of the room); the closed surfaces of interiors are dark on
//! their far side, so this is right for them whichever way they face. A thin panel lit on one
//! side and seen from the other would leak light through. ordered along a balanced kd-tree so that
//! neighbouring indices are neighbouring points (the transfer vectors over them are then
//! smooth, which is what makes their Haar images sparse) and so that every subtree is a range
//! of indices (the N-body traversal of [`crate::transfer`]).

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
    /// The area it stands for.
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

impl Gather {
    /// `count` gather samples on the non-emitting meshes of `scene` (none if it has none).
    pub fn new(scene: &RenderScene, count: usize, seed: u64) -> Self {
        let mut prims = Vec::new();
        for (s, shape) in scene.scene.shapes.iter().enumerate() {
            if let (ShapeKind::Mesh(m), None) = (&shape.kind, &shape.emission) {
                prims.extend((0..m.indices.len()).map(|t| (s, t, m.triangle_area(t))));
            }
        }
        let areas: Vec<f32> = prims.iter().map(|p| p.2).collect();
        let total: f32 = areas.iter().sum();
        let mut samples = Vec::with_capacity(count);
        if total > 0.0 {
            let pick = Distribution1D::new(&areas);
            for i in 0..count as u32 {
                let mut sampler = Sampler::new(seed, 0, i);
                let (k, _, _) = pick.sample_discrete(sampler.next_1d());
                let (s, t, _) = prims[k];
                let shape = &scene.scene.shapes[s];
                let ShapeKind::Mesh(m) = &shape.kind else {
                    continue;
                };
                let b = warp::square_to_triangle(sampler.next_2d());
                let [p0, p1, p2] = m.triangle(t);
                let p = p0 * (1.0 - b.x - b.y) + p1 * b.x + p2 * b.y;
                let si = SurfaceInteraction::on_surface(shape, s, t, p, b.x, b.y);
                let albedo = match &*scene.bsdf_at(&si) {
                    Bsdf::Diffuse(d) => d.reflectance,
                    b => b.lambertian_split().map_or(Rgb::ZERO, |(a, _)| a),
                };
                samples.push(GatherSample {
                    p: si.p,
                    n: si.ng,
                    area: total / count as f32,
                    albedo,
                    shape: s as u32,
                    triangle: t as u32,
                    b,
                    triangle_area: m.triangle_area(t),
                });
            }
        }
        let mut gather = Gather {
            samples,
            nodes: Vec::new(),
        };
        if !gather.samples.is_empty() {
            gather.build(0, gather.samples.len());
        }
        gather
    }

    /// The same samples (same order and tree) on `scene`, the scene they were made on with
    /// its shapes moved (an animation's frame): positions, normals and areas follow their
    /// triangles, and the tree's bounds are refitted.
    pub fn posed(&self, scene: &RenderScene) -> Gather {
        let mut out = self.clone();
        for g in &mut out.samples {
            let (s, t) = (g.shape as usize, g.triangle as usize);
            let shape = &scene.scene.shapes[s];
            let ShapeKind::Mesh(m) = &shape.kind else {
                continue;
            };
            let [p0, p1, p2] = m.triangle(t);
            let p = p0 * (1.0 - g.b.x - g.b.y) + p1 * g.b.x + p2 * g.b.y;
            let si = SurfaceInteraction::on_surface(shape, s, t, p, g.b.x, g.b.y);
            let area = m.triangle_area(t);
            g.area *= area / g.triangle_area;
            g.triangle_area = area;
            g.p = si.p;
            g.n = si.ng;
        }
        // Children come after their parent: refit from the last node back.
        for i in (0..out.nodes.len()).rev() {
            let node = out.nodes[i];
            let (min, max, area) = if node.children == [0, 0] {
                bounds(&out.samples[node.lo as usize..node.hi as usize])
            } else {
                let [l, r] = node.children.map(|c| out.nodes[c as usize]);
                (l.min.min(r.min), l.max.max(r.max), l.area + r.area)
            };
            out.nodes[i] = Node {
                min,
                max,
                area,
                ..node
            };
        }
        out
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
