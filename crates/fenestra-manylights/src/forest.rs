//! The seed's light-cluster forest (seed 004 §3.4.2) and the cut through it at a point
//! (§3.5.1, §4.4.3). Lights are leaves; clusters are built bottom-up, greedily pairing the two
//! clusters whose union has the smallest bounding sphere. Dissimilar lights stay apart: one
//! tree for omnidirectional lights (points, spheres), six for oriented lights by the cube face
//! their normal points to (X+, X-, Y+, Y-, Z+, Z-); lights at infinity are kept aside (the
//! seed's environment regions). A cut descends each tree while a cluster's bounding sphere
//! subtends more than the solid-angle bound from the point, and prunes clusters that
//! provably send nothing there: below the surface, or with every emitter facing away.

use crate::bounds::LightBounds;
use crate::bvh::light_bounds;
use fenestra_core::{Vec3, PI};
use fenestra_render::light::{Light, Lights};
use fenestra_scene::Scene;

/// The seed's cluster size bound (§4.4.3): 0.02 sr.
pub const CUT_SOLID_ANGLE: f32 = 0.02;

/// A bounding sphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Centre.
    pub center: Vec3,
    /// Radius.
    pub radius: f32,
}

impl Sphere {
    /// The smallest sphere holding both.
    pub fn union(a: Sphere, b: Sphere) -> Sphere {
        let d = b.center - a.center;
        let dist = d.length();
        if dist + b.radius <= a.radius {
            return a;
        }
        if dist + a.radius <= b.radius {
            return b;
        }
        let radius = 0.5 * (dist + a.radius + b.radius);
        // The new centre lies on the line of centres, radius - a.radius from a's centre;
        // a hair larger so that rounding never leaves a child sticking out.
        let center = a.center + d * ((radius - a.radius) / dist);
        Sphere {
            center,
            radius: radius * (1.0 + 1e-6),
        }
    }

    /// The solid angle the sphere subtends from `p` (4 pi when `p` is inside it).
    pub fn solid_angle(&self, p: Vec3) -> f32 {
        let d2 = (self.center - p).length_squared();
        let r2 = self.radius * self.radius;
        if d2 <= r2 {
            return 4.0 * PI;
        }
        // 2 pi (1 - cos theta), with 1 - cos written to stay exact for small spheres.
        let sin2 = r2 / d2;
        2.0 * PI * sin2 / (1.0 + (1.0 - sin2).sqrt())
    }
}

/// A node of a cluster tree: a light (leaf) or the union of two clusters.
#[derive(Clone, Debug)]
pub struct Cluster {
    /// Bounding sphere of its lights.
    pub sphere: Sphere,
    /// Its lights' bounds (flux, normal cone, sidedness).
    pub bounds: LightBounds,
    /// Total emitted power of its lights (what lights are picked by inside it).
    pub power: f32,
    /// Leaf: `None`; interior: its children's node indices.
    pub children: Option<[u32; 2]>,
    /// Leaf: the light's index in the scene's `Lights`.
    pub light: u32,
    /// The cluster it belongs to ([`NO_PARENT`] for a root).
    pub parent: u32,
    /// The angles of its normal cone and of its emission spread (theta_o, theta_e), for the
    /// cuts' facing test.
    angles: [f32; 2],
}

impl Cluster {
    fn new(sphere: Sphere, bounds: LightBounds, power: f32, children: Option<[u32; 2]>) -> Self {
        let angles = [
            bounds.normals.cos_theta.clamp(-1.0, 1.0).acos(),
            bounds.cos_theta_e.clamp(-1.0, 1.0).acos(),
        ];
        Cluster {
            sphere,
            bounds,
            power,
            children,
            light: u32::MAX,
            parent: NO_PARENT,
            angles,
        }
    }
}

/// The parent of a root.
pub const NO_PARENT: u32 = u32::MAX;

