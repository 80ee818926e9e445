//! The spatial cache's index (Ward et al. 1988): an octree in which a record of validity
//! radius rho sits in the deepest node, containing its position, whose half-size is at least
//! rho. Each node also keeps the largest radius in its subtree, so that a lookup visits only
//! the nodes whose records may reach the point.

use fenestra_core::Vec3;

/// An octree over record positions.
#[derive(Clone, Debug)]
pub struct Octree {
    center: Vec3,
    half: f32,
    nodes: Vec<Node>,
}

#[derive(Clone, Debug, Default)]
struct Node {
    /// Child node indices (0: none; the root is never a child).
    children: [u32; 8],
    /// Records stored here.
    records: Vec<u32>,
    /// Largest validity radius of the records in its subtree.
    reach: f32,
}

impl Octree {
    /// An empty octree over the box `lo`..`hi` (records outside it sit at the root).
    pub fn new(lo: Vec3, hi: Vec3) -> Self {
        let half = ((hi - lo).max_element() * 0.5).max(1e-6) * 1.001;
        Octree {
            center: (lo + hi) * 0.5,
            half,
            nodes: vec![Node::default()],
        }
    }

    /// Adds record `id` at `p`, able to serve points within `radius` of it.
    pub fn insert(&mut self, id: u32, p: Vec3, radius: f32) {
        let (mut node, mut center, mut half) = (0usize, self.center, self.half);
        let inside = (p - center).abs().max_element() <= half;
        loop {
            let n = &mut self.nodes[node];
            n.reach = n.reach.max(radius);
            if !(inside && half * 0.5 >= radius && half > 1e-6) {
                break;
            }
            let (octant, child_center) = octant(center, half, p);
            let child = match self.nodes[node].children[octant] {
                0 => {
                    self.nodes.push(Node::default());
                    let c = (self.nodes.len() - 1) as u32;
                    self.nodes[node].children[octant] = c;
                    c
                }
                c => c,
            };
            node = child as usize;
            center = child_center;
            half *= 0.5;
        }
        self.nodes[node].records.push(id);
    }

    /// Calls `visit` with every record whose validity sphere may contain `p`.
    pub fn candidates(&self, p: Vec3, mut visit: impl FnMut(u32)) {
        self.visit(0, self.center, self.half, p, &mut visit);
    }

    /// The records of node `index` (centre `center`, half-size `half`) and of the children
    /// whose records may reach `p`.
    fn visit(&self, index: u32, center: Vec3, half: f32, p: Vec3, visit: &mut impl FnMut(u32)) {
        let node = &self.nodes[index as usize];
        node.records.iter().for_each(|&r| visit(r));
        let h = half * 0.5;
        for (octant, &child) in node.children.iter().enumerate() {
            if child == 0 {
                continue;
            }
            // A child's records lie in its cube and reach at most its `reach` beyond it.
            let c = child_center(center, h, octant);
            let outside = ((p - c).abs() - Vec3::splat(h)).max(Vec3::ZERO);
            let reach = self.nodes[child as usize].reach;
            if outside.length_squared() <= reach * reach {
                self.visit(child, c, h, p, visit);
            }
        }
    }
}

fn octant(center: Vec3, half: f32, p: Vec3) -> (usize, Vec3) {
    let o = usize::from(p.x > center.x)
        | usize::from(p.y > center.y) << 1
        | usize::from(p.z > center.z) << 2;
    (o, child_center(center, half * 0.5, o))
}

fn child_center(center: Vec3, h: f32, octant: usize) -> Vec3 {
    let s = |bit: usize| if octant & bit != 0 { h } else { -h };
    center + Vec3::new(s(1), s(2), s(4))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lookups_find_every_record_whose_sphere_holds_the_point() {
        let mut rng = fenestra_core::Rng::new(77);
        let mut next = || rng.next_f32();
        let mut tree = Octree::new(Vec3::splat(-1.0), Vec3::new(1.0, 2.0, 1.0));
        let mut records = Vec::new();
        for id in 0..2000u32 {
            // Some outside the box, radii over four orders of magnitude.
            let p = Vec3::new(next(), next(), next()) * 2.4 - Vec3::splat(1.2);
            let radius = 10f32.powf(-3.5 + 4.0 * next());
            tree.insert(id, p, radius);
            records.push((p, radius));
        }
        for _ in 0..2000 {
            let p = Vec3::new(next(), next(), next()) * 2.4 - Vec3::splat(1.2);
            let mut found = Vec::new();
            tree.candidates(p, |id| found.push(id));
            for (id, (q, r)) in records.iter().enumerate() {
                if (p - *q).length() < *r {
                    assert!(
                        found.contains(&(id as u32)),
                        "record {id} at {q} r {r}, p {p}"
                    );
                }
            }
        }
    }
}
