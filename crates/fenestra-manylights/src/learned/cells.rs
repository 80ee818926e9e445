//! The cells the learned sampler learns in: a grid of boxes over the scene with six normal
//! directions each, boxes of half their side where the samples are many, and the table that
//! finds a point's cell by its key (a spatial hash with open addressing).

use fenestra_core::Vec3;

/// Levels of cells: the grid's boxes, and boxes of half their side where the samples of all
/// passes so far fill them (two: [`halves`] finds the stand-ins one level down).
pub(super) const LEVELS: u32 = 2;

/// Bits of a cell's key for its box's index along an axis.
pub(super) const AXIS_BITS: u32 = 19;

/// Where a cell's key keeps its level (after three axes and the normal's class).
pub(super) const LEVEL_SHIFT: u32 = 3 * AXIS_BITS + 3;

/// Samples a cell finer than the grid's boxes needs to be used, in first-pass records per
/// cell (`learned.cell_records`, which sizes the grid's boxes).
pub(super) const FINE_SAMPLES: u32 = 8;

/// The grid of cells: boxes of one size over the scene, six normal directions each.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Grid {
    pub(super) lo: Vec3,
    pub(super) inv_size: f32,
}

impl Grid {
    /// The cell of a point with normal `n` on `level` (0: this grid's boxes; each level
    /// halves them).
    pub(super) fn key(&self, p: Vec3, n: Vec3, level: u32) -> u64 {
        let q = (p - self.lo) * (self.inv_size * (1 << level) as f32);
        let axis = |v: f32| (v.max(0.0) as u64).min((1 << AXIS_BITS) - 1);
        let a = n.abs();
        let (k, s) = if a.x >= a.y && a.x >= a.z {
            (0, n.x)
        } else if a.y >= a.z {
            (1, n.y)
        } else {
            (2, n.z)
        };
        let class = 2 * k + u64::from(s < 0.0);
        axis(q.x)
            | axis(q.y) << AXIS_BITS
            | axis(q.z) << (2 * AXIS_BITS)
            | class << (3 * AXIS_BITS)
            | u64::from(level) << LEVEL_SHIFT
    }
}

/// The learned distributions of one pass: per cell, its groups in increasing order with
/// their cumulative probabilities.
#[derive(Default)]
pub(super) struct Table {
    /// The cells.
    pub(super) grid: Grid,
    /// Open addressing by key: (key, first entry, entries); empty slots have no entries.
    pub(super) slots: Vec<(u64, u32, u32)>,
    /// (group, cumulative probability) of every cell, cell after cell.
    pub(super) entries: Vec<(u32, f32)>,
}

impl Table {
    /// The table of `sums` (ordered by cell and group): each group's share in its cell in
    /// proportion to its summed weight. Cells finer than the grid's boxes are kept where they
    /// hold `min_samples` samples.
    pub(super) fn new(grid: Grid, sums: &[Sum], min_samples: u32) -> Self {
        let mut cells: Vec<(u64, u32, u32)> = Vec::new();
        let mut entries = Vec::with_capacity(sums.len());
        let useful = |s: &&Sum| s.weight > 0.0 && s.weight.is_finite();
        for run in sums.chunk_by(|a, b| a.key == b.key) {
            let key = run[0].key;
            let fine = key >> LEVEL_SHIFT > 0;
            let samples: u32 = run.iter().map(|s| s.samples).sum();
            let total: f64 = run.iter().filter(useful).map(|s| s.weight).sum();
            if (fine && samples < min_samples) || total <= 0.0 || !total.is_finite() {
                continue;
            }
            let first = entries.len() as u32;
            let mut acc = 0.0;
            for s in run.iter().filter(useful) {
                acc += s.weight;
                entries.push((s.group, (acc / total) as f32));
            }
            if let Some(last) = entries.last_mut() {
                last.1 = 1.0;
            }
            cells.push((key, first, entries.len() as u32 - first));
        }
        // A point looks its finest cell up only: the finer cells that did not learn enough
        // stand for their box's.
        let learned_finer = |key: u64| cells.binary_search_by_key(&key, |c| c.0).is_ok();
        let stand_ins: Vec<(u64, u32, u32)> = cells
            .iter()
            .filter(|c| c.0 >> LEVEL_SHIFT == 0)
            .flat_map(|&(key, first, len)| halves(key).map(|half| (half, first, len)))
            .filter(|c| !learned_finer(c.0))
            .collect();
        cells.extend(stand_ins);
        let capacity = (2 * cells.len()).next_power_of_two().max(2);
        let mut slots = vec![(0, 0, 0); capacity];
        for cell in cells {
            let mut s = slot(cell.0, capacity);
            while slots[s].2 != 0 {
                s = (s + 1) & (capacity - 1);
            }
            slots[s] = cell;
        }
        Table {
            grid,
            slots,
            entries,
        }
    }

