//! The spatial cache (seed 003 §2.4.2): records in an octree. While a pass renders, the
//! cache is read-only and each 8x8 block keeps what it adds (new records, new samples of any
//! record) in its own [`Delta`], which it searches too; between passes the deltas are merged
//! in block order. Renders therefore do not depend on the number of threads, though blocks
//! of one pass do not see each other's additions.

use crate::ltree::Sample;
use crate::octree::Octree;
use crate::record::Record;
use fenestra_core::Vec3;
use std::collections::HashMap;

/// What a block added during a pass.
#[derive(Debug, Default)]
pub struct Delta {
    /// New records; record `cache.len() + k` is the k-th.
    records: Vec<Record>,
    /// New samples by record.
    samples: HashMap<u32, Vec<Sample>>,
    /// Work done, for the statistics.
    pub counts: Counts,
    /// Records near the current point with their weights (scratch, kept to avoid
    /// allocating per sample).
    pub near: Vec<(u32, f32)>,
    /// Pixels (x, y) of the samples whose indirect light the cache gave, one entry a sample.
    pub served: Vec<(u32, u32)>,
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
pub struct SpatialCache {
    records: Vec<Record>,
    octree: Octree,
    /// Largest maximum error any lookup uses: a record reaches `reach * R_i`.
    reach: f32,
    /// Everything counted so far.
    pub counts: Counts,
}

impl SpatialCache {
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
    pub fn records(&self) -> &[Record] {
        &self.records
    }

    /// Record `id`, from the cache or from `delta`.
    pub fn record<'a>(&'a self, delta: &'a Delta, id: u32) -> &'a Record {
        let id = id as usize;
        match id.checked_sub(self.records.len()) {
            None => &self.records[id],
            Some(k) => &delta.records[k],
        }
    }

    /// The samples `delta` added to record `id`.
    pub fn added<'a>(&self, delta: &'a Delta, id: u32) -> &'a [Sample] {
        delta.samples.get(&id).map_or(&[], |v| v.as_slice())
    }

    /// Fills `delta.near` with the records that may serve `p` (normal `n`) with maximum
    /// error `a` (eq. 2.1), and their weights (eq. 2.2), in id order.
    pub fn lookup(&self, delta: &mut Delta, p: Vec3, n: Vec3, a: f32) {
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
    }

    /// Adds a record to `delta`; returns its id.
    pub fn create(&self, delta: &mut Delta, record: Record) -> u32 {
        delta.records.push(record);
        (self.records.len() + delta.records.len() - 1) as u32
    }

    /// Adds a sample of record `id` to `delta`.
    pub fn add(&self, delta: &mut Delta, id: u32, s: Sample) {
        delta.samples.entry(id).or_default().push(s);
    }

    /// Merges the blocks' additions, in block order: records get their ids, radii are clamped
    /// between neighbours (Krivanek et al.'s neighbour clamping: R_i <= R_j + |p_i - p_j|),
    /// samples go into their records' L-trees.
    pub fn merge(&mut self, deltas: Vec<Delta>) {
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
            let mut ids: Vec<u32> = delta.samples.keys().copied().collect();
            ids.sort_unstable();
            for id in ids {
                let target = &mut self.records[remap(id) as usize].ltree;
                for &s in &delta.samples[&id] {
                    target.insert(s);
                }
            }
        }
    }

    /// Bytes the records take (L-trees and the records themselves).
    pub fn bytes(&self) -> usize {
        self.records
            .iter()
            .map(|r| r.ltree.bytes() + std::mem::size_of::<Record>())
            .sum()
    }

    /// Radiance samples over all records.
    pub fn samples(&self) -> usize {
        self.records.iter().map(|r| r.ltree.len()).sum()
    }
}
