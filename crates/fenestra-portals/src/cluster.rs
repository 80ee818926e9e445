//! DBSCAN(eps, m) over the photons (seed 000 §4.3, Alg. 2): each spatially separate group of
//! photons becomes one cluster, and so one portal.
//!
//! The result is the classic algorithm's: a point is a core point when at least m points
//! (itself included) lie within eps; core points within eps of each other share a cluster;
//! a border point joins the first cluster (by lowest core index) that reaches it; a cluster
//! smaller than m is noise. It is computed on a grid of cells eps/sqrt(3) wide, in which any
//! two points of a cell are within eps (Gunawan 2013): a cell holding m points is all core
//! points and one piece of a cluster, and neighbouring cells join when one pair of their core
//! points is within eps. Memory stays linear in the photons and time near it; a library that
//! stores every neighbourhood (petal-clustering, used before) needed memory growing with the
//! square of the photons in dense clusters (2.2 GB for 262,144 photons on hall-windows).

use fenestra_core::Vec3;
use glam::DVec3;
use rayon::prelude::*;
use std::collections::HashMap;

/// DBSCAN(eps, m) of seed 000 Alg. 2.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct DbscanParams {
    /// Neighbourhood radius eps in metres (seed §5.2: 0.125).
    pub eps: f32,
    /// Minimum neighbourhood size m of a core point (16).
    pub min_points: usize,
}

impl Default for DbscanParams {
    fn default() -> Self {
        DbscanParams {
            eps: 0.125,
            min_points: 16,
        }
    }
}

/// Clusters of `points` as lists of indices, largest first (ties by first index); points in
/// no cluster are noise.
pub fn dbscan(points: &[Vec3], params: DbscanParams) -> Vec<Vec<usize>> {
    if points.is_empty() || !(params.eps > 0.0) {
        return Vec::new();
    }
    let grid = Grid::new(points, params.eps as f64);
    let m = params.min_points;
    let core: Vec<bool> = (0..points.len())
        .into_par_iter()
        .map(|i| grid.cell_size(i) >= m || grid.count_within(i, m) >= m)
        .collect();
    // Connected components of the core points.
    let mut sets = UnionFind::new(points.len());
    let cells: Vec<_> = grid.cells.iter().collect();
    for &(key, &(a, b)) in &cells {
        let cores: Vec<usize> = grid.members(a, b).filter(|&i| core[i]).collect();
        for w in cores.windows(2) {
            sets.union(w[0], w[1]);
        }
        let Some(&first) = cores.first() else {
            continue;
        };
        for other in grid.neighbour_cells(*key) {
            // Each pair of cells once.
            if other <= *key {
                continue;
            }
            let Some(&(c, d)) = grid.cells.get(&other) else {
                continue;
            };
            let Some(q) = grid.members(c, d).find(|&j| core[j]) else {
                continue;
            };
            if sets.find(first) == sets.find(q) {
                continue;
            }
            let joined = cores
                .iter()
                .any(|&i| grid.members(c, d).any(|j| core[j] && grid.within(i, j)));
            if joined {
                sets.union(first, q);
            }
        }
    }
    // Each component is named by its lowest core index, the order the classic algorithm
    // would grow it in.
    let mut seed = vec![usize::MAX; points.len()];
    for i in (0..points.len()).filter(|&i| core[i]) {
        let r = sets.find(i);
        seed[r] = seed[r].min(i);
    }
    let label: Vec<Option<usize>> = (0..points.len())
        .into_par_iter()
        .map(|i| {
            if core[i] {
                return Some(seed[sets.find_readonly(i)]);
            }
            let mut best = None;
            grid.visit_within(i, |j| {
                if core[j] {
                    let s = seed[sets.find_readonly(j)];
                    best = Some(best.map_or(s, |b: usize| b.min(s)));
                }
                true
            });
            best
        })
        .collect();
    let mut by_seed: HashMap<usize, Vec<usize>> = HashMap::new();
    for (i, l) in label.into_iter().enumerate() {
        if let Some(s) = l {
            by_seed.entry(s).or_default().push(i);
        }
    }
    let mut clusters: Vec<Vec<usize>> = by_seed.into_values().filter(|c| c.len() >= m).collect();
    clusters.sort_by(|a, b| b.len().cmp(&a.len()).then(a[0].cmp(&b[0])));
    clusters
}

/// Disjoint sets with path halving.
struct UnionFind {
    parent: Vec<usize>,
}