    /// The entries of the cell of a point with normal `n`, if it learned anything.
    pub(super) fn at(&self, p: Vec3, n: Vec3) -> Option<&[(u32, f32)]> {
        if self.entries.is_empty() {
            return None;
        }
        self.cell(self.grid.key(p, n, LEVELS - 1))
    }

    /// The entries of cell `key`, if it learned anything.
    pub(super) fn cell(&self, key: u64) -> Option<&[(u32, f32)]> {
        let mask = self.slots.len() - 1;
        let mut s = slot(key, self.slots.len());
        loop {
            let (k, first, len) = self.slots[s];
            if len == 0 {
                return None;
            }
            if k == key {
                return Some(&self.entries[first as usize..(first + len) as usize]);
            }
            s = (s + 1) & mask;
        }
    }
}

/// The keys of the eight boxes of half the side of cell `key`'s (its normal direction's).
pub(super) fn halves(key: u64) -> [u64; 8] {
    let mask = (1 << AXIS_BITS) - 1;
    let axis = |a: u32| (key >> (a * AXIS_BITS)) & mask;
    let rest = key >> (3 * AXIS_BITS) & 7;
    let level = (key >> LEVEL_SHIFT) + 1;
    std::array::from_fn(|i| {
        let half = |a: u32| (2 * axis(a) + (i as u64 >> a & 1)).min(mask);
        half(0)
            | half(1) << AXIS_BITS
            | half(2) << (2 * AXIS_BITS)
            | rest << (3 * AXIS_BITS)
            | level << LEVEL_SHIFT
    })
}

/// The home slot of `key` in a table of `capacity` (a power of two) slots.
pub(super) fn slot(key: u64, capacity: usize) -> usize {
    (key.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 32) as usize & (capacity - 1)
}

/// The samples of one group in one cell that found light: their summed weights, and their
/// number.
pub(super) struct Sum {
    pub(super) key: u64,
    pub(super) group: u32,
    pub(super) weight: f64,
    pub(super) samples: u32,
}

/// The finest grid whose boxes (the scene's diagonal over a power of two) hold `per_cell`
/// of `points` on average, counting each normal direction's cell apart.
pub(super) fn grid_for(points: &[(Vec3, Vec3)], lo: Vec3, diagonal: f32, per_cell: u32) -> Grid {
    let wanted = (points.len() / per_cell.max(1) as usize).max(1);
    let mut keys = Vec::with_capacity(points.len());
    let mut grid = Grid {
        lo,
        inv_size: 1.0 / diagonal,
    };
    for k in 1..=AXIS_BITS - (LEVELS - 1) {
        let finer = Grid {
            lo,
            inv_size: (1u32 << k) as f32 / diagonal,
        };
        keys.clear();
        keys.extend(points.iter().map(|&(p, n)| finer.key(p, n, 0)));
        keys.sort_unstable();
        keys.dedup();
        if keys.len() > wanted {
            break;
        }
        grid = finer;
    }
    grid
}