/// The seven trees over a scene's lights, and its lights at infinity.
pub struct Forest {
    /// Every tree's nodes, in one array.
    pub nodes: Vec<Cluster>,
    /// The root of each non-empty tree: omnidirectional lights first, then the oriented ones
    /// by normal class.
    pub roots: Vec<u32>,
    /// Lights at infinity (environments, distant lights), outside the trees.
    pub infinite: Vec<usize>,
    /// Each light's leaf by light index ([`NO_PARENT`] for lights outside the trees).
    pub leaf_of: Vec<u32>,
}

/// Which tree a light goes to: 0 for omnidirectional, 1 + the cube face of its normal.
fn tree_of(bounds: &LightBounds) -> usize {
    if bounds.two_sided || bounds.normals.cos_theta <= -1.0 + 1e-6 {
        // Point and sphere lights emit every way; a two-sided flat emitter does too, as far
        // as which side of it a point lies on is concerned.
        return 0;
    }
    let w = bounds.normals.w;
    let a = w.abs();
    let axis = if a.x >= a.y && a.x >= a.z {
        0
    } else if a.y >= a.z {
        1
    } else {
        2
    };
    1 + 2 * axis + usize::from(w[axis] < 0.0)
}

impl Forest {
    /// The forest over `lights` of `scene`. Lights that send nothing are left out.
    pub fn new(scene: &Scene, lights: &Lights) -> Self {
        let mut groups: [Vec<Cluster>; 7] = Default::default();
        let mut infinite = Vec::new();
        for (i, light) in lights.lights.iter().enumerate() {
            let Some(bounds) = light_bounds(scene, light) else {
                infinite.push(i);
                continue;
            };
            if !(bounds.phi > 0.0 && bounds.phi.is_finite()) {
                continue;
            }
            let sphere = match light {
                Light::Area(_) | Light::Point(_) | Light::Spot(_) => Sphere {
                    center: bounds.centroid(),
                    radius: 0.5 * (bounds.hi - bounds.lo).length(),
                },
                Light::Distant(_) | Light::Environment(_) => continue,
            };
            groups[tree_of(&bounds)].push(Cluster {
                light: i as u32,
                ..Cluster::new(sphere, bounds, light.power(scene), None)
            });
        }
        let mut forest = Forest {
            nodes: Vec::new(),
            roots: Vec::new(),
            infinite,
            leaf_of: vec![NO_PARENT; lights.lights.len()],
        };
        for group in groups.into_iter().filter(|g| !g.is_empty()) {
            let root = forest.build_tree(group);
            forest.roots.push(root);
        }
        for (i, node) in forest.nodes.iter().enumerate() {
            if node.children.is_none() {
                forest.leaf_of[node.light as usize] = i as u32;
            }
        }
        forest
    }

