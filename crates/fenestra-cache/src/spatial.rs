//! The spatial cache (seed 003 §2.4.2): records in an octree. While a pass renders, the
//! cache is read-only and each 8x8 block keeps what it adds (new records, new samples of any
//! record) in its own [`Delta`], which it searches too; between passes the deltas are merged
//! in block order. Renders therefore do not depend on the number of threads, though blocks
//! of one pass do not see each other's additions.

use crate::octree::Octree;
use crate::record::{Payload, Record};
use fenestra_core::Vec3;
use std::collections::HashMap;

/// What a block added during a pass.
#[derive(Debug)]
pub struct Delta<P: Payload> {
    /// New records; record `cache.len() + k` is the k-th.
    records: Vec<Record<P>>,
    /// Additions by record.
    added: HashMap<u32, Vec<P::Update>>,
    /// Work done, for the statistics.
    pub counts: Counts,
    /// Records near the current point with their weights (scratch, kept to avoid
    /// allocating per sample).
    pub near: Vec<(u32, f32)>,
}

impl<P: Payload> Default for Delta<P> {
    fn default() -> Self {
        Delta {
            records: Vec::new(),
            added: HashMap::new(),
            counts: Counts::default(),
            near: Vec::new(),
        }
    }
}

/// Work counted by the cache.
#[derive(Clone, Copy, Debug, Default)]
pub struct Counts {
    /// Rays traced to create records.
    pub record_rays: u64,
    /// Rays traced to add samples to existing records (the seed's additional rays).
    pub update_rays: u64,
    /// Directions dropped because no record near the point could take them.
    pub rejected: u64,
    /// Directions interpolated from cached samples.
    pub interpolated: u64,
    /// Shading points the cache served.
    pub points: u64,
    /// Records used over those points (their mean is the records per interpolation).
    pub records_used: u64,
}

impl std::ops::AddAssign for Counts {
    fn add_assign(&mut self, o: Counts) {
        self.record_rays += o.record_rays;
        self.update_rays += o.update_rays;
        self.rejected += o.rejected;
        self.interpolated += o.interpolated;
        self.points += o.points;
        self.records_used += o.records_used;
    }
}

/// Records and their octree.
#[derive(Debug)]
pub struct SpatialCache<P> {
    records: Vec<Record<P>>,
    octree: Octree,
    /// Largest maximum error any lookup uses: a record reaches `reach * R_i`.
    reach: f32,
    /// Everything counted so far.
    pub counts: Counts,
}

impl<P: Payload> SpatialCache<P> {
    /// An empty cache over the box `lo`..`hi` for lookups with maximum error up to `reach`.
    pub fn new(lo: Vec3, hi: Vec3, reach: f32) -> Self {
        SpatialCache {
            records: Vec::new(),
            octree: Octree::new(lo, hi),
            reach,
            counts: Counts::default(),
        }
    }

    /// Number of records.
    pub fn len(&self) -> usize {
        self.records.len()
    }

    /// Whether it holds no record.
    pub fn is_empty(&self) -> bool {
        self.records.is_empty()
    }

    /// The records.
    pub fn records(&self) -> &[Record<P>] {
        &self.records
    }

    /// Record `id`, from the cache or from `delta`.
    pub fn record<'a>(&'a self, delta: &'a Delta<P>, id: u32) -> &'a Record<P> {
        let id = id as usize;
        match id.checked_sub(self.records.len()) {
            None => &self.records[id],
            Some(k) => &delta.records[k],
        }
    }

    /// What `delta` added to record `id`.
    pub fn added<'a>(&self, delta: &'a Delta<P>, id: u32) -> &'a [P::Update] {
        delta.added.get(&id).map_or(&[], |v| v.as_slice())
    }

    /// Fills `delta.near` with the records that may serve `p` (normal `n`) with maximum
    /// error `a` (eq. 2.1), and their weights (eq. 2.2), in id order; whether there are any.
    pub fn lookup(&self, delta: &mut Delta<P>, p: Vec3, n: Vec3, a: f32) -> bool {
        let mut near = std::mem::take(&mut delta.near);
        near.clear();
        self.octree.candidates(p, |id| {
            if let Some(w) = self.records[id as usize].weight(p, n, a) {
                near.push((id, w));
            }
        });
        let first = self.records.len() as u32;
        for (k, r) in delta.records.iter().enumerate() {
            if let Some(w) = r.weight(p, n, a) {
                near.push((first + k as u32, w));
            }
        }
        // The octree's order depends on its shape; the sum over records must not.
        near.sort_unstable_by_key(|&(id, _)| id);
        delta.near = near;
        !delta.near.is_empty()
    }

    /// Adds a record to `delta`, which becomes the only one near (a point gets a record where
    /// no other serves it).
    pub fn create(&self, delta: &mut Delta<P>, record: Record<P>) {
        delta.records.push(record);
        let id = (self.records.len() + delta.records.len() - 1) as u32;
        delta.near.clear();
        delta.near.push((id, 1.0));
    }

    /// Adds `update` of record `id` to `delta`.
    pub fn add(&self, delta: &mut Delta<P>, id: u32, update: P::Update) {
        delta.added.entry(id).or_default().push(update);
    }

    /// Merges the blocks' additions, in block order: records get their ids, radii are clamped
    /// between neighbours (Krivanek et al.'s neighbour clamping: R_i <= R_j + |p_i - p_j|),
    /// additions go into their records.
    pub fn merge(&mut self, deltas: Vec<Delta<P>>) {
        let first = self.records.len() as u32;
        for delta in deltas {
            let base = self.records.len() as u32;
            let remap = |id: u32| if id >= first { base + (id - first) } else { id };
            self.counts += delta.counts;
            for mut record in delta.records {
                let id = self.records.len() as u32;
                let mut neighbours = Vec::new();
                self.octree.candidates(record.si.p, |j| neighbours.push(j));
                for j in neighbours {
                    let other = &mut self.records[j as usize];
                    let d = (other.si.p - record.si.p).length();
                    record.r = record.r.min(other.r + d);
                    other.r = other.r.min(record.r + d);
                }
                self.octree.insert(id, record.si.p, self.reach * record.r);
                self.records.push(record);
            }
            let mut ids: Vec<u32> = delta.added.keys().copied().collect();
            ids.sort_unstable();
            for id in ids {
                let target = &mut self.records[remap(id) as usize].payload;
                for &u in &delta.added[&id] {
                    target.absorb(u);
                }
            }
        }
    }

    /// Bytes the records take.
    pub fn bytes(&self) -> usize {
        self.records
            .iter()
            .map(|r| r.payload.bytes() + std::mem::size_of::<Record<P>>())
            .sum()
    }
}
