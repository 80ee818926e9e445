//! The L-tree (seed 003 §2.4.3-2.4.4): a record's incoming radiance samples as points of the
//! paraboloid disc D, quantised to 256 x 256, radiance in RGBE, in an implicit kd-tree of
//! 8-byte nodes (ranges of up to 8 samples are unsorted leaves); samples added later wait in a buffer, searched linearly, until it is full and
//! the tree is rebuilt with them.

use crate::record::Payload;
use crate::rgbe::Rgbe;
use fenestra_core::{Rgb, Vec2};

/// Quantisation steps across D's [-1, 1] (one byte a coordinate).
const STEPS: f32 = 255.0;

/// Samples the buffer holds before the tree is rebuilt with them.
const BUFFER: usize = 16;

/// Ranges of at most this many samples are leaves, searched linearly.
const LEAF: u32 = 8;

/// One radiance sample: its quantised position in D, its radiance, and the split axis of the
/// kd-tree node it is (the 2 bytes of bookkeeping): 8 bytes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[repr(C)]
pub struct Sample {
    q: [u8; 2],
    radiance: Rgbe,
    axis: u16,
}

const _: () = assert!(std::mem::size_of::<Sample>() == 8);

impl Sample {
    /// The sample of radiance `l` arriving from the point `d` of D.
    pub fn new(d: Vec2, l: Rgb) -> Sample {
        let q = |v: f32| ((v.clamp(-1.0, 1.0) + 1.0) * 0.5 * STEPS).round() as u8;
        Sample {
            q: [q(d.x), q(d.y)],
            radiance: Rgbe::encode(l),
            axis: 0,
        }
    }

    /// Its position in D (the centre of its quantisation cell).
    pub fn position(&self) -> Vec2 {
        Vec2::new(self.q[0] as f32, self.q[1] as f32) * (2.0 / STEPS) - Vec2::ONE
    }

    /// Its radiance.
    pub fn radiance(&self) -> Rgb {
        self.radiance.decode()
    }

    /// Squared distance in D from its position to `c` (as [`LTree::within`] measures it).
    pub fn distance2(&self, c: Vec2) -> f32 {
        steps_distance2(self.q, to_steps(c))
    }
}

/// A point of D in quantisation steps.
fn to_steps(c: Vec2) -> Vec2 {
    (c + Vec2::ONE) * (0.5 * STEPS)
}

/// Squared distance in D between quantised `q` and `qc` (in steps).
fn steps_distance2(q: [u8; 2], qc: Vec2) -> f32 {
    let d = Vec2::new(q[0] as f32, q[1] as f32) - qc;
    d.length_squared() * ((2.0 / STEPS) * (2.0 / STEPS))
}

/// A record's radiance samples.
#[derive(Clone, Debug, Default)]
pub struct LTree {
    /// The kd-tree: the node of a range is its middle element, its children the halves.
    nodes: Vec<Sample>,
    /// Samples added since the last build.
    buffer: Vec<Sample>,
}

impl LTree {
    /// The tree over `samples`.
    pub fn build(samples: Vec<Sample>) -> LTree {
        let mut t = LTree {
            nodes: samples,
            buffer: Vec::new(),
        };
        split(&mut t.nodes);
        t
    }

    /// Adds a sample: to the buffer, and the tree is rebuilt when the buffer is full.
    pub fn insert(&mut self, s: Sample) {
        self.buffer.push(s);
        if self.buffer.len() >= BUFFER {
            self.nodes.append(&mut self.buffer);
            split(&mut self.nodes);
        }
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.nodes.len() + self.buffer.len()
    }

    /// Whether it holds no sample.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Bytes it takes, buffer capacity included.
    pub fn bytes(&self) -> usize {
        (self.nodes.capacity() + self.buffer.capacity()) * std::mem::size_of::<Sample>()
    }