    /// Builds one tree over `leaves` by greedy agglomeration (seed §3.4.2): repeatedly join
    /// the two clusters whose union has the smallest bounding sphere. Each cluster keeps its
    /// best partner; a join invalidates only the partners that pointed at the joined two.
    /// O(n^2) per build (the forest is built once per scene).
    fn build_tree(&mut self, leaves: Vec<Cluster>) -> u32 {
        let mut active: Vec<u32> = Vec::with_capacity(leaves.len());
        for leaf in leaves {
            active.push(self.nodes.len() as u32);
            self.nodes.push(leaf);
        }
        let radius_of = |nodes: &[Cluster], a: u32, b: u32| {
            Sphere::union(nodes[a as usize].sphere, nodes[b as usize].sphere).radius
        };
        // best[k]: (radius, partner) of active[k].
        let best_of = |nodes: &[Cluster], active: &[u32], k: usize| {
            active
                .iter()
                .enumerate()
                .filter(|&(j, _)| j != k)
                .map(|(_, &b)| (radius_of(nodes, active[k], b), b))
                .min_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)))
        };
        let mut best: Vec<Option<(f32, u32)>> = (0..active.len())
            .map(|k| best_of(&self.nodes, &active, k))
            .collect();
        while active.len() > 1 {
            // The globally smallest join (ties by node index, so the tree never depends on
            // anything but the scene).
            let (k, (_, partner)) = best
                .iter()
                .enumerate()
                .filter_map(|(k, b)| b.map(|b| (k, b)))
                .min_by(|x, y| {
                    x.1 .0
                        .total_cmp(&y.1 .0)
                        .then(active[x.0].min(x.1 .1).cmp(&active[y.0].min(y.1 .1)))
                })
                .unwrap_or_else(|| unreachable!("two active clusters have a best partner"));
            let (a, b) = (active[k], partner);
            let node = self.join(a, b);
            let kb = active
                .iter()
                .position(|&x| x == b)
                .unwrap_or_else(|| unreachable!("a partner is active"));
            // Replace a by the new cluster, drop b.
            active[k] = node;
            active.swap_remove(kb);
            best.swap_remove(kb);
            let k = active
                .iter()
                .position(|&x| x == node)
                .unwrap_or_else(|| unreachable!("the new cluster is active"));
            for j in 0..active.len() {
                let stale = match best[j] {
                    Some((_, p)) => p == a || p == b,
                    None => true,
                };
                if j == k || stale {
                    best[j] = best_of(&self.nodes, &active, j);
                } else if let Some((r, _)) = best[j] {
                    // The new cluster may be a better partner than the old one.
                    let rn = radius_of(&self.nodes, active[j], node);
                    if rn < r {
                        best[j] = Some((rn, node));
                    }
                }
            }
        }
        active[0]
    }

    fn join(&mut self, a: u32, b: u32) -> u32 {
        let (x, y) = (&self.nodes[a as usize], &self.nodes[b as usize]);
        let cluster = Cluster::new(
            Sphere::union(x.sphere, y.sphere),
            LightBounds::union(&x.bounds, &y.bounds),
            x.power + y.power,
            Some([a, b]),
        );
        let node = self.nodes.len() as u32;
        self.nodes.push(cluster);
        self.nodes[a as usize].parent = node;
        self.nodes[b as usize].parent = node;
        node
    }

    /// The cut at point `p` with normal `n` (zero: a point lit from every side): every tree
    /// descended while a cluster subtends more than `max_solid_angle`, leaving out clusters
    /// that provably send nothing to `p` (seed §3.5.1). Returns node indices.
    pub fn cut(&self, p: Vec3, n: Vec3, max_solid_angle: f32, out: &mut Vec<u32>) {
        out.clear();
        let mut stack: Vec<u32> = self.roots.clone();
        while let Some(i) = stack.pop() {
            let c = &self.nodes[i as usize];
            if !reaches(c, p, n) {
                continue;
            }
            match c.children {
                Some([a, b]) if c.sphere.solid_angle(p) > max_solid_angle => {
                    stack.push(b);
                    stack.push(a);
                }
                _ => out.push(i),
            }
        }
    }

    /// A light below node `i` picked in proportion to power by `u` in [0, 1): the light's
    /// node and its probability given `i`.
    pub fn pick_by_power(&self, mut i: u32, mut u: f32) -> (u32, f32) {
        let mut p = 1.0;
        while let Some(children) = self.nodes[i as usize].children {
            let first = self.first_share(children);
            if u < first {
                u = (u / first).min(1.0 - f32::EPSILON);
                p *= first;
                i = children[0];
            } else {
                u = ((u - first) / (1.0 - first)).min(1.0 - f32::EPSILON);
                p *= 1.0 - first;
                i = children[1];
            }
        }
        (i, p)
    }

    /// The probability that a pick by power between `children` goes to the first.
    fn first_share(&self, [a, b]: [u32; 2]) -> f32 {
        let (pa, pb) = (self.nodes[a as usize].power, self.nodes[b as usize].power);
        if pa + pb > 0.0 {
            pa / (pa + pb)
        } else {
            0.5
        }
    }

    /// The cluster that node `i` belongs to, and the probability that a pick by power there
    /// goes towards `i` (`None` at a root).
    pub fn up(&self, i: u32) -> Option<(u32, f32)> {
        let parent = self.nodes[i as usize].parent;
        let children = self.nodes.get(parent as usize)?.children?;
        let first = self.first_share(children);
        Some((parent, if children[0] == i { first } else { 1.0 - first }))
    }

    /// The lights below node `i`.
    pub fn lights_below(&self, i: u32, out: &mut Vec<u32>) {
        match self.nodes[i as usize].children {
            None => out.push(self.nodes[i as usize].light),
            Some([a, b]) => {
                self.lights_below(a, out);
                self.lights_below(b, out);
            }
        }
    }
}

