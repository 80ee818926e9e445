//! The k nearest of a fixed set of points in space-time (eq. 4.2's distance is Euclidean once
//! positions are scaled by w1 and frames by w2): an implicit kd-tree, the points reordered by
//! median splits along the widest axis, each range's middle point the split, down to leaves
//! of a few points; the points are stored in the tree's order. Exploration and
//! reconstruction ask it for the explored view samples nearest every view sample.

/// A point: scaled position and scaled time.
pub type Point = [f32; 4];

/// Ranges of at most this many points are leaves, scanned in order.
const LEAF: usize = 8;

/// The kd-tree: the points and their indices in tree order, and each range's split axis.
#[derive(Clone, Debug)]
pub struct PointTree {
    points: Vec<Point>,
    ids: Vec<u32>,
    /// The split axis of the range whose middle is at each position.
    axis: Vec<u8>,
}

impl PointTree {
    /// The tree over `points` (indices are positions in this slice).
    pub fn new(points: &[Point]) -> Self {
        let mut order: Vec<u32> = (0..points.len() as u32).collect();
        let mut axis = vec![0; points.len()];
        build(points, &mut order, &mut axis, 0, points.len());
        PointTree {
            points: order.iter().map(|&i| points[i as usize]).collect(),
            ids: order,
            axis,
        }
    }

    /// The `k` points nearest `q` as (squared distance, index), nearest first, ties by index;
    /// `out` is reused.
    pub fn nearest(&self, q: &Point, k: usize, out: &mut Vec<(f32, u32)>) {
        out.clear();
        if k > 0 {
            self.search(q, k, 0, self.ids.len(), out);
        }
    }

    /// Offers the point at tree position `at` to `out`.
    fn offer(&self, q: &Point, k: usize, at: usize, out: &mut Vec<(f32, u32)>) {
        let p = &self.points[at];
        let d2: f32 = (0..4).map(|a| (p[a] - q[a]) * (p[a] - q[a])).sum();
        let e = (d2, self.ids[at]);
        let worse = |a: &(f32, u32), b: &(f32, u32)| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1));
        if out.len() < k || worse(&e, &out[out.len() - 1]).is_lt() {
            let at = out.partition_point(|x| worse(x, &e).is_lt());
            out.insert(at, e);
            out.truncate(k);
        }
    }

    fn search(&self, q: &Point, k: usize, lo: usize, hi: usize, out: &mut Vec<(f32, u32)>) {
        if hi - lo <= LEAF {
            (lo..hi).for_each(|at| self.offer(q, k, at, out));
            return;
        }
        let mid = (lo + hi) / 2;
        self.offer(q, k, mid, out);
        let axis = self.axis[mid] as usize;
        let delta = q[axis] - self.points[mid][axis];
        let (near, far) = if delta < 0.0 {
            ((lo, mid), (mid + 1, hi))
        } else {
            ((mid + 1, hi), (lo, mid))
        };
        self.search(q, k, near.0, near.1, out);
        if out.len() < k || delta * delta <= out[out.len() - 1].0 {
            self.search(q, k, far.0, far.1, out);
        }
    }
}

/// Orders `order[lo..hi]` by median splits along the widest axis, each range's middle the
/// split, down to leaves.
fn build(points: &[Point], order: &mut [u32], axis: &mut [u8], lo: usize, hi: usize) {
    if hi - lo <= LEAF {
        return;
    }
    let (mut min, mut max) = ([f32::INFINITY; 4], [f32::NEG_INFINITY; 4]);
    for &i in &order[lo..hi] {
        for a in 0..4 {
            min[a] = min[a].min(points[i as usize][a]);
            max[a] = max[a].max(points[i as usize][a]);
        }
    }
    let split = (0..4)
        .max_by(|&a, &b| (max[a] - min[a]).total_cmp(&(max[b] - min[b])))
        .unwrap_or(0);
    let mid = (lo + hi) / 2;
    order[lo..hi].select_nth_unstable_by(mid - lo, |&i, &j| {
        points[i as usize][split].total_cmp(&points[j as usize][split])
    });
    axis[mid] = split as u8;
    build(points, order, axis, lo, mid);
    build(points, order, axis, mid + 1, hi);
}

#[cfg(test)]
mod tests {
    use super::*;
    use fenestra_core::Rng;

    #[test]
    fn nearest_points_are_those_brute_force_finds() {
        let mut rng = Rng::new(3);
        // Clustered points with duplicates, so that ties are exercised.
        let mut points: Vec<Point> = (0..2000)
            .map(|_| {
                let c = (rng.next_f32() * 4.0).floor();
                [c + rng.next_f32() * 0.1, rng.next_f32(), c, 0.0]
            })
            .collect();
        let twins = points[..50].to_vec();
        points.extend(twins);
        let tree = PointTree::new(&points);
        let mut got = Vec::new();
        for t in 0..300 {
            let q = [
                rng.next_f32() * 4.0,
                rng.next_f32(),
                rng.next_f32() * 3.0,
                0.1 * t as f32 % 1.0,
            ];
            let k = 1 + t % 12;
            tree.nearest(&q, k, &mut got);
            let mut all: Vec<(f32, u32)> = (points.iter().enumerate())
                .map(|(i, p)| {
                    (
                        (0..4).map(|a| (p[a] - q[a]) * (p[a] - q[a])).sum(),
                        i as u32,
                    )
                })
                .collect();
            all.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            assert_eq!(got, all[..k], "query {t}");
        }
        assert!(PointTree::new(&[]).ids.is_empty());
    }
}
