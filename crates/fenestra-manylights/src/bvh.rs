//! The light BVH (Conty Estevez and Kulla 2018; pbrt-v4's BVHLightSampler): one light per
//! leaf, built top-down by a surface-area-orientation heuristic over 12 buckets per axis, and
//! sampled by descending with probabilities in proportion to the children's importance at
//! the shading point. Lights at infinity (environments, distant lights) are outside the tree
//! and share the probability of one more child with it, as in pbrt-v4.

use crate::bounds::{DirectionCone, ImportanceBounds, LightBounds};
use fenestra_core::{Vec3, PI};
use fenestra_render::light::{Light, LightContext, LightSampler, Lights, Picks};
use fenestra_scene::{Scene, ShapeKind, SurfaceInteraction};

/// Buckets per axis of the split search.
const BUCKETS: usize = 12;

/// Depth from which subtrees are split at their middle: at most 64 + log2(lights) < 128
/// turns, all of which a trail records.
const MEDIAN_DEPTH: u32 = 64;

/// The trail of a light outside the tree (no trail reaches bit 127).
const NO_TRAIL: u128 = u128::MAX;

/// A node: its bounds as importance reads them, and either its light (a leaf) or its second
/// child (the first follows it in the array).
#[derive(Clone, Debug)]
struct Node {
    bounds: ImportanceBounds,
    /// Leaf: the light's index; interior: the second child's node index.
    index: u32,
    leaf: bool,
}

fenestra_render::options! {
    /// The light tree (light.selection bvh).
    pub struct BvhOptions in "bvh", flags "bvh" {
        /// Adaptive splitting: near the top of the tree, a node whose box the point sees with
        /// 1/d^2 varying by more than this factor gets a light sample for each child (up to 8
        /// per estimate) instead of a choice between them; 0 never splits.
        pub split: f32 = 0.0,
    }
}

impl fenestra_render::options::Validate for BvhOptions {
    fn validate(&self) -> Result<(), fenestra_render::options::OptionError> {
        fenestra_render::options::non_negative("split", self.split)
    }
}

/// The light BVH over a scene's lights.
pub struct LightBvh {
    nodes: Vec<Node>,
    /// Each node's box (low and high corners).
    boxes: Vec<(Vec3, Vec3)>,
    /// Lights at infinity, picked uniformly among themselves.
    infinite: Vec<usize>,
    /// For each light in the tree, the turns from the root to its leaf (bit k: the second
    /// child at depth k); [`NO_TRAIL`] for lights at infinity and lights that send nothing.
    trail: Vec<u128>,
    /// Adaptive splitting: the spread of 1/d^2 over a node's box above which both its
    /// children are sampled (0: never).
    split: f32,
}

/// Depth down to which nodes may be split: at most 2^3 = 8 picks
/// ([`fenestra_render::light::MAX_PICKS`]).
const SPLIT_DEPTH: u32 = 3;

