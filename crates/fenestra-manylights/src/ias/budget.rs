//! Rendering to a time budget (a render's time limit; beyond the seed, whose renders stop on a fixed
//! threshold): each block takes the threshold that the blocks done so far say fits the time
//! left. A pixel's shadow rays grow about as 1 / threshold, so a block's seconds times its
//! threshold measure its work whatever threshold it had; blocks are taken in a shuffled order
//! so that the first ones done are a fair sample of the image.

use fenestra_core::sampler::hash_u32;
use std::sync::Mutex;

/// The finest and coarsest thresholds a budget may set.
const FINEST: f32 = 1e-5;
const COARSEST: f32 = 1.0;

/// The threshold of the blocks still to start, kept from what the finished ones cost.
pub(super) struct Budget {
    /// When the render must be done, on the render control's clock (seconds).
    deadline: f64,
    blocks: usize,
    threads: usize,
    state: Mutex<State>,
}

struct State {
    threshold: f32,
    /// Blocks finished, and the sum of their seconds times their threshold.
    done: usize,
    work: f64,
    /// The finest and coarsest thresholds given out.
    range: [f32; 2],
}

impl Budget {
    /// A budget ending at `deadline` for `blocks` blocks rendered `threads` at a time, the
    /// first ones at `threshold`.
    pub(super) fn new(deadline: f64, blocks: usize, threads: usize, threshold: f32) -> Self {
        Budget {
            deadline,
            blocks,
            threads: threads.max(1),
            state: Mutex::new(State {
                threshold,
                done: 0,
                work: 0.0,
                range: [f32::INFINITY, 0.0],
            }),
        }
    }

    /// The threshold for a block about to start.
    pub(super) fn threshold(&self) -> f32 {
        let mut s = self.state.lock().unwrap_or_else(|e| e.into_inner());
        let t = s.threshold;
        s.range = [s.range[0].min(t), s.range[1].max(t)];
        t
    }

    /// Records a block that took `seconds` at `threshold`, finished at `now`, and sets the
    /// threshold of the blocks still to start so that, at the mean work per block so far,
    /// they fill the threads for the time left. Once the first blocks have been timed (two
    /// per thread) it jumps there; after that it moves by at most 15% a block, so that one
    /// unusual block cannot swing it and the image's noise stays even. (A pixel takes at
    /// least two passes and at most the options' passes, so the work stops following
    /// 1 / threshold at both ends: there the threshold drifts to its bounds, harmlessly.)
    pub(super) fn finished(&self, seconds: f64, threshold: f32, now: f64) {
        let mut s = self.state.lock().unwrap_or_else(|e| e.into_inner());
        s.done += 1;
        s.work += seconds * f64::from(threshold);
        let left = self.blocks.saturating_sub(s.done);
        let first = 2 * self.threads;
        if left == 0 || s.done < first {
            return;
        }
        let per_block = s.work / s.done as f64;
        let time = (self.deadline - now).max(1e-3) * self.threads as f64;
        let wanted = (per_block * left as f64 / time) as f32;
        let t = s.threshold;
        let step = if s.done == first { 100.0 } else { 1.15 };
        s.threshold = wanted.clamp(t / step, t * step).clamp(FINEST, COARSEST);
    }

    /// The finest and coarsest thresholds given to blocks.
    pub(super) fn range(&self) -> [f32; 2] {
        self.state.lock().unwrap_or_else(|e| e.into_inner()).range
    }
}

/// The order blocks are rendered in: 0..n shuffled by a fixed hash (the same every render).
pub(super) fn shuffled(n: u32) -> Vec<u32> {
    let mut order: Vec<u32> = (0..n).collect();
    order.sort_by_key(|&b| (hash_u32(b), b));
    order
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_threshold_follows_the_time_left() {
        // Blocks that take 0.1 s at 1e-3 (work 1e-4 each), 100 blocks, 1 thread.
        let budget = Budget::new(20.0, 100, 1, 1e-3);
        // The first block changes nothing; after the second (0.2 s), 98 blocks and 19.8 s
        // are left: 98 x 1e-4 / 19.8.
        budget.finished(0.1, 1e-3, 0.1);
        assert_eq!(budget.threshold(), 1e-3);
        budget.finished(0.1, 1e-3, 0.2);
        let t = budget.threshold();
        assert!((t - 98.0 * 1e-4 / 19.8).abs() < 1e-7, "{t}");
        // Out of time: coarser, by at most 15% a block.
        budget.finished(0.1, t, 30.0);
        assert_eq!(budget.threshold(), 1.15 * t);
        assert_eq!(budget.range(), [1e-3_f32.min(t), 1e-3_f32.max(1.15 * t)]);
    }

    #[test]
    fn the_shuffle_is_a_permutation() {
        for n in [0, 1, 7, 225] {
            let mut order = shuffled(n);
            assert_ne!(
                n > 2,
                order.windows(2).all(|w| w[0] < w[1]),
                "{n} unshuffled"
            );
            order.sort_unstable();
            assert_eq!(order, (0..n).collect::<Vec<_>>());
        }
    }
}
