//! A block's statistics per cut node and normal class (seed 004 §3.3.3, §3.5.4): what
//! every pass so far learned, read by the block PDFs (with the undersampling guard,
//! §4.6.2), and what the pass under way adds (Step FB at its end).

use super::feedback::{blend, component, guarded, unguarded, Stat};
use super::point::Point;
use crate::forest::{Forest, NO_PARENT};

/// Normal classes (the cube faces, §3.5.4).
const CLASSES: usize = 6;

/// The statistics of one block.
pub(super) struct BlockStats {
    /// The slot of each forest node and outside cluster in the block's cuts (`u32::MAX`:
    /// in none); the statistics are kept per slot.
    slot: Vec<u32>,
    /// Slots in use.
    slots: usize,
    /// Per class and slot: what the passes before this one saw.
    earlier: Vec<Vec<Stat>>,
    /// The block's F per class and slot, as the current pass's PDFs read them.
    read: Vec<Vec<Option<f64>>>,
    /// Per class and slot: what the current pass adds.
    current: Vec<Vec<Stat>>,
}

impl BlockStats {
    /// Empty statistics over the clusters of `cuts`, among `clusters` (the forest's nodes
    /// and the clusters outside it).
    pub(super) fn new<'a>(clusters: usize, cuts: impl Iterator<Item = &'a [u32]>) -> Self {
        let mut slot = vec![u32::MAX; clusters];
        let mut slots = 0;
        for cut in cuts {
            for &c in cut {
                if slot[c as usize] == u32::MAX {
                    slot[c as usize] = slots as u32;
                    slots += 1;
                }
            }
        }
        BlockStats {
            slot,
            slots,
            earlier: vec![vec![Stat::default(); slots]; CLASSES],
            read: Vec::new(),
            current: Vec::new(),
        }
    }

    /// Fresh statistics for a pixel's points of one class.
    pub(super) fn pixel_rows(&self) -> Vec<Stat> {
        vec![Stat::default(); self.slots]
    }

    /// Starts a pass: its PDFs read the earlier passes' statistics.
    pub(super) fn begin_pass(&mut self) {
        self.read = self
            .earlier
            .iter()
            .map(|rows| rows.iter().map(guarded).collect())
            .collect();
        self.current = vec![vec![Stat::default(); self.slots]; CLASSES];
    }

    /// Ends a pass (Step FB): its statistics join the earlier ones.
    pub(super) fn end_pass(&mut self) {
        for (all, new) in self.earlier.iter_mut().zip(&self.current) {
            for (a, n) in all.iter_mut().zip(new) {
                a.sum += n.sum;
                a.count += n.count;
                a.visible += n.visible;
            }
        }
    }

    /// The PDF over point `q`'s cut in pass `pass` (eq. 3.2, 3.7, 3.8) from the block's
    /// statistics and the pixel's (`pixel`, of `q`'s class), with the undersampling guard on
    /// the block part (§4.6.2).
    pub(super) fn pdf(&self, q: &Point, pixel: Option<&[Stat]>, pass: u32) -> Vec<f32> {
        let block = &self.read[q.class];
        let slot = |c: u32| self.slot[c as usize] as usize;
        blend(
            q.cut.len(),
            pass,
            component(q.cut.iter().map(|&c| block[slot(c)])),
            pixel.and_then(|s| component(q.cut.iter().map(|&c| unguarded(&s[slot(c)])))),
        )
    }

    /// Adds a sample of the light at `leaf` (its contribution `value`, the light's `power`,
    /// whether it was `visible`) to the current pass's statistics of every cut node of the
    /// block above it, of class `class`, and to the pixel's (`pixel`): at node a it
    /// estimates a's contribution as v P_a / P_leaf (lights inside a cluster are picked by
    /// power; §3.5.4).
    pub(super) fn record(
        &mut self,
        forest: &Forest,
        mut pixel: Option<&mut [Stat]>,
        class: usize,
        (leaf, value, power, visible): (u32, f64, f32, bool),
    ) {
        let mut node = leaf;
        loop {
            let s = self.slot[node as usize];
            if s != u32::MAX {
                let scale = if (node as usize) < forest.nodes.len() && power > 0.0 {
                    f64::from(forest.nodes[node as usize].power / power)
                } else {
                    1.0
                };
                for stat in std::iter::once(&mut self.current[class][s as usize])
                    .chain(pixel.as_deref_mut().map(|px| &mut px[s as usize]))
                {
                    stat.sum += value * scale;
                    stat.count += 1;
                    stat.visible += u32::from(visible);
                }
            }
            if (node as usize) >= forest.nodes.len() {
                break;
            }
            let parent = forest.nodes[node as usize].parent;
            if parent == NO_PARENT {
                break;
            }
            node = parent;
        }
    }
}