/// The bounds of one light, `None` for lights at infinity; lights that send nothing get a
/// zero `phi`.
pub fn light_bounds(scene: &Scene, light: &Light) -> Option<LightBounds> {
    let point = |p: Vec3, phi: f32, normals: DirectionCone, cos_theta_e: f32| LightBounds {
        lo: p,
        hi: p,
        phi,
        normals,
        cos_theta_e,
        two_sided: false,
    };
    match light {
        Light::Point(l) => Some(point(
            l.position(),
            l.intensity().luminance(),
            DirectionCone::sphere(),
            0.0,
        )),
        Light::Spot(l) => {
            let (p, axis, cos_start, cos_end, intensity) = l.cone();
            // Full intensity up to the falloff's start, none beyond the edge.
            let spread = cos_end.clamp(-1.0, 1.0).acos() - cos_start.clamp(-1.0, 1.0).acos();
            Some(point(
                p,
                intensity.luminance(),
                DirectionCone {
                    w: axis,
                    cos_theta: cos_start,
                },
                spread.max(0.0).cos(),
            ))
        }
        Light::Area(a) => {
            let (shape_index, prim) = a.location();
            let shape = &scene.shapes[shape_index];
            let emission = a.emission();
            let radiance = emission.radiance.luminance();
            let (lo, hi) = shape.primitive_bounds(prim);
            let (phi, normals) = match &shape.kind {
                ShapeKind::Sphere { radius, .. } => {
                    (radiance * PI * radius * radius, DirectionCone::sphere())
                }
                kind => {
                    let area = match kind {
                        ShapeKind::Mesh(m) => m.triangle_area(prim),
                        _ => shape.area(),
                    };
                    let c = 0.5 * (lo + hi);
                    let si = SurfaceInteraction::on_surface(
                        shape,
                        shape_index,
                        prim,
                        c,
                        1.0 / 3.0,
                        1.0 / 3.0,
                    );
                    let n = si.ng;
                    let normals = if n == Vec3::ZERO {
                        DirectionCone::sphere()
                    } else {
                        DirectionCone {
                            w: n,
                            cos_theta: 1.0,
                        }
                    };
                    (radiance * area, normals)
                }
            };
            Some(LightBounds {
                lo,
                hi,
                phi,
                normals,
                cos_theta_e: 0.0,
                two_sided: emission.two_sided,
            })
        }
        Light::Distant(_) | Light::Environment(_) => None,
    }
}

impl LightBvh {
    /// The tree over `lights` of `scene`.
    pub fn new(scene: &Scene, lights: &Lights) -> Self {
        let mut infinite = Vec::new();
        let mut items = Vec::new();
        for (i, light) in lights.lights.iter().enumerate() {
            match light_bounds(scene, light) {
                None => infinite.push(i),
                Some(b) if b.phi > 0.0 && b.phi.is_finite() => items.push((i, b)),
                Some(_) => {}
            }
        }
        let mut bvh = LightBvh {
            nodes: Vec::with_capacity(2 * items.len()),
            boxes: Vec::with_capacity(2 * items.len()),
            infinite,
            trail: vec![NO_TRAIL; lights.lights.len()],
            split: 0.0,
        };
        if !items.is_empty() {
            bvh.build(&mut items, 0, 0);
        }
        bvh
    }

    /// Builds the subtree of `items` at depth `depth` whose turns so far are `bits`; returns
    /// its node's index.
    fn build(&mut self, items: &mut [(usize, LightBounds)], bits: u128, depth: u32) -> usize {
        let node = self.nodes.len();
        if let [(light, bounds)] = *items {
            self.push(&bounds, light as u32, true);
            self.trail[light] = bits;
            return node;
        }
        let bounds = items
            .iter()
            .skip(1)
            .fold(items[0].1, |acc, (_, b)| LightBounds::union(&acc, b));
        let mid = if depth < MEDIAN_DEPTH {
            split(items, &bounds)
        } else {
            items.len() / 2
        };
        self.push(&bounds, 0, false);
        let (first, second) = items.split_at_mut(mid);
        self.build(first, bits, depth + 1);
        let right = self.build(second, bits | (1 << depth), depth + 1);
        self.nodes[node].index = right as u32;
        node
    }

    /// Adds a node.
    fn push(&mut self, bounds: &LightBounds, index: u32, leaf: bool) {
        self.nodes.push(Node {
            bounds: bounds.into(),
            index,
            leaf,
        });
        self.boxes.push((bounds.lo, bounds.hi));
    }

    /// Probability of picking the tree (rather than a light at infinity).
    pub(crate) fn tree_probability(&self) -> f32 {
        if self.nodes.is_empty() {
            0.0
        } else {
            1.0 / (self.infinite.len() + 1) as f32
        }
    }

    /// The tree with adaptive splitting (after Conty Estevez and Kulla 2018, with our own
    /// criterion): a node within [`SPLIT_DEPTH`] of the root whose box the point sees with
    /// 1/d^2 varying by more than `threshold` (farthest over nearest squared distance; the
    /// point inside the box counts as infinite) is not chosen between: each child gets a
    /// pick of its own, so one next-event estimate takes up to 8 lights where the tree's
    /// importance says least. 0 turns splitting off.
    pub fn with_splitting(mut self, threshold: f32) -> Self {
        self.split = threshold.max(0.0);
        self
    }