impl UnionFind {
    fn new(n: usize) -> Self {
        UnionFind {
            parent: (0..n).collect(),
        }
    }

    fn find(&mut self, mut i: usize) -> usize {
        while self.parent[i] != i {
            self.parent[i] = self.parent[self.parent[i]];
            i = self.parent[i];
        }
        i
    }

    /// `find` without compressing (for parallel reads once the sets are built).
    fn find_readonly(&self, mut i: usize) -> usize {
        while self.parent[i] != i {
            i = self.parent[i];
        }
        i
    }

    fn union(&mut self, a: usize, b: usize) {
        let (a, b) = (self.find(a), self.find(b));
        if a != b {
            self.parent[a.max(b)] = a.min(b);
        }
    }
}

/// How many cells away, per axis, a point within eps can lie: ceil(sqrt(3)).
const REACH: i64 = 2;

/// The points sorted into cubic cells eps/sqrt(3) wide.
struct Grid<'a> {
    points: &'a [Vec3],
    eps: f64,
    side: f64,
    /// Point indices ordered by cell.
    order: Vec<u32>,
    /// Each cell's range in `order`.
    cells: HashMap<[i64; 3], (u32, u32)>,
    /// Each point's cell size.
    cell_of: Vec<u32>,
}

impl<'a> Grid<'a> {
    fn new(points: &'a [Vec3], eps: f64) -> Self {
        let side = eps / 3f64.sqrt();
        let cell = |p: Vec3| p.as_dvec3().to_array().map(|c| (c / side).floor() as i64);
        let mut order: Vec<u32> = (0..points.len() as u32).collect();
        order.sort_unstable_by_key(|&i| cell(points[i as usize]));
        let mut cells = HashMap::new();
        let mut cell_of = vec![0u32; points.len()];
        let mut start = 0;
        while start < order.len() {
            let key = cell(points[order[start] as usize]);
            let mut end = start + 1;
            while end < order.len() && cell(points[order[end] as usize]) == key {
                end += 1;
            }
            cells.insert(key, (start as u32, end as u32));
            for &i in &order[start..end] {
                cell_of[i as usize] = (end - start) as u32;
            }
            start = end;
        }
        Grid {
            points,
            eps,
            side,
            order,
            cells,
            cell_of,
        }
    }

    fn key(&self, p: DVec3) -> [i64; 3] {
        p.to_array().map(|x| (x / self.side).floor() as i64)
    }

    /// Points in the same cell as point `i` (all within eps of it).
    fn cell_size(&self, i: usize) -> usize {
        self.cell_of[i] as usize
    }