    /// Calls `found` with every sample within `radius` of `c` (in D) and its squared
    /// distance to `c`.
    pub fn within(&self, c: Vec2, radius: f32, mut found: impl FnMut(&Sample, f32)) {
        // The query in quantisation steps, to compare with the samples' bytes (the radius a
        // little wider, so that rounding never prunes a sample on the boundary).
        let qc = to_steps(c);
        let qr = radius * 0.5 * STEPS + 1e-3;
        let r2 = radius * radius;
        let mut visit = |s: &Sample| {
            let d2 = steps_distance2(s.q, qc);
            if d2 < r2 {
                found(s, d2);
            }
        };
        self.buffer.iter().for_each(&mut visit);
        // Ranges still to visit; each level pushes at most two, and the depth is below 32.
        let mut stack = [(0u32, 0u32); 64];
        let mut top = 0;
        if !self.nodes.is_empty() {
            stack[0] = (0, self.nodes.len() as u32);
            top = 1;
        }
        while top > 0 {
            top -= 1;
            let (lo, hi) = stack[top];
            if hi - lo <= LEAF {
                self.nodes[lo as usize..hi as usize]
                    .iter()
                    .for_each(&mut visit);
                continue;
            }
            let mid = (lo + hi) / 2;
            let node = &self.nodes[mid as usize];
            visit(node);
            let axis = node.axis as usize;
            let diff = qc[axis] - node.q[axis] as f32;
            if diff <= qr {
                stack[top] = (lo, mid);
                top += 1;
            }
            if diff >= -qr {
                stack[top] = (mid + 1, hi);
                top += 1;
            }
        }
    }
}

impl Payload for LTree {
    type Update = Sample;

    fn absorb(&mut self, s: Sample) {
        self.insert(s);
    }

    fn bytes(&self) -> usize {
        LTree::bytes(self)
    }
}

/// Arranges `nodes` as an implicit kd-tree: the middle element splits the range along the
/// axis of its larger extent, smaller coordinates before it, larger after.
fn split(nodes: &mut [Sample]) {
    if nodes.len() <= LEAF as usize {
        return;
    }
    let (mut lo, mut hi) = ([u8::MAX; 2], [0u8; 2]);
    for n in nodes.iter() {
        for a in 0..2 {
            lo[a] = lo[a].min(n.q[a]);
            hi[a] = hi[a].max(n.q[a]);
        }
    }
    let axis = usize::from(hi[1] - lo[1] > hi[0] - lo[0]);
    let mid = nodes.len() / 2;
    nodes.select_nth_unstable_by_key(mid, |n| n.q[axis]);
    nodes[mid].axis = axis as u16;
    let (left, rest) = nodes.split_at_mut(mid);
    split(left);
    split(&mut rest[1..]);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn samples(n: usize, seed: u32) -> Vec<Sample> {
        let mut rng = fenestra_core::Rng::new(seed as u64);
        let mut next = || rng.next_f32();
        (0..n)
            .map(|i| {
                // Clustered, as BRDF-sampled directions are, with duplicates of cells.
                let c = Vec2::new(next() * 2.0 - 1.0, next() * 2.0 - 1.0) * 0.3;
                let d = c * if i % 3 == 0 { 3.0 } else { 0.2 };
                Sample::new(d, Rgb::new(next(), next(), i as f32))
            })
            .collect()
    }

    fn brute(all: &[Sample], c: Vec2, r: f32) -> Vec<(Sample, u32)> {
        let mut v: Vec<_> = all
            .iter()
            .filter(|s| s.distance2(c) < r * r)
            .map(|s| (Sample { axis: 0, ..*s }, s.distance2(c).to_bits()))
            .collect();
        v.sort_by_key(|(s, d)| (s.q, s.radiance.0, *d));
        v
    }

    fn query(t: &LTree, c: Vec2, r: f32) -> Vec<(Sample, u32)> {
        let mut v = Vec::new();
        t.within(c, r, |s, d2| {
            v.push((Sample { axis: 0, ..*s }, d2.to_bits()))
        });
        v.sort_by_key(|(s, d)| (s.q, s.radiance.0, *d));
        v
    }

    #[test]
    fn range_queries_find_what_brute_force_finds() {
        for (n, seed) in [(0, 1), (1, 2), (2, 3), (7, 4), (512, 5), (3000, 6)] {
            let all = samples(n, seed);
            let mut tree = LTree::build(all[..n / 2].to_vec());
            for s in &all[n / 2..] {
                tree.insert(*s);
            }
            assert_eq!(tree.len(), n);
            for (k, c) in samples(200, seed + 100).iter().enumerate() {
                let r = [0.001, 0.01, 0.05, 0.15, 3.0][k % 5];
                let c = c.position();
                assert_eq!(query(&tree, c, r), brute(&all, c, r), "n {n}, c {c}, r {r}");
            }
        }
    }

    #[test]
    fn positions_are_quantised_to_a_256th_of_the_disc() {
        for s in samples(1000, 9) {
            let p = s.position();
            let again = Sample::new(p, Rgb::ZERO).position();
            assert_eq!(p, again);
        }
        let d = Vec2::new(0.3331, -0.77);
        let e = (Sample::new(d, Rgb::ZERO).position() - d).abs();
        assert!(e.x <= 1.0 / STEPS && e.y <= 1.0 / STEPS, "{e}");
    }
}