    /// Whether both children of `node`, at `depth`, get picks at `ctx`.
    fn splits(&self, node: usize, depth: u32, ctx: &LightContext) -> bool {
        if self.split <= 0.0 || depth >= SPLIT_DEPTH || self.nodes[node].leaf {
            return false;
        }
        let (lo, hi) = self.boxes[node];
        let nearest = ctx.p.clamp(lo, hi) - ctx.p;
        let farthest = (ctx.p - lo).abs().max((ctx.p - hi).abs());
        farthest.length_squared() > self.split * nearest.length_squared()
    }

    /// Picks by splitting from `node` at `depth`, reached with probability `pmf`.
    fn split_picks(
        &self,
        node: usize,
        depth: u32,
        pmf: f32,
        ctx: &LightContext,
        u: f32,
        picks: &mut Picks,
    ) {
        if self.splits(node, depth, ctx) {
            let (first, second) = self.children(node).expect("split nodes are interior");
            for child in [first, second] {
                // A child that cannot light the point gets no pick (it would send nothing).
                if self.nodes[child].bounds.importance(ctx.p, ctx.n) > 0.0 {
                    self.split_picks(child, depth + 1, pmf, ctx, u, picks);
                }
            }
        } else if let Some(pick) = self.descend(node, pmf, ctx, u, |_, _| {}) {
            picks.push(pick);
        }
    }

    /// Bytes the tree takes per light in it.
    pub fn bytes_per_light(&self) -> f32 {
        let lights = self.trail.iter().filter(|&&t| t != NO_TRAIL).count().max(1);
        let per_node = std::mem::size_of::<Node>() + std::mem::size_of::<(Vec3, Vec3)>();
        (self.nodes.len() * per_node + lights * std::mem::size_of::<u128>()) as f32 / lights as f32
    }
}

/// Where to split `items` (reordered so the split is at the returned index): the bucket
/// boundary of least cost phi M_omega K_r area over the three axes (Conty Estevez and Kulla,
/// eq. 4-6), or the middle when every centroid is the same.
fn split(items: &mut [(usize, LightBounds)], bounds: &LightBounds) -> usize {
    let (mut clo, mut chi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for (_, b) in items.iter() {
        clo = clo.min(b.centroid());
        chi = chi.max(b.centroid());
    }
    let extent = bounds.hi - bounds.lo;
    let mut best: Option<(f32, usize, usize)> = None;
    for axis in 0..3 {
        let width = chi[axis] - clo[axis];
        if width <= 0.0 {
            continue;
        }
        let bucket = |b: &LightBounds| {
            (((b.centroid()[axis] - clo[axis]) / width * BUCKETS as f32) as usize).min(BUCKETS - 1)
        };
        let mut buckets: [Option<LightBounds>; BUCKETS] = [None; BUCKETS];
        for (_, b) in items.iter() {
            let k = bucket(b);
            buckets[k] = Some(buckets[k].map_or(*b, |acc| LightBounds::union(&acc, b)));
        }
        let kr = extent.max_element() / extent[axis].max(1e-12);
        // Unions of the buckets below each cut (forwards) and above it (backwards).
        let sweep = |order: &mut dyn Iterator<Item = usize>| {
            let mut acc: Option<LightBounds> = None;
            let mut out = [None; BUCKETS];
            for k in order {
                if let Some(b) = &buckets[k] {
                    acc = Some(acc.map_or(*b, |a| LightBounds::union(&a, b)));
                }
                out[k] = acc;
            }
            out
        };
        let below = sweep(&mut (0..BUCKETS));
        let above = sweep(&mut (0..BUCKETS).rev());
        for cut in 1..BUCKETS {
            let (Some(a), Some(b)) = (below[cut - 1], above[cut]) else {
                continue;
            };
            let cost = kr * (orientation_cost(&a) + orientation_cost(&b));
            if best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, axis, cut));
            }
        }
    }
    let mid = match best {
        Some((_, axis, cut)) => {
            let width = chi[axis] - clo[axis];
            let left = |b: &LightBounds| {
                ((((b.centroid()[axis] - clo[axis]) / width * BUCKETS as f32) as usize)
                    .min(BUCKETS - 1))
                    < cut
            };
            partition(items, |(_, b)| left(b))
        }
        None => items.len() / 2,
    };
    if mid == 0 || mid == items.len() {
        items.len() / 2
    } else {
        mid
    }
}