    fn members(&self, a: u32, b: u32) -> impl Iterator<Item = usize> + '_ {
        self.order[a as usize..b as usize]
            .iter()
            .map(|&i| i as usize)
    }

    /// The cells that may hold points within eps of cell `key`'s (itself excluded).
    fn neighbour_cells(&self, key: [i64; 3]) -> impl Iterator<Item = [i64; 3]> {
        (-REACH..=REACH).flat_map(move |dx| {
            (-REACH..=REACH).flat_map(move |dy| {
                (-REACH..=REACH)
                    .filter(move |&dz| (dx, dy, dz) != (0, 0, 0))
                    .map(move |dz| [key[0] + dx, key[1] + dy, key[2] + dz])
            })
        })
    }

    fn within(&self, i: usize, j: usize) -> bool {
        (self.points[i].as_dvec3() - self.points[j].as_dvec3()).length_squared()
            <= self.eps * self.eps
    }

    /// Calls `f` with the points within eps of point `i` (`i` included) until it returns
    /// false.
    fn visit_within(&self, i: usize, mut f: impl FnMut(usize) -> bool) {
        let c = self.key(self.points[i].as_dvec3());
        for key in std::iter::once(c).chain(self.neighbour_cells(c)) {
            let Some(&(a, b)) = self.cells.get(&key) else {
                continue;
            };
            for j in self.members(a, b) {
                if self.within(i, j) && !f(j) {
                    return;
                }
            }
        }
    }

    /// The points within eps of point `i`, counted up to `enough`.
    fn count_within(&self, i: usize, enough: usize) -> usize {
        let mut n = 0;
        self.visit_within(i, |_| {
            n += 1;
            n < enough
        });
        n
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fenestra_core::Rng;

    #[test]
    fn separated_blobs_are_found_and_scattered_points_are_noise() {
        let mut rng = Rng::new(7);
        let mut r = || rng.next_f64() as f32;
        let centres = [
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 3.0, 1.0),
        ];
        let mut points = Vec::new();
        let mut truth = Vec::new();
        for (k, c) in centres.iter().enumerate() {
            for _ in 0..100 + 50 * k {
                let d = Vec3::new(r() - 0.5, r() - 0.5, r() - 0.5) * 0.4;
                points.push(*c + d);
                truth.push(Some(k));
            }
        }
        // Noise: isolated points far from the blobs and from one another.
        for i in 0..20 {
            points.push(Vec3::new(10.0 + i as f32, -5.0, 7.0));
            truth.push(None);
        }
        let clusters = dbscan(
            &points,
            DbscanParams {
                eps: 0.15,
                min_points: 8,
            },
        );
        assert_eq!(clusters.len(), 3);
        // Largest first: blob 2 (200 points), then 1, then 0; each cluster is one blob exactly.
        for (c, blob) in clusters.iter().zip([2, 1, 0]) {
            let expected: Vec<usize> = (0..points.len())
                .filter(|&i| truth[i] == Some(blob))
                .collect();
            assert_eq!(c, &expected, "blob {blob}");
        }
    }

    #[test]
    fn chains_join_into_one_cluster_and_sparse_sets_give_none() {
        // Points 0.1 apart on a line: density-reachable end to end with eps 0.15, m 3.
        let line: Vec<Vec3> = (0..50).map(|i| Vec3::X * (0.1 * i as f32)).collect();
        let c = dbscan(
            &line,
            DbscanParams {
                eps: 0.15,
                min_points: 3,
            },
        );
        assert_eq!(c.len(), 1);
        assert_eq!(c[0].len(), 50);
        assert!(dbscan(
            &line,
            DbscanParams {
                eps: 0.05,
                min_points: 3
            }
        )
        .is_empty());
        assert!(dbscan(&[], DbscanParams::default()).is_empty());
    }

    /// DBSCAN as petal-clustering ran it: every neighbourhood stored, clusters expanded from
    /// core points in index order, clusters smaller than m dropped.
    fn reference(points: &[Vec3], eps: f32, m: usize) -> Vec<Vec<usize>> {
        let near = |a: Vec3, b: Vec3| (a.as_dvec3() - b.as_dvec3()).length() <= eps as f64;
        let hoods: Vec<Vec<usize>> = points
            .iter()
            .map(|&p| (0..points.len()).filter(|&q| near(p, points[q])).collect())
            .collect();
        let mut visited = vec![false; points.len()];
        let mut clusters = Vec::new();
        for seed in 0..points.len() {
            if visited[seed] || hoods[seed].len() < m {
                continue;
            }
            let (mut cluster, mut stack) = (Vec::new(), vec![seed]);
            while let Some(p) = stack.pop() {
                if visited[p] {
                    continue;
                }
                visited[p] = true;
                cluster.push(p);
                if hoods[p].len() >= m {
                    stack.extend(hoods[p].iter().filter(|&&q| !visited[q]));
                }
            }
            if cluster.len() >= m {
                cluster.sort_unstable();
                clusters.push(cluster);
            }
        }
        clusters.sort_by(|a, b| b.len().cmp(&a.len()).then(a[0].cmp(&b[0])));
        clusters
    }

    #[test]
    fn the_grid_finds_exactly_what_stored_neighbourhoods_find() {
        let mut rng = Rng::new(11);
        let cases = [
            (400, 1.0, 0.1, 4),
            (600, 2.0, 0.2, 8),
            (300, 0.5, 0.05, 3),
            (800, 1.0, 0.07, 5),
            (500, 3.0, 0.3, 6),
        ];
        for (n, spread, eps, m) in cases {
            // Clumps, filaments and scattered points, with coordinates on both sides of cell
            // boundaries.
            let mut points = Vec::new();
            for k in 0..n {
                let c = Vec3::new((k % 5) as f32, (k % 3) as f32 * 0.7, 0.0) * spread;
                let jitter = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - 0.5;
                points.push(c + jitter * spread * if k % 7 == 0 { 4.0 } else { 0.3 });
            }
            let p = DbscanParams { eps, min_points: m };
            let expected = reference(&points, eps, m);
            let clustered: usize = expected.iter().map(Vec::len).sum();
            assert!(
                expected.len() >= 3 && clustered < n,
                "n {n}: {} clusters, {clustered} clustered: a test needs clusters and noise",
                expected.len()
            );
            assert_eq!(dbscan(&points, p), expected, "n {n}, eps {eps}, m {m}");
        }
    }
}