/// Whether the cluster may send light to `p` (normal `n`): false when its bounding sphere
/// lies wholly below the surface, or when every emitter of it faces away from `p` (the angle
/// between its normal cone and the direction to `p`, less the sphere's angular radius, is
/// beyond the emission spread).
fn reaches(c: &Cluster, p: Vec3, n: Vec3) -> bool {
    let to_c = c.sphere.center - p;
    if n != Vec3::ZERO && to_c.dot(n) < -c.sphere.radius {
        return false;
    }
    let b = &c.bounds;
    if b.two_sided || b.normals.cos_theta <= -1.0 + 1e-6 {
        return true;
    }
    let d = to_c.length();
    if d <= c.sphere.radius {
        return true;
    }
    // Angle from the cone's axis to the direction from the cluster to p.
    let theta_w = b.normals.w.dot(-to_c / d).clamp(-1.0, 1.0).acos();
    let [theta_o, theta_e] = c.angles;
    let theta_b = (c.sphere.radius / d).clamp(0.0, 1.0).asin();
    theta_w - theta_o - theta_b < theta_e
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bounds::DirectionCone;

    /// The normal cone of a single emitter.
    fn facing(w: Vec3) -> DirectionCone {
        DirectionCone { w, cos_theta: 1.0 }
    }
    use fenestra_core::{warp, Rng};

    #[test]
    fn sphere_unions_hold_both_and_solid_angles_are_exact() {
        let mut rng = Rng::new(2);
        for _ in 0..1000 {
            let s = |rng: &mut Rng| Sphere {
                center: warp::square_to_uniform_sphere(rng.next_2d()) * 5.0 * rng.next_f32(),
                radius: rng.next_f32(),
            };
            let (a, b) = (s(&mut rng), s(&mut rng));
            let u = Sphere::union(a, b);
            for c in [a, b] {
                assert!((c.center - u.center).length() + c.radius <= u.radius * (1.0 + 1e-5));
            }
        }
        // A sphere of radius 1 at distance 2 subtends 2 pi (1 - cos 30 degrees).
        let s = Sphere {
            center: Vec3::new(0.0, 0.0, 2.0),
            radius: 1.0,
        };
        let expect = 2.0 * PI * (1.0 - (PI / 6.0).cos());
        assert!((s.solid_angle(Vec3::ZERO) - expect).abs() < 1e-5);
    }

    #[test]
    fn a_cluster_behind_the_surface_or_facing_away_is_pruned() {
        let cluster = |center: Vec3, w: Vec3| {
            let sphere = Sphere {
                center,
                radius: 0.1,
            };
            let bounds = LightBounds {
                lo: center - Vec3::splat(0.05),
                hi: center + Vec3::splat(0.05),
                phi: 1.0,
                normals: facing(w),
                cos_theta_e: 0.0,
                two_sided: false,
            };
            Cluster {
                light: 0,
                ..Cluster::new(sphere, bounds, 1.0, None)
            }
        };
        let (p, n) = (Vec3::ZERO, Vec3::Z);
        // Above the point, facing down onto it: reaches.
        assert!(reaches(&cluster(Vec3::Z, -Vec3::Z), p, n));
        // Above, facing up (away): pruned.
        assert!(!reaches(&cluster(Vec3::Z, Vec3::Z), p, n));
        // Below the surface: pruned whatever it faces; with no normal, it reaches.
        assert!(!reaches(&cluster(-Vec3::Z, Vec3::Z), p, n));
        assert!(reaches(&cluster(-Vec3::Z, Vec3::Z), p, Vec3::ZERO));
        // Grazing: the sphere straddles the tangent plane, kept.
        assert!(reaches(
            &cluster(Vec3::new(1.0, 0.0, -0.05), -Vec3::X),
            p,
            n
        ));
    }
}