/// Moves the items for which `left` holds to the front; returns how many there are.
fn partition<T>(items: &mut [T], left: impl Fn(&T) -> bool) -> usize {
    let mut k = 0;
    for i in 0..items.len() {
        if left(&items[i]) {
            items.swap(i, k);
            k += 1;
        }
    }
    k
}

/// phi M_omega area: the flux, the solid-angle measure of the directions the cluster can
/// emit into (Conty Estevez and Kulla eq. 5) and the box's surface area.
fn orientation_cost(b: &LightBounds) -> f32 {
    let theta_o = b.normals.cos_theta.clamp(-1.0, 1.0).acos();
    let theta_e = b.cos_theta_e.clamp(-1.0, 1.0).acos();
    let theta_w = (theta_o + theta_e).min(PI);
    let (sin_o, cos_o) = theta_o.sin_cos();
    let m_omega = 2.0 * PI * (1.0 - cos_o)
        + PI / 2.0
            * (2.0 * theta_w * sin_o - (theta_o - 2.0 * theta_w).cos() - 2.0 * theta_o * sin_o
                + cos_o);
    let d = b.hi - b.lo;
    let area = 2.0 * (d.x * d.y + d.y * d.z + d.z * d.x);
    // A cluster of coincident points still has a cost in proportion to its flux.
    b.phi * m_omega * area.max(1e-12)
}

impl LightBvh {
    /// Lights at infinity (outside the tree).
    pub(crate) fn infinite(&self) -> &[usize] {
        &self.infinite
    }

    /// Number of nodes; the root is node 0.
    pub(crate) fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// The children of an interior node, `None` for a leaf.
    pub(crate) fn children(&self, node: usize) -> Option<(usize, usize)> {
        let n = &self.nodes[node];
        (!n.leaf).then_some((node + 1, n.index as usize))
    }

    /// The light of a leaf.
    pub(crate) fn leaf_light(&self, node: usize) -> Option<usize> {
        let n = &self.nodes[node];
        n.leaf.then_some(n.index as usize)
    }

    /// Diagonal of a node's bounding box.
    pub(crate) fn extent(&self, node: usize) -> f32 {
        let (lo, hi) = self.boxes[node];
        (hi - lo).length()
    }

    /// Descends from `node`, reached with probability `pmf`, to a light, choosing children in
    /// proportion to their importance at `ctx`; `visit` sees every node passed and the
    /// probability of reaching it. `None` where no light below can reach the point.
    pub(crate) fn descend(
        &self,
        mut node: usize,
        mut pmf: f32,
        ctx: &LightContext,
        mut u: f32,
        mut visit: impl FnMut(usize, f32),
    ) -> Option<(usize, f32)> {
        loop {
            visit(node, pmf);
            let n = &self.nodes[node];
            if n.leaf {
                let ok = node > 0 || n.bounds.importance(ctx.p, ctx.n) > 0.0;
                return ok.then_some((n.index as usize, pmf));
            }
            let (first, second) = (node + 1, n.index as usize);
            let c0 = self.nodes[first].bounds.importance(ctx.p, ctx.n);
            let c1 = self.nodes[second].bounds.importance(ctx.p, ctx.n);
            if c0 + c1 <= 0.0 {
                return None;
            }
            let p0 = c0 / (c0 + c1);
            if u < p0 {
                node = first;
                u = (u / p0).min(1.0 - f32::EPSILON);
                pmf *= p0;
            } else {
                node = second;
                u = ((u - p0) / (1.0 - p0)).min(1.0 - f32::EPSILON);
                pmf *= 1.0 - p0;
            }
        }
    }

    /// Probability that a descent from the root picks the tree's `light` at `ctx`, following
    /// its trail; `visit` sees every node on the way and the probability of reaching it, and
    /// may stop the walk there (by returning false): the probability of reaching that node
    /// is returned then.
    pub(crate) fn replay(
        &self,
        light: usize,
        ctx: &LightContext,
        visit: impl FnMut(usize, f32) -> bool,
    ) -> f32 {
        self.replay_from(light, 0, 0, self.tree_probability(), ctx, visit)
    }

    /// [`LightBvh::replay`] from `node`, an ancestor of `light` at `depth`, reached with
    /// probability `pmf`.
    pub(crate) fn replay_from(
        &self,
        light: usize,
        mut node: usize,
        mut depth: u32,
        mut pmf: f32,
        ctx: &LightContext,
        mut visit: impl FnMut(usize, f32) -> bool,
    ) -> f32 {
        let bits = self.trail.get(light).copied().unwrap_or(NO_TRAIL);
        if bits == NO_TRAIL {
            return 0.0;
        }
        // Splitting stops at the first node that is chosen in (the descent below it does
        // not split).
        let mut splitting = self.split > 0.0;
        loop {
            if !visit(node, pmf) {
                return pmf;
            }
            let n = &self.nodes[node];
            if n.leaf {
                let ok = node > 0 || n.bounds.importance(ctx.p, ctx.n) > 0.0;
                return if ok { pmf } else { 0.0 };
            }
            let (first, second) = (node + 1, n.index as usize);
            splitting = splitting && self.splits(node, depth, ctx);
            if splitting {
                // Both children have picks: the light's is in its child for sure.
                node = if bits & (1 << depth) == 0 {
                    first
                } else {
                    second
                };
                depth += 1;
                continue;
            }
            let c0 = self.nodes[first].bounds.importance(ctx.p, ctx.n);
            let c1 = self.nodes[second].bounds.importance(ctx.p, ctx.n);
            if c0 + c1 <= 0.0 {
                return 0.0;
            }
            if bits & (1 << depth) == 0 {
                pmf *= c0 / (c0 + c1);
                node = first;
            } else {
                pmf *= c1 / (c0 + c1);
                node = second;
            }
            depth += 1;
        }
    }

    /// Probability of picking the light at infinity `light` (0 for any other light).
    pub(crate) fn infinite_pmf(&self, light: usize) -> f32 {
        if self.infinite.contains(&light) {
            (1.0 - self.tree_probability()) / self.infinite.len() as f32
        } else {
            0.0
        }
    }
}

impl LightSampler for LightBvh {
    fn sample(&self, ctx: &LightContext, u: f32) -> Option<(usize, f32)> {
        let p_tree = self.tree_probability();
        if u >= p_tree {
            // A light at infinity, uniformly.
            let n = self.infinite.len();
            if n == 0 {
                return None;
            }
            let k = (((u - p_tree) / (1.0 - p_tree) * n as f32) as usize).min(n - 1);
            return Some((self.infinite[k], (1.0 - p_tree) / n as f32));
        }
        self.descend(0, p_tree, ctx, u / p_tree, |_, _| {})
    }

    /// With splitting, the picks of one estimate; `sample` alone is then the unsplit
    /// descent, whose probabilities `pmf` no longer gives (a one-pick mixture such as
    /// lp_hf's `portal.light_mix` cannot use a splitting tree).
    fn sample_all(&self, ctx: &LightContext, u: f32, picks: &mut Picks) {
        let p_tree = self.tree_probability();
        if u >= p_tree || self.split <= 0.0 {
            if let Some(pick) = self.sample(ctx, u) {
                picks.push(pick);
            }
            return;
        }
        self.split_picks(0, 0, p_tree, ctx, u / p_tree, picks);
    }

    fn pmf(&self, ctx: &LightContext, light: usize) -> f32 {
        if self.infinite.contains(&light) {
            return self.infinite_pmf(light);
        }
        self.replay(light, ctx, |_, _| true)
    }
}
